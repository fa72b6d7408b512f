//! Furniture for generated rooms: light things the guarded push slides and heavy or bolted things
//! it cannot, partitions with doors, and a floor plan that keeps them apart.
//!
//! Light things slide at μ m g between 6 and 15 N, below the truth's movable line (80 % of the 20 N
//! push limit, `crate::truth`); heavy things need 240 N or more. The band between is left to the
//! force-limit family, which skips the part the truth does not score.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use crate::scenario::{GRAVITY, ObjectKind, ObjectSpec, Texture};

/// Wall thickness of a partition (m).
pub const PARTITION: f64 = 0.15;
/// Gap kept between pieces of furniture, and around the start and goal discs (m): wide enough for
/// the camera to see between them, not enough for the robot (0.7 m across) to pass.
const GAP: f64 = 0.1;

/// A bolted partition piece: a box from `a` to `b` (its long axis x or y), 2 m high.
pub fn partition(name: String, a: [f64; 2], b: [f64; 2]) -> ObjectSpec {
    let (dx, dy) = ((b[0] - a[0]).abs(), (b[1] - a[1]).abs());
    ObjectSpec {
        name,
        kind: ObjectKind::Box,
        position: [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0],
        yaw: 0.0,
        size: vec![dx.max(PARTITION), dy.max(PARTITION), 2.0],
        elevation: 0.0,
        mass: 500.0,
        friction: 0.8,
        fixed: true,
        colour: [200, 196, 186],
        texture: Texture::Plain,
    }
}

/// A light thing the push slides: a chair or a box of 3–6 kg at μ m g 6–15 N, coloured and
/// textured so colour ICP has something to hold on to.
pub fn light(rng: &mut ChaCha8Rng, name: String) -> ObjectSpec {
    let mass = rng.random_range(3.0..6.0);
    let slide = rng.random_range(6.0..15.0);
    let (kind, size) = if rng.random_bool(0.5) {
        (ObjectKind::Chair, vec![0.5, 0.5, 0.85])
    } else {
        let side = rng.random_range(0.45..0.7);
        (
            ObjectKind::Box,
            vec![
                side,
                rng.random_range(0.45..0.7),
                rng.random_range(0.5..0.9),
            ],
        )
    };
    with_slide(
        ObjectSpec {
            name,
            kind,
            position: [0.0, 0.0],
            yaw: 0.0,
            size,
            elevation: 0.0,
            mass,
            friction: 0.6,
            fixed: false,
            colour: colour(rng),
            texture: Texture::Noise,
        },
        slide,
    )
}

/// A heavy thing the push cannot slide: a bolted table or shelf, or a 40–90 kg cabinet (≥ 240 N).
pub fn heavy(rng: &mut ChaCha8Rng, name: String) -> ObjectSpec {
    let (kind, size, fixed) = match rng.random_range(0..3) {
        0 => (
            ObjectKind::Table,
            vec![rng.random_range(0.8..1.6), rng.random_range(0.6..0.9), 0.72],
            true,
        ),
        1 => (
            ObjectKind::Cylinder,
            vec![rng.random_range(0.4..0.8), rng.random_range(0.8..1.2)],
            true,
        ),
        _ => (
            ObjectKind::Box,
            vec![
                rng.random_range(0.6..1.4),
                rng.random_range(0.4..0.7),
                rng.random_range(0.9..1.6),
            ],
            false,
        ),
    };
    ObjectSpec {
        name,
        kind,
        position: [0.0, 0.0],
        yaw: 0.0,
        size,
        elevation: 0.0,
        mass: rng.random_range(40.0..90.0),
        friction: 0.6,
        fixed,
        colour: colour(rng),
        texture: Texture::Checker,
    }
}

/// `spec` with its friction set so that μ m g is `slide` newtons.
pub fn with_slide(mut spec: ObjectSpec, slide: f64) -> ObjectSpec {
    spec.friction = slide / (spec.mass * GRAVITY);
    spec
}

/// Radius of the disc that holds `spec`'s footprint (m).
pub fn reach(spec: &ObjectSpec) -> f64 {
    match spec.kind {
        ObjectKind::Cylinder => spec.size[0] / 2.0,
        _ => spec.size[0].hypot(spec.size[1]) / 2.0,
    }
}

/// Where things already stand: discs that new furniture keeps clear of.
#[derive(Default)]
pub struct FloorPlan {
    taken: Vec<([f64; 2], f64)>,
}

impl FloorPlan {
    /// Keeps a disc of `radius` around `centre` clear (the start, the goal, a doorway).
    pub fn keep_clear(&mut self, centre: [f64; 2], radius: f64) {
        self.taken.push((centre, radius));
    }

    /// Puts `spec` at a random pose inside `[x0, x1] × [y0, y1]` clear of everything placed, trying
    /// 50 times; returns whether it found room.
    pub fn place(
        &mut self,
        rng: &mut ChaCha8Rng,
        spec: &mut ObjectSpec,
        [x0, x1]: [f64; 2],
        [y0, y1]: [f64; 2],
    ) -> bool {
        let r = reach(spec);
        if x1 - x0 <= 2.0 * r || y1 - y0 <= 2.0 * r {
            return false;
        }
        for _ in 0..50 {
            let c = [
                rng.random_range(x0 + r..x1 - r),
                rng.random_range(y0 + r..y1 - r),
            ];
            let clear = self
                .taken
                .iter()
                .all(|(o, or)| (c[0] - o[0]).hypot(c[1] - o[1]) > r + or + GAP);
            if clear {
                spec.position = c;
                spec.yaw = f64::from(rng.random_range(0..8_u8)) * 45.0;
                self.taken.push((c, r));
                return true;
            }
        }
        false
    }
}

/// A saturated colour away from the floor's and the walls' greys.
pub fn colour(rng: &mut ChaCha8Rng) -> [u8; 3] {
    let hue = rng.random_range(0.0..6.0_f64);
    let (hi, lo) = (rng.random_range(170..235_u8), rng.random_range(30..80_u8));
    let mid = |f: f64| (f64::from(lo) + f * f64::from(hi - lo)) as u8;
    let f = hue.fract();
    match hue as u8 {
        0 => [hi, mid(f), lo],
        1 => [mid(1.0 - f), hi, lo],
        2 => [lo, hi, mid(f)],
        3 => [lo, mid(1.0 - f), hi],
        4 => [mid(f), lo, hi],
        _ => [hi, lo, mid(1.0 - f)],
    }
}
