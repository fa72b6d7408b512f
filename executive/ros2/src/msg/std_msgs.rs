//! `std_msgs`: the header every stamped message starts with.

use serde::{Deserialize, Serialize};

use super::{Time, ros_message};

/// `std_msgs/msg/Header`: when and in which frame.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Header {
    /// When the data was taken.
    pub stamp: Time,
    /// The frame the data is expressed in.
    pub frame_id: String,
}
ros_message!(Header, "std_msgs", "Header");
