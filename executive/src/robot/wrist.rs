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
}
