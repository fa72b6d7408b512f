//! Nearest neighbour among a tree's nodes: an incremental 2-d tree (no rebalancing; RRT nodes
//! arrive in random order, which keeps it shallow) whose nodes also keep their subtree's bounding
//! box, so queries far from every node (common early in RRT) prune whole subtrees at once.
//!
//! Ties go to the lowest node index, so the answer does not depend on the search order.

use nalgebra::Point2;

use crate::space::Bounds;

const NONE: u32 = u32::MAX;

#[derive(Clone, Copy, Debug)]
struct KdNode {
    point: [f64; 2],
    item: u32,
    children: [u32; 2],
    /// Bounding box of this subtree: min x, min y, max x, max y.
    bbox: [f64; 4],
}

impl KdNode {
    /// Squared distance from `q` to this subtree's box (0 inside).
    fn bound(&self, q: &[f64; 2]) -> f64 {
        let dx = (self.bbox[0] - q[0]).max(0.0).max(q[0] - self.bbox[2]);
        let dy = (self.bbox[1] - q[1]).max(0.0).max(q[1] - self.bbox[3]);
        dx * dx + dy * dy
    }
}

/// A 2-d tree over inserted positions.
#[derive(Clone, Debug, Default)]
pub struct NearestIndex {
    nodes: Vec<KdNode>,
    /// Search stack kept between queries to avoid an allocation per query.
    stack: Vec<(u32, f64)>,
}

impl NearestIndex {
    /// An empty index (a k-d tree needs no bounds; the parameter keeps constructors uniform).
    pub fn new(_bounds: &Bounds) -> Self {
        Self::default()
    }

    /// Records node `i` at `p`.
    pub fn insert(&mut self, p: &Point2<f64>, i: usize) {
        let new = self.nodes.len() as u32;
        self.nodes.push(KdNode {
            point: [p.x, p.y],
            item: i as u32,
            children: [NONE, NONE],
            bbox: [p.x, p.y, p.x, p.y],
        });
        if new == 0 {
            return;
        }
        let mut at = 0usize;
        let mut axis = 0;
        loop {
            let node = &mut self.nodes[at];
            node.bbox = [
                node.bbox[0].min(p.x),
                node.bbox[1].min(p.y),
                node.bbox[2].max(p.x),
                node.bbox[3].max(p.y),
            ];
            let side = usize::from(p[axis] >= node.point[axis]);
            let next = node.children[side];
            if next == NONE {
                node.children[side] = new;
                return;
            }
            at = next as usize;
            axis ^= 1;
        }
    }

    /// The item of the inserted node nearest to `q` (ties: lowest item); 0 when empty.
    pub fn nearest(&mut self, q: &Point2<f64>) -> usize {
        if self.nodes.is_empty() {
            return 0;
        }
        let q = [q.x, q.y];
        let mut best = (f64::INFINITY, u32::MAX);
        let mut stack = std::mem::take(&mut self.stack);
        stack.clear();
        stack.push((0, 0.0));
        while let Some((at, bound)) = stack.pop() {
            if bound > best.0 {
                continue;
            }
            let node = &self.nodes[at as usize];
            let dx = node.point[0] - q[0];
            let dy = node.point[1] - q[1];
            let d = dx * dx + dy * dy;
            if d < best.0 || (d == best.0 && node.item < best.1) {
                best = (d, node.item);
            }
            let [c0, c1] = node.children;
            let b0 = (c0 != NONE).then(|| self.nodes[c0 as usize].bound(&q));
            let b1 = (c1 != NONE).then(|| self.nodes[c1 as usize].bound(&q));
            // Push the farther child first so the nearer is searched first.
            match (b0, b1) {
                (Some(b0), Some(b1)) if b0 <= b1 => {
                    stack.push((c1, b1));
                    stack.push((c0, b0));
                }
                (Some(b0), Some(b1)) => {
                    stack.push((c0, b0));
                    stack.push((c1, b1));
                }
                (Some(b0), None) => stack.push((c0, b0)),
                (None, Some(b1)) => stack.push((c1, b1)),
                (None, None) => {}
            }
        }
        self.stack = stack;
        best.1 as usize
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
            assert_eq!(index.nearest(&q), scan);
        }
    }
}
