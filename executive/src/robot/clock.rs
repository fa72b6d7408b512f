//! Time, which only the adapter owns.

use super::RobotError;

/// The robot clock. In simulation it is simulated time; nothing in nudge reads the wall clock to decide.
pub trait Clock {
    /// Current robot-clock time (s).
    fn now(&self) -> f64;

    /// Lets `dt` seconds of robot time pass: a simulation steps its physics, a real robot waits for
    /// its next control period. Running actions progress meanwhile.
    fn advance(&mut self, dt: f64) -> Result<(), RobotError>;
}
