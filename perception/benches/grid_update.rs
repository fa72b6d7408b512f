//! Obstacle-type grid update speed.
//!
//! - `laser_361`: one 361-beam scan (180° at 0.5°, 8 m limit) of a 10 × 12 m office with furniture into
//!   an 800 × 600 grid of 5 cm cells (Chen et al.'s setting), classification included. The robot walks
//!   2 cm per frame, so every frame re-classifies. Two variants: the `RangeFrame` prebuilt, and built
//!   from the raw ranges inside the timed loop.
//! - `cloud_176x144`: one organised 176 × 144 colour cloud of the kakiuchi room seen from 1.4 m, pitched
//!   down 25°, reduced per column and folded into the room's grid (140 × 92 cells of 5 cm).

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::{Isometry3, Point2, Translation3, UnitQuaternion, Vector3};
use nudge_perception::grid::{
    ColumnReduction, GridConfig, GridGeometry, LaserScan, ObstacleGrid, RangeFrame, Traversal,
};
use nudge_perception::{CloudFrame, ColourCloud};

/// Axis-aligned boxes (min, max), 3D; the 2D scanner sees their footprints.
type Aabb = ([f64; 3], [f64; 3]);

/// Slab test: entry distance of the ray o + s·d into the box, if it is hit ahead.
fn ray_box(o: [f64; 3], d: [f64; 3], b: &Aabb, dims: usize) -> Option<f64> {
    let (mut lo, mut hi) = (0.0_f64, f64::INFINITY);
    for k in 0..dims {
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

/// Distance to the inside of a room's walls (a box seen from inside).
fn ray_room_inside(o: [f64; 3], d: [f64; 3], room: &Aabb, dims: usize) -> f64 {
    (0..dims)
        .filter(|&k| d[k].abs() > 1e-12)
        .map(|k| {
            let wall = if d[k] > 0.0 { room.1[k] } else { room.0[k] };
            (wall - o[k]) / d[k]
        })
        .fold(f64::INFINITY, f64::min)
}

fn office() -> (Aabb, Vec<Aabb>) {
    let room = ([15.0, 9.0, 0.0], [25.0, 21.0, 2.5]);
    let furniture = vec![
        ([21.0, 12.0, 0.0], [22.6, 12.8, 0.75]),
        ([21.0, 17.0, 0.0], [22.6, 17.8, 0.75]),
        ([18.5, 19.5, 0.0], [19.0, 20.0, 0.9]),
        ([23.5, 14.5, 0.0], [24.9, 15.3, 1.8]),
        ([17.0, 10.0, 0.0], [17.5, 10.5, 0.9]),
    ];
    (room, furniture)
}

fn laser_ranges(pos: Point2<f64>, room: &Aabb, furniture: &[Aabb]) -> Vec<f32> {
    (0..361)
        .map(|i| {
            let a = (-90.0 + 0.5 * i as f64).to_radians();
            let (o, d) = ([pos.x, pos.y, 0.3], [a.cos(), a.sin(), 0.0]);
            let walls = ray_room_inside(o, d, room, 2);
            let nearest = furniture
                .iter()
                .filter_map(|b| ray_box(o, d, b, 2))
                .fold(walls, f64::min);
            nearest as f32
        })
        .collect()
}

fn bench_laser(c: &mut Criterion) {
    let geom = GridGeometry::with_cells(Point2::new(0.0, 0.0), 800, 600, 0.05).expect("valid");
    let (room, furniture) = office();
    let poses: Vec<Point2<f64>> = (0..20)
        .map(|k| Point2::new(16.0 + 0.02 * k as f64, 15.03))
        .collect();
    let ranges: Vec<Vec<f32>> = poses
        .iter()
        .map(|&p| laser_ranges(p, &room, &furniture))
        .collect();
    let scan = |k: usize| LaserScan {
        position: poses[k],
        yaw: 0.0,
        angle_min: -std::f64::consts::FRAC_PI_2,
        angle_increment: 0.5_f64.to_radians(),
        range_max: 8.0,
        ranges: &ranges[k],
    };
    let frames: Vec<RangeFrame> = (0..poses.len())
        .map(|k| RangeFrame::from_laser_scan(&scan(k)).expect("finite scan"))
        .collect();

    // Reference under the same machine load: the bare Amanatides–Woo walk of the same beams.
    c.bench_function("grid/laser_361_plain_traversal_800x600", |b| {
        let f = &frames[0];
        b.iter(|| {
            let mut n = 0usize;
            for beam in f.beams() {
                n += Traversal::new(&geom, f.sensor(), black_box(beam.end)).count();
            }
            n
        })
    });
    let mut grid = ObstacleGrid::new(geom, GridConfig::default());
    let mut k = 0usize;
    c.bench_function("grid/laser_361_update_800x600", |b| {
        b.iter(|| {
            let f = &frames[k % frames.len()];
            grid.update(black_box(f), k as f64 * 0.1).expect("in order");
            k += 1;
        })
    });
    let mut grid = ObstacleGrid::new(geom, GridConfig::default());
    let mut k = 0usize;
    c.bench_function("grid/laser_361_scan_to_grid_800x600", |b| {
        b.iter(|| {
            let f = RangeFrame::from_laser_scan(black_box(&scan(k % poses.len())))
                .expect("finite scan");
            grid.update(&f, k as f64 * 0.1).expect("in order");
            k += 1;
        })
    });
}

/// A synthetic 176 × 144 range camera (43.6° × 34.6° field of view, like a SwissRanger SR4000) at
/// `pos`, 1.4 m up, pitched down 25°, looking along +x, in the kakiuchi room.
fn kakiuchi_cloud(pos: Point2<f64>, stamp: f64) -> ColourCloud {
    let (w, h) = (176usize, 144usize);
    let room: Aabb = ([0.0, 0.0, 0.0], [6.0, 3.6, 2.0]);
    let furniture: [Aabb; 3] = [
        ([2.6, 1.2, 0.0], [3.4, 2.4, 0.72]),
        ([3.55, 0.6, 0.0], [4.05, 1.1, 0.85]),
        ([3.55, 2.5, 0.0], [4.05, 3.0, 0.85]),
    ];
    let pitch = 25.0_f64.to_radians();
    let pose = Isometry3::from_parts(
        Translation3::new(pos.x, pos.y, 1.4),
        UnitQuaternion::from_euler_angles(0.0, pitch, 0.0),
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
            let o = [pos.x, pos.y, 1.4];
            let d = [dm.x, dm.y, dm.z];
            let walls = ray_room_inside(o, d, &room, 3);
            let s = furniture
                .iter()
                .filter_map(|b| ray_box(o, d, b, 3))
                .fold(walls, f64::min);
            if s.is_finite() && s < 8.0 {
                let p = ds * s;
                let i = v * w + u;
                (xs[i], ys[i], zs[i]) = (p.x as f32, p.y as f32, p.z as f32);
            }
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

fn bench_cloud(c: &mut Criterion) {
    let geom = GridGeometry::from_rect(Point2::new(0.0, 0.0), Point2::new(6.0, 3.6), 0.5, 0.05)
        .expect("valid room");
    let clouds: Vec<ColourCloud> = (0..10)
        .map(|k| kakiuchi_cloud(Point2::new(0.6 + 0.015 * k as f64, 1.8), k as f64 * 0.1))
        .collect();
    let cfg = ColumnReduction::default();
    let probe = RangeFrame::from_cloud(&clouds[0], &cfg).expect("organised");
    assert!(probe.beams().len() > 150, "a room fills most columns");
    let mut grid = ObstacleGrid::new(geom, GridConfig::default());
    let mut k = 0usize;
    c.bench_function("grid/cloud_176x144_to_grid", |b| {
        b.iter(|| {
            let cloud = &clouds[k % clouds.len()];
            let f = RangeFrame::from_cloud(black_box(cloud), &cfg).expect("organised");
            grid.update(&f, k as f64 * 0.1).expect("in order");
            k += 1;
        })
    });
    c.bench_function("grid/cloud_176x144_column_reduction_only", |b| {
        b.iter(|| RangeFrame::from_cloud(black_box(&clouds[0]), &cfg).expect("organised"))
    });
}

criterion_group!(benches, bench_laser, bench_cloud);
criterion_main!(benches);
