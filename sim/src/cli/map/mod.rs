//! `--map FILE.png`: an [`Observer`] that collects what a run saw and did, then draws it top-down
//! with one force-over-time panel per push test below the map (the paper's Fig. 12).

mod draw;
mod font;

pub use draw::draw;

use crate::scenario::Scenario;
use nalgebra::{Point2, Vector2};
use nudge_executive::record::{GridView, Observer, RobotFrames};
use nudge_executive::robot::Wrench;
use nudge_executive::{Edge, PushEvidence, PushIntent, Question, State, Verdict, Viewpoint};
use nudge_perception::{ObjectId, Prism};

/// The robot's track keeps a point each time the base moved this far (m).
const TRACK_STEP: f64 = 0.01;

/// The latest obstacle-type grid.
#[derive(Clone, Debug, PartialEq)]
pub struct GridCopy {
    /// Corner of cell (0, 0) in the map frame (m).
    pub origin: Point2<f64>,
    /// Cell side (m).
    pub resolution: f64,
    /// Cells along x.
    pub width: usize,
    /// Cells along y.
    pub height: usize,
    /// Class codes, row-major from (0, 0), rows along x.
    pub classes: Vec<u8>,
}

/// A push as it ran (a test or a clearing push), with the map-frame force it peaked at.
#[derive(Clone, Debug, PartialEq)]
pub struct PushMark {
    /// What was pushed, from where, which way.
    pub intent: PushIntent,
    /// Peak force vector (map frame, N).
    pub force: Vector2<f64>,
}

/// The wrist force of one push test over time.
#[derive(Clone, Debug, PartialEq)]
pub struct ForceTrace {
    /// The object tested.
    pub object: Option<ObjectId>,
    /// 1 for the first test of the object, 2 for the retest.
    pub attempt: u8,
    /// (robot time s, force magnitude N).
    pub samples: Vec<(f64, f64)>,
    /// The verdict the test led to, if it led to one.
    pub verdict: Option<Verdict>,
    /// The force limit of the test (N).
    pub limit: Option<f64>,
}

/// What a map shows, collected while the run goes.
#[derive(Clone, Debug)]
pub struct MapCollector {
    /// The scenario (room, start, goal, true objects).
    pub scenario: Scenario,
    /// The latest grid, when the runner reports one.
    pub grid: Option<GridCopy>,
    /// The latest obstacles.
    pub prisms: Vec<Prism>,
    /// Base positions over time.
    pub track: Vec<Point2<f64>>,
    /// Every path the robot set out on, in order.
    pub paths: Vec<Vec<Point2<f64>>>,
    /// Every push that ran, in order.
    pub pushes: Vec<PushMark>,
    /// Every push test's force trace, in order.
    pub tests: Vec<ForceTrace>,
    /// The last verdict on each object.
    pub verdicts: Vec<(ObjectId, Verdict)>,
    /// Every viewpoint the robot set out for, in order, with what it was to show.
    pub views: Vec<(Question, Viewpoint)>,
    /// Half the angle a look-around spans about the body's heading (rad), for drawing viewpoints.
    pub look_half_angle: f64,
    in_test: bool,
}

impl MapCollector {
    /// An empty collection for a run of `scenario`.
    pub fn new(scenario: &Scenario) -> Self {
        Self {
            scenario: scenario.clone(),
            grid: None,
            prisms: Vec::new(),
            track: Vec::new(),
            paths: Vec::new(),
            pushes: Vec::new(),
            tests: Vec::new(),
            verdicts: Vec::new(),
            views: Vec::new(),
            look_half_angle: crate::run::run_config(
                scenario,
                scenario.seed,
                nudge_executive::CandidatePolicy::Nearest,
            )
            .look_coverage()
            .half_angle,
            in_test: false,
        }
    }

    /// The verdict on `object`, if it has one.
    pub fn verdict_of(&self, object: ObjectId) -> Option<&Verdict> {
        self.verdicts
            .iter()
            .rev()
            .find(|(id, _)| *id == object)
            .map(|(_, v)| v)
    }
}

impl Observer for MapCollector {
    fn transition(&mut self, _stamp: f64, _from: Option<&State>, _edge: Edge, to: &State) {
        match to {
            State::PushTest {
                target, attempt, ..
            } if !self.in_test => {
                self.in_test = true;
                self.tests.push(ForceTrace {
                    object: Some(*target),
                    attempt: *attempt,
                    samples: Vec::new(),
                    verdict: None,
                    limit: None,
                });
            }
            State::PushTest { .. } => {}
            State::GoToView { question, view } => {
                self.views.push((question.clone(), view.clone()));
                self.in_test = false;
            }
            _ => self.in_test = false,
        }
    }

    fn verdict(
        &mut self,
        _stamp: f64,
        object: ObjectId,
        verdict: &Verdict,
        evidence: &PushEvidence,
    ) {
        self.verdicts.push((object, verdict.clone()));
        if let Some(t) = self
            .tests
            .iter_mut()
            .rev()
            .find(|t| t.object == Some(object))
        {
            t.verdict = Some(verdict.clone());
            t.limit = Some(evidence.force_limit);
        }
    }

    fn prisms(&mut self, _stamp: f64, prisms: &[Prism]) {
        self.prisms = prisms.to_vec();
    }

    fn grid(&mut self, _stamp: f64, grid: &GridView<'_>) {
        self.grid = Some(GridCopy {
            origin: grid.origin,
            resolution: grid.resolution,
            width: grid.width,
            height: grid.height,
            classes: grid.classes.to_vec(),
        });
    }

    fn path(&mut self, _stamp: f64, waypoints: &[Point2<f64>]) {
        self.paths.push(waypoints.to_vec());
    }

    fn push(&mut self, _stamp: f64, intent: &PushIntent, force: Option<Vector2<f64>>) {
        if let Some(force) = force {
            self.pushes.push(PushMark {
                intent: intent.clone(),
                force,
            });
        }
    }

    fn frames(&mut self, _stamp: f64, frames: &RobotFrames) {
        let here = Point2::from(frames.base.translation.vector);
        if self
            .track
            .last()
            .is_none_or(|last| (here - last).norm() >= TRACK_STEP)
        {
            self.track.push(here);
        }
    }

    fn wrench(&mut self, stamp: f64, wrench: &Wrench) {
        if self.in_test
            && let Some(t) = self.tests.last_mut()
        {
            t.samples.push((stamp, wrench.force_norm()));
        }
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{Isometry2, Unit};
    use nudge_perception::grid::CellClass;

    use super::*;

    fn room() -> MapCollector {
        let scenario = Scenario::default_room().expect("default room");
        let mut run = MapCollector::new(&scenario);
        // A 10 × 10 grid of 0.1 m cells at (1, 1): a band of each class.
        let classes: Vec<u8> = (0..100u8).map(|i| (i / 20).min(4)).collect();
        run.grid(
            0.0,
            &GridView {
                origin: Point2::new(1.0, 1.0),
                resolution: 0.1,
                width: 10,
                height: 10,
                classes: &classes,
            },
        );
        run.path(1.0, &[Point2::new(0.6, 1.8), Point2::new(2.0, 0.5)]);
        run
    }

    #[test]
    fn push_tests_collect_their_force_and_verdict() {
        // Invariant: wrist samples land in the push test under way (none outside one), and the verdict after it is attached to it.
        let mut run = room();
        let target = ObjectId(4);
        let intent = PushIntent {
            target,
            stand: Isometry2::translation(3.0, 0.55),
            hand_height: 0.6,
            clear_height: 0.6,
            direction: Unit::new_normalize(Vector2::x()),
            distance: 0.8,
            opens_way: true,
        };
        let wrench = |f: f64| Wrench {
            force: nalgebra::Vector3::new(f, 0.0, 0.0),
            torque: nalgebra::Vector3::zeros(),
        };
        run.wrench(0.5, &wrench(3.0));
        let testing = State::PushTest {
            target,
            intent: intent.clone(),
            attempt: 1,
        };
        run.transition(1.0, Some(&State::LookAround), Edge::Cleared, &testing);
        run.wrench(1.1, &wrench(5.0));
        run.wrench(1.2, &wrench(12.0));
        run.transition(2.0, Some(&testing), Edge::Cleared, &State::LookAround);
        run.wrench(2.5, &wrench(7.0));
        run.push(2.0, &intent, Some(Vector2::new(-12.0, 0.0)));
        assert_eq!(run.tests.len(), 1);
        assert_eq!(run.tests[0].samples, vec![(1.1, 5.0), (1.2, 12.0)]);
        assert_eq!(run.tests[0].object, Some(target));
        assert_eq!(run.pushes.len(), 1);
        let path = std::env::temp_dir().join(format!("nudge-map-test-{}.png", std::process::id()));
        let file = std::fs::File::create(&path).expect("temp file");
        draw(&run, file, &path).expect("draws");
        let image = image::open(&path).expect("a PNG").to_rgb8();
        let _ = std::fs::remove_file(&path);
        let has = |rgb: [u8; 4]| image.pixels().any(|p| p.0 == [rgb[0], rgb[1], rgb[2]]);
        // Free cells are white like the background; unknown ones are drawn lighter than the palette's.
        for class in [CellClass::Stationary, CellClass::Movable, CellClass::Moving] {
            assert!(has(class.colour()), "{class:?} cells are drawn");
        }
        assert!(has([215, 215, 215, 255]), "unknown cells are drawn");
        assert!(has([20, 160, 60, 255]), "the path");
        assert!(image.height() > 700 + 200, "a force panel below the map");
    }
}
