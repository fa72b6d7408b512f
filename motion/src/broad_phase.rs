//! Broad phase: a uniform grid of boxes, so a query only looks at obstacles near it.
//!
//! Each box is listed in every cell it overlaps. A query visits the cells its own box overlaps and
//! reports each candidate once, without a "seen" set: a box is reported only from the first cell (in
//! row-major order) of the overlap between its cell range and the query's.

use nalgebra::Point2;

use crate::obstacle::Aabb;

/// A uniform grid over a set of boxes.
#[derive(Clone, Debug)]
pub struct Grid {
    extent: Aabb,
    cell: f64,
    nx: usize,
    ny: usize,
    starts: Vec<u32>,
    items: Vec<u32>,
    ranges: Vec<CellRange>,
    boxes: Vec<Aabb>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct CellRange {
    x0: usize,
    y0: usize,
    x1: usize,
    y1: usize,
}

/// Up to this many boxes a plain scan beats walking cells.
const SCAN_UP_TO: usize = 8;

/// Most cells per axis: beyond this the lists get long but memory stays bounded.
const MAX_CELLS_PER_AXIS: usize = 256;

impl Grid {
    /// A grid holding `boxes`, indexed by their position in the slice.
    pub fn new(boxes: &[Aabb]) -> Self {
        let extent = union(boxes);
        let size = extent.max - extent.min;
        let longest = size.x.max(size.y).max(1e-6);
        // About two cells per box along the longest side keeps lists short for evenly spread boxes.
        let per_axis = ((boxes.len() as f64).sqrt() * 2.0).ceil() as usize;
        let per_axis = per_axis.clamp(1, MAX_CELLS_PER_AXIS);
        let cell = longest / per_axis as f64;
        let nx = ((size.x / cell).ceil() as usize).clamp(1, MAX_CELLS_PER_AXIS);
        let ny = ((size.y / cell).ceil() as usize).clamp(1, MAX_CELLS_PER_AXIS);
        let mut grid = Self {
            extent,
            cell,
            nx,
            ny,
            starts: vec![0; nx * ny + 1],
            items: Vec::new(),
            ranges: Vec::with_capacity(boxes.len()),
            boxes: boxes.to_vec(),
        };
        grid.ranges = boxes.iter().map(|b| grid.range_of(b)).collect();
        let mut counts = vec![0u32; nx * ny];
        for r in &grid.ranges {
            for y in r.y0..=r.y1 {
                for x in r.x0..=r.x1 {
                    counts[y * nx + x] += 1;
                }
            }
        }
        for (i, c) in counts.iter().enumerate() {
            grid.starts[i + 1] = grid.starts[i] + c;
        }
        let mut fill: Vec<u32> = grid.starts[..nx * ny].to_vec();
        grid.items = vec![0; grid.starts[nx * ny] as usize];
        for (index, r) in grid.ranges.iter().enumerate() {
            for y in r.y0..=r.y1 {
                for x in r.x0..=r.x1 {
                    let slot = &mut fill[y * nx + x];
                    grid.items[*slot as usize] = index as u32;
                    *slot += 1;
                }
            }
        }
        grid
    }

    /// Calls `visit` once for every box whose cells overlap `query`'s, until it returns `true`;
    /// returns whether it did. Candidates may not overlap `query` itself: test them exactly.
    pub fn any(&self, query: &Aabb, mut visit: impl FnMut(usize) -> bool) -> bool {
        if self.ranges.is_empty() || !self.extent.overlaps(query) {
            return false;
        }
        if self.boxes.len() <= SCAN_UP_TO {
            return (0..self.boxes.len()).any(|i| self.boxes[i].overlaps(query) && visit(i));
        }
        let q = self.range_of(query);
        for y in q.y0..=q.y1 {
            for x in q.x0..=q.x1 {
                let cell = y * self.nx + x;
                let (s, e) = (self.starts[cell] as usize, self.starts[cell + 1] as usize);
                for &index in &self.items[s..e] {
                    let r = &self.ranges[index as usize];
                    // Report from the first shared cell only.
                    if x == r.x0.max(q.x0) && y == r.y0.max(q.y0) && visit(index as usize) {
                        return true;
                    }
                }
            }
        }
        false
    }

    /// Calls `visit` once for every box that may overlap `query`.
    pub fn for_each(&self, query: &Aabb, mut visit: impl FnMut(usize)) {
        self.any(query, |i| {
            visit(i);
            false
        });
    }

    /// Whether `p` is inside the grid's extent (outside it no box can contain `p`).
    pub fn covers(&self, p: &Point2<f64>) -> bool {
        self.extent.overlaps(&Aabb { min: *p, max: *p })
    }

    fn range_of(&self, b: &Aabb) -> CellRange {
        let (x0, y0) = self.cell_of(&b.min);
        let (x1, y1) = self.cell_of(&b.max);
        CellRange { x0, y0, x1, y1 }
    }

    fn cell_of(&self, p: &Point2<f64>) -> (usize, usize) {
        let fx = ((p.x - self.extent.min.x) / self.cell).floor();
        let fy = ((p.y - self.extent.min.y) / self.cell).floor();
        // Clamping is safe: a query is only used where it overlaps the extent.
        let x = if fx.is_nan() {
            0.0
        } else {
            fx.clamp(0.0, (self.nx - 1) as f64)
        };
        let y = if fy.is_nan() {
            0.0
        } else {
            fy.clamp(0.0, (self.ny - 1) as f64)
        };
        (x as usize, y as usize)
    }
}

fn union(boxes: &[Aabb]) -> Aabb {
    let mut it = boxes.iter();
    let Some(first) = it.next() else {
        return Aabb {
            min: Point2::origin(),
            max: Point2::origin(),
        };
    };
    it.fold(*first, |acc, b| Aabb {
        min: acc.min.inf(&b.min),
        max: acc.max.sup(&b.max),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn random_box(rng: &mut ChaCha8Rng) -> Aabb {
        let x: f64 = rng.random_range(0.0..10.0);
        let y: f64 = rng.random_range(0.0..10.0);
        let w: f64 = rng.random_range(0.0..2.0);
        let h: f64 = rng.random_range(0.0..2.0);
        Aabb {
            min: Point2::new(x, y),
            max: Point2::new(x + w, y + h),
        }
    }

    #[test]
    fn reports_every_overlapping_box_exactly_once() {
        // Invariant: a query sees every box that overlaps it, and no box twice.
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let boxes: Vec<Aabb> = (0..300).map(|_| random_box(&mut rng)).collect();
        let grid = Grid::new(&boxes);
        for _ in 0..200 {
            let q = random_box(&mut rng);
            let mut seen = Vec::new();
            grid.for_each(&q, |i| seen.push(i));
            let before = seen.len();
            seen.sort_unstable();
            seen.dedup();
            assert_eq!(before, seen.len(), "a box was reported twice");
            for (i, b) in boxes.iter().enumerate() {
                if b.overlaps(&q) {
                    assert!(seen.binary_search(&i).is_ok(), "box {i} missed");
                }
            }
        }
    }
}
