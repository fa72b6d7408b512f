//! The ROS 2 messages the adapter uses, field for field as their `.msg` files define them (Humble
//! and later), so their CDR is what any ROS 2 node sends. Each type says its ROS name
//! ([`RosMessage::TYPE_NAME`]) and its DDS type name ([`RosMessage::DDS_TYPE`]).

mod builtin_interfaces;
mod geometry_msgs;
mod rosgraph_msgs;
mod sensor_msgs;
mod std_msgs;
mod tf2_msgs;
mod trajectory_msgs;

pub use builtin_interfaces::{Duration, Time};
pub use geometry_msgs::{
    Quaternion, Transform, TransformStamped, Twist, TwistStamped, Vector3, Wrench, WrenchStamped,
};
pub use rosgraph_msgs::Clock;
pub use sensor_msgs::{JointState, PointCloud2, PointField};
pub use std_msgs::Header;
pub use tf2_msgs::TFMessage;
pub use trajectory_msgs::{JointTrajectory, JointTrajectoryPoint};

/// A ROS 2 message type.
pub trait RosMessage: serde::Serialize + serde::de::DeserializeOwned {
    /// Its ROS name, `package/msg/Name`.
    const TYPE_NAME: &'static str;
    /// Its DDS type name, `package::msg::dds_::Name_`, which DDS discovery matches on.
    const DDS_TYPE: &'static str;
}

/// Implements [`RosMessage`] for `$ty` as `$package/msg/$name`.
macro_rules! ros_message {
    ($ty:ty, $package:literal, $name:literal) => {
        impl $crate::msg::RosMessage for $ty {
            const TYPE_NAME: &'static str = concat!($package, "/msg/", $name);
            const DDS_TYPE: &'static str = concat!($package, "::msg::dds_::", $name, "_");
        }
    };
}
pub(crate) use ros_message;
