//! `tf2_msgs`: what `/tf` carries.

use serde::{Deserialize, Serialize};

use super::{TransformStamped, ros_message};

/// `tf2_msgs/msg/TFMessage`: transforms published together.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TFMessage {
    /// The transforms.
    pub transforms: Vec<TransformStamped>,
}
ros_message!(TFMessage, "tf2_msgs", "TFMessage");
