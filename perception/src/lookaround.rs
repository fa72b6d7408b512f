//! Look-around: the head's view sequence and the fusion of its clouds into one map-frame cloud.
//!
//! The sensor's field of view (43.6° × 34.6° on the paper's SR-4000) is too narrow to see the room from
//! one pose, so the head pans and tilts through a fixed sequence of views (Kakiuchi et al. 2010, §IV-B:
//! tilt 45°, 30°, 20° × pan 50°, 25°, 0°, −25°, −50°) and the clouds are fused in the map frame.

use nalgebra::Isometry3;
use rayon::prelude::*;

use crate::cloud::{CloudFrame, ColourCloud};

/// One head pose of a look-around (degrees, as a person types them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeadView {
    /// Tilt down from horizontal (degrees, positive looks down).
    pub tilt_deg: f64,
    /// Pan to the left of straight ahead (degrees, positive looks left).
    pub pan_deg: f64,
}

/// The view sequence of one look-around.
#[derive(Clone, Debug, PartialEq)]
pub struct LookAroundConfig {
    /// Tilt angles (degrees, positive down). Default: 45, 30, 20 (the paper's).
    pub tilts_deg: Vec<f64>,
    /// Pan angles (degrees, positive left). Default: 50, 25, 0, −25, −50 (the paper's).
    pub pans_deg: Vec<f64>,
}

impl HeadView {
    /// Tilt in radians (positive looks down).
    pub fn tilt_rad(&self) -> f64 {
        self.tilt_deg.to_radians()
    }

    /// Pan in radians (positive looks left).
    pub fn pan_rad(&self) -> f64 {
        self.pan_deg.to_radians()
    }
}

impl Default for LookAroundConfig {
    fn default() -> Self {
        Self {
            tilts_deg: vec![45.0, 30.0, 20.0],
            pans_deg: vec![50.0, 25.0, 0.0, -25.0, -50.0],
        }
    }
}

impl LookAroundConfig {
    /// The views in capture order: for each tilt, every pan (15 views by default).
    pub fn views(&self) -> Vec<HeadView> {
        self.tilts_deg
            .iter()
            .flat_map(|&tilt_deg| {
                self.pans_deg
                    .iter()
                    .map(move |&pan_deg| HeadView { tilt_deg, pan_deg })
            })
            .collect()
    }
}

/// Fuses the clouds of one look-around into one unorganised map-frame cloud of their valid points.
///
/// Each cloud is moved into the map frame with its own `sensor_pose` (clouds already in the map frame are
/// taken as they are); no-return and non-finite slots are dropped. Points keep the input order (cloud by
/// cloud, slot by slot) whatever the thread count. The result carries the first cloud's sensor pose and
/// the latest stamp; no input gives an empty cloud.
pub fn fuse(clouds: &[ColourCloud]) -> ColourCloud {
    let pose = clouds
        .first()
        .map(|c| *c.sensor_pose())
        .unwrap_or_else(Isometry3::identity);
    let stamp = clouds
        .iter()
        .map(ColourCloud::stamp)
        .filter(|s| s.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    let stamp = if stamp.is_finite() { stamp } else { 0.0 };
    // Count first, then let each cloud fill its own slice of the output in parallel: no intermediate
    // buffers, and the output order is cloud by cloud, slot by slot, whatever the thread count.
    let counts: Vec<usize> = clouds.par_iter().map(valid_slots).collect();
    let total: usize = counts.iter().sum();
    let mut x = vec![0f32; total];
    let mut y = vec![0f32; total];
    let mut z = vec![0f32; total];
    let mut rgb = vec![[0u8; 3]; total];
    let mut jobs = Vec::with_capacity(clouds.len());
    let (mut xr, mut yr, mut zr, mut cr) = (&mut x[..], &mut y[..], &mut z[..], &mut rgb[..]);
    for (cloud, &n) in clouds.iter().zip(&counts) {
        let (xa, xb) = xr.split_at_mut(n);
        let (ya, yb) = yr.split_at_mut(n);
        let (za, zb) = zr.split_at_mut(n);
        let (ca, cb) = cr.split_at_mut(n);
        jobs.push((cloud, xa, ya, za, ca));
        (xr, yr, zr, cr) = (xb, yb, zb, cb);
    }
    jobs.into_par_iter()
        .for_each(|(cloud, xo, yo, zo, co)| to_map_into(cloud, xo, yo, zo, co));
    ColourCloud::from_arrays(x, y, z, rgb, CloudFrame::Map, pose, stamp)
        .unwrap_or_else(|| ColourCloud::empty(CloudFrame::Map, pose, stamp))
}

/// Slots of `cloud` with finite coordinates.
pub(crate) fn valid_slots(cloud: &ColourCloud) -> usize {
    let (xs, ys, zs) = (cloud.xs(), cloud.ys(), cloud.zs());
    xs.iter()
        .zip(ys)
        .zip(zs)
        .filter(|((x, y), z)| x.is_finite() && y.is_finite() && z.is_finite())
        .count()
}

/// Writes the valid points of `cloud` in the map frame into the given slices (exactly
/// [`valid_slots`] long): one tight pass with a rotation matrix (faster than applying the quaternion
/// point by point, which is what [`ColourCloud::to_map`] does).
fn to_map_into(
    cloud: &ColourCloud,
    xo: &mut [f32],
    yo: &mut [f32],
    zo: &mut [f32],
    co: &mut [crate::cloud::Rgb],
) {
    let (r, t) = match cloud.frame() {
        CloudFrame::Sensor => {
            let pose = cloud.sensor_pose().cast::<f32>();
            (
                pose.rotation.to_rotation_matrix().into_inner(),
                pose.translation.vector,
            )
        }
        CloudFrame::Map => (nalgebra::Matrix3::identity(), nalgebra::Vector3::zeros()),
    };
    let (xs, ys, zs, cs) = (cloud.xs(), cloud.ys(), cloud.zs(), cloud.colours());
    let mut k = 0;
    for i in 0..xs.len() {
        let (x, y, z) = (xs[i], ys[i], zs[i]);
        if !(x.is_finite() && y.is_finite() && z.is_finite()) || k >= xo.len() {
            continue;
        }
        xo[k] = r[(0, 0)] * x + r[(0, 1)] * y + r[(0, 2)] * z + t.x;
        yo[k] = r[(1, 0)] * x + r[(1, 1)] * y + r[(1, 2)] * z + t.y;
        zo[k] = r[(2, 0)] * x + r[(2, 1)] * y + r[(2, 2)] * z + t.z;
        co[k] = cs.get(i).copied().unwrap_or([0, 0, 0]);
        k += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Point3, Translation3, UnitQuaternion};

    #[test]
    fn default_look_around_is_the_papers_fifteen_views() {
        // Invariant: the default sequence is tilt 45/30/20 × pan 50/25/0/−25/−50, tilt-major.
        let views = LookAroundConfig::default().views();
        assert_eq!(views.len(), 15);
        assert_eq!(
            views[0],
            HeadView {
                tilt_deg: 45.0,
                pan_deg: 50.0
            }
        );
        assert_eq!(
            views[14],
            HeadView {
                tilt_deg: 20.0,
                pan_deg: -50.0
            }
        );
    }

    #[test]
    fn fuse_moves_each_cloud_by_its_own_pose_and_drops_no_returns() {
        // Invariant: fused points are each cloud's valid points under that cloud's sensor pose, in order.
        let a = ColourCloud::organised(
            2,
            1,
            vec![1.0, f32::NAN],
            vec![0.0, 0.0],
            vec![0.0, 0.0],
            vec![[1, 2, 3], [0, 0, 0]],
            CloudFrame::Sensor,
            Isometry3::translation(1.0, 0.0, 0.0),
            1.0,
        )
        .expect("lengths match");
        let b = ColourCloud::organised(
            1,
            1,
            vec![1.0],
            vec![0.0],
            vec![0.0],
            vec![[4, 5, 6]],
            CloudFrame::Sensor,
            Isometry3::from_parts(
                Translation3::new(0.0, 0.0, 1.0),
                UnitQuaternion::from_euler_angles(0.0, 0.0, std::f64::consts::FRAC_PI_2),
            ),
            2.0,
        )
        .expect("lengths match");
        let fused = fuse(&[a, b]);
        assert_eq!(fused.len(), 2);
        assert_eq!(fused.frame(), CloudFrame::Map);
        assert!((fused.point(0).expect("valid") - Point3::new(2.0, 0.0, 0.0)).norm() < 1e-6);
        assert!((fused.point(1).expect("valid") - Point3::new(0.0, 1.0, 1.0)).norm() < 1e-6);
        assert_eq!(fused.colours(), &[[1, 2, 3], [4, 5, 6]]);
        assert_eq!(fused.stamp(), 2.0);
    }

    #[test]
    fn fuse_of_nothing_is_empty() {
        // Invariant: no clouds give an empty cloud, not a panic.
        assert!(fuse(&[]).is_empty());
    }
}
