//! Scoring a run against the simulation's ground truth.

use nalgebra::Point2;
use nudge_executive::{RunReport, Verdict};
use nudge_perception::ObjectId;
use nudge_sim::adapter::SimRobot;
use nudge_sim::truth::{Movability, Truth};

/// One verdict matched to the scenario object it was about.
#[derive(Clone, Debug, PartialEq)]
pub struct Scored {
    /// The executive's id.
    pub id: ObjectId,
    /// The scenario object's name, if the obstacle matched one.
    pub object: Option<String>,
    /// The executive's verdict.
    pub verdict: Verdict,
    /// Whether the verdict agrees with the object's true movability.
    pub correct: bool,
}

/// Farthest an obstacle's centroid may lie from a true object's centre to be that object (m).
const MATCH_DISTANCE: f64 = 0.4;

/// Matches every verdict of `report` to the true object nearest its obstacle, at the end of the run.
pub fn score(report: &RunReport, robot: &SimRobot) -> Vec<Scored> {
    let world = robot.world();
    let truth = Truth::new(world);
    report
        .knowledge
        .explanation
        .verdicts
        .iter()
        .map(|(id, verdict)| {
            let centroid = report.obstacles.iter().find(|p| p.id == *id).map(|p| {
                let sum = p
                    .footprint
                    .iter()
                    .fold(nalgebra::Vector2::zeros(), |a, v| a + v.coords);
                Point2::from(sum / p.footprint.len().max(1) as f64)
            });
            let nearest = centroid.and_then(|c| {
                world
                    .objects()
                    .iter()
                    .enumerate()
                    .filter_map(|(i, (spec, _))| {
                        let pose = truth.object_pose(i)?;
                        let d = (Point2::new(pose.translation.x, pose.translation.y) - c).norm();
                        (d <= MATCH_DISTANCE).then(|| (d, i, spec.name.clone()))
                    })
                    .min_by(|a, b| a.0.total_cmp(&b.0))
            });
            let (object, correct) = match nearest {
                Some((_, i, name)) => {
                    let truly_movable = truth.movability(i) == Some(Movability::Movable);
                    (Some(name), truly_movable == verdict.is_movable())
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
