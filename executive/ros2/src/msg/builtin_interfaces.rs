//! `builtin_interfaces`: time on the wire.

use serde::{Deserialize, Serialize};

use super::ros_message;

/// `builtin_interfaces/msg/Time`: seconds and nanoseconds since the clock's epoch.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Time {
    /// Whole seconds.
    pub sec: i32,
    /// Nanoseconds past `sec`, below 10⁹.
    pub nanosec: u32,
}
ros_message!(Time, "builtin_interfaces", "Time");

/// `builtin_interfaces/msg/Duration`: a span of time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Duration {
    /// Whole seconds.
    pub sec: i32,
    /// Nanoseconds past `sec`, below 10⁹.
    pub nanosec: u32,
}
ros_message!(Duration, "builtin_interfaces", "Duration");
