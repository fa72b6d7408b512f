//! Push sequences: when no single push opens the way, two pushes whose combined result does.
//!
//! In the spirit of Stilman and Kuffner's NAMO planners, which choose the order in which obstacles are
//! moved and where each goes, kept small and bounded: sequences of two pushes, of two different
//! objects among the few nearest candidates. A caller searches only when no single push can open the
//! way: when no candidate's removal alone opens it ([`single_removal_opens`], a flood fill per
//! candidate). What is searched, in this order:
//!
//! 1. **Pairs.** Each ordered pair (A, B) of candidates, at most [`SequenceConfig::max_candidates`]
//!    of them: first those the cheapest way to the goal crosses when candidates may be driven
//!    through at a cost ([`cheapest_crossing`], in the order it meets them), then the others in the
//!    order given (nearest first). A pair whose joint removal leaves the goal unreachable (a flood
//!    fill, [`certainly_unreachable`]) is ruled out at once: no pushing of the two can open the way.
//! 2. **First pushes.** A's pushes whose sweep is valid ([`swept_pushes`]), at the distances of
//!    [`SequenceConfig::first_distances`], stand poses nearest the robot first. One whose result,
//!    with B removed, still leaves the goal unreachable is passed over (flood fill).
//! 3. **Second push.** B's push, planned as a single push ([`plan_push_over`]) at the same few
//!    distances in the world after A's push, from where A's push leaves the robot: it must open the
//!    way. The floor under it is not
//!    checked here: the robot looks again before it is made, and plans it afresh from what it sees.
//!
//! The first sequence found is returned; when none is, every pair considered with what stopped it.
//! The executive makes the first push and looks again: the second is then a single push that opens
//! the way, planned from what the robot sees.

use nalgebra::Point2;
use nudge_perception::{ObjectId, Prism};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::blocking::{CrossingConfig, cheapest_crossing};
use crate::problem::{GoalRegion, Problem};
use crate::push::{
    PushConfig, PushError, PushPlan, SweptPush, plan_of_swept, plan_push_over, swept_pushes,
};
use crate::reach::{Change, ReachMemo, certainly_unreachable};
use crate::seen_floor::FloorCheck;
use crate::validity::Validity;

/// How much to search.
#[derive(Clone, Debug, PartialEq)]
pub struct SequenceConfig {
    /// Candidates taken into pairs, nearest first: four give twelve ordered pairs.
    pub max_candidates: usize,
    /// Distances of the first push to try (m): a few, spread over the single push's range, since
    /// the second push is planned in full.
    pub first_distances: Vec<f64>,
    /// The grid on which the candidates the way crosses are found.
    pub crossing: CrossingConfig,
}

impl Default for SequenceConfig {
    fn default() -> Self {
        Self {
            max_candidates: 4,
            first_distances: vec![0.5, 1.0, 1.5, 2.0, 3.0],
            // It only orders candidates: cells twice the flood fill's still find a doorway's
            // obstacles, at a quarter of the cost.
            crossing: CrossingConfig {
                resolution: 0.1,
                ..CrossingConfig::default()
            },
        }
    }
}

/// Two pushes that together open the way.
#[derive(Clone, Debug, PartialEq)]
pub struct Sequence {
    /// The push to make first, its approach planned from the robot.
    pub first: PushPlan,
    /// The push that then opens the way, as planned now (the executive plans it again after a look).
    pub second: PushPlan,
}

/// What stopped one ordered pair.
#[derive(Clone, Debug, PartialEq)]
pub enum PairMiss {
    /// Even with both objects gone, the goal is unreachable.
    RemovalDoesNotOpen,
    /// The first object has no push to try.
    NoFirstPush(PushError),
    /// No first push leaves the way open to a push of the second.
    FirstPushesBlockTheWay {
        /// First pushes tried.
        tried: usize,
    },
    /// After some first push, the second object could not be pushed out of the way.
    NoSecondPush {
        /// Why, for the last first push tried.
        last: PushError,
    },
    /// Every first push that could open the way has no reachable stand pose.
    FirstUnreachable,
}

impl std::fmt::Display for PairMiss {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PairMiss::RemovalDoesNotOpen => write!(f, "even with both gone there is no way"),
            PairMiss::NoFirstPush(e) => write!(f, "no first push: {e}"),
            PairMiss::FirstPushesBlockTheWay { tried } => {
                write!(f, "each of {tried} first pushes leaves the way shut")
            }
            PairMiss::NoSecondPush { last } => write!(f, "no second push: {last}"),
            PairMiss::FirstUnreachable => write!(f, "no first push has a reachable stand pose"),
        }
    }
}

/// An ordered pair considered and what stopped it.
#[derive(Clone, Debug, PartialEq)]
pub struct PairRecord {
    /// Pushed first.
    pub first: ObjectId,
    /// Pushed second.
    pub second: ObjectId,
    /// Why the pair gives no sequence.
    pub miss: PairMiss,
}

impl std::fmt::Display for PairRecord {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} then {}: {}", self.first, self.second, self.miss)
    }
}

/// Whether removing some one of `candidates` (ids not in `validity` skipped) leaves the goal maybe
/// reachable: then a single push of it may open the way, and a sequence is not needed.
pub fn single_removal_opens(
    candidates: &[&Prism],
    validity: &Validity,
    robot: &Point2<f64>,
    goal: &GoalRegion,
) -> bool {
    candidates
        .iter()
        .filter(|p| validity.obstacle(p.id).is_some())
        .any(|p| !certainly_unreachable(&validity.without(&[p.id]), robot, goal))
}

/// Searches for two pushes, of two of `candidates` (nearest first; ids not in `validity` skipped; those
/// the way crosses taken first),
/// that together open the way from `robot` to `goal`; the first push keeps to seen floor when
/// `floor` is given. `first_only` restricts the search to sequences that push that object first.
/// When none is found, every pair considered with what stopped it.
#[allow(clippy::too_many_arguments)]
pub fn plan_sequence(
    candidates: &[&Prism],
    validity: &Validity,
    robot: &Point2<f64>,
    goal: &GoalRegion,
    config: &PushConfig,
    search: &SequenceConfig,
    floor: Option<FloorCheck<'_>>,
    first_only: Option<ObjectId>,
    rng: &mut ChaCha8Rng,
) -> Result<Sequence, Vec<PairRecord>> {
    let seed: u64 = rng.random();
    let present: Vec<&Prism> = candidates
        .iter()
        .copied()
        .filter(|p| validity.obstacle(p.id).is_some())
        .collect();
    let ids: Vec<ObjectId> = present.iter().map(|p| p.id).collect();
    let crossed = Problem::new(*robot, goal.centre(), goal.tolerance())
        .ok()
        .and_then(|problem| cheapest_crossing(&problem, validity, &ids, &search.crossing).ok())
        .map(|c| c.crossed)
        .unwrap_or_default();
    let mut prisms: Vec<&Prism> = crossed
        .iter()
        .filter_map(|id| present.iter().copied().find(|p| p.id == *id))
        .collect();
    prisms.extend(present.iter().copied().filter(|p| !crossed.contains(&p.id)));
    prisms.truncate(search.max_candidates);
    let mut records = Vec::new();
    let mut memo = ReachMemo::new(validity);
    for a in &prisms {
        if first_only.is_some_and(|id| id != a.id) {
            continue;
        }
        let mut firsts: Option<Result<Vec<SweptPush>, PushError>> = None;
        for b in prisms.iter().filter(|b| b.id != a.id) {
            let mut own =
                ChaCha8Rng::seed_from_u64(seed ^ (u64::from(a.id.0) << 32) ^ u64::from(b.id.0));
            let miss = match try_pair(
                a,
                b,
                validity,
                robot,
                goal,
                config,
                search,
                floor,
                &mut firsts,
                &mut memo,
                &mut own,
            ) {
                Ok(sequence) => return Ok(sequence),
                Err(miss) => miss,
            };
            records.push(PairRecord {
                first: a.id,
                second: b.id,
                miss,
            });
        }
    }
    Err(records)
}

/// One ordered pair: A's first pushes (computed once per A into `firsts`), each followed by a
/// single push of B.
#[allow(clippy::too_many_arguments)]
fn try_pair(
    a: &Prism,
    b: &Prism,
    validity: &Validity,
    robot: &Point2<f64>,
    goal: &GoalRegion,
    config: &PushConfig,
    search: &SequenceConfig,
    floor: Option<FloorCheck<'_>>,
    firsts: &mut Option<Result<Vec<SweptPush>, PushError>>,
    memo: &mut ReachMemo<'_>,
    rng: &mut ChaCha8Rng,
) -> Result<Sequence, PairMiss> {
    let both = [a.id, b.id];
    let removed = Change {
        removed: &both,
        moved: None,
    };
    if memo.certainly_unreachable(&validity.without(&both), removed, robot, goal) {
        return Err(PairMiss::RemovalDoesNotOpen);
    }
    let pushes = firsts
        .get_or_insert_with(|| {
            swept_pushes(
                a,
                validity,
                robot,
                goal,
                config,
                floor,
                &search.first_distances,
            )
        })
        .as_ref()
        .map_err(|e| PairMiss::NoFirstPush(e.clone()))?;
    // The second push at the first's few distances: it only has to exist here; the executive plans
    // it again, over the whole range, after a look.
    let coarse = PushConfig {
        distances: search.first_distances.clone(),
        ..config.clone()
    };
    let mut last: Option<PushError> = None;
    let mut unreachable = false;
    for push in pushes {
        let Ok(after) = validity.with_moved(a.id, &push.offset()) else {
            continue;
        };
        let moved = Change {
            removed: &[b.id],
            moved: Some(a.id),
        };
        if memo.certainly_unreachable(&after.without(&[b.id]), moved, &push.end, goal) {
            continue;
        }
        match plan_push_over(b, &after, &push.end, goal, &coarse, None, rng) {
            Ok(second) if second.opens_path => {
                let Some(first) = plan_of_swept(push, a, validity, robot, config, rng) else {
                    unreachable = true;
                    continue;
                };
                return Ok(Sequence { first, second });
            }
            Ok(_) => last = Some(PushError::OpensNoWay(b.id)),
            Err(e) => last = Some(e),
        }
    }
    Err(match (last, unreachable) {
        (_, true) => PairMiss::FirstUnreachable,
        (Some(last), false) => PairMiss::NoSecondPush { last },
        (None, false) => PairMiss::FirstPushesBlockTheWay {
            tried: pushes.len(),
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::space::Bounds;
    use crate::validity::{RobotCylinder, ValidityConfig};
    use nalgebra::Isometry3;
    use nudge_perception::{CloudFrame, ColourCloud};

    fn block(id: u32, x0: f64, y0: f64, x1: f64, y1: f64, top: f64) -> Prism {
        Prism {
            id: ObjectId(id),
            footprint: vec![
                Point2::new(x0, y0),
                Point2::new(x1, y0),
                Point2::new(x1, y1),
                Point2::new(x0, y1),
            ],
            z_min: 0.0,
            z_max: top,
            points: ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0),
        }
    }

    /// A 8 × 4 m room split at x 3.9..4.1 by a wall with a 1.2 m door (y 1.4..2.6); a crate (id 1)
    /// fills the door, a chair (id 2) stands where the robot would stand to push the crate, and
    /// `extra` obstacles besides. The robot at (1, 2), the goal at (7, 2).
    fn room(extra: Vec<Prism>) -> (Vec<Prism>, Validity) {
        let mut prisms = vec![
            block(1, 3.7, 1.5, 4.3, 2.5, 0.7),
            block(2, 3.0, 1.75, 3.5, 2.25, 0.85),
            block(10, 3.9, 0.0, 4.1, 1.4, 2.0),
            block(11, 3.9, 2.6, 4.1, 4.0, 2.0),
        ];
        prisms.extend(extra);
        let robot = RobotCylinder {
            radius: 0.35,
            height: 1.5,
        };
        let walls = Bounds::new(Point2::new(0.0, 0.0), Point2::new(8.0, 4.0)).expect("room");
        let validity =
            Validity::new(robot, walls, &prisms, ValidityConfig::default()).expect("validity");
        (prisms, validity)
    }

    fn search(
        prisms: &[Prism],
        validity: &Validity,
        candidates: &[u32],
    ) -> Result<Sequence, Vec<PairRecord>> {
        let chosen: Vec<&Prism> = candidates
            .iter()
            .filter_map(|id| prisms.iter().find(|p| p.id.0 == *id))
            .collect();
        let goal = GoalRegion::new(Point2::new(7.0, 2.0), 0.2).expect("goal");
        plan_sequence(
            &chosen,
            validity,
            &Point2::new(1.0, 2.0),
            &goal,
            &PushConfig::default(),
            &SequenceConfig::default(),
            None,
            None,
            &mut ChaCha8Rng::seed_from_u64(7),
        )
    }

    #[test]
    fn two_objects_needed_are_pushed_in_the_order_that_opens_the_way() {
        // Invariant: when the crate in the door cannot be pushed from where the chair stands and no push of the chair alone opens the way, the search finds the chair pushed first (out of the crate's stand pose) and then the crate pushed through the door, which opens the way; the chair's push leaves the crate's stand pose free.
        let (prisms, validity) = room(vec![]);
        let goal = GoalRegion::new(Point2::new(7.0, 2.0), 0.2).expect("goal");
        let crate_alone = crate::push::plan_push(
            &prisms[0],
            &validity,
            &Point2::new(1.0, 2.0),
            &goal,
            &PushConfig::default(),
            &mut ChaCha8Rng::seed_from_u64(1),
        );
        assert!(
            !crate_alone.as_ref().is_ok_and(|p| p.opens_path),
            "the crate alone must not open the way: {crate_alone:?}"
        );
        let sequence = search(&prisms, &validity, &[2, 1]).expect("a sequence");
        assert_eq!(sequence.first.object, ObjectId(2));
        assert_eq!(sequence.second.object, ObjectId(1));
        assert!(sequence.second.opens_path);
        assert!(
            sequence.second.direction.x > 0.9,
            "the crate goes through the door"
        );
    }

    #[test]
    fn no_sequence_when_the_far_side_is_blocked_and_every_pair_says_why() {
        // Invariant: with a bolted block 0.55 m behind the door (the crate cannot be pushed through, and the way round it stays open once both are gone), no sequence is found, and every ordered pair of the candidates is reported with what stopped it, naming the block the crate's pushes run into; a pair whose removal opens nothing says so.
        let (prisms, validity) = room(vec![block(12, 4.85, 1.0, 5.45, 3.0, 1.0)]);
        let records = search(&prisms, &validity, &[2, 1]).expect_err("no sequence");
        assert_eq!(records.len(), 2);
        assert!(
            records
                .iter()
                .any(|r| r.first == ObjectId(2) && r.second == ObjectId(1))
        );
        assert!(
            records
                .iter()
                .any(|r| r.first == ObjectId(1) && r.second == ObjectId(2))
        );
        for r in &records {
            println!("{r}");
            assert_ne!(r.miss, PairMiss::RemovalDoesNotOpen, "{r}");
            // The crate's pushes meet the bolted block, and say so.
            assert!(r.to_string().contains("obj-12"), "{r}");
        }
        // With the door's crate bolted too (not a candidate), the chair alone has no partner.
        let (prisms, validity) = room(vec![block(12, 4.85, 1.0, 5.45, 3.0, 1.0)]);
        assert!(
            search(&prisms, &validity, &[2])
                .expect_err("none")
                .is_empty()
        );
    }
}
