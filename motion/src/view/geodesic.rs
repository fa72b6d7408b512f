//! Least-cost walking distances over a lattice, and the paths that realise them.
//!
//! Dijkstra over the 8-neighbourhood with integer step costs — [`STRAIGHT`] (70) along an axis,
//! [`DIAGONAL`] (99) across, times the weight of the cell stepped into — in a bucket queue (Dial's
//! algorithm): costs come out in increasing order with no heap, each cell settled once. A diagonal
//! step needs both cells beside it open, so a path never cuts the corner of a blocked cell. With
//! weight 1 everywhere a cost of 70 is one lattice cell, and 99/70 is √2 to 0.01 % (the common
//! 14/10 is 1 % short, which a walking distance would carry); the ring of buckets is 128 long.

use nalgebra::Point2;

use crate::view::lattice::{Lattice, LatticeCell};

/// Cost of a step along an axis into a cell of weight 1.
pub const STRAIGHT: u32 = 70;
/// Cost of a diagonal step into a cell of weight 1 (70·√2 = 98.995 rounded).
pub const DIAGONAL: u32 = 99;

/// Costs from one start position to every lattice cell it can reach (or, for a search stopped
/// early, to every cell up to the cost it stopped at).
#[derive(Clone, Debug)]
pub struct DistanceField<'a> {
    lattice: &'a Lattice,
    start: Point2<f64>,
    start_cell: LatticeCell,
    /// Cost per padded index (`u32::MAX`: not reached); final up to `limit`.
    cost: Vec<u32>,
    /// The largest cost settled: every cell with a least cost up to it has it in `cost`.
    limit: u32,
}

/// The eight neighbours as (dx, dy), the axis steps first: a path walks back through the first
/// neighbour that realises a cost, so it prefers straight steps, deterministically.
const NEIGHBOURS: [(isize, isize); 8] = [
    (1, 0),
    (-1, 0),
    (0, 1),
    (0, -1),
    (1, 1),
    (-1, 1),
    (1, -1),
    (-1, -1),
];

impl<'a> DistanceField<'a> {
    /// Searches `lattice` from `start` (in `start_cell`). The start cell is entered whatever its
    /// weight (the robot is there); the search spreads only into open cells. `go_on(i, cost)` is
    /// called with each cell's padded index ([`Lattice::padded_index`]) as it is settled, in
    /// increasing cost; when it returns false the search stops there, and cells of higher cost
    /// read as not reached.
    pub(crate) fn search(
        lattice: &'a Lattice,
        start: Point2<f64>,
        start_cell: LatticeCell,
        mut go_on: impl FnMut(usize, u32) -> bool,
    ) -> Self {
        let (weights, w) = lattice.padded();
        let mut cost = vec![u32::MAX; weights.len()];
        let max_weight = u32::from(weights.iter().copied().max().unwrap_or(1).max(1));
        // Every pending cost lies within one step of the cost being settled, so a ring of buckets
        // longer than the largest step never wraps onto itself.
        let ring = ((DIAGONAL * max_weight + 1) as usize).next_power_of_two();
        let mask = ring - 1;
        let mut buckets: Vec<Vec<u32>> = vec![Vec::new(); ring];
        let Some(s) = lattice.padded_index(start_cell) else {
            return Self {
                lattice,
                start,
                start_cell,
                cost,
                limit: 0,
            };
        };
        cost[s] = 0;
        buckets[0].push(s as u32);
        let mut pending = 1usize;
        let mut d = 0u32;
        let mut current = Vec::new();
        let mut stopped = false;
        while pending > 0 && !stopped {
            let slot = d as usize & mask;
            std::mem::swap(&mut current, &mut buckets[slot]);
            for &p in &current {
                pending -= 1;
                let p = p as usize;
                if cost[p] != d {
                    continue; // settled cheaper already
                }
                if !go_on(p, d) {
                    stopped = true;
                    break;
                }
                // The border is blocked, so every neighbour of a cell settled here (never a
                // border cell) lies inside the padded array.
                let wt = |i: usize| weights.get(i).map_or(0, |&v| u32::from(v));
                let (east, west, north, south) = (wt(p + 1), wt(p - 1), wt(p + w), wt(p - w));
                // A diagonal step needs both cells beside it open.
                let diagonal = |i: usize, a: u32, b: u32| if a != 0 && b != 0 { wt(i) } else { 0 };
                let ne = diagonal(p + w + 1, north, east);
                let nw = diagonal(p + w - 1, north, west);
                let se = diagonal(p - w + 1, south, east);
                let sw = diagonal(p - w - 1, south, west);
                // One call per direction, unrolled: each comparison is its own branch, which a
                // wave spreading one way predicts well.
                let mut relax = |n: usize, weight: u32, step: u32| {
                    let nd = if weight != 0 {
                        d + step * weight
                    } else {
                        u32::MAX
                    };
                    if let Some(c) = cost.get_mut(n)
                        && nd < *c
                    {
                        *c = nd;
                        buckets[nd as usize & mask].push(n as u32);
                        pending += 1;
                    }
                };
                relax(p + 1, east, STRAIGHT);
                relax(p - 1, west, STRAIGHT);
                relax(p + w, north, STRAIGHT);
                relax(p - w, south, STRAIGHT);
                relax(p + w + 1, ne, DIAGONAL);
                relax(p + w - 1, nw, DIAGONAL);
                relax(p - w + 1, se, DIAGONAL);
                relax(p - w - 1, sw, DIAGONAL);
            }
            current.clear();
            std::mem::swap(&mut current, &mut buckets[slot]);
            if !stopped {
                d += 1;
            }
        }
        Self {
            lattice,
            start,
            start_cell,
            cost,
            // Stopped while settling cost d: every cost up to d is final (set from cells of lower
            // cost, all expanded); higher ones may not be.
            limit: if stopped { d } else { u32::MAX },
        }
    }

    /// The lattice searched.
    pub fn lattice(&self) -> &'a Lattice {
        self.lattice
    }

    /// The start position.
    pub fn start(&self) -> Point2<f64> {
        self.start
    }

    /// The start position's cell.
    pub fn start_cell(&self) -> LatticeCell {
        self.start_cell
    }

    /// The least cost from the start to `cell` (in [`STRAIGHT`] units per cell edge and weight),
    /// `None` where it cannot be reached.
    pub fn cost(&self, cell: LatticeCell) -> Option<u32> {
        let i = self.lattice.padded_index(cell)?;
        let c = self.cost[i];
        (c != u32::MAX && c <= self.limit).then_some(c)
    }

    /// The least cost to `cell` in metres (the cost over [`STRAIGHT`], times the cell size): on a
    /// lattice of weight-1 cells, the geodesic walking distance from the start cell's centre.
    pub fn distance(&self, cell: LatticeCell) -> Option<f64> {
        self.cost(cell)
            .map(|c| f64::from(c) / f64::from(STRAIGHT) * self.lattice.cell_size())
    }

    /// The waypoints of a least-cost path from the start to `cell`: the start position itself,
    /// then the centres of the cells where the path turns, then `cell`'s centre (only the start
    /// for the start cell). `None` where `cell` cannot be reached.
    pub fn path_to(&self, cell: LatticeCell) -> Option<Vec<Point2<f64>>> {
        let (weights, w) = self.lattice.padded();
        let w = w as isize;
        let mut p = self.lattice.padded_index(cell)?;
        self.cost(cell)?;
        let s = self.lattice.padded_index(self.start_cell)?;
        // Walk back: from each cell, to the first neighbour whose cost plus the step into this
        // cell is this cell's cost (one always is, as the search set it so).
        let mut back = vec![p];
        while p != s {
            let here = self.cost[p];
            let wp = u32::from(weights[p]).max(1);
            let mut found = None;
            for (k, &(dx, dy)) in NEIGHBOURS.iter().enumerate() {
                let q = p.wrapping_add_signed(-(dx + dy * w));
                let Some(&cq) = self.cost.get(q) else {
                    continue;
                };
                if cq == u32::MAX {
                    continue;
                }
                // The step q → p: a diagonal needs both cells beside it open.
                let step = if k < 4 {
                    STRAIGHT
                } else {
                    let side_x = q.wrapping_add_signed(dx);
                    let side_y = q.wrapping_add_signed(dy * w);
                    if weights[side_x] == 0 || weights[side_y] == 0 {
                        continue;
                    }
                    DIAGONAL
                };
                if cq.checked_add(step * wp) == Some(here) {
                    found = Some((q, (dx, dy)));
                    break;
                }
            }
            let (q, _) = found?;
            back.push(q);
            p = q;
        }
        back.reverse();
        // Keep the cells where the direction changes, and the last.
        let mut points = vec![self.start];
        for k in 1..back.len() {
            let turn = back.get(k + 1).is_none_or(|&next| {
                let (a, b, c) = (back[k - 1] as isize, back[k] as isize, next as isize);
                b - a != c - b
            });
            if turn {
                let c = self.lattice.cell_at_padded(back[k])?;
                points.push(self.lattice.centre(c));
            }
        }
        Some(points)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nudge_perception::grid::GridGeometry;

    fn lattice(w: usize, h: usize, blocked: &[(u32, u32)]) -> Lattice {
        let g = GridGeometry::with_cells(Point2::new(0.0, 0.0), w, h, 0.1).expect("grid");
        let mut l = Lattice::open(&g, 1).expect("lattice");
        for &(x, y) in blocked {
            l.set_weight(LatticeCell::new(x, y), 0);
        }
        l
    }

    #[test]
    fn costs_are_octile_distances_in_open_space() {
        // Invariant: with nothing blocked, the cost from a cell is 70·max + 29·min of the axis
        // offsets (octile), and the distance is that over 70 times the cell size.
        let l = lattice(30, 20, &[]);
        let f = l.distances(Point2::new(0.55, 0.35)).expect("inside");
        for y in 0..20u32 {
            for x in 0..30u32 {
                let (dx, dy) = ((x as i64 - 5).unsigned_abs(), (y as i64 - 3).unsigned_abs());
                let want = 70 * dx.max(dy) + 29 * dx.min(dy);
                assert_eq!(f.cost(LatticeCell::new(x, y)), Some(want as u32));
            }
        }
        let d = f.distance(LatticeCell::new(8, 3)).expect("reached");
        assert!((d - 0.3).abs() < 1e-12);
        assert_eq!(
            f.path_to(LatticeCell::new(5, 3)),
            Some(vec![Point2::new(0.55, 0.35)])
        );
    }

    #[test]
    fn paths_go_round_walls_and_never_cut_corners() {
        // Invariant: a wall with one gap makes the cost the detour's, the path's waypoints lie on
        // open cells joined by straight or diagonal runs, its length equals the cost, and a cell
        // walled off entirely is unreachable.
        let mut wall: Vec<(u32, u32)> = (0..19).map(|y| (10, y)).collect();
        wall.extend([
            (25, 5),
            (26, 5),
            (27, 5),
            (25, 7),
            (26, 7),
            (27, 7),
            (25, 6),
            (27, 6),
        ]);
        let mut l = lattice(30, 20, &wall);
        l.set_weight(LatticeCell::new(26, 6), 1); // enclosed: open but unreachable
        let f = l.distances(Point2::new(0.55, 0.55)).expect("inside");
        let goal = LatticeCell::new(15, 5);
        let cost = f.cost(goal).expect("reachable through the gap at y = 19");
        assert!(cost > 10 * STRAIGHT, "the straight line is walled: {cost}");
        let path = f.path_to(goal).expect("reachable");
        let length: f64 = path.windows(2).map(|s| (s[1] - s[0]).norm()).sum();
        // 99/70 against √2: the cost is the path's length to 0.01 %.
        let d = f.distance(goal).expect("reachable");
        assert!((length - d).abs() < 1e-4 * d, "{length} vs {d}");
        assert!(path.iter().any(|p| p.y > 1.9), "{path:?}");
        for s in path.windows(2) {
            let n = ((s[1] - s[0]).norm() / 0.01) as usize;
            for k in 0..=n {
                let p = s[0] + (s[1] - s[0]) * (k as f64 / n.max(1) as f64);
                let c = l.cell_of(p).expect("inside");
                assert!(l.is_passable(c) || c == f.start_cell(), "{p:?}");
            }
        }
        assert_eq!(f.cost(LatticeCell::new(26, 6)), None);
        assert_eq!(f.path_to(LatticeCell::new(26, 6)), None);
        // A diagonal between two blocked cells is not taken.
        let l = lattice(3, 3, &[(1, 0), (0, 1)]);
        let f = l.distances(Point2::new(0.05, 0.05)).expect("inside");
        assert_eq!(f.cost(LatticeCell::new(1, 1)), None);
    }

    #[test]
    fn weights_multiply_the_step_cost() {
        // Invariant: stepping into a cell of weight w costs w times as much, and the search goes
        // round an expensive strip when that is cheaper.
        let g = GridGeometry::with_cells(Point2::new(0.0, 0.0), 10, 3, 0.1).expect("grid");
        let mut weights = vec![1u8; 30];
        for y in 0..2 {
            weights[y * 10 + 5] = 9;
        }
        let l = Lattice::from_weights(&g, 1, &weights).expect("lattice");
        let f = l.distances(Point2::new(0.05, 0.05)).expect("inside");
        assert_eq!(f.cost(LatticeCell::new(5, 0)), Some(4 * 70 + 9 * 70));
        // Round the strip through row 2: (5, 2) at octile 3·70 + 2·99, then a diagonal and a
        // straight step.
        assert_eq!(
            f.cost(LatticeCell::new(6, 0)),
            Some(3 * 70 + 2 * 99 + 99 + 70)
        );
    }
}
