//! Nearest neighbour among a tree's nodes: an incremental k-d tree with bucket leaves.
//!
//! A full leaf splits at the median of its points along its wider side, so the tree adapts to the
//! data even when points arrive in order along a line (as CONNECT adds them). Every node keeps its
//! subtree's bounding box, so queries far from all points (common early in RRT) prune whole
//! subtrees at once. Ties go to the lowest item, so the answer does not depend on the search order.

use nalgebra::Point2;

use crate::space::Bounds;

const NONE: u32 = u32::MAX;
/// Points per leaf before it splits.
const BUCKET: usize = 12;

#[derive(Clone, Debug)]
struct KdNode {
    /// Bounding box of this subtree: min x, min y, max x, max y.
    bbox: [f64; 4],
    axis: usize,
    split: f64,
    /// Children (below, at-or-above the split); `NONE` for a leaf.
    children: [u32; 2],
    /// A leaf's items.
    items: Vec<u32>,
    /// Their positions, kept beside them so a leaf scan reads one contiguous array.
    points: Vec<[f64; 2]>,
}

impl KdNode {
    fn leaf(items: Vec<u32>, points: &[[f64; 2]]) -> Self {
        let mut bbox = [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ];
        for &i in &items {
            grow(&mut bbox, &points[i as usize]);
        }
        Self {
            bbox,
            axis: 0,
            split: 0.0,
            children: [NONE, NONE],
            points: items.iter().map(|&i| points[i as usize]).collect(),
            items,
        }
    }

    /// Squared distance from `q` to this subtree's box (0 inside).
    fn bound(&self, q: &[f64; 2]) -> f64 {
        let dx = (self.bbox[0] - q[0]).max(0.0).max(q[0] - self.bbox[2]);
        let dy = (self.bbox[1] - q[1]).max(0.0).max(q[1] - self.bbox[3]);
        dx * dx + dy * dy
    }
}

fn grow(bbox: &mut [f64; 4], p: &[f64; 2]) {
    bbox[0] = bbox[0].min(p[0]);
    bbox[1] = bbox[1].min(p[1]);
    bbox[2] = bbox[2].max(p[0]);
    bbox[3] = bbox[3].max(p[1]);
}

/// A k-d tree over inserted positions, identified by the item given at insertion.
#[derive(Clone, Debug, Default)]
pub struct NearestIndex {
    points: Vec<[f64; 2]>,
    nodes: Vec<KdNode>,
    /// Search stack kept between queries to avoid an allocation per query.
    stack: Vec<(u32, f64)>,
}

impl NearestIndex {
    /// An empty index (a k-d tree needs no bounds; the parameter keeps constructors uniform).
    pub fn new(_bounds: &Bounds) -> Self {
        Self::default()
    }

    /// Records item `i` at `p`; items must be inserted as 0, 1, 2, …
    pub fn insert(&mut self, p: &Point2<f64>, i: usize) {
        let q = [p.x, p.y];
        debug_assert_eq!(i, self.points.len());
        self.points.push(q);
        let item = i as u32;
        if self.nodes.is_empty() {
            self.nodes.push(KdNode::leaf(vec![item], &self.points));
            return;
        }
        let mut at = 0usize;
        loop {
            let node = &mut self.nodes[at];
            grow(&mut node.bbox, &q);
            if node.children[0] == NONE {
                node.items.push(item);
                node.points.push(q);
                if node.items.len() > BUCKET {
                    self.split(at);
                }
                return;
            }
            at = node.children[usize::from(q[node.axis] >= node.split)] as usize;
        }
    }

    /// Splits leaf `at` at the median of its points along its wider side (the other side when
    /// all share one coordinate; never when all points coincide).
    fn split(&mut self, at: usize) {
        let bbox = self.nodes[at].bbox;
        let wider = usize::from(bbox[3] - bbox[1] > bbox[2] - bbox[0]);
        for axis in [wider, 1 - wider] {
            let mut items = self.nodes[at].items.clone();
            let points = &self.points;
            items.sort_by(|a, b| {
                points[*a as usize][axis]
                    .total_cmp(&points[*b as usize][axis])
                    .then(a.cmp(b))
            });
            let split = points[items[items.len() / 2] as usize][axis];
            let cut = items.partition_point(|&i| points[i as usize][axis] < split);
            if cut == 0 {
                continue;
            }
            let upper = items.split_off(cut);
            let below = self.nodes.len() as u32;
            self.nodes.push(KdNode::leaf(items, &self.points));
            self.nodes.push(KdNode::leaf(upper, &self.points));
            let node = &mut self.nodes[at];
            node.axis = axis;
            node.split = split;
            node.children = [below, below + 1];
            node.items = Vec::new();
            node.points = Vec::new();
            return;
        }
    }

    /// The item of the inserted point nearest to `q` (ties: lowest item); 0 when empty.
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
            let [c0, c1] = node.children;
            if c0 == NONE {
                for (&i, p) in node.items.iter().zip(&node.points) {
                    let (dx, dy) = (p[0] - q[0], p[1] - q[1]);
                    let d = dx * dx + dy * dy;
                    if d < best.0 || (d == best.0 && i < best.1) {
                        best = (d, i);
                    }
                }
                continue;
            }
            let b0 = self.nodes[c0 as usize].bound(&q);
            let b1 = self.nodes[c1 as usize].bound(&q);
            // Push the farther child first so the nearer is searched first.
            if b0 <= b1 {
                stack.push((c1, b1));
                stack.push((c0, b0));
            } else {
                stack.push((c0, b0));
                stack.push((c1, b1));
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
