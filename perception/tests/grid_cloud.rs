//! Range-camera frames into the grid: the kakiuchi room seen from the robot's start, 1.4 m up.
//!
//! A synthetic 176 × 144 camera (43.6° × 34.6°, pitched down 25°) looks along +x from (0.6, 1.8) at the
//! room of the brief: walls 2 m high around 6.0 × 3.6 m, the table at x 2.6..3.4, y 1.2..2.4 (0.72 m
//! high), chairs at x 3.55..4.05.

use nalgebra::{Isometry3, Point2, Translation3, UnitQuaternion, Vector3};
use nudge_perception::grid::{
    CellClass, ColumnReduction, GridConfig, GridGeometry, ObstacleGrid, RangeFrame,
};
use nudge_perception::{CloudFrame, ColourCloud};

type Aabb = ([f64; 3], [f64; 3]);

fn ray_box(o: [f64; 3], d: [f64; 3], b: &Aabb) -> Option<f64> {
    let (mut lo, mut hi) = (0.0_f64, f64::INFINITY);
    for k in 0..3 {
        if d[k].abs() < 1e-12 {
            if o[k] < b.0[k] || o[k] > b.1[k] {
                return None;
            }
            continue;
        }
        let (t0, t1) = ((b.0[k] - o[k]) / d[k], (b.1[k] - o[k]) / d[k]);
        lo = lo.max(t0.min(t1));
        hi = hi.min(t0.max(t1));
    }
    (lo <= hi && lo > 1e-9).then_some(lo)
}

fn inside_room(o: [f64; 3], d: [f64; 3], room: &Aabb) -> f64 {
    (0..3)
        .filter(|&k| d[k].abs() > 1e-12)
        .map(|k| ((if d[k] > 0.0 { room.1[k] } else { room.0[k] }) - o[k]) / d[k])
        .fold(f64::INFINITY, f64::min)
}

fn room_cloud(stamp: f64) -> ColourCloud {
    let (w, h) = (176usize, 144usize);
    let room: Aabb = ([0.0, 0.0, 0.0], [6.0, 3.6, 2.0]);
    let furniture: [Aabb; 3] = [
        ([2.6, 1.2, 0.0], [3.4, 2.4, 0.72]),
        ([3.55, 0.6, 0.0], [4.05, 1.1, 0.85]),
        ([3.55, 2.5, 0.0], [4.05, 3.0, 0.85]),
    ];
    let pose = Isometry3::from_parts(
        Translation3::new(0.6, 1.8, 1.4),
        UnitQuaternion::from_euler_angles(0.0, 25.0_f64.to_radians(), 0.0),
    );
    let (hfov, vfov) = (43.6_f64.to_radians(), 34.6_f64.to_radians());
    let n = w * h;
    let (mut xs, mut ys, mut zs) = (vec![f32::NAN; n], vec![f32::NAN; n], vec![f32::NAN; n]);
    for v in 0..h {
        for u in 0..w {
            let az = hfov * (0.5 - (u as f64 + 0.5) / w as f64);
            let el = vfov * (0.5 - (v as f64 + 0.5) / h as f64);
            let ds = Vector3::new(1.0, az.tan(), el.tan()).normalize();
            let dm = pose.rotation * ds;
            let o = [0.6, 1.8, 1.4];
            let d = [dm.x, dm.y, dm.z];
            let s = furniture
                .iter()
                .filter_map(|b| ray_box(o, d, b))
                .fold(inside_room(o, d, &room), f64::min);
            let p = ds * s;
            let i = v * w + u;
            (xs[i], ys[i], zs[i]) = (p.x as f32, p.y as f32, p.z as f32);
        }
    }
    ColourCloud::organised(
        w,
        h,
        xs,
        ys,
        zs,
        vec![[150, 150, 140]; n],
        CloudFrame::Sensor,
        pose,
        stamp,
    )
    .expect("consistent arrays")
}

#[test]
fn the_table_edge_becomes_stationary_and_the_floor_before_it_free() {
    // Invariant: per-column reduction keeps the nearest obstacle (the table's near edge), the floor
    // seen is free space (not under the lowest ray), three frames make returns stationary.
    let geom = GridGeometry::from_rect(Point2::new(0.0, 0.0), Point2::new(6.0, 3.6), 0.5, 0.05)
        .expect("valid room");
    let mut grid = ObstacleGrid::new(geom, GridConfig::default());
    let cfg = ColumnReduction::default();
    for k in 0..3 {
        let cloud = room_cloud(k as f64 * 0.1);
        let frame = RangeFrame::from_cloud(&cloud, &cfg).expect("organised cloud");
        assert_eq!(frame.beams().len(), 176, "every column sees something");
        grid.update(&frame, cloud.stamp()).expect("in order");
    }
    // The floor between the robot and the table is free from where the lowest ray (42.3° down, on the
    // floor at x ≈ 2.14) is below the 0.4 m clear height, x ≈ 1.7; nearer, something could stand under
    // that ray, so those cells stay unknown.
    for x in [2.2, 2.4] {
        assert_eq!(
            grid.class_at(Point2::new(x, 1.8)),
            Some(CellClass::Free),
            "x = {x}"
        );
    }
    assert_eq!(
        grid.class_at(Point2::new(1.6, 1.8)),
        Some(CellClass::Unknown)
    );
    // The table's near edge (x = 2.6, exactly a cell boundary: returns fall on either side) is
    // stationary along the part the camera sees, and nothing is moving or movable.
    for y in [1.5, 1.8, 2.1] {
        let sides = [2.57, 2.62].map(|x| grid.class_at(Point2::new(x, y)));
        assert!(
            sides.contains(&Some(CellClass::Stationary)),
            "y = {y}: {sides:?}"
        );
    }
    let counts = grid.class_counts();
    assert_eq!(counts[CellClass::Moving.code() as usize], 0);
    assert_eq!(counts[CellClass::Movable.code() as usize], 0);
    // Behind the table edge nothing was seen in 2D.
    assert_eq!(
        grid.class_at(Point2::new(3.0, 1.8)),
        Some(CellClass::Unknown)
    );
}
