//! Nearest neighbour among a tree's nodes: a uniform bucket grid searched ring by ring.
//!
//! Ties go to the lowest node index, so the answer does not depend on the search order.

use nalgebra::Point2;

use crate::space::Bounds;

/// Below this many nodes a plain scan is faster than the grid.
const SCAN_BELOW: usize = 48;
/// Cells along the longer side of the bounds.
const CELLS: usize = 48;

/// A bucket grid over the sampling bounds.
#[derive(Clone, Debug)]
pub struct NearestIndex {
    min: Point2<f64>,
    cell: f64,
    nx: usize,
    ny: usize,
    buckets: Vec<Vec<u32>>,
    count: usize,
}

impl NearestIndex {
    /// An empty index over `bounds`.
    pub fn new(bounds: &Bounds) -> Self {
        let size = bounds.size();
        let cell = size.x.max(size.y) / CELLS as f64;
        let nx = ((size.x / cell).ceil() as usize).clamp(1, CELLS);
        let ny = ((size.y / cell).ceil() as usize).clamp(1, CELLS);
        Self {
            min: bounds.min(),
            cell,
            nx,
            ny,
            buckets: vec![Vec::new(); nx * ny],
            count: 0,
        }
    }

    /// Records node `i` at `p`.
    pub fn insert(&mut self, p: &Point2<f64>, i: usize) {
        let (x, y) = self.cell_of(p);
        self.buckets[y * self.nx + x].push(i as u32);
        self.count += 1;
    }

    /// The index of the node of `points` nearest to `q` (ties: lowest index); `points` must be the
    /// positions inserted, by index, and not empty.
    pub fn nearest(&self, q: &Point2<f64>, points: &[Point2<f64>]) -> usize {
        let better =
            |d: f64, i: usize, best: (f64, usize)| d < best.0 || (d == best.0 && i < best.1);
        if self.count < SCAN_BELOW {
            let mut best = (f64::INFINITY, 0);
            for (i, p) in points.iter().enumerate() {
                let d = (p - q).norm_squared();
                if better(d, i, best) {
                    best = (d, i);
                }
            }
            return best.1;
        }
        let (cx, cy) = self.cell_of(q);
        let mut best = (f64::INFINITY, 0usize);
        let max_ring = self.nx.max(self.ny);
        for ring in 0..=max_ring {
            // Every point in ring k is at least (k - 1) cells away from q.
            let reach = (ring as f64 - 1.0).max(0.0) * self.cell;
            if reach * reach > best.0 {
                break;
            }
            self.for_ring(cx, cy, ring, |bucket| {
                for &i in bucket {
                    let i = i as usize;
                    let d = (points[i] - q).norm_squared();
                    if better(d, i, best) {
                        best = (d, i);
                    }
                }
            });
        }
        best.1
    }

    fn for_ring(&self, cx: usize, cy: usize, ring: usize, mut visit: impl FnMut(&[u32])) {
        let (cx, cy, r) = (cx as isize, cy as isize, ring as isize);
        let (nx, ny) = (self.nx as isize, self.ny as isize);
        let mut cell = |x: isize, y: isize| {
            if x >= 0 && y >= 0 && x < nx && y < ny {
                visit(&self.buckets[(y * nx + x) as usize]);
            }
        };
        if r == 0 {
            cell(cx, cy);
            return;
        }
        for x in (cx - r)..=(cx + r) {
            cell(x, cy - r);
            cell(x, cy + r);
        }
        for y in (cy - r + 1)..=(cy + r - 1) {
            cell(cx - r, y);
            cell(cx + r, y);
        }
    }

    fn cell_of(&self, p: &Point2<f64>) -> (usize, usize) {
        let fx = ((p.x - self.min.x) / self.cell).floor();
        let fy = ((p.y - self.min.y) / self.cell).floor();
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

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn matches_a_linear_scan() {
        // Invariant: the grid answers exactly what a full scan answers, ties to the lowest index.
        let bounds = Bounds::new(Point2::new(0.0, 0.0), Point2::new(10.0, 4.0)).expect("bounds");
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut index = NearestIndex::new(&bounds);
        let mut points = Vec::new();
        for i in 0..500 {
            // Quantised so that exact ties happen.
            let p = Point2::new(
                (rng.random_range(0.0..10.0_f64) * 4.0).round() / 4.0,
                (rng.random_range(0.0..4.0_f64) * 4.0).round() / 4.0,
            );
            points.push(p);
            index.insert(&p, i);
            let q = bounds.sample(&mut rng);
            let scan = points
                .iter()
                .enumerate()
                .min_by(|a, b| {
                    let da = (a.1 - q).norm_squared();
                    let db = (b.1 - q).norm_squared();
                    da.total_cmp(&db).then(a.0.cmp(&b.0))
                })
                .map(|(i, _)| i)
                .expect("not empty");
            assert_eq!(index.nearest(&q, &points), scan);
        }
    }
}
