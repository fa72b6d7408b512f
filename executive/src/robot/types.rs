//! Small value types shared by the capability traits.

use nalgebra::Vector3;

/// A value stamped with the robot clock (s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stamped<T> {
    /// Robot-clock time of the reading (s).
    pub stamp: f64,
    /// The reading.
    pub value: T,
}

/// A force/torque reading in the wrist frame (N, N·m).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Wrench {
    /// Force (N), wrist frame.
    pub force: Vector3<f64>,
    /// Torque (N·m), wrist frame.
    pub torque: Vector3<f64>,
}

impl Wrench {
    /// The norm of the force, the quantity the paper thresholds (its Fig. 12).
    pub fn force_norm(&self) -> f64 {
        self.force.norm()
    }
}

/// The state of an action that was started and is being polled.
#[derive(Clone, Debug, PartialEq)]
pub enum ActionStatus<O> {
    /// Still under way.
    Running,
    /// Finished, with its outcome.
    Done(O),
}
