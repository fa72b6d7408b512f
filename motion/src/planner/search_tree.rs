//! The trees a planner grew, as plain edges: OMPL's `PlannerData`, for recordings and pictures.

use nalgebra::Point2;

use super::Tree;

/// Every edge (parent, child) of the trees one solve grew, in the order the nodes were added.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SearchTree {
    /// Edges from a node's parent to the node (map frame, m).
    pub edges: Vec<[Point2<f64>; 2]>,
}

impl SearchTree {
    /// The edges of `trees`, tree by tree.
    pub(crate) fn of(trees: &[Tree]) -> Self {
        Self {
            edges: trees.iter().flat_map(Tree::edges).collect(),
        }
    }

    /// Whether the search grew nothing beyond its roots.
    pub fn is_empty(&self) -> bool {
        self.edges.is_empty()
    }
}
