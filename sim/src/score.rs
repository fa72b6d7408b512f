//! Scoring a run against the simulation's ground truth: which scenario object each verdict was
//! about, whether the verdict was right, and whether the run met its scenario's `[expect]` block.

use nalgebra::Isometry3;
use nalgebra::{Point2, Vector2};
use nudge_executive::{RunReport, State, Verdict};
use nudge_perception::prism::convex_intersection_area;
use nudge_perception::{ObjectId, Prism};

use crate::adapter::SimRobot;
use crate::scenario::{Expect, ExpectedOutcome, Footprint, ObjectSpec};
use crate::truth::{Movability, Truth};

/// One verdict matched to the scenario object it was about.
#[derive(Clone, Debug, PartialEq)]
pub struct Scored {
    /// The executive's id.
    pub id: ObjectId,
    /// The scenario object's name, if the obstacle matched one.
    pub object: Option<String>,
    /// The executive's verdict.
    pub verdict: Verdict,
    /// Whether the verdict agrees with the object's true movability (false when it matched no object).
    pub correct: bool,
}

/// Farthest an obstacle's centroid may lie from a true object's centre to be that object (m).
pub const MATCH_DISTANCE: f64 = 0.4;

/// Matches every verdict of `report` to the true object its obstacle covers most of when the push
/// test that led to it began (the obstacle as the executive knew it then, against each object's
/// footprint where it stood then, [`nudge_executive::runner::Decision`]): a verdict is about what the
/// robot pushed, and a later push may move another object into where the obstacle lay (a bin cleared
/// against a partition found static). A verdict without that record is matched at the end of the
/// run, the obstacle and the objects as they are then. An obstacle seen in part (a long shelf's near end) has its centroid far from the object's
/// centre, but it lies on the object. An obstacle that covers no object is matched to the object
/// whose centre lies nearest its centroid within [`MATCH_DISTANCE`].
pub fn score(report: &RunReport, robot: &SimRobot) -> Vec<Scored> {
    let world = robot.world();
    let truth = &Truth::new(world);
    // Every scenario object with its index and its true pose at `time` (now when `None`).
    let standing = |time: Option<f64>| {
        world
            .objects()
            .iter()
            .enumerate()
            .filter_map(move |(i, (spec, _))| {
                let pose = match time {
                    Some(t) => world.object_pose_at(i, t),
                    None => truth.object_pose(i),
                };
                Some((i, spec, pose?))
            })
    };
    report
        .knowledge
        .explanation
        .verdicts
        .iter()
        .map(|(id, verdict)| {
            let (prism, time) = match report.decisions.get(id) {
                Some(decision) => (Some(&decision.prism), Some(decision.stamp)),
                None => (report.obstacle(*id), None),
            };
            let covered = prism.and_then(|p| {
                standing(time)
                    .filter_map(|(i, spec, pose)| {
                        let outline = true_outline(spec, &pose)?;
                        let area = convex_intersection_area(&p.footprint, &outline);
                        (area > 0.0).then(|| (area, i, spec.name.clone()))
                    })
                    .max_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)))
            });
            let centroid = prism.map(centroid);
            let nearest = covered.or_else(|| {
                centroid.and_then(|c| {
                    standing(time)
                        .filter_map(|(i, spec, pose)| {
                            let d =
                                (Point2::new(pose.translation.x, pose.translation.y) - c).norm();
                            (d <= MATCH_DISTANCE).then(|| (d, i, spec.name.clone()))
                        })
                        .min_by(|a, b| a.0.total_cmp(&b.0))
                })
            });
            let (object, correct) = match nearest {
                Some((_, i, name)) => {
                    let truly_movable = truth.movability(i) == Some(Movability::Movable);
                    (Some(name), truly_movable == verdict.is_movable())
                }
                // The room's own walls are no scenario object, and they never move.
                None if prism.is_some_and(|p| on_room_wall(&p.footprint, world.room_size())) => {
                    (Some(ROOM_WALL.to_string()), !verdict.is_movable())
                }
                None => (None, false),
            };
            Scored {
                id: *id,
                object,
                verdict: verdict.clone(),
                correct,
            }
        })
        .collect()
}

/// The name a verdict about the room's own walls is scored under.
pub const ROOM_WALL: &str = "room wall";

/// Whether an obstacle's `footprint` lies on the walls of a room of `size` (its floor `0..size`):
/// every vertex within [`MATCH_DISTANCE`] of the floor's edge, so a wall's piece seen from inside
/// (its footprint a few centimetres deep) and its corner pieces count, a thing standing in the room
/// not.
fn on_room_wall(footprint: &[Point2<f64>], size: [f64; 2]) -> bool {
    let [w, h] = size;
    !footprint.is_empty()
        && footprint.iter().all(|p| {
            let to_edge = p.x.min(w - p.x).min(p.y).min(h - p.y);
            to_edge <= MATCH_DISTANCE
        })
}

/// The footprint of the object `spec` describes, standing at `pose` (its true pose now), as a
/// counter-clockwise polygon.
fn true_outline(spec: &ObjectSpec, pose: &Isometry3<f64>) -> Option<Vec<Point2<f64>>> {
    let centre = Point2::new(pose.translation.x, pose.translation.y);
    let yaw = pose.rotation.euler_angles().2;
    Some(
        match spec.footprint()? {
            Footprint::Rectangle { half_extents, .. } => Footprint::Rectangle {
                centre,
                half_extents,
                yaw,
            },
            Footprint::Disc { radius, .. } => Footprint::Disc { centre, radius },
        }
        .polygon(),
    )
}

/// The mean of `prism`'s footprint vertices (the origin for an empty footprint).
pub(crate) fn centroid(prism: &Prism) -> Point2<f64> {
    let sum = prism
        .footprint
        .iter()
        .fold(Vector2::zeros(), |a, v| a + v.coords);
    Point2::from(sum / prism.footprint.len().max(1) as f64)
}

/// How a run ended, in the words of scenario files and result lines.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Outcome {
    /// The robot reached the goal.
    Goal,
    /// The executive proved there is no path.
    NoPath,
    /// The run was aborted (robot failure, limit, time budget, cancel).
    Aborted,
}

impl Outcome {
    /// The outcome of a terminal state (anything not Goal or NoPathToGoal counts as aborted).
    pub fn of(state: &State) -> Self {
        match state {
            State::Goal => Self::Goal,
            State::NoPathToGoal(_) => Self::NoPath,
            _ => Self::Aborted,
        }
    }

    /// "goal", "no_path" or "aborted".
    pub fn word(self) -> &'static str {
        match self {
            Self::Goal => "goal",
            Self::NoPath => "no_path",
            Self::Aborted => "aborted",
        }
    }
}

impl From<ExpectedOutcome> for Outcome {
    fn from(e: ExpectedOutcome) -> Self {
        match e {
            ExpectedOutcome::Goal => Self::Goal,
            ExpectedOutcome::NoPath => Self::NoPath,
        }
    }
}

/// One way a run differed from its `[expect]` block.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Mismatch {
    /// The run ended otherwise.
    Outcome {
        /// What the scenario expects.
        expected: Outcome,
        /// What happened.
        got: Outcome,
    },
    /// An object got the other verdict, or none.
    Verdict {
        /// The scenario object's name.
        object: String,
        /// True when the scenario expects it movable.
        expected_movable: bool,
        /// The verdict it got: `Some(true)` movable, `Some(false)` static, `None` never classified.
        got_movable: Option<bool>,
    },
}

impl std::fmt::Display for Mismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let word = |movable: bool| if movable { "movable" } else { "static" };
        match self {
            Self::Outcome { expected, got } => {
                write!(f, "outcome {} (expected {})", got.word(), expected.word())
            }
            Self::Verdict {
                object,
                expected_movable,
                got_movable,
            } => match got_movable {
                Some(m) => write!(
                    f,
                    "{object} {} (expected {})",
                    word(*m),
                    word(*expected_movable)
                ),
                None => write!(
                    f,
                    "{object} never classified (expected {})",
                    word(*expected_movable)
                ),
            },
        }
    }
}

/// Every way the run (its report and scored verdicts) differs from `expect`; empty when it passes.
/// Objects the block does not name may get any verdict or none.
pub fn compare(expect: &Expect, outcome: Outcome, scored: &[Scored]) -> Vec<Mismatch> {
    let mut mismatches = Vec::new();
    let expected = Outcome::from(expect.outcome);
    if outcome != expected {
        mismatches.push(Mismatch::Outcome {
            expected,
            got: outcome,
        });
    }
    let named = expect
        .movable
        .iter()
        .map(|n| (n, true))
        .chain(expect.static_.iter().map(|n| (n, false)));
    for (name, expected_movable) in named {
        // An object split into several obstacles counts as movable when any part moved.
        let verdicts: Vec<bool> = scored
            .iter()
            .filter(|s| s.object.as_deref() == Some(name.as_str()))
            .map(|s| s.verdict.is_movable())
            .collect();
        let got_movable = (!verdicts.is_empty()).then(|| verdicts.iter().any(|&m| m));
        if got_movable != Some(expected_movable) {
            mismatches.push(Mismatch::Verdict {
                object: name.clone(),
                expected_movable,
                got_movable,
            });
        }
    }
    mismatches
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scored(name: &str, movable: bool) -> Scored {
        Scored {
            id: ObjectId(0),
            object: Some(name.into()),
            verdict: if movable {
                Verdict::Movable
            } else {
                Verdict::Static {
                    after_ambiguity: false,
                }
            },
            correct: true,
        }
    }

    fn expect(outcome: ExpectedOutcome, movable: &[&str], static_: &[&str]) -> Expect {
        Expect {
            outcome,
            movable: movable.iter().map(|s| s.to_string()).collect(),
            static_: static_.iter().map(|s| s.to_string()).collect(),
        }
    }

    #[test]
    fn a_run_matching_its_expect_block_has_no_mismatch() {
        // Invariant: the right outcome and every named object with its expected verdict pass; unnamed objects are free.
        let e = expect(ExpectedOutcome::Goal, &["chair-1"], &["table"]);
        let s = [
            scored("table", false),
            scored("chair-1", true),
            scored("chair-2", false),
        ];
        assert!(compare(&e, Outcome::Goal, &s).is_empty());
    }

    #[test]
    fn each_difference_from_the_expect_block_is_reported() {
        // Invariant: a wrong outcome, a wrong verdict and a missing verdict each give one mismatch, in block order.
        let e = expect(ExpectedOutcome::NoPath, &["chair-1"], &["table", "chair-2"]);
        let s = [scored("table", true), scored("chair-1", true)];
        let m = compare(&e, Outcome::Aborted, &s);
        assert_eq!(
            m,
            vec![
                Mismatch::Outcome {
                    expected: Outcome::NoPath,
                    got: Outcome::Aborted
                },
                Mismatch::Verdict {
                    object: "table".into(),
                    expected_movable: false,
                    got_movable: Some(true)
                },
                Mismatch::Verdict {
                    object: "chair-2".into(),
                    expected_movable: false,
                    got_movable: None
                },
            ]
        );
        assert_eq!(m[1].to_string(), "table movable (expected static)");
        assert_eq!(
            m[2].to_string(),
            "chair-2 never classified (expected static)"
        );
    }

    #[test]
    fn a_piece_of_the_rooms_wall_is_the_room_wall_and_a_box_in_the_room_is_not() {
        // Invariant: an obstacle whose outline lies along the room's edge (a wall seen from inside, a corner piece) is a piece of the room's wall, scored as static in truth; one standing in the room, or reaching into it from a wall, is not.
        let square = |x0: f64, y0: f64, x1: f64, y1: f64| {
            [(x0, y0), (x1, y0), (x1, y1), (x0, y1)].map(|(x, y)| Point2::new(x, y))
        };
        let room = [9.0, 4.0];
        assert!(on_room_wall(&square(4.4, 3.9, 4.6, 4.02), room));
        assert!(on_room_wall(&square(-0.02, 0.0, 0.05, 1.8), room));
        assert!(on_room_wall(&square(8.7, 3.7, 9.0, 4.0), room));
        assert!(!on_room_wall(&square(4.1, 1.6, 4.9, 2.4), room));
        assert!(!on_room_wall(&square(4.4, 2.5, 4.6, 4.0), room));
    }
}
