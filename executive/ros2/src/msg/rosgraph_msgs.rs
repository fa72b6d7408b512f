//! `rosgraph_msgs`: the simulated clock.

use serde::{Deserialize, Serialize};

use super::{Time, ros_message};

/// `rosgraph_msgs/msg/Clock`: the time a simulator has reached, on `/clock`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Clock {
    /// Simulated time.
    pub clock: Time,
}
ros_message!(Clock, "rosgraph_msgs", "Clock");
