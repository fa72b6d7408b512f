//! The wrist force/torque sensor.

use super::{RobotError, Stamped, Wrench};

/// A 6-axis wrist force/torque sensor.
pub trait WristSensor {
    /// Zeroes the sensor: later readings subtract the current mean reading.
    fn tare(&mut self) -> Result<(), RobotError>;

    /// The latest reading (wrist frame).
    fn wrench(&mut self) -> Result<Stamped<Wrench>, RobotError>;

    /// Every reading taken since the previous call, oldest first, at the sensor's own rate — the force
    /// trace of a push test.
    fn drain_wrenches(&mut self) -> Result<Vec<Stamped<Wrench>>, RobotError>;

    /// Forgets every reading taken so far, so the next drain starts now: what the runner does before
    /// a stroke, after a walk that may have left a minute of readings waiting. An adapter that can
    /// drop them without handing them over should; the default drains them and drops them.
    fn discard_wrenches(&mut self) -> Result<(), RobotError> {
        self.drain_wrenches().map(drop)
    }
}
