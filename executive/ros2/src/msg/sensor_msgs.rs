//! `sensor_msgs`: point clouds.

use serde::{Deserialize, Serialize};

use super::{Header, ros_message};

/// `sensor_msgs/msg/PointField`: one field of a cloud's points.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct PointField {
    /// Its name (`x`, `rgb`, …).
    pub name: String,
    /// Byte offset in a point.
    pub offset: u32,
    /// Its type: one of the `PointField::*` constants.
    pub datatype: u8,
    /// Elements in the field (1 for a scalar).
    pub count: u32,
}
ros_message!(PointField, "sensor_msgs", "PointField");

impl PointField {
    /// `INT8`.
    pub const INT8: u8 = 1;
    /// `UINT8`.
    pub const UINT8: u8 = 2;
    /// `INT16`.
    pub const INT16: u8 = 3;
    /// `UINT16`.
    pub const UINT16: u8 = 4;
    /// `INT32`.
    pub const INT32: u8 = 5;
    /// `UINT32`.
    pub const UINT32: u8 = 6;
    /// `FLOAT32`.
    pub const FLOAT32: u8 = 7;
    /// `FLOAT64`.
    pub const FLOAT64: u8 = 8;
}

/// `sensor_msgs/msg/PointCloud2`: points as packed records; organised (an image of `width` ×
/// `height`) when `height` > 1.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PointCloud2 {
    /// Stamp, and the frame the points are in.
    pub header: Header,
    /// Rows (1 for an unorganised cloud).
    pub height: u32,
    /// Points per row.
    pub width: u32,
    /// The fields of a point.
    pub fields: Vec<PointField>,
    /// Whether the data is big-endian.
    pub is_bigendian: bool,
    /// Bytes per point.
    pub point_step: u32,
    /// Bytes per row.
    pub row_step: u32,
    /// The points, row after row.
    #[serde(with = "serde_bytes")]
    pub data: Vec<u8>,
    /// Whether no point is invalid (NaN).
    pub is_dense: bool,
}
ros_message!(PointCloud2, "sensor_msgs", "PointCloud2");

/// `sensor_msgs/msg/JointState`: named joints' positions (rad), velocities (rad/s) and efforts; any
/// of the three arrays may be empty.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct JointState {
    /// When the joints were read.
    pub header: Header,
    /// Joint names.
    pub name: Vec<String>,
    /// Positions, in `name`'s order.
    pub position: Vec<f64>,
    /// Velocities, in `name`'s order.
    pub velocity: Vec<f64>,
    /// Efforts, in `name`'s order.
    pub effort: Vec<f64>,
}
ros_message!(JointState, "sensor_msgs", "JointState");
