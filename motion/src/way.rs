//! Could floor nobody has seen open a way? The hypothesis behind "no path means no path".
//!
//! An obstacle's outline is the convex hull of the points perception saw of it. Where the hull covers
//! floor that was seen (free, or holding the object's own returns) it is the object; where it covers
//! floor nobody has seen, it is a guess: two wall runs on either side of a door seen edge-on become one
//! hull across the door, and a chair's outline seen from far swallows the gap beside it. This module
//! asks whether the robot could reach the goal if every such guess were wrong — walking through hull
//! cells never seen, but never through a cell that held a return or a hull cell that was seen — on a
//! coarse lattice, with the unseen hull cells weighted so that the hypothesis assumes as little as it
//! can. The unseen hull cells under that way are what a look must show before the run may end in "no
//! path"; when no such way exists, obstacles already seen close every way, and no look could change
//! that.

use nalgebra::Point2;
use nudge_perception::Prism;
use nudge_perception::grid::{CellClass, CellIndex, ObstacleGrid};

use crate::validity::RobotCylinder;
use crate::view::{Lattice, LatticeCell};

/// Lattice cell side in grid cells: 10 cm on the 5 cm grid, as the view planner's lattice.
const FACTOR: usize = 2;

/// Step weight of a lattice cell whose floor is a guess (an unseen cell inside a hull): crossing a
/// metre of it costs as much as walking a hundred metres of seen floor, so the hypothesis takes the
/// fewest guesses, then the shortest walk.
const GUESS_WEIGHT: u8 = 100;

/// What a grid cell is to the hypothesis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Kind {
    /// Seen free, or unseen outside every hull (paths are hypotheses there anyway).
    Floor,
    /// Unseen, inside a hull, still worth a look: a guess.
    Guess,
    /// Held a return, or inside a hull where the floor was seen, or unseen but given up on.
    Blocked,
}

/// The answer.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum WayHypothesis {
    /// Obstacles seen close every way from the robot to the goal: no unseen floor could open one.
    Closed,
    /// A way exists if these unseen grid cells (indices, sorted) inside obstacle outlines are floor.
    Through(Vec<usize>),
}

/// Whether the robot at `start` could reach the disc of `tolerance` around `goal` if the unseen floor
/// inside obstacle outlines were free (see the module's doc). `seen(i)` says whether grid cell `i` was
/// seen; `open(i)` whether an unseen cell is still worth a look. Prisms the robot steps over (top
/// below `step_height`) or walks under (bottom at or above its height) are left out, as the validity
/// checker leaves them out.
pub fn unseen_way(
    grid: &ObstacleGrid,
    prisms: &[Prism],
    robot: RobotCylinder,
    step_height: f64,
    (start, goal, tolerance): (Point2<f64>, Point2<f64>, f64),
    seen: &dyn Fn(usize) -> bool,
    open: &dyn Fn(usize) -> bool,
) -> WayHypothesis {
    let geometry = grid.geometry();
    let kinds = cell_kinds(grid, prisms, robot, step_height, seen, open);
    let Ok(mut lattice) = Lattice::open(geometry, FACTOR) else {
        return WayHypothesis::Closed;
    };
    let (cols, rows) = (lattice.cols(), lattice.rows());
    let mut coarse = vec![Kind::Floor; cols * rows];
    for (i, kind) in kinds.iter().enumerate() {
        let (x, y) = (i % geometry.width() / FACTOR, i / geometry.width() / FACTOR);
        let c = &mut coarse[y * cols + x];
        *c = (*c).max(*kind);
    }
    // The robot's disc may not overlap anything blocked: grow the blocked cells by its radius less
    // half a lattice cell (the hypothesis errs towards a way, as a lattice cell's centre may lie half
    // a cell from the obstacle it holds).
    let reach = (robot.radius - lattice.cell_size() / 2.0).max(0.0);
    let blocked = dilate(&coarse, cols, rows, reach / lattice.cell_size());
    for y in 0..rows {
        for x in 0..cols {
            let k = y * cols + x;
            let weight = match (blocked[k], coarse[k]) {
                (true, _) => 0,
                (false, Kind::Guess) => GUESS_WEIGHT,
                _ => 1,
            };
            lattice.set_weight(LatticeCell::new(x as u32, y as u32), weight);
        }
    }
    // The robot stands where it is: nothing there blocks it.
    for y in 0..rows {
        for x in 0..cols {
            let cell = LatticeCell::new(x as u32, y as u32);
            if (lattice.centre(cell) - start).norm() <= robot.radius && !lattice.is_passable(cell) {
                lattice.set_weight(cell, 1);
            }
        }
    }
    let Ok(field) = lattice.distances(start) else {
        return WayHypothesis::Closed;
    };
    let mut best: Option<(u32, LatticeCell)> = None;
    for y in 0..rows {
        for x in 0..cols {
            let cell = LatticeCell::new(x as u32, y as u32);
            if (lattice.centre(cell) - goal).norm() > tolerance {
                continue;
            }
            if let Some(c) = field.cost(cell)
                && best.is_none_or(|(b, _)| c < b)
            {
                best = Some((c, cell));
            }
        }
    }
    let Some(path) = best.and_then(|(_, cell)| field.path_to(cell)) else {
        return WayHypothesis::Closed;
    };
    WayHypothesis::Through(guesses_along(grid, &kinds, &path, robot.radius))
}

/// Each grid cell's kind (see [`Kind`]).
fn cell_kinds(
    grid: &ObstacleGrid,
    prisms: &[Prism],
    robot: RobotCylinder,
    step_height: f64,
    seen: &dyn Fn(usize) -> bool,
    open: &dyn Fn(usize) -> bool,
) -> Vec<Kind> {
    let geometry = grid.geometry();
    let mut kinds: Vec<Kind> = grid
        .class_codes()
        .iter()
        .map(|&c| match CellClass::from_code(c) {
            Some(class) if class.is_obstacle() => Kind::Blocked,
            _ => Kind::Floor,
        })
        .collect();
    let blocks = |p: &Prism| p.z_min < robot.height && p.z_max > step_height;
    for prism in prisms.iter().filter(|p| blocks(p)) {
        let Some(first) = prism.footprint.first() else {
            continue;
        };
        let (lo, hi) = prism
            .footprint
            .iter()
            .fold((*first, *first), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
        let (Some(a), Some(b)) = (clamped_cell(grid, lo), clamped_cell(grid, hi)) else {
            continue;
        };
        for y in a.y..=b.y {
            for x in a.x..=b.x {
                let cell = CellIndex::new(x, y);
                let Some(i) = geometry.index(cell) else {
                    continue;
                };
                if !prism.contains_xy(&geometry.centre(cell)) {
                    continue;
                }
                let kind = if seen(i) || !open(i) {
                    Kind::Blocked
                } else {
                    Kind::Guess
                };
                kinds[i] = kinds[i].max(kind);
            }
        }
        // Its returns are where it certainly is.
        for (_, p, _) in prism.points.iter_valid() {
            let z = f64::from(p.z);
            if z <= step_height || z >= robot.height {
                continue;
            }
            let q = Point2::new(f64::from(p.x), f64::from(p.y));
            if let Some(i) = geometry.cell_of(q).and_then(|c| geometry.index(c)) {
                kinds[i] = Kind::Blocked;
            }
        }
    }
    kinds
}

/// The grid cell holding `p`, or the grid's cell nearest it when `p` lies outside.
fn clamped_cell(grid: &ObstacleGrid, p: Point2<f64>) -> Option<CellIndex> {
    let geometry = grid.geometry();
    let (o, r) = (geometry.origin(), geometry.resolution());
    let inner = |v: f64, lo: f64, n: usize| v.clamp(lo + r / 2.0, lo + (n as f64 - 0.5) * r);
    geometry.cell_of(Point2::new(
        inner(p.x, o.x, geometry.width()),
        inner(p.y, o.y, geometry.height()),
    ))
}

/// Lattice cells within `radius` (in cells) of a blocked one, blocked ones included.
fn dilate(kinds: &[Kind], cols: usize, rows: usize, radius: f64) -> Vec<bool> {
    let r = radius.floor() as isize;
    let stencil: Vec<(isize, isize)> = (-r..=r)
        .flat_map(|dy| (-r..=r).map(move |dx| (dx, dy)))
        .filter(|(dx, dy)| ((dx * dx + dy * dy) as f64) <= radius * radius)
        .collect();
    let mut out = vec![false; kinds.len()];
    for y in 0..rows as isize {
        for x in 0..cols as isize {
            if kinds[y as usize * cols + x as usize] != Kind::Blocked {
                continue;
            }
            for (dx, dy) in &stencil {
                let (u, v) = (x + dx, y + dy);
                if u >= 0 && v >= 0 && (u as usize) < cols && (v as usize) < rows {
                    out[v as usize * cols + u as usize] = true;
                }
            }
        }
    }
    out
}

/// The guessed grid cells within `radius` of the polyline `path`, sorted.
fn guesses_along(
    grid: &ObstacleGrid,
    kinds: &[Kind],
    path: &[Point2<f64>],
    radius: f64,
) -> Vec<usize> {
    let geometry = grid.geometry();
    let step = geometry.resolution();
    let mut out = Vec::new();
    let mut visit = |p: Point2<f64>| {
        let r = nalgebra::Vector2::repeat(radius);
        let (Some(a), Some(b)) = (clamped_cell(grid, p - r), clamped_cell(grid, p + r)) else {
            return;
        };
        for y in a.y..=b.y {
            for x in a.x..=b.x {
                let cell = CellIndex::new(x, y);
                if let Some(i) = geometry.index(cell)
                    && kinds[i] == Kind::Guess
                    && (geometry.centre(cell) - p).norm() <= radius
                {
                    out.push(i);
                }
            }
        }
    };
    if let [only] = path {
        visit(*only);
    }
    for w in path.windows(2) {
        let len = (w[1] - w[0]).norm();
        let n = (len / step).ceil().max(1.0) as usize;
        for k in 0..=n {
            visit(w[0] + (w[1] - w[0]) * (k as f64 / n as f64));
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}
