//! nudge over ROS 2.
//!
//! This first part holds the wire: the standard ROS 2 messages the adapter exchanges with a robot
//! (`sensor_msgs/PointCloud2` for the camera, `geometry_msgs/WrenchStamped` for the wrist, `/tf`
//! for the base and hand, `geometry_msgs/Twist` for walking, `trajectory_msgs/JointTrajectory` for
//! the head), their CDR encoding as DDS carries it ([`cdr`]), the conversions between them and
//! nudge's own types ([`convert`]), and how a robot's graph is named — topics, frames, head joints,
//! QoS, the clock — read from TOML ([`config::Ros2Config`]). The adapter that implements the robot traits over DDS and the
//! bridge that makes the simulation a ROS 2 robot build on these.

#![warn(missing_docs)]

pub mod adapter;
pub mod cdr;
pub mod config;
pub mod convert;
pub mod msg;
pub mod node;
