//! The pan/tilt head that carries the colour range sensor.

use super::{ActionStatus, RobotError, Stamped};

/// A pan/tilt head.
pub trait Head {
    /// Current (pan, tilt) in rad; pan left positive, tilt down positive.
    fn head_angles(&mut self) -> Result<Stamped<(f64, f64)>, RobotError>;

    /// Starts moving the head to (pan, tilt), rad.
    fn start_point_head(&mut self, pan: f64, tilt: f64) -> Result<(), RobotError>;

    /// Polls the head motion.
    fn head_status(&mut self) -> Result<ActionStatus<()>, RobotError>;
}
