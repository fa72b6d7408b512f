//! Colour point clouds in structure-of-arrays layout.
//!
//! A [`ColourCloud`] is either *organised* (one slot per sensor ray, row-major, `width × height`, a ray
//! with no return holds NaN coordinates) or unorganised (`height == 1`, every point valid by convention
//! but not by force: consumers skip non-finite points). Coordinates are `f32` for bulk storage; poses
//! are `f64`.
//!
//! The sensor frame follows REP-103 for a camera *link* (not the optical frame): x forward along the
//! optical axis, y left, z up.

use nalgebra::{Isometry3, Point3};

/// An RGB colour, 0–255 per channel.
pub type Rgb = [u8; 3];

/// Which frame a cloud's coordinates are expressed in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum CloudFrame {
    /// The sensor's own frame (x forward, y left, z up); `sensor_pose` maps it to the map frame.
    #[default]
    Sensor,
    /// The map frame; `sensor_pose` still records where the sensor was.
    Map,
}

/// Why a cloud could not be built.
#[derive(Debug, thiserror::Error, Clone, PartialEq, Eq)]
pub enum CloudError {
    /// The coordinate and colour arrays do not all have `width × height` entries.
    #[error(
        "cloud arrays have lengths x={x}, y={y}, z={z}, rgb={rgb}; expected {expected} (width × height)"
    )]
    LengthMismatch {
        /// Length of `x`.
        x: usize,
        /// Length of `y`.
        y: usize,
        /// Length of `z`.
        z: usize,
        /// Length of `rgb`.
        rgb: usize,
        /// `width × height`.
        expected: usize,
    },
}

/// A colour point cloud, stamped with the robot clock and the sensor pose.
#[derive(Clone, Debug, PartialEq)]
pub struct ColourCloud {
    width: usize,
    height: usize,
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
    rgb: Vec<Rgb>,
    frame: CloudFrame,
    sensor_pose: Isometry3<f64>,
    stamp: f64,
}

impl ColourCloud {
    /// An empty unorganised cloud in `frame`, captured from `sensor_pose` at `stamp` (robot clock, s).
    pub fn empty(frame: CloudFrame, sensor_pose: Isometry3<f64>, stamp: f64) -> Self {
        Self {
            width: 0,
            height: 1,
            x: Vec::new(),
            y: Vec::new(),
            z: Vec::new(),
            rgb: Vec::new(),
            frame,
            sensor_pose,
            stamp,
        }
    }

    /// An empty unorganised cloud with room for `capacity` points.
    pub fn with_capacity(
        frame: CloudFrame,
        sensor_pose: Isometry3<f64>,
        stamp: f64,
        capacity: usize,
    ) -> Self {
        let mut cloud = Self::empty(frame, sensor_pose, stamp);
        cloud.x.reserve(capacity);
        cloud.y.reserve(capacity);
        cloud.z.reserve(capacity);
        cloud.rgb.reserve(capacity);
        cloud
    }

    /// An organised cloud from its arrays (row-major, `width × height` each; NaN marks no return).
    #[allow(clippy::too_many_arguments)]
    pub fn organised(
        width: usize,
        height: usize,
        x: Vec<f32>,
        y: Vec<f32>,
        z: Vec<f32>,
        rgb: Vec<Rgb>,
        frame: CloudFrame,
        sensor_pose: Isometry3<f64>,
        stamp: f64,
    ) -> Result<Self, CloudError> {
        let expected = width * height;
        if [x.len(), y.len(), z.len(), rgb.len()]
            .iter()
            .any(|&n| n != expected)
        {
            return Err(CloudError::LengthMismatch {
                x: x.len(),
                y: y.len(),
                z: z.len(),
                rgb: rgb.len(),
                expected,
            });
        }
        Ok(Self {
            width,
            height,
            x,
            y,
            z,
            rgb,
            frame,
            sensor_pose,
            stamp,
        })
    }

    /// Appends a point; the cloud becomes (or stays) unorganised.
    pub fn push(&mut self, p: Point3<f32>, colour: Rgb) {
        self.x.push(p.x);
        self.y.push(p.y);
        self.z.push(p.z);
        self.rgb.push(colour);
        self.width = self.x.len();
        self.height = 1;
    }

    /// Number of slots (valid points plus no-return slots of an organised cloud).
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// True when the cloud has no slots at all.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Columns of an organised cloud (the point count of an unorganised one).
    pub fn width(&self) -> usize {
        self.width
    }

    /// Rows of an organised cloud (1 for an unorganised one).
    pub fn height(&self) -> usize {
        self.height
    }

    /// True when the cloud keeps the sensor's row/column layout.
    pub fn is_organised(&self) -> bool {
        self.height > 1
    }

    /// The frame the coordinates are expressed in.
    pub fn frame(&self) -> CloudFrame {
        self.frame
    }

    /// Pose of the sensor in the map frame at capture time.
    pub fn sensor_pose(&self) -> &Isometry3<f64> {
        &self.sensor_pose
    }

    /// Capture time on the robot clock (s).
    pub fn stamp(&self) -> f64 {
        self.stamp
    }

    /// X coordinates, one per slot.
    pub fn xs(&self) -> &[f32] {
        &self.x
    }

    /// Y coordinates, one per slot.
    pub fn ys(&self) -> &[f32] {
        &self.y
    }

    /// Z coordinates, one per slot.
    pub fn zs(&self) -> &[f32] {
        &self.z
    }

    /// Colours, one per slot.
    pub fn colours(&self) -> &[Rgb] {
        &self.rgb
    }

    /// The point in slot `i`, or `None` for a no-return slot, a non-finite point or an index past the end.
    pub fn point(&self, i: usize) -> Option<Point3<f32>> {
        let p = Point3::new(*self.x.get(i)?, *self.y.get(i)?, *self.z.get(i)?);
        (p.x.is_finite() && p.y.is_finite() && p.z.is_finite()).then_some(p)
    }

    /// Valid (finite) points with their slot index and colour.
    pub fn iter_valid(&self) -> impl Iterator<Item = (usize, Point3<f32>, Rgb)> + '_ {
        (0..self.len()).filter_map(move |i| self.point(i).map(|p| (i, p, self.rgb[i])))
    }

    /// Number of valid (finite) points.
    pub fn valid_count(&self) -> usize {
        (0..self.len()).filter(|&i| self.point(i).is_some()).count()
    }

    /// This cloud's valid points expressed in the map frame, unorganised.
    ///
    /// A cloud already in the map frame is returned with its invalid slots dropped.
    pub fn to_map(&self) -> ColourCloud {
        let mut out =
            Self::with_capacity(CloudFrame::Map, self.sensor_pose, self.stamp, self.len());
        let to_map = self.sensor_pose.cast::<f32>();
        for (_, p, c) in self.iter_valid() {
            let q = match self.frame {
                CloudFrame::Sensor => to_map * p,
                CloudFrame::Map => p,
            };
            out.push(q, c);
        }
        out
    }
}

impl ColourCloud {
    /// An unorganised cloud from equally long arrays (`None` when their lengths differ).
    pub fn from_arrays(
        x: Vec<f32>,
        y: Vec<f32>,
        z: Vec<f32>,
        rgb: Vec<Rgb>,
        frame: CloudFrame,
        sensor_pose: Isometry3<f64>,
        stamp: f64,
    ) -> Option<Self> {
        let n = x.len();
        Self::organised(n, 1, x, y, z, rgb, frame, sensor_pose, stamp).ok()
    }

    /// Appends every slot of `other` (coordinates taken as they are; the caller keeps frames consistent).
    /// The cloud becomes unorganised.
    pub fn extend_from(&mut self, other: &ColourCloud) {
        self.x.extend_from_slice(&other.x);
        self.y.extend_from_slice(&other.y);
        self.z.extend_from_slice(&other.z);
        self.rgb.extend_from_slice(&other.rgb);
        self.width = self.x.len();
        self.height = 1;
    }

    /// The cloud with every point moved by `motion` (a map-frame rigid motion), invalid slots dropped.
    pub fn transformed(&self, motion: &Isometry3<f64>) -> ColourCloud {
        let mut out = Self::with_capacity(self.frame, self.sensor_pose, self.stamp, self.len());
        for (_, p, c) in self.iter_valid() {
            let q = motion * p.cast::<f64>();
            out.push(q.cast::<f32>(), c);
        }
        out
    }

    /// Mean of the valid points, or `None` when there is none.
    pub fn centroid(&self) -> Option<Point3<f64>> {
        let mut sum = nalgebra::Vector3::zeros();
        let mut n = 0usize;
        for (_, p, _) in self.iter_valid() {
            sum += p.cast::<f64>().coords;
            n += 1;
        }
        (n > 0).then(|| Point3::from(sum / n as f64))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion};

    #[test]
    fn organised_cloud_refuses_arrays_of_the_wrong_length() {
        // Invariant: every array of an organised cloud has width × height entries.
        let err = ColourCloud::organised(
            2,
            2,
            vec![0.0; 4],
            vec![0.0; 4],
            vec![0.0; 3],
            vec![[0; 3]; 4],
            CloudFrame::Sensor,
            Isometry3::identity(),
            0.0,
        );
        assert!(matches!(err, Err(CloudError::LengthMismatch { z: 3, .. })));
    }

    #[test]
    fn to_map_applies_the_sensor_pose_and_drops_no_returns() {
        // Invariant: a map-frame point is the sensor pose applied to the sensor-frame point.
        let pose = Isometry3::from_parts(
            Translation3::new(1.0, 2.0, 1.4),
            UnitQuaternion::from_euler_angles(0.0, 0.0, std::f64::consts::FRAC_PI_2),
        );
        let cloud = ColourCloud::organised(
            2,
            1,
            vec![1.0, f32::NAN],
            vec![0.0, 0.0],
            vec![0.0, 0.0],
            vec![[10, 20, 30], [0, 0, 0]],
            CloudFrame::Sensor,
            pose,
            3.0,
        )
        .expect("lengths match");
        let map = cloud.to_map();
        assert_eq!(map.len(), 1);
        let p = map.point(0).expect("valid");
        assert!((p - Point3::new(1.0, 3.0, 1.4)).norm() < 1e-5);
        assert_eq!(map.colours()[0], [10, 20, 30]);
        assert_eq!(map.frame(), CloudFrame::Map);
    }
}
