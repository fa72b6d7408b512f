//! Localisation and locomotion of the robot's base.

use nalgebra::{Isometry2, Point2};

use super::{ActionStatus, RobotError, Stamped};

/// How a walk ended.
#[derive(Clone, Debug, PartialEq)]
pub enum WalkOutcome {
    /// The last waypoint was reached.
    Arrived,
    /// Something was in the way; the robot stopped short at `at` (map frame) without touching it.
    Blocked {
        /// Where the base stopped.
        at: Isometry2<f64>,
    },
    /// [`Base::stop_walk`] ended the walk.
    Stopped,
}

/// The mobile base: where it is, and walking a path.
pub trait Base {
    /// Base pose (`base_link` in `map`) with its stamp.
    fn base_pose(&mut self) -> Result<Stamped<Isometry2<f64>>, RobotError>;

    /// Starts walking through `waypoints` (map frame, m) at the robot's walking speed; the base faces
    /// its direction of travel. Replaces any walk under way.
    fn start_walk(&mut self, waypoints: &[Point2<f64>]) -> Result<(), RobotError>;

    /// Starts turning on the spot to face `yaw` (rad, map frame).
    fn start_turn(&mut self, yaw: f64) -> Result<(), RobotError>;

    /// Polls the walk or turn under way.
    fn walk_status(&mut self) -> Result<ActionStatus<WalkOutcome>, RobotError>;

    /// Stops walking as soon as it is safe.
    fn stop_walk(&mut self) -> Result<(), RobotError>;
}
