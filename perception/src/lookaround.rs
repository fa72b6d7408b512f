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
    let parts: Vec<Soa> = clouds.par_iter().map(to_map_soa).collect();
    let total = parts.iter().map(|p| p.x.len()).sum();
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
    let mut all = Soa::with_capacity(total);
    for part in &parts {
        all.x.extend_from_slice(&part.x);
        all.y.extend_from_slice(&part.y);
        all.z.extend_from_slice(&part.z);
        all.rgb.extend_from_slice(&part.rgb);
    }
    ColourCloud::from_arrays(all.x, all.y, all.z, all.rgb, CloudFrame::Map, pose, stamp)
        .unwrap_or_else(|| ColourCloud::empty(CloudFrame::Map, pose, stamp))
}

/// Bare arrays of one cloud's valid map-frame points.
struct Soa {
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
    rgb: Vec<crate::cloud::Rgb>,
}

impl Soa {
    fn with_capacity(n: usize) -> Self {
        Self {
            x: Vec::with_capacity(n),
            y: Vec::with_capacity(n),
            z: Vec::with_capacity(n),
            rgb: Vec::with_capacity(n),
        }
    }
}

/// The valid points of `cloud` in the map frame: one tight pass with a rotation matrix (faster than
/// applying the quaternion point by point, which is what [`ColourCloud::to_map`] does).
fn to_map_soa(cloud: &ColourCloud) -> Soa {
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
    let n = xs.len().min(ys.len()).min(zs.len()).min(cs.len());
    let mut out = Soa::with_capacity(n);
    for i in 0..n {
        let (x, y, z) = (xs[i], ys[i], zs[i]);
        if !(x.is_finite() && y.is_finite() && z.is_finite()) {
            continue;
        }
        out.x
            .push(r[(0, 0)] * x + r[(0, 1)] * y + r[(0, 2)] * z + t.x);
        out.y
            .push(r[(1, 0)] * x + r[(1, 1)] * y + r[(1, 2)] * z + t.y);
        out.z
            .push(r[(2, 0)] * x + r[(2, 1)] * y + r[(2, 2)] * z + t.z);
        out.rgb.push(cs[i]);
    }
    out
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
