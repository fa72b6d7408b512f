//! Worlds for the view planner's tests and benchmark: axis-aligned boxes (walls, furniture), their
//! prisms with points on every face, and a grid filled by real 360° laser scans from chosen poses, so
//! that "observed" is what the grid's own update made of them.
#![allow(dead_code)]

use nalgebra::{Isometry3, Point2, Point3};
use nudge_motion::{Bounds, RobotCylinder, Validity, ValidityConfig};
use nudge_perception::grid::{
    CellClass, CellIndex, GridConfig, GridGeometry, LaserScan, ObstacleGrid, RangeFrame,
};
use nudge_perception::{CloudFrame, ColourCloud, ObjectId, Prism};

/// The laser's height: it sees every box whose height range holds it.
pub const LASER_Z: f64 = 0.3;
/// The laser's range limit (m).
pub const LASER_RANGE: f64 = 8.0;

/// An axis-aligned box standing in the world.
#[derive(Clone, Copy, Debug)]
pub struct Block {
    /// Lower-left corner (m).
    pub min: [f64; 2],
    /// Upper-right corner (m).
    pub max: [f64; 2],
    /// Bottom and top (m).
    pub z: [f64; 2],
}

impl Block {
    /// A box from `x0, y0` to `x1, y1`, `z0` to `z1` high.
    pub fn new(x0: f64, y0: f64, x1: f64, y1: f64, z0: f64, z1: f64) -> Self {
        Self {
            min: [x0, y0],
            max: [x1, y1],
            z: [z0, z1],
        }
    }

    /// Entry distance of the ray `o + s·d` into the box's footprint, if ahead.
    fn hit(&self, o: Point2<f64>, d: [f64; 2]) -> Option<f64> {
        let (mut lo, mut hi) = (0.0_f64, f64::INFINITY);
        for (k, (&dk, ok)) in d.iter().zip([o.x, o.y]).enumerate() {
            if dk.abs() < 1e-12 {
                if ok < self.min[k] || ok > self.max[k] {
                    return None;
                }
                continue;
            }
            let (t0, t1) = ((self.min[k] - ok) / dk, (self.max[k] - ok) / dk);
            lo = lo.max(t0.min(t1));
            hi = hi.min(t0.max(t1));
        }
        (lo <= hi && lo > 1e-9).then_some(lo)
    }

    /// The box as a prism with points every `step` metres over its four side faces and its top.
    pub fn prism(&self, id: u32, step: f64) -> Prism {
        self.prism_sampled(id, step, step)
    }

    /// The box as a prism with points every `along` metres across its faces and its top, and every
    /// `up` metres up its side faces (the top edge always).
    pub fn prism_sampled(&self, id: u32, along: f64, up: f64) -> Prism {
        let step = along;
        let [x0, y0] = self.min;
        let [x1, y1] = self.max;
        let footprint = vec![
            Point2::new(x0, y0),
            Point2::new(x1, y0),
            Point2::new(x1, y1),
            Point2::new(x0, y1),
        ];
        let mut points = ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0);
        let n = |a: f64, b: f64| ((b - a) / step).ceil().max(1.0) as usize;
        let levels = ((self.z[1] - self.z[0]) / up).ceil().max(1.0) as usize;
        let zs: Vec<f64> = (0..=levels)
            .map(|k| (self.z[0] + k as f64 * up).min(self.z[1]))
            .collect();
        let mut push = |x: f64, y: f64, z: f64| {
            points.push(Point3::new(x as f32, y as f32, z as f32), [128, 128, 128])
        };
        for k in 0..=n(x0, x1) {
            let x = (x0 + k as f64 * step).min(x1);
            for &z in &zs {
                push(x, y0, z);
                push(x, y1, z);
            }
        }
        for k in 0..=n(y0, y1) {
            let y = (y0 + k as f64 * step).min(y1);
            for &z in &zs {
                push(x0, y, z);
                push(x1, y, z);
            }
        }
        for i in 0..=n(x0, x1) {
            for j in 0..=n(y0, y1) {
                push(
                    (x0 + i as f64 * step).min(x1),
                    (y0 + j as f64 * step).min(y1),
                    self.z[1],
                );
            }
        }
        Prism {
            id: ObjectId(id),
            footprint,
            z_min: self.z[0],
            z_max: self.z[1],
            points,
        }
    }
}

/// A world: a rectangle of floor with boxes on it.
#[derive(Clone, Debug)]
pub struct World {
    /// The floor's lower-left and upper-right corners (m); the grid covers it exactly.
    pub size: [f64; 2],
    /// The boxes, walls included.
    pub blocks: Vec<Block>,
}

/// The robot of these worlds: the paper's HRP-2-sized cylinder.
pub const ROBOT: RobotCylinder = RobotCylinder {
    radius: 0.3,
    height: 1.5,
};

impl World {
    /// An empty grid of 5 cm cells over the world.
    pub fn grid(&self) -> ObstacleGrid {
        let geom = GridGeometry::new(Point2::new(0.0, 0.0), self.size, 0.05).expect("grid");
        ObstacleGrid::new(geom, GridConfig::default())
    }

    /// The boxes as prisms (ids from 1), points every 2.5 cm.
    pub fn prisms(&self) -> Vec<Prism> {
        self.prisms_sampled(0.025, 0.025)
    }

    /// The boxes as prisms (ids from 1), points every `along` m across faces, `up` m up them.
    pub fn prisms_sampled(&self, along: f64, up: f64) -> Vec<Prism> {
        self.blocks
            .iter()
            .enumerate()
            .map(|(k, b)| b.prism_sampled(k as u32 + 1, along, up))
            .collect()
    }

    /// The validity checker for [`ROBOT`] in the world.
    pub fn validity(&self, prisms: &[Prism]) -> Validity {
        let walls = Bounds::new(
            Point2::new(0.0, 0.0),
            Point2::new(self.size[0], self.size[1]),
        )
        .expect("bounds");
        Validity::new(ROBOT, walls, prisms, ValidityConfig::default()).expect("validity")
    }

    /// The ranges of a scan of `beams` bearings from `angle_min` every `step` (rad, map frame)
    /// at `position`, at the laser's height.
    pub fn ranges(
        &self,
        position: Point2<f64>,
        angle_min: f64,
        step: f64,
        beams: usize,
    ) -> Vec<f32> {
        (0..beams)
            .map(|i| {
                let a = angle_min + step * i as f64;
                let d = [a.cos(), a.sin()];
                self.blocks
                    .iter()
                    .filter(|b| b.z[0] <= LASER_Z && LASER_Z <= b.z[1])
                    .filter_map(|b| b.hit(position, d))
                    .fold(f64::INFINITY, f64::min) as f32
            })
            .collect()
    }

    /// Folds `frames` identical scans (0.5° steps over `span` rad centred on `yaw`) from
    /// `position` into `grid`, 0.1 s apart after its last frame: three or more classify what they
    /// return (Stationary).
    pub fn scan(
        &self,
        grid: &mut ObstacleGrid,
        position: Point2<f64>,
        yaw: f64,
        span: f64,
        frames: usize,
    ) {
        let step = 0.5_f64.to_radians();
        let beams = (span / step).round() as usize;
        let angle_min = -span / 2.0;
        let ranges = self.ranges(position, yaw + angle_min, step, beams);
        let scan = LaserScan {
            position,
            yaw,
            angle_min,
            angle_increment: step,
            range_max: LASER_RANGE,
            ranges: &ranges,
        };
        let frame = RangeFrame::from_laser_scan(&scan).expect("finite scan");
        for _ in 0..frames {
            let now = grid.frames() as f64 * 0.1;
            grid.update(&frame, now).expect("in order");
        }
    }

    /// A full-circle scan, four frames, from each of `poses`.
    pub fn scan_all(&self, grid: &mut ObstacleGrid, poses: &[Point2<f64>]) {
        for &p in poses {
            self.scan(grid, p, 0.0, std::f64::consts::TAU, 4);
        }
    }
}

/// The never-observed cells of `grid` whose centres lie in the rectangle `lo..hi` (m).
pub fn unobserved_in(grid: &ObstacleGrid, lo: [f64; 2], hi: [f64; 2]) -> Vec<CellIndex> {
    let g = grid.geometry();
    (0..g.len())
        .filter_map(|i| g.cell_at(i))
        .filter(|&c| {
            let p = g.centre(c);
            p.x >= lo[0] && p.x <= hi[0] && p.y >= lo[1] && p.y <= hi[1] && !grid.observed(c)
        })
        .collect()
}

/// The cells of `grid` of class `class` whose centres lie in the rectangle `lo..hi` (m).
pub fn cells_of_class(
    grid: &ObstacleGrid,
    class: CellClass,
    lo: [f64; 2],
    hi: [f64; 2],
) -> Vec<CellIndex> {
    let g = grid.geometry();
    (0..g.len())
        .filter_map(|i| g.cell_at(i))
        .filter(|&c| {
            let p = g.centre(c);
            p.x >= lo[0]
                && p.x <= hi[0]
                && p.y >= lo[1]
                && p.y <= hi[1]
                && grid.class(c) == Some(class)
        })
        .collect()
}

/// Whether the segment `a → b` crosses the footprint of `block`.
pub fn segment_crosses(block: &Block, a: Point2<f64>, b: Point2<f64>) -> bool {
    let d = b - a;
    let len = d.norm();
    if len == 0.0 {
        return false;
    }
    let inside = |p: Point2<f64>| {
        p.x >= block.min[0] && p.x <= block.max[0] && p.y >= block.min[1] && p.y <= block.max[1]
    };
    inside(a)
        || block
            .hit(a, [d.x / len, d.y / len])
            .is_some_and(|t| t <= len)
}

/// A 40 × 30 m office (an 800 × 600 grid): a corridor along y = 12..14; rooms 5 m wide on both
/// sides of it (y 6..12 and 14..20) and along the bottom (y 0..6), each with a 1 m door in its
/// wall towards the corridor (or towards the room above, for the bottom band); an open-plan area
/// with desks above (y 20..30). Every room has a desk and a cabinet; walls are 0.15 m thick and
/// 2.5 m high, split at the doors and at every room so that no prism spans the whole map.
pub fn office() -> World {
    let mut blocks = Vec::new();
    let t = 0.15;
    let wall = |x0: f64, y0: f64, x1: f64, y1: f64| Block::new(x0, y0, x1, y1, 0.0, 2.5);
    // Outer walls.
    for k in 0..8 {
        let x = 5.0 * k as f64;
        blocks.push(wall(x, 0.0, x + 5.0, t));
        blocks.push(wall(x, 30.0 - t, x + 5.0, 30.0));
    }
    for k in 0..6 {
        let y = 5.0 * k as f64;
        blocks.push(wall(0.0, y, t, y + 5.0));
        blocks.push(wall(40.0 - t, y, 40.0, y + 5.0));
    }
    // Horizontal walls with a door in the middle of each 5 m room (at y = 6, 12, 14, 20).
    for &y in &[6.0, 12.0, 14.0, 20.0] {
        for k in 0..8 {
            let x = 5.0 * k as f64;
            if y == 20.0 && k % 2 == 1 {
                // The open-plan area opens onto the rooms below it through wide gaps.
                blocks.push(wall(x, y, x + 1.0, y + t));
                blocks.push(wall(x + 4.0, y, x + 5.0, y + t));
                continue;
            }
            blocks.push(wall(x, y, x + 2.0, y + t));
            blocks.push(wall(x + 3.0, y, x + 5.0, y + t));
        }
    }
    // Walls between rooms.
    for k in 1..8 {
        let x = 5.0 * k as f64;
        for (y0, y1) in [(0.0, 6.0), (6.0, 12.0), (14.0, 20.0)] {
            blocks.push(wall(x, y0, x + t, y1));
        }
    }
    // Furniture: a desk and a cabinet in every room, desks in the open plan.
    for k in 0..8 {
        let x = 5.0 * k as f64;
        for &y in &[0.0, 6.0, 14.0] {
            blocks.push(Block::new(x + 0.6, y + 3.2, x + 2.2, y + 4.0, 0.0, 0.75));
            blocks.push(Block::new(x + 4.2, y + 0.8, x + 4.7, y + 1.8, 0.0, 1.8));
        }
        blocks.push(Block::new(x + 1.0, 24.0, x + 3.0, 24.8, 0.0, 0.75));
        blocks.push(Block::new(x + 2.5, 27.0, x + 4.0, 27.6, 0.0, 1.1));
    }
    World {
        size: [40.0, 30.0],
        blocks,
    }
}

/// Where the office was scanned from: along the corridor, through the open plan, and the centres
/// of some rooms (not the room at x 20..25, y 14..20, seen only through its door).
pub fn office_scan_poses() -> Vec<Point2<f64>> {
    let mut poses: Vec<Point2<f64>> = (0..13)
        .map(|k| Point2::new(1.5 + 3.0 * k as f64, 13.0))
        .collect();
    poses.extend((0..6).map(|k| Point2::new(3.5 + 6.5 * k as f64, 25.5)));
    for (x, y) in [
        (2.5, 9.0),
        (12.5, 9.0),
        (27.5, 9.0),
        (7.5, 17.0),
        (32.5, 17.0),
        (12.5, 3.0),
    ] {
        poses.push(Point2::new(x, y));
    }
    poses
}

/// The office's target region: the room at x 20..25, y 14..20 (behind its door).
pub const OFFICE_TARGET_ROOM: ([f64; 2], [f64; 2]) = ([20.2, 14.2], [24.9, 19.9]);
