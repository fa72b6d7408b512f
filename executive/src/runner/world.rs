//! What the runner knows of the world between commands: the latest look, the obstacles, the plans.

use nalgebra::{Isometry3, Point2};
use nudge_motion::{Bounds, Path, Problem, PushPlan, Validity};
use nudge_perception::{ColourCloud, Prism};

use super::config::RunConfig;

/// The runner's world model.
#[derive(Clone, Debug, Default)]
pub(crate) struct WorldModel {
    /// Clouds of the latest look-around.
    pub views: Vec<ColourCloud>,
    /// Obstacles of the latest detection.
    pub prisms: Vec<Prism>,
    /// The path being walked.
    pub path: Option<Path>,
    /// The push plan being executed.
    pub push_plan: Option<PushPlan>,
    /// Where the camera was at the latest capture.
    pub camera: Option<Isometry3<f64>>,
}

/// Margin around everything known when no room is given (m).
const BOUNDS_MARGIN: f64 = 1.0;

impl WorldModel {
    /// The planning bounds: everything seen, the robot and the goal, with a margin.
    pub fn bounds(&self, robot: &Point2<f64>, config: &RunConfig) -> Option<Bounds> {
        let mut lo = robot.coords.inf(&config.goal.coords);
        let mut hi = robot.coords.sup(&config.goal.coords);
        for p in self.prisms.iter().flat_map(|p| p.footprint.iter()) {
            lo = lo.inf(&p.coords);
            hi = hi.sup(&p.coords);
        }
        let m = nalgebra::Vector2::repeat(BOUNDS_MARGIN);
        Bounds::new(Point2::from(lo - m), Point2::from(hi + m)).ok()
    }

    /// The validity checker for the current obstacles.
    pub fn validity(&self, robot: &Point2<f64>, config: &RunConfig) -> Result<Validity, String> {
        let bounds = self
            .bounds(robot, config)
            .ok_or_else(|| "no planning bounds".to_string())?;
        Validity::new(config.robot, bounds, &self.prisms, config.validity)
            .map_err(|e| e.to_string())
    }

    /// The problem from `robot` to the goal.
    pub fn problem(robot: &Point2<f64>, config: &RunConfig) -> Result<Problem, String> {
        Problem::new(*robot, config.goal, config.goal_tolerance).map_err(|e| e.to_string())
    }
}
