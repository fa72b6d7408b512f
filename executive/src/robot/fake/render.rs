//! The fake robot's range camera: a pinhole ray caster over its [`FakeScene`], giving organised
//! colour clouds in the sensor frame as a real camera would, with a millimetre or two of range noise
//! drawn from the pixel and the stamp (so a capture is the same whenever it is repeated).

use nalgebra::{Isometry2, Isometry3, Point3, Vector3};
use nudge_perception::{CloudFrame, ColourCloud, Rgb};
use nudge_robot_model::{CameraModel, RobotModel};

use super::scene::{FakeScene, SceneBox};

/// The camera's image and range, the paper's robot's camera ([`RobotModel::default`]) by default.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FakeCamera {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Horizontal field of view, edge to edge (rad).
    pub h_fov: f64,
    /// Vertical field of view, edge to edge (rad).
    pub v_fov: f64,
    /// Nearest return (m).
    pub min_range: f64,
    /// Farthest return (m).
    pub max_range: f64,
    /// Largest range error (m), uniform either way. Default 1.5 mm.
    pub noise: f64,
}

impl Default for FakeCamera {
    fn default() -> Self {
        Self::of(&RobotModel::default().camera)
    }
}

impl FakeCamera {
    /// `camera`'s image and range, with a millimetre and a half of range noise.
    pub fn of(camera: &CameraModel) -> Self {
        Self {
            width: camera.width,
            height: camera.height,
            h_fov: camera.h_fov(),
            v_fov: camera.v_fov(),
            min_range: camera.min_range,
            max_range: camera.max_range,
            noise: 0.0015,
        }
    }
}

/// Colour of a ray with no return.
const NO_RETURN: Rgb = [128, 128, 128];

/// What `scene` shows a camera at `pose` (its x forward, y left, z up) at `stamp`.
pub(super) fn render(scene: &FakeScene, pose: &Isometry3<f64>, stamp: f64) -> ColourCloud {
    let c = scene.camera;
    let n = c.width * c.height;
    let (mut xs, mut ys, mut zs) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    let mut rgb = Vec::with_capacity(n);
    let (half_w, half_h) = ((c.h_fov / 2.0).tan(), (c.v_fov / 2.0).tan());
    let origin = Point3::from(pose.translation.vector);
    let seed = stamp.to_bits();
    // Each box's map-to-box transform, once per frame rather than once per ray.
    let boxes: Vec<_> = scene.boxes.iter().map(|b| (b, b.pose.inverse())).collect();
    for row in 0..c.height {
        let up = half_h * (1.0 - (2.0 * row as f64 + 1.0) / c.height as f64);
        for col in 0..c.width {
            let left = half_w * (1.0 - (2.0 * col as f64 + 1.0) / c.width as f64);
            let local = Vector3::new(1.0, left, up).normalize();
            let dir = pose.rotation * local;
            match cast(scene, &boxes, &origin, &dir) {
                Some((t, colour)) if (c.min_range..=c.max_range).contains(&t) => {
                    let jitter = c.noise * unit_noise(seed, row, col);
                    let p = local * (t + jitter);
                    xs.push(p.x as f32);
                    ys.push(p.y as f32);
                    zs.push(p.z as f32);
                    rgb.push(colour);
                }
                _ => {
                    xs.push(f32::NAN);
                    ys.push(f32::NAN);
                    zs.push(f32::NAN);
                    rgb.push(NO_RETURN);
                }
            }
        }
    }
    ColourCloud::organised(
        c.width,
        c.height,
        xs,
        ys,
        zs,
        rgb,
        CloudFrame::Sensor,
        *pose,
        stamp,
    )
    .unwrap_or_else(|_| ColourCloud::empty(CloudFrame::Sensor, *pose, stamp))
}

/// The nearest surface along the ray from `origin` along the unit `dir` (map frame): its distance
/// and colour. Only the nearest surface is textured (the texture's sines are most of a frame's cost);
/// at equal distances the first box wins, then the floor.
fn cast(
    scene: &FakeScene,
    boxes: &[(&SceneBox, Isometry2<f64>)],
    origin: &Point3<f64>,
    dir: &Vector3<f64>,
) -> Option<(f64, Rgb)> {
    let floor = (dir.z < -1e-9)
        .then(|| -origin.z / dir.z)
        .filter(|t| *t > 0.0);
    let nearest = boxes
        .iter()
        .filter_map(|(b, inv)| hit_box(b, inv, origin, dir).map(|(t, local)| (t, b, local)))
        .min_by(|a, b| a.0.total_cmp(&b.0));
    match (nearest, floor) {
        (Some((t, b, local)), f) if f.is_none_or(|f| t <= f) => {
            Some((t, texture(b.colour, &local, 40.0)))
        }
        (_, Some(t)) => Some((t, texture(scene.floor, &(origin + dir * t).coords, 12.0))),
        (_, None) => None,
    }
}

/// Where the ray meets `b` (`inv`: the inverse of its pose): its distance, and the point in the
/// box's own frame (for its texture).
fn hit_box(
    b: &SceneBox,
    inv: &Isometry2<f64>,
    origin: &Point3<f64>,
    dir: &Vector3<f64>,
) -> Option<(f64, Vector3<f64>)> {
    let o2 = inv * nalgebra::Point2::new(origin.x, origin.y);
    let d2 = inv.rotation * nalgebra::Vector2::new(dir.x, dir.y);
    let o = Vector3::new(o2.x, o2.y, origin.z);
    let d = Vector3::new(d2.x, d2.y, dir.z);
    let lo = Vector3::new(-b.size.x / 2.0, -b.size.y / 2.0, 0.0);
    let hi = Vector3::new(b.size.x / 2.0, b.size.y / 2.0, b.size.z);
    let (mut near, mut far) = (f64::NEG_INFINITY, f64::INFINITY);
    for axis in 0..3 {
        if d[axis].abs() < 1e-12 {
            if o[axis] < lo[axis] || o[axis] > hi[axis] {
                return None;
            }
            continue;
        }
        let (a, c) = (
            (lo[axis] - o[axis]) / d[axis],
            (hi[axis] - o[axis]) / d[axis],
        );
        near = near.max(a.min(c));
        far = far.min(a.max(c));
    }
    if near > far || near <= 0.0 {
        return None;
    }
    Some((near, o + d * near))
}

/// `base` varied by a smooth pattern of the position `p` (in the surface's own frame), `amplitude`
/// levels either way: enough structure for colour ICP, bound to the surface so it moves with it.
fn texture(base: Rgb, p: &Vector3<f64>, amplitude: f64) -> Rgb {
    use std::f64::consts::TAU;
    let (x, y, z) = (p.x, p.y, p.z);
    let s = (x * TAU / 0.06).sin() * 0.5
        + (y * TAU / 0.083 + 0.7).sin() * 0.3
        + (z * TAU / 0.071 + 1.3).sin() * 0.3
        + ((x + y) * TAU / 0.13).sin() * 0.2
        + ((y - z) * TAU / 0.11).cos() * 0.2;
    let level = |c: u8, k: f64| (f64::from(c) + amplitude * s * k).clamp(0.0, 255.0) as u8;
    [
        level(base[0], 1.0),
        level(base[1], 0.8),
        level(base[2], 0.6),
    ]
}

/// A number in [-1, 1] drawn from the capture's `seed` and the pixel (SplitMix64).
fn unit_noise(seed: u64, row: usize, col: usize) -> f64 {
    let mut z = seed ^ ((row as u64) << 32 | col as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
}
