//! `trajectory_msgs`: joint trajectories (the head's pan and tilt).

use serde::{Deserialize, Serialize};

use super::{Duration, Header, ros_message};

/// `trajectory_msgs/msg/JointTrajectoryPoint`: where the joints are at a time from the start.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct JointTrajectoryPoint {
    /// Joint positions (rad), in the trajectory's joint order.
    pub positions: Vec<f64>,
    /// Joint velocities (rad/s); empty when not given.
    pub velocities: Vec<f64>,
    /// Joint accelerations (rad/s²); empty when not given.
    pub accelerations: Vec<f64>,
    /// Joint efforts; empty when not given.
    pub effort: Vec<f64>,
    /// When the point is to be reached, from the trajectory's start.
    pub time_from_start: Duration,
}
ros_message!(
    JointTrajectoryPoint,
    "trajectory_msgs",
    "JointTrajectoryPoint"
);

/// `trajectory_msgs/msg/JointTrajectory`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct JointTrajectory {
    /// Stamp (zero: start now).
    pub header: Header,
    /// The joints, by name.
    pub joint_names: Vec<String>,
    /// The points, in time order.
    pub points: Vec<JointTrajectoryPoint>,
}
ros_message!(JointTrajectory, "trajectory_msgs", "JointTrajectory");
