//! Worlds shared by the tests and the benchmark: the narrow passages A and Z and the paper's room.
#![allow(dead_code)]

use nalgebra::{Isometry3, Point2};
use nudge_motion::{Bounds, Problem, RobotCylinder, Validity, ValidityConfig};
use nudge_perception::{CloudFrame, ColourCloud, ObjectId, Prism};

/// An axis-aligned box prism.
pub fn boxed(id: u32, x0: f64, y0: f64, x1: f64, y1: f64, z_min: f64, z_max: f64) -> Prism {
    Prism {
        id: ObjectId(id),
        footprint: vec![
            Point2::new(x0, y0),
            Point2::new(x1, y0),
            Point2::new(x1, y1),
            Point2::new(x0, y1),
        ],
        z_min,
        z_max,
        points: ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0),
    }
}

/// Robot of the narrow-passage problems.
pub const NARROW_ROBOT: RobotCylinder = RobotCylinder {
    radius: 0.3,
    height: 1.5,
};
/// Gap width: the diameter plus 10 cm of clearance.
pub const GAP: f64 = 2.0 * 0.3 + 0.1;
/// Wall thickness in the narrow-passage problems.
pub const WALL: f64 = 0.2;

fn ten_by_ten() -> Bounds {
    Bounds::new(Point2::new(0.0, 0.0), Point2::new(10.0, 10.0)).expect("10 m × 10 m")
}

/// A wall across the world at height `y` (its lower face) with a gap starting at `gap_x`.
fn wall_with_gap(first_id: u32, y: f64, gap_x: f64) -> [Prism; 2] {
    [
        boxed(first_id, 0.0, y, gap_x, y + WALL, 0.0, 2.0),
        boxed(first_id + 1, gap_x + GAP, y, 10.0, y + WALL, 0.0, 2.0),
    ]
}

/// Problem A: one wall across the middle, an off-centre gap of 0.7 m (10 cm of clearance).
pub fn narrow_a() -> (Validity, Problem) {
    let prisms = wall_with_gap(1, 4.9, 6.8);
    let v = Validity::new(
        NARROW_ROBOT,
        ten_by_ten(),
        &prisms,
        ValidityConfig::default(),
    )
    .expect("world A");
    let p = Problem::new(Point2::new(2.0, 1.5), Point2::new(2.0, 8.5), 0.1).expect("problem A");
    (v, p)
}

/// Problem Z: two walls with staggered gaps, the path must zig-zag.
pub fn narrow_z() -> (Validity, Problem) {
    let mut prisms = wall_with_gap(1, 3.2, 7.8).to_vec();
    prisms.extend(wall_with_gap(3, 6.6, 1.5));
    let v = Validity::new(
        NARROW_ROBOT,
        ten_by_ten(),
        &prisms,
        ValidityConfig::default(),
    )
    .expect("world Z");
    let p = Problem::new(Point2::new(2.0, 1.5), Point2::new(8.0, 8.5), 0.1).expect("problem Z");
    (v, p)
}

/// Ids in the paper's room.
pub const TABLE: ObjectId = ObjectId(10);
/// Chair 1 (low y).
pub const CHAIR_1: ObjectId = ObjectId(11);
/// Chair 2 (high y).
pub const CHAIR_2: ObjectId = ObjectId(12);
/// The mat on the floor.
pub const MAT: ObjectId = ObjectId(13);

/// The robot of the paper's room (BRIEF).
pub const ROOM_ROBOT: RobotCylinder = RobotCylinder {
    radius: 0.35,
    height: 1.54,
};

/// The paper's room: four thin wall prisms just outside 6.0 × 3.6 m, table, two chairs, mat.
pub fn room_prisms() -> Vec<Prism> {
    vec![
        boxed(1, -0.1, -0.1, 6.1, 0.0, 0.0, 2.0),
        boxed(2, -0.1, 3.6, 6.1, 3.7, 0.0, 2.0),
        boxed(3, -0.1, 0.0, 0.0, 3.6, 0.0, 2.0),
        boxed(4, 6.0, 0.0, 6.1, 3.6, 0.0, 2.0),
        boxed(TABLE.0, 2.6, 1.2, 3.4, 2.4, 0.0, 0.72),
        boxed(CHAIR_1.0, 3.55, 0.6, 4.05, 1.1, 0.0, 0.85),
        boxed(CHAIR_2.0, 3.55, 2.5, 4.05, 3.0, 0.0, 0.85),
        boxed(MAT.0, 1.3, 2.7, 1.9, 3.1, 0.0, 0.01),
    ]
}

/// The room's validity checker (bounds a little outside the wall prisms) and start → goal problem.
pub fn room() -> (Validity, Problem) {
    let bounds = Bounds::new(Point2::new(-0.2, -0.2), Point2::new(6.2, 3.8)).expect("room bounds");
    let v = Validity::new(
        ROOM_ROBOT,
        bounds,
        &room_prisms(),
        ValidityConfig::default(),
    )
    .expect("room");
    let p = Problem::new(Point2::new(0.6, 1.8), Point2::new(5.4, 1.8), 0.2).expect("room problem");
    (v, p)
}

/// The least wall time of `n` runs of `f`: the run the shared machine's load disturbed least (the
/// benchmarks print it beside criterion's figures).
pub fn best_of(n: usize, mut f: impl FnMut()) -> std::time::Duration {
    (0..n)
        .map(|_| {
            let t = std::time::Instant::now();
            f();
            t.elapsed()
        })
        .min()
        .unwrap_or_default()
}
