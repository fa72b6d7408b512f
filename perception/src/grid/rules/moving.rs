//! Moving obstacles (Tamura 3.1): a return where the previous frame saw free space.

use super::super::class::CellClass;
use super::super::geometry::GridGeometry;
use super::super::layers::Layers;

/// Tamura 3.1: the cell holds a return now and was in the visible area V_{t−1} as free space.
///
/// Guard (Chen 2.4's 8-neighbourhood): nothing was returned in the cell's 8-neighbourhood at t−1. A
/// ray grazing a wall crosses wall cells just before its return; the next frame's return in such a cell
/// is the same wall, one cell along, not a new obstacle. A real moving obstacle entering free space has
/// no return next to its new cells in the previous frame.
pub(crate) fn appeared_in_free_space(l: &Layers, g: &GridGeometry, i: usize, f: u32) -> bool {
    if l.class[i] != CellClass::Free as u8 || l.crossed(i, f) & 0b10 == 0 {
        return false;
    }
    let mut quiet = true;
    g.for_3x3(i, |j| quiet &= l.hits(j, f) & 0b10 == 0);
    quiet
}

/// The cell lies within `moving_step` of a cell that was moving at t−1 (stamped at the start of the
/// frame from the previous frame's moving cells).
pub(crate) fn near_previous_motion(l: &Layers, i: usize, f: u32) -> bool {
    l.near_moving[i] == f
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
    fn a_return_in_last_frames_free_space_is_moving() {
        // Invariant: free at t−1 (crossed, nothing returned around) + return at t ⇒ moving.
        let (g, mut l) = grid();
        let i = 55;
        l.class[i] = CellClass::Free as u8;
        l.record_crossing(i, 1, true);
        l.record_hit(i, 2);
        assert!(appeared_in_free_space(&l, &g, i, 2));
    }

    #[test]
    fn a_return_next_to_last_frames_return_is_not_moving() {
        // Invariant: a return in the 8-neighbourhood at t−1 (a grazed wall) blocks the moving rule.
        let (g, mut l) = grid();
        let i = 55;
        l.class[i] = CellClass::Free as u8;
        l.record_crossing(i, 1, false);
        l.record_hit(i + 11, 1);
        l.record_hit(i, 2);
        assert!(!appeared_in_free_space(&l, &g, i, 2));
    }

    #[test]
    fn free_space_seen_only_long_ago_is_not_last_frames_visible_area() {
        // Invariant: only V_{t−1} counts; a cell crossed at t−2 but not t−1 is not moving.
        let (g, mut l) = grid();
        let i = 55;
        l.class[i] = CellClass::Free as u8;
        l.record_crossing(i, 1, true);
        l.record_hit(i, 3);
        assert!(!appeared_in_free_space(&l, &g, i, 3));
        // And a cell that was never free (unknown) is not moving either.
        l.class[i] = CellClass::Unknown as u8;
        l.record_crossing(i, 2, true);
        assert!(!appeared_in_free_space(&l, &g, i, 3));
    }
}
