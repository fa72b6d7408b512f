//! Between ROS 2 messages and nudge's types: time, transforms, wrenches, organised colour clouds.

use nalgebra::{Isometry3, Quaternion as NaQuaternion, Translation3, UnitQuaternion};
use nudge_executive::robot::Wrench as NudgeWrench;
use nudge_perception::{CloudFrame, ColourCloud};

use crate::msg::{Header, PointCloud2, PointField, Quaternion, Time, Transform, Vector3, Wrench};

/// A robot time (s since the clock's epoch) as a `Time`, to the nearest nanosecond; `None` when it
/// does not fit (negative, NaN, or past 2038, where `sec` overflows).
pub fn time_from_seconds(t: f64) -> Option<Time> {
    if !(t.is_finite() && t >= 0.0) {
        return None;
    }
    let nanos = (t * 1e9).round();
    if nanos >= (i32::MAX as f64 + 1.0) * 1e9 {
        return None;
    }
    let nanos = nanos as u64;
    Some(Time {
        sec: (nanos / 1_000_000_000) as i32,
        nanosec: (nanos % 1_000_000_000) as u32,
    })
}

/// A `Time` in seconds.
pub fn seconds(t: &Time) -> f64 {
    f64::from(t.sec) + f64::from(t.nanosec) * 1e-9
}

/// A pose as a `Transform`.
pub fn transform(pose: &Isometry3<f64>) -> Transform {
    let t = pose.translation.vector;
    let q = pose.rotation.quaternion();
    Transform {
        translation: Vector3 {
            x: t.x,
            y: t.y,
            z: t.z,
        },
        rotation: Quaternion {
            x: q.i,
            y: q.j,
            z: q.k,
            w: q.w,
        },
    }
}

/// A `Transform` as a pose; `None` when a number is not finite or the rotation has no length.
pub fn pose(t: &Transform) -> Option<Isometry3<f64>> {
    let (v, q) = (t.translation, t.rotation);
    let numbers = [v.x, v.y, v.z, q.x, q.y, q.z, q.w];
    let length = (q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w).sqrt();
    (numbers.iter().all(|n| n.is_finite()) && length > 1e-9).then(|| {
        Isometry3::from_parts(
            Translation3::new(v.x, v.y, v.z),
            UnitQuaternion::from_quaternion(NaQuaternion::new(q.w, q.x, q.y, q.z)),
        )
    })
}

/// A wrench as the message carries it.
pub fn wrench(w: &NudgeWrench) -> Wrench {
    let v = |v: &nalgebra::Vector3<f64>| Vector3 {
        x: v.x,
        y: v.y,
        z: v.z,
    };
    Wrench {
        force: v(&w.force),
        torque: v(&w.torque),
    }
}

/// A message's wrench as nudge's.
pub fn nudge_wrench(w: &Wrench) -> NudgeWrench {
    let v = |v: &Vector3| nalgebra::Vector3::new(v.x, v.y, v.z);
    NudgeWrench {
        force: v(&w.force),
        torque: v(&w.torque),
    }
}

/// Bytes of a point in [`point_cloud`]'s layout: x, y, z as float32, then `rgb`, a float32 whose bits
/// are 0x00RRGGBB (PCL's and RViz's packing).
pub const POINT_STEP: u32 = 16;

/// An organised colour cloud as a `PointCloud2` in `frame` (the sensor's optical frame for a cloud in
/// the sensor frame, the map's otherwise), little-endian, no-return slots kept as NaN.
pub fn point_cloud(cloud: &ColourCloud, stamp: Time, frame: &str) -> PointCloud2 {
    let field = |name: &str, offset| PointField {
        name: name.into(),
        offset,
        datatype: PointField::FLOAT32,
        count: 1,
    };
    let n = cloud.len();
    let mut data = Vec::with_capacity(n * POINT_STEP as usize);
    let (xs, ys, zs, rgb) = (cloud.xs(), cloud.ys(), cloud.zs(), cloud.colours());
    let mut dense = true;
    for i in 0..n {
        dense &= xs[i].is_finite() && ys[i].is_finite() && zs[i].is_finite();
        data.extend_from_slice(&xs[i].to_le_bytes());
        data.extend_from_slice(&ys[i].to_le_bytes());
        data.extend_from_slice(&zs[i].to_le_bytes());
        let [r, g, b] = rgb[i];
        let packed = u32::from(r) << 16 | u32::from(g) << 8 | u32::from(b);
        data.extend_from_slice(&packed.to_le_bytes());
    }
    PointCloud2 {
        header: Header {
            stamp,
            frame_id: frame.into(),
        },
        height: cloud.height() as u32,
        width: cloud.width() as u32,
        fields: vec![
            field("x", 0),
            field("y", 4),
            field("z", 8),
            field("rgb", 12),
        ],
        is_bigendian: false,
        point_step: POINT_STEP,
        row_step: POINT_STEP * cloud.width() as u32,
        data,
        is_dense: dense,
    }
}

/// Why a `PointCloud2` is not a colour cloud nudge can use.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum CloudError {
    /// A field nudge needs is missing or not a float32 (`x`, `y`, `z`, `rgb`).
    #[error("field `{0}` missing or not FLOAT32")]
    Field(&'static str),
    /// The sizes do not add up: `data` shorter than `row_step × height`, or a point past its row.
    #[error("{0}")]
    Size(String),
    /// Big-endian data.
    #[error("big-endian clouds are not read")]
    BigEndian,
}

/// A `PointCloud2` with float32 `x`, `y`, `z` and packed `rgb` as an organised colour cloud in the
/// sensor frame, seen from `sensor_pose`.
pub fn colour_cloud(
    msg: &PointCloud2,
    sensor_pose: Isometry3<f64>,
    stamp: f64,
) -> Result<ColourCloud, CloudError> {
    if msg.is_bigendian {
        return Err(CloudError::BigEndian);
    }
    let offset = |name: &'static str| {
        msg.fields
            .iter()
            .find(|f| f.name == name && f.datatype == PointField::FLOAT32 && f.count == 1)
            .map(|f| f.offset as usize)
            .ok_or(CloudError::Field(name))
    };
    let (ox, oy, oz, oc) = (offset("x")?, offset("y")?, offset("z")?, offset("rgb")?);
    let (w, h) = (msg.width as usize, msg.height as usize);
    let (step, row) = (msg.point_step as usize, msg.row_step as usize);
    let widest = ox.max(oy).max(oz).max(oc) + 4;
    if widest > step || w.saturating_mul(step) > row || row.saturating_mul(h) > msg.data.len() {
        return Err(CloudError::Size(format!(
            "{w} × {h} points of {step} bytes in rows of {row} need {} bytes, got {}",
            row.saturating_mul(h),
            msg.data.len()
        )));
    }
    let f32_at = |at: usize| {
        let bytes = [
            msg.data[at],
            msg.data[at + 1],
            msg.data[at + 2],
            msg.data[at + 3],
        ];
        f32::from_le_bytes(bytes)
    };
    let n = w * h;
    let (mut x, mut y, mut z, mut rgb) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    for r in 0..h {
        for c in 0..w {
            let at = r * row + c * step;
            x.push(f32_at(at + ox));
            y.push(f32_at(at + oy));
            z.push(f32_at(at + oz));
            let packed = f32_at(at + oc).to_bits();
            rgb.push([(packed >> 16) as u8, (packed >> 8) as u8, packed as u8]);
        }
    }
    ColourCloud::organised(w, h, x, y, z, rgb, CloudFrame::Sensor, sensor_pose, stamp)
        .map_err(|e| CloudError::Size(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cloud() -> ColourCloud {
        let pose = Isometry3::translation(0.5, 0.0, 1.4);
        ColourCloud::organised(
            2,
            2,
            vec![1.0, f32::NAN, 2.5, -0.0],
            vec![0.5, f32::NAN, -1.25, 3.0],
            vec![0.25, f32::NAN, 1e-7, 4.0],
            vec![[10, 20, 30], [0, 0, 0], [255, 255, 255], [1, 0, 2]],
            CloudFrame::Sensor,
            pose,
            3.25,
        )
        .expect("a 2 × 2 cloud")
    }

    #[test]
    fn an_organised_cloud_survives_point_cloud2_bit_for_bit() {
        // Invariant: a sensor-frame colour cloud written as a PointCloud2 and read back has the same size, the same coordinate bits (NaN slots included) and the same colours.
        let c = cloud();
        let msg = point_cloud(&c, time_from_seconds(3.25).expect("time"), "camera");
        assert_eq!((msg.width, msg.height, msg.row_step), (2, 2, 32));
        assert!(!msg.is_dense);
        let back = colour_cloud(&msg, *c.sensor_pose(), c.stamp()).expect("readable");
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(back.xs()), bits(c.xs()));
        assert_eq!(bits(back.ys()), bits(c.ys()));
        assert_eq!(bits(back.zs()), bits(c.zs()));
        assert_eq!(back.colours(), c.colours());
        assert_eq!((back.width(), back.height()), (2, 2));
    }

    #[test]
    fn a_cloud_that_does_not_add_up_is_an_error() {
        // Invariant: missing or mistyped fields, data shorter than its rows and big-endian data are errors naming what is wrong, never a panic.
        let c = cloud();
        let good = point_cloud(&c, Time::default(), "camera");
        let pose = *c.sensor_pose();
        let mut short = good.clone();
        short.data.truncate(20);
        assert!(matches!(
            colour_cloud(&short, pose, 0.0),
            Err(CloudError::Size(_))
        ));
        let mut no_rgb = good.clone();
        no_rgb.fields.retain(|f| f.name != "rgb");
        assert_eq!(
            colour_cloud(&no_rgb, pose, 0.0),
            Err(CloudError::Field("rgb"))
        );
        let mut doubles = good.clone();
        doubles.fields[0].datatype = PointField::FLOAT64;
        assert_eq!(
            colour_cloud(&doubles, pose, 0.0),
            Err(CloudError::Field("x"))
        );
        let mut narrow = good.clone();
        narrow.point_step = 8;
        assert!(matches!(
            colour_cloud(&narrow, pose, 0.0),
            Err(CloudError::Size(_))
        ));
        let mut huge = good.clone();
        huge.width = u32::MAX;
        huge.height = u32::MAX;
        assert!(colour_cloud(&huge, pose, 0.0).is_err());
        let mut big = good;
        big.is_bigendian = true;
        assert_eq!(colour_cloud(&big, pose, 0.0), Err(CloudError::BigEndian));
    }

    #[test]
    fn times_and_poses_convert_both_ways() {
        // Invariant: robot time goes to the nearest nanosecond and back; a pose survives a Transform to 1e-12; times that do not fit and transforms with NaN or a zero rotation are refused.
        let t = time_from_seconds(192.600_000_001).expect("fits");
        assert_eq!((t.sec, t.nanosec), (192, 600_000_001));
        assert!((seconds(&t) - 192.600_000_001).abs() < 1e-9);
        assert_eq!(time_from_seconds(-1.0), None);
        assert_eq!(time_from_seconds(f64::NAN), None);
        assert_eq!(time_from_seconds(3.0e9), None);
        let p = Isometry3::from_parts(
            Translation3::new(1.0, -2.0, 0.5),
            UnitQuaternion::from_euler_angles(0.1, -0.2, 2.9),
        );
        let q = pose(&transform(&p)).expect("a pose");
        assert!((q.translation.vector - p.translation.vector).norm() < 1e-12);
        assert!(q.rotation.angle_to(&p.rotation) < 1e-12);
        let mut bad = transform(&p);
        bad.rotation = Quaternion {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            w: 0.0,
        };
        assert_eq!(pose(&bad), None);
        bad.rotation.w = f64::NAN;
        assert_eq!(pose(&bad), None);
    }
}
