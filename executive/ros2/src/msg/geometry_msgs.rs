//! `geometry_msgs`: vectors, rotations, transforms, wrenches and twists.

use serde::{Deserialize, Serialize};

use super::{Header, ros_message};

/// `geometry_msgs/msg/Vector3`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Vector3 {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
}
ros_message!(Vector3, "geometry_msgs", "Vector3");

/// `geometry_msgs/msg/Quaternion` (x, y, z, w; the identity is w = 1).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Quaternion {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
    /// w.
    pub w: f64,
}
ros_message!(Quaternion, "geometry_msgs", "Quaternion");

impl Default for Quaternion {
    fn default() -> Self {
        Self {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            w: 1.0,
        }
    }
}

/// `geometry_msgs/msg/Transform`: a child frame's pose in its parent.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Transform {
    /// Translation (m).
    pub translation: Vector3,
    /// Rotation.
    pub rotation: Quaternion,
}
ros_message!(Transform, "geometry_msgs", "Transform");

/// `geometry_msgs/msg/TransformStamped`: one edge of the `/tf` tree.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TransformStamped {
    /// Stamp, and the parent frame.
    pub header: Header,
    /// The child frame.
    pub child_frame_id: String,
    /// The child's pose in the parent.
    pub transform: Transform,
}
ros_message!(TransformStamped, "geometry_msgs", "TransformStamped");

/// `geometry_msgs/msg/Wrench`: force (N) and torque (N·m).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Wrench {
    /// Force (N).
    pub force: Vector3,
    /// Torque (N·m).
    pub torque: Vector3,
}
ros_message!(Wrench, "geometry_msgs", "Wrench");

/// `geometry_msgs/msg/WrenchStamped`: what a force/torque sensor driver publishes.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WrenchStamped {
    /// Stamp, and the sensor's frame.
    pub header: Header,
    /// The reading.
    pub wrench: Wrench,
}
ros_message!(WrenchStamped, "geometry_msgs", "WrenchStamped");

/// `geometry_msgs/msg/Twist`: linear (m/s) and angular (rad/s) velocity, what `/cmd_vel` carries.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Twist {
    /// Linear velocity (m/s).
    pub linear: Vector3,
    /// Angular velocity (rad/s).
    pub angular: Vector3,
}
ros_message!(Twist, "geometry_msgs", "Twist");

/// `geometry_msgs/msg/TwistStamped`: a twist in a frame (MoveIt Servo's Cartesian command).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TwistStamped {
    /// Stamp, and the frame the twist is in.
    pub header: Header,
    /// The velocity.
    pub twist: Twist,
}
ros_message!(TwistStamped, "geometry_msgs", "TwistStamped");
