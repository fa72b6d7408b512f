//! Nearest neighbours in 3-D through kiddo 6's immutable k-d tree.

use std::num::NonZeroUsize;

use kiddo::{Eytzinger, KdTree, SquaredEuclidean, VecOfArenas};

/// Points per leaf. kiddo's default (32) suits large trees; the ICP's target has a few thousand
/// points and every nearest-neighbour query scans whole leaves, so smaller leaves scan less.
const BUCKET: usize = 16;

/// kiddo's immutable tree layout with smaller leaves.
type Tree = KdTree<f32, u32, Eytzinger, VecOfArenas<f32, u32, 3, BUCKET>, 3, BUCKET>;

/// An immutable k-d tree over 3-D points (indices are positions in the slice it was built from).
pub struct PointTree {
    tree: Option<Tree>,
    len: usize,
}

impl PointTree {
    /// Builds the tree. Points must be finite (the ICP filters them first); an empty slice or a build
    /// failure gives a tree that finds nothing.
    pub fn new(points: &[[f32; 3]]) -> Self {
        let tree = if points.is_empty() {
            None
        } else {
            Tree::new_from_slice(points).ok()
        };
        Self {
            tree,
            len: points.len(),
        }
    }

    /// Number of points in the tree.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when the tree holds no point.
    pub fn is_empty(&self) -> bool {
        self.tree.is_none()
    }

    /// The nearest point: (index, squared distance), or `None` for an empty tree.
    pub fn nearest(&self, q: &[f32; 3]) -> Option<(usize, f32)> {
        let tree = self.tree.as_ref()?;
        let hit = tree
            .query(q)
            .nearest_one::<SquaredEuclidean<f32>>()
            .execute();
        Some((hit.item as usize, hit.distance))
    }

    /// The `k` nearest points, nearest first: (index, squared distance).
    pub fn nearest_k(&self, q: &[f32; 3], k: usize) -> Vec<(usize, f32)> {
        let (Some(tree), Some(k)) = (self.tree.as_ref(), NonZeroUsize::new(k)) else {
            return Vec::new();
        };
        tree.query(q)
            .nearest_n::<SquaredEuclidean<f32>>(k)
            .execute()
            .into_iter()
            .map(|r| (r.item as usize, r.distance))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_and_k_nearest_agree_with_brute_force() {
        // Invariant: the tree returns the same neighbours as an exhaustive search.
        let pts: Vec<[f32; 3]> = (0..200)
            .map(|i| {
                let f = i as f32;
                [(f * 0.37).sin(), (f * 0.71).cos(), (f * 0.13).sin() * 0.5]
            })
            .collect();
        let tree = PointTree::new(&pts);
        let q = [0.1, -0.2, 0.05];
        let d =
            |p: &[f32; 3]| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2);
        let mut brute: Vec<(usize, f32)> = pts.iter().enumerate().map(|(i, p)| (i, d(p))).collect();
        brute.sort_by(|a, b| a.1.total_cmp(&b.1));
        assert_eq!(tree.nearest(&q).map(|h| h.0), Some(brute[0].0));
        let k: Vec<usize> = tree.nearest_k(&q, 5).iter().map(|h| h.0).collect();
        let b: Vec<usize> = brute[..5].iter().map(|h| h.0).collect();
        assert_eq!(k, b);
        assert!(PointTree::new(&[]).nearest(&q).is_none());
    }
}
