//! A small deterministic synthetic-scene generator: boxes (walls, furniture, a mat) on a floor, seen
//! by a pinhole colour range sensor from a pose, with range noise and position-bound textures.
//!
//! Textures are functions of the box-local position, so they move with the object (what colour ICP
//! relies on). Noise comes from a ChaCha stream seeded per (seed, row), so renders are identical whatever
//! the thread count.
#![allow(dead_code)]

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use nudge_perception::{CloudFrame, ColourCloud, Rgb};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// How a box's faces are coloured (as a function of box-local position).
#[derive(Clone, Copy, Debug)]
pub enum Texture {
    /// One colour.
    Uniform(Rgb),
    /// Stripes plus smooth 2-D variation: rich enough for colour ICP.
    Striped {
        /// Base colour.
        base: Rgb,
        /// Brightness swing (levels).
        amplitude: f64,
    },
}

impl Texture {
    fn colour(&self, local: &Vector3<f64>) -> Rgb {
        match *self {
            Texture::Uniform(c) => c,
            Texture::Striped { base, amplitude } => {
                let (x, y, z) = (local.x, local.y, local.z);
                let s = (x * 2.0 * std::f64::consts::PI / 0.06).sin() * 0.5
                    + (y * 2.0 * std::f64::consts::PI / 0.083 + 0.7).sin() * 0.3
                    + (z * 2.0 * std::f64::consts::PI / 0.071 + 1.3).sin() * 0.3
                    + ((x + y) * 2.0 * std::f64::consts::PI / 0.13).sin() * 0.2
                    + ((y - z) * 2.0 * std::f64::consts::PI / 0.11).cos() * 0.2;
                let f = |c: u8, k: f64| (f64::from(c) + amplitude * s * k).clamp(0.0, 255.0) as u8;
                [f(base[0], 1.0), f(base[1], 0.8), f(base[2], 0.6)]
            }
        }
    }
}

/// An oriented box (yaw about z), part of an object.
#[derive(Clone, Debug)]
pub struct SynthBox {
    /// Pose of the box centre in its object's frame.
    pub pose: Isometry3<f64>,
    /// Half extents (m).
    pub half: Vector3<f64>,
    /// Face colouring, in the object's frame.
    pub texture: Texture,
}

/// A rigid object made of boxes.
#[derive(Clone, Debug)]
pub struct SynthObject {
    /// Name for tests.
    pub name: &'static str,
    /// Object pose in the map frame.
    pub pose: Isometry3<f64>,
    /// The boxes, in the object's frame.
    pub boxes: Vec<SynthBox>,
}

/// A scene: objects on an (optional) floor plane at z = 0.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The objects.
    pub objects: Vec<SynthObject>,
    /// Floor colour, or `None` for no floor.
    pub floor: Option<Rgb>,
}

/// A pinhole range sensor.
#[derive(Clone, Debug)]
pub struct Sensor {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Horizontal field of view (rad).
    pub hfov: f64,
    /// Vertical field of view (rad).
    pub vfov: f64,
    /// Range noise standard deviation (m).
    pub range_sigma: f64,
    /// Greatest range (m).
    pub max_range: f64,
}

impl Sensor {
    /// The paper's SR-4000: 176 × 144, 43.6° × 34.6°, ~3 mm noise.
    pub fn sr4000() -> Self {
        Self {
            width: 176,
            height: 144,
            hfov: 43.6f64.to_radians(),
            vfov: 34.6f64.to_radians(),
            range_sigma: 0.003,
            max_range: 8.0,
        }
    }
}

/// Axis-aligned box in object coordinates, world-placed.
fn box_xyz(cx: f64, cy: f64, cz: f64, sx: f64, sy: f64, sz: f64, texture: Texture) -> SynthBox {
    SynthBox {
        pose: Isometry3::translation(cx, cy, cz),
        half: Vector3::new(sx / 2.0, sy / 2.0, sz / 2.0),
        texture,
    }
}

/// A planar pose (x, y, yaw) as an isometry.
pub fn planar(x: f64, y: f64, yaw: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(x, y, 0.0),
        UnitQuaternion::from_euler_angles(0.0, 0.0, yaw),
    )
}

/// A chair (seat, back on the +x side, four legs), 0.5 × 0.5 × 0.85, origin at the footprint centre.
pub fn chair(name: &'static str, pose: Isometry3<f64>, base: Rgb) -> SynthObject {
    let tex = Texture::Striped {
        base,
        amplitude: 60.0,
    };
    let legs = Texture::Uniform([60, 60, 60]);
    let mut boxes = vec![
        box_xyz(0.0, 0.0, 0.45, 0.5, 0.5, 0.04, tex),
        box_xyz(0.23, 0.0, 0.66, 0.04, 0.5, 0.38, tex),
    ];
    for (x, y) in [(-0.22, -0.22), (-0.22, 0.22), (0.22, -0.22), (0.22, 0.22)] {
        boxes.push(box_xyz(x, y, 0.215, 0.04, 0.04, 0.43, legs));
    }
    SynthObject { name, pose, boxes }
}

/// A table 1.2 × 0.8 × 0.72 (length along local x), origin at the footprint centre.
pub fn table(name: &'static str, pose: Isometry3<f64>) -> SynthObject {
    let top = Texture::Striped {
        base: [120, 90, 60],
        amplitude: 30.0,
    };
    let legs = Texture::Uniform([90, 70, 50]);
    let mut boxes = vec![box_xyz(0.0, 0.0, 0.70, 1.2, 0.8, 0.04, top)];
    for (x, y) in [(-0.56, -0.36), (-0.56, 0.36), (0.56, -0.36), (0.56, 0.36)] {
        boxes.push(box_xyz(x, y, 0.34, 0.05, 0.05, 0.68, legs));
    }
    SynthObject { name, pose, boxes }
}

/// The default room (kakiuchi-room): 6.0 × 3.6 m, 2 m walls, table, two chairs, a red mat.
pub fn kakiuchi_room() -> Scene {
    let wall = Texture::Uniform([200, 200, 190]);
    let walls = SynthObject {
        name: "walls",
        pose: Isometry3::identity(),
        boxes: vec![
            box_xyz(-0.05, 1.8, 1.0, 0.1, 3.8, 2.0, wall),
            box_xyz(6.05, 1.8, 1.0, 0.1, 3.8, 2.0, wall),
            box_xyz(3.0, -0.05, 1.0, 6.2, 0.1, 2.0, wall),
            box_xyz(3.0, 3.65, 1.0, 6.2, 0.1, 2.0, wall),
        ],
    };
    let mat = SynthObject {
        name: "mat",
        pose: planar(1.6, 2.9, 0.0),
        boxes: vec![box_xyz(
            0.0,
            0.0,
            0.005,
            0.6,
            0.4,
            0.01,
            Texture::Uniform([180, 40, 40]),
        )],
    };
    Scene {
        objects: vec![
            walls,
            table("table", planar(3.0, 1.8, std::f64::consts::FRAC_PI_2)),
            chair("chair-1", planar(3.8, 0.85, 0.0), [40, 90, 160]),
            chair("chair-2", planar(3.8, 2.75, 0.0), [40, 140, 90]),
            mat,
        ],
        floor: Some([150, 150, 140]),
    }
}

/// The sensor pose for a robot at planar `base` with the head at (pan, tilt) degrees (tilt down positive).
pub fn head_pose(base: &Isometry3<f64>, pan_deg: f64, tilt_deg: f64) -> Isometry3<f64> {
    base * Isometry3::translation(0.05, 0.0, 1.45)
        * Isometry3::rotation(Vector3::z() * pan_deg.to_radians())
        * Isometry3::rotation(Vector3::y() * tilt_deg.to_radians())
}

/// Ray–box intersection distance (entering face), if any, with the hit's object-local position.
fn hit_box(
    origin: &Point3<f64>,
    dir: &Vector3<f64>,
    world_from_box: &Isometry3<f64>,
    half: &Vector3<f64>,
) -> Option<f64> {
    let inv = world_from_box.inverse();
    let o = inv * origin;
    let d = inv * dir;
    let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
    for a in 0..3 {
        if d[a].abs() < 1e-12 {
            if o[a].abs() > half[a] {
                return None;
            }
            continue;
        }
        let (mut ta, mut tb) = ((-half[a] - o[a]) / d[a], (half[a] - o[a]) / d[a]);
        if ta > tb {
            std::mem::swap(&mut ta, &mut tb);
        }
        t0 = t0.max(ta);
        t1 = t1.min(tb);
        if t0 > t1 {
            return None;
        }
    }
    (t0 > 1e-6).then_some(t0)
}

/// Renders `scene` from `sensor_pose` (sensor→map): an organised sensor-frame cloud.
pub fn render(
    scene: &Scene,
    sensor: &Sensor,
    sensor_pose: &Isometry3<f64>,
    seed: u64,
    stamp: f64,
) -> ColourCloud {
    let boxes: Vec<(Isometry3<f64>, &SynthBox, Isometry3<f64>)> = scene
        .objects
        .iter()
        .flat_map(|o| o.boxes.iter().map(move |b| (o.pose * b.pose, b, o.pose)))
        .collect();
    let origin = Point3::from(sensor_pose.translation.vector);
    let (w, h) = (sensor.width, sensor.height);
    let rows: Vec<Vec<([f32; 3], Rgb)>> = (0..h)
        .into_par_iter()
        .map(|r| {
            let mut rng =
                ChaCha8Rng::seed_from_u64(seed.wrapping_mul(1_000_003).wrapping_add(r as u64));
            (0..w)
                .map(|c| {
                    let az = sensor.hfov / 2.0 - sensor.hfov * c as f64 / (w - 1).max(1) as f64;
                    let el = sensor.vfov / 2.0 - sensor.vfov * r as f64 / (h - 1).max(1) as f64;
                    let local_dir = Vector3::new(1.0, az.tan(), el.tan()).normalize();
                    let dir = sensor_pose.rotation * local_dir;
                    let mut best = f64::INFINITY;
                    let mut colour = [0u8; 3];
                    for (world_from_box, b, world_from_obj) in &boxes {
                        if let Some(t) = hit_box(&origin, &dir, world_from_box, &b.half)
                            && t < best
                        {
                            best = t;
                            let p = origin + dir * t;
                            let local = world_from_obj.inverse() * p;
                            colour = b.texture.colour(&local.coords);
                        }
                    }
                    if let Some(fc) = scene.floor
                        && dir.z < -1e-9
                    {
                        let t = -origin.z / dir.z;
                        if t > 0.0 && t < best {
                            best = t;
                            colour = fc;
                        }
                    }
                    // Gaussian range noise by Box–Muller.
                    let u1: f64 = rng.random::<f64>().max(1e-12);
                    let u2: f64 = rng.random::<f64>();
                    let n = (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos();
                    if best.is_finite() && best <= sensor.max_range {
                        let range = best + n * sensor.range_sigma;
                        let p = local_dir * range;
                        ([p.x as f32, p.y as f32, p.z as f32], colour)
                    } else {
                        ([f32::NAN; 3], [0, 0, 0])
                    }
                })
                .collect()
        })
        .collect();
    let mut x = Vec::with_capacity(w * h);
    let mut y = Vec::with_capacity(w * h);
    let mut z = Vec::with_capacity(w * h);
    let mut rgb = Vec::with_capacity(w * h);
    for row in rows {
        for (p, c) in row {
            x.push(p[0]);
            y.push(p[1]);
            z.push(p[2]);
            rgb.push(c);
        }
    }
    ColourCloud::organised(w, h, x, y, z, rgb, CloudFrame::Sensor, *sensor_pose, stamp)
        .expect("renderer fills every array to width × height")
}

/// The 15 clouds of a look-around from planar base pose `base`.
pub fn look_around(scene: &Scene, base: &Isometry3<f64>, seed: u64) -> Vec<ColourCloud> {
    let sensor = Sensor::sr4000();
    let mut clouds = Vec::new();
    for (k, tilt) in [45.0, 30.0, 20.0].iter().enumerate() {
        for (l, pan) in [50.0, 25.0, 0.0, -25.0, -50.0].iter().enumerate() {
            let view = (k * 5 + l) as u64;
            clouds.push(render(
                scene,
                &sensor,
                &head_pose(base, *pan, *tilt),
                seed + view,
                view as f64,
            ));
        }
    }
    clouds
}

/// The map-frame points of one object only (render a scene holding just it, no floor).
pub fn object_points(object: &SynthObject, sensor_pose: &Isometry3<f64>, seed: u64) -> ColourCloud {
    let scene = Scene {
        objects: vec![object.clone()],
        floor: None,
    };
    render(&scene, &Sensor::sr4000(), sensor_pose, seed, 0.0).to_map()
}

/// A sensor pose at `eye` looking at `target`, x forward, z up.
pub fn look_at(eye: Point3<f64>, target: Point3<f64>) -> Isometry3<f64> {
    let fwd = (target - eye).normalize();
    let left = Vector3::z().cross(&fwd).normalize();
    let up = fwd.cross(&left);
    let rot = nalgebra::Rotation3::from_basis_unchecked(&[fwd, left, up]);
    Isometry3::from_parts(
        Translation3::from(eye.coords),
        UnitQuaternion::from_rotation_matrix(&rot),
    )
}

/// Like [`object_points`], with the sensor pixels in `cols × rows` hidden (an arm in front of it).
pub fn object_points_occluded(
    object: &SynthObject,
    sensor_pose: &Isometry3<f64>,
    seed: u64,
    cols: std::ops::Range<usize>,
    rows: std::ops::Range<usize>,
) -> ColourCloud {
    let scene = Scene {
        objects: vec![object.clone()],
        floor: None,
    };
    let c = render(&scene, &Sensor::sr4000(), sensor_pose, seed, 0.0);
    let (w, h) = (c.width(), c.height());
    let mut x = c.xs().to_vec();
    for r in rows.clone() {
        for col in cols.clone() {
            if r < h && col < w {
                x[r * w + col] = f32::NAN;
            }
        }
    }
    ColourCloud::organised(
        w,
        h,
        x,
        c.ys().to_vec(),
        c.zs().to_vec(),
        c.colours().to_vec(),
        CloudFrame::Sensor,
        *sensor_pose,
        0.0,
    )
    .expect("same shape")
    .to_map()
}

/// A thin textured panel `width` wide (local y) × 1.6 m tall, 5 mm thick, standing at the origin.
pub fn panel(name: &'static str, pose: Isometry3<f64>, width: f64) -> SynthObject {
    SynthObject {
        name,
        pose,
        boxes: vec![box_xyz(
            0.0,
            0.0,
            0.8,
            0.005,
            width,
            1.6,
            Texture::Striped {
                base: [128, 128, 128],
                amplitude: 80.0,
            },
        )],
    }
}
