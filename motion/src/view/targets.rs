//! The grid cells a decision needs seen, each with a weight.

use nudge_perception::grid::CellIndex;

/// A set of grid cells to see, with weights (1 = ordinary; a cell worth twice as much counts
/// twice its area). Sorted row-major and deduplicated, so that iteration order never depends on
/// how the set was built.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Targets {
    cells: Vec<(CellIndex, f64)>,
}

impl Targets {
    /// The cells of `cells` with their weights. A cell listed twice keeps its larger weight; cells
    /// with a weight that is not finite and positive are dropped.
    pub fn new(cells: impl IntoIterator<Item = (CellIndex, f64)>) -> Self {
        let mut v: Vec<(CellIndex, f64)> = cells
            .into_iter()
            .filter(|(_, w)| w.is_finite() && *w > 0.0)
            .collect();
        // Row-major (y, then x), the grid's linear order; the larger weight first among equals.
        v.sort_by(|a, b| {
            (a.0.y, a.0.x)
                .cmp(&(b.0.y, b.0.x))
                .then(b.1.total_cmp(&a.1))
        });
        v.dedup_by_key(|(c, _)| *c);
        Self { cells: v }
    }

    /// The cells of `cells`, each of weight 1.
    pub fn uniform(cells: impl IntoIterator<Item = CellIndex>) -> Self {
        Self::new(cells.into_iter().map(|c| (c, 1.0)))
    }

    /// The cells and their weights, row-major.
    pub fn cells(&self) -> &[(CellIndex, f64)] {
        &self.cells
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.cells.len()
    }

    /// True when there is no cell.
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    /// The weight of `cell`, if it is a target.
    pub fn weight(&self, cell: CellIndex) -> Option<f64> {
        self.cells
            .binary_search_by(|(c, _)| (c.y, c.x).cmp(&(cell.y, cell.x)))
            .ok()
            .map(|k| self.cells[k].1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn targets_are_row_major_deduplicated_and_positive() {
        // Invariant: whatever the input order, cells come out row-major, once each with their
        // largest weight, and non-positive or non-finite weights are dropped.
        let c = CellIndex::new;
        let t = Targets::new([
            (c(3, 1), 1.0),
            (c(0, 2), 2.0),
            (c(3, 1), 4.0),
            (c(5, 0), 1.0),
            (c(1, 1), 0.0),
            (c(2, 1), f64::NAN),
        ]);
        assert_eq!(t.cells(), &[(c(5, 0), 1.0), (c(3, 1), 4.0), (c(0, 2), 2.0)]);
        assert_eq!(t.weight(c(3, 1)), Some(4.0));
        assert_eq!(t.weight(c(1, 1)), None);
        assert_eq!(Targets::uniform([c(1, 1), c(0, 0)]).len(), 2);
        assert!(Targets::default().is_empty());
    }
}
