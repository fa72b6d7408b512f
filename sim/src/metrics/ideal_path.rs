//! The ideal path of a run, the `L*` of SPL and of iGibson's path efficiency: the shortest way from
//! the robot's start into the goal disc in the true world with every movable object taken away, for
//! the robot's bounding cylinder. Found on a 5 cm grid by Dijkstra with 16 neighbours (the eight
//! of a cell and the eight knight's moves): its lengths exceed the true shortest path by at most
//! 2.7 % in open floor (the worst heading between two move directions, 1 − cos(13.3°)), and it is
//! never shorter, so an efficiency above 1 cannot come from the grid.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use nalgebra::Point2;

use crate::truth::{TrueClass, Truth};
use crate::world::World;

/// Grid cell of the search (m): the planner's flood-fill cell, small beside the robot's 0.35 m
/// radius, and coarse enough to search a 20 m flat in milliseconds.
pub const CELL: f64 = nudge_motion::reach::REACH_CELL;

/// The 16 moves: (dx, dy) in cells.
const MOVES: [(i32, i32); 16] = [
    (1, 0),
    (-1, 0),
    (0, 1),
    (0, -1),
    (1, 1),
    (1, -1),
    (-1, 1),
    (-1, -1),
    (2, 1),
    (2, -1),
    (-2, 1),
    (-2, -1),
    (1, 2),
    (1, -2),
    (-1, 2),
    (-1, -2),
];

/// Length of the ideal path (m), or `None` when the goal cannot be reached even with every movable
/// object gone (a room whose way is shut by static things: `no_path` is then the right answer).
pub fn ideal_path_length(
    world: &World,
    start: Point2<f64>,
    goal: Point2<f64>,
    tolerance: f64,
    radius: f64,
) -> Option<f64> {
    let grid = Clearance::of(world, radius);
    let start = grid.cell_of(start)?;
    let goal_cells = |c: (i32, i32)| (centre(c) - goal).norm() <= tolerance;
    shortest(&grid, start, goal_cells)
}

/// Where the robot's centre can get to from a start in the true world: every cell of the same
/// search as [`ideal_path_length`] that a way of free cells joins to the start's.
pub struct Reachable {
    grid: Clearance,
    reached: Vec<bool>,
}

impl Reachable {
    /// The cells the robot's cylinder of `radius` can reach from `start` in `world` now, movable
    /// objects taken as free floor (bolt them in the scenario to count them). `None` when the start
    /// lies outside the room.
    pub fn from(world: &World, start: Point2<f64>, radius: f64) -> Option<Self> {
        let grid = Clearance::of(world, radius);
        let start = grid.cell_of(start)?;
        let mut reached = vec![false; grid.free.len()];
        reached[grid.index(start)] = true;
        let mut stack = vec![start];
        while let Some(cell) = stack.pop() {
            for m in MOVES {
                let next = (cell.0 + m.0, cell.1 + m.1);
                if grid.move_free(cell, m) && !reached[grid.index(next)] {
                    reached[grid.index(next)] = true;
                    stack.push(next);
                }
            }
        }
        Some(Self { grid, reached })
    }

    /// Whether the robot's centre gets within `tolerance` of `p`: some reached cell's centre lies
    /// that close.
    pub fn near(&self, p: Point2<f64>, tolerance: f64) -> bool {
        let span = (tolerance / CELL).ceil() as i32;
        let Some((x, y)) = self.grid.cell_of(p) else {
            return false;
        };
        (-span..=span).any(|dy| {
            (-span..=span).any(|dx| {
                let c = (x + dx, y + dy);
                self.grid.inside(c)
                    && self.reached[self.grid.index(c)]
                    && (centre(c) - p).norm() <= tolerance
            })
        })
    }
}

/// Cells where the robot's centre may stand: its cylinder clear of walls and static objects.
struct Clearance {
    width: i32,
    height: i32,
    free: Vec<bool>,
}

impl Clearance {
    /// Rasterises the true world now (movable objects and people count as free floor), then keeps a
    /// cell only if no blocked cell and no wall lies within `radius` of its centre.
    fn of(world: &World, radius: f64) -> Self {
        let truth = Truth::new(world);
        let [w, h] = world.room_size();
        let (width, height) = ((w / CELL).ceil() as i32, (h / CELL).ceil() as i32);
        let blocked: Vec<bool> = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| truth.true_class_at(centre((x, y))) == TrueClass::Stationary)
            .collect();
        let reach = (radius / CELL).ceil() as i32;
        let mut free: Vec<bool> = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| {
                let c = centre((x, y));
                c.x >= radius && c.y >= radius && c.x <= w - radius && c.y <= h - radius
            })
            .collect();
        // A blocked cell's centre within the radius plus half a cell's diagonal (the cell's own
        // extent) of a centre takes that centre away; the offsets looked at reach `reach` cells each
        // way, so along the axes the radius itself is the bound.
        let limit = radius + CELL * std::f64::consts::FRAC_1_SQRT_2;
        for y in 0..height {
            for x in 0..width {
                if !blocked[(y * width + x) as usize] {
                    continue;
                }
                for dy in -reach..=reach {
                    for dx in -reach..=reach {
                        let (nx, ny) = (x + dx, y + dy);
                        if nx < 0 || ny < 0 || nx >= width || ny >= height {
                            continue;
                        }
                        if f64::from(dx).hypot(f64::from(dy)) * CELL <= limit {
                            free[(ny * width + nx) as usize] = false;
                        }
                    }
                }
            }
        }
        Self {
            width,
            height,
            free,
        }
    }

    fn cell_of(&self, p: Point2<f64>) -> Option<(i32, i32)> {
        let c = ((p.x / CELL).floor() as i32, (p.y / CELL).floor() as i32);
        self.inside(c).then_some(c)
    }

    fn inside(&self, (x, y): (i32, i32)) -> bool {
        x >= 0 && y >= 0 && x < self.width && y < self.height
    }

    fn index(&self, (x, y): (i32, i32)) -> usize {
        (y * self.width + x) as usize
    }

    fn is_free(&self, c: (i32, i32)) -> bool {
        self.inside(c) && self.free[self.index(c)]
    }

    /// Whether the move from `c` by `(dx, dy)` stays on free cells: its end, and for a diagonal or
    /// knight's move the cells it cuts through.
    fn move_free(&self, (x, y): (i32, i32), (dx, dy): (i32, i32)) -> bool {
        let end = (x + dx, y + dy);
        if !self.is_free(end) {
            return false;
        }
        match (dx.abs(), dy.abs()) {
            (1, 1) => self.is_free((x + dx, y)) && self.is_free((x, y + dy)),
            (2, 1) => self.is_free((x + dx.signum(), y)) && self.is_free((x + dx.signum(), y + dy)),
            (1, 2) => self.is_free((x, y + dy.signum())) && self.is_free((x + dx, y + dy.signum())),
            _ => true,
        }
    }
}

/// The centre of cell `(x, y)` on the floor (m).
fn centre((x, y): (i32, i32)) -> Point2<f64> {
    Point2::new((f64::from(x) + 0.5) * CELL, (f64::from(y) + 0.5) * CELL)
}

/// Dijkstra from `start` (taken as free: the robot stands there) to the first cell `goal` accepts.
fn shortest(grid: &Clearance, start: (i32, i32), goal: impl Fn((i32, i32)) -> bool) -> Option<f64> {
    let mut best = vec![f64::INFINITY; grid.free.len()];
    let mut queue = BinaryHeap::new();
    best[grid.index(start)] = 0.0;
    // Costs in whole micrometres keep the heap's order total and the result the same on every
    // machine.
    queue.push(Reverse((0_u64, start)));
    while let Some(Reverse((cost, cell))) = queue.pop() {
        let length = cost as f64 * 1.0e-6;
        if length > best[grid.index(cell)] {
            continue;
        }
        if goal(cell) {
            return Some(length);
        }
        for m in MOVES {
            if !grid.move_free(cell, m) {
                continue;
            }
            let next = (cell.0 + m.0, cell.1 + m.1);
            let step = f64::from(m.0).hypot(f64::from(m.1)) * CELL;
            let through = ((length + step) * 1.0e6).round();
            let i = grid.index(next);
            if through * 1.0e-6 < best[i] {
                best[i] = through * 1.0e-6;
                queue.push(Reverse((through as u64, next)));
            }
        }
    }
    None
}
