//! The one error type every adapter call returns.

/// Why an adapter call failed. The executive ends in `Aborted` with this as the reason.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum RobotError {
    /// The capability is missing or not ready (no sensor, driver down).
    #[error("{capability} is unavailable: {reason}")]
    Unavailable {
        /// Which capability, e.g. "arm".
        capability: &'static str,
        /// What the adapter knows.
        reason: String,
    },
    /// The command was refused before it started (out of reach, invalid argument, busy).
    #[error("{capability} refused the command: {reason}")]
    Refused {
        /// Which capability.
        capability: &'static str,
        /// Why.
        reason: String,
    },
    /// The adapter gave up waiting for the hardware.
    #[error("{capability} timed out after {seconds} s")]
    Timeout {
        /// Which capability.
        capability: &'static str,
        /// How long it waited (robot clock).
        seconds: f64,
    },
    /// The hardware or simulation reported a fault.
    #[error("{capability} fault: {reason}")]
    Fault {
        /// Which capability.
        capability: &'static str,
        /// What went wrong.
        reason: String,
    },
}
