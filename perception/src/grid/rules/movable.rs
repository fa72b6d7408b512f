//! Movable obstacles (Tamura 3.2): addition, retention and deletion.

use super::super::class::CellClass;
use super::super::geometry::GridGeometry;
use super::super::layers::Layers;

/// Retention (Tamura 3.2.2): a return in a movable cell stays movable; so does a return that has been
/// in place for three frames (`rested`) next to a movable cell (a new face of the same object coming
/// into view). Requiring rest for the neighbour case stops a movable label from riding along with an
/// object that is being carried away.
pub(crate) fn retained(
    l: &Layers,
    g: &GridGeometry,
    i: usize,
    class: CellClass,
    rested: bool,
) -> bool {
    if class == CellClass::Movable {
        return true;
    }
    if !rested || class == CellClass::Stationary {
        return false;
    }
    let mut near = false;
    g.for_3x3(i, |j| near |= l.class[j] == CellClass::Movable as u8);
    near
}

/// Addition (Tamura 3.2.1): a return near last frame's moving returns, in place for three frames,
/// rests — it is movable unless other motion (`motion`, grid coordinates of this frame's moving
/// returns) lies within `radius_cells`, which means the moving obstacle is still there and moving.
pub(crate) fn added(cell: (i32, i32), motion: &[(i32, i32)], radius_cells: f64) -> bool {
    let r2 = radius_cells * radius_cells;
    !motion.iter().any(|&(x, y)| {
        let (dx, dy) = (f64::from(x - cell.0), f64::from(y - cell.1));
        dx * dx + dy * dy <= r2
    })
}

/// Deletion (Tamura 3.2.3): a movable cell in the visible area V_t, crossed at least the clear margin
/// before the ray's return, is free again: the movable obstacle has gone.
pub(crate) fn deleted(l: &Layers, i: usize, f: u32) -> bool {
    l.crossed_far(i, f) & 1 == 1 && l.hits(i, f) & 1 == 0
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point2;

    fn grid() -> (GridGeometry, Layers) {
        let g = GridGeometry::with_cells(Point2::new(0.0, 0.0), 10, 10, 0.05).expect("valid");
        let l = Layers::new(g.len());
        (g, l)
    }

    #[test]
    fn retention_keeps_movable_and_spreads_only_to_resting_neighbours() {
        // Invariant: movable stays movable; a neighbour joins only when at rest, never a stationary one.
        let (g, mut l) = grid();
        l.class[44] = CellClass::Movable as u8;
        assert!(retained(&l, &g, 44, CellClass::Movable, false));
        assert!(retained(&l, &g, 45, CellClass::Unknown, true));
        assert!(!retained(&l, &g, 45, CellClass::Unknown, false));
        assert!(!retained(&l, &g, 45, CellClass::Stationary, true));
        assert!(!retained(&l, &g, 47, CellClass::Unknown, true));
    }

    #[test]
    fn addition_needs_no_motion_nearby() {
        // Invariant: a resting return is added as movable only with no moving return within the radius.
        assert!(added((5, 5), &[], 6.0));
        assert!(added((5, 5), &[(12, 5)], 6.0));
        assert!(!added((5, 5), &[(11, 5)], 6.0));
    }

    #[test]
    fn deletion_needs_a_far_crossing_and_no_return() {
        // Invariant: only a crossing well before the return, with no return in the cell, deletes.
        let mut l = Layers::new(1);
        l.record_crossing(0, 4, false);
        assert!(!deleted(&l, 0, 4));
        l.record_crossing(0, 5, true);
        assert!(deleted(&l, 0, 5));
        l.record_hit(0, 5);
        assert!(!deleted(&l, 0, 5));
    }
}
