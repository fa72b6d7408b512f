//! The arm and hand that push.

use nalgebra::{Point3, Vector3};

use super::{ActionStatus, RobotError, Stamped, Wrench};

/// A straight-line hand motion that stops itself when the wrist force reaches a limit.
#[derive(Clone, Debug, PartialEq)]
pub struct GuardedMove {
    /// Where the line starts, in `base_link` (m). The hand goes there first, unguarded but slow.
    pub from: Point3<f64>,
    /// Where the line ends, in `base_link` (m).
    pub to: Point3<f64>,
    /// Hand speed along the line (m/s).
    pub speed: f64,
    /// The move stops when the norm of the tared wrist force reaches this (N).
    pub force_limit: f64,
    /// Largest acceleration of the hand along the line (m/s²); `None`: the arm's own. A move that
    /// starts with the hand against something raises the force at the wrist's stiffness times the
    /// hand's speed, so a gentle speed ramp is a gentle force ramp: the object breaks free while the
    /// hand is still slow, and its start from rest barely adds to the force.
    pub acceleration: Option<f64>,
}

impl GuardedMove {
    /// Unit direction of the push, or `None` when `from` and `to` coincide.
    pub fn direction(&self) -> Option<Vector3<f64>> {
        (self.to - self.from).try_normalize(1e-9)
    }
}

/// How a guarded move ended.
#[derive(Clone, Debug, PartialEq)]
pub enum HandOutcome {
    /// The hand reached the end of the line below the force limit.
    Reached,
    /// The force limit was reached; the hand stopped where it was.
    ForceLimit {
        /// The reading that crossed the limit.
        wrench: Stamped<Wrench>,
        /// Hand position at the stop, `base_link` (m).
        at: Point3<f64>,
    },
    /// [`Arm::stop_hand`] ended the move.
    Stopped,
}

/// One arm with a hand, able to push.
pub trait Arm {
    /// Hand position in `base_link` (m), from joint angles through forward kinematics on a real robot.
    fn hand_position(&mut self) -> Result<Stamped<Point3<f64>>, RobotError>;

    /// Starts a guarded straight-line move.
    fn start_guarded_move(&mut self, motion: GuardedMove) -> Result<(), RobotError>;

    /// Starts retracting the hand to its rest pose beside the body.
    fn start_retract(&mut self) -> Result<(), RobotError>;

    /// Polls the hand motion under way.
    fn hand_status(&mut self) -> Result<ActionStatus<HandOutcome>, RobotError>;

    /// Stops the hand where it is.
    fn stop_hand(&mut self) -> Result<(), RobotError>;
}
