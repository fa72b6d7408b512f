//! Moving obstacles (Tamura 3.1): a return where the previous frame saw free space.

use super::super::class::CellClass;
use super::super::geometry::GridGeometry;
use super::super::layers::Layers;

/// Tamura 3.1: the cell holds a return now and was in the visible area V_{t−1} (and V_{t−2}) as free
/// space.
///
/// Guard (Chen 2.4's 8-neighbourhood, over two frames): nothing was returned in the cell's
/// 8-neighbourhood at t−1 or t−2. A ray grazing a surface crosses the surface's cells just before its
/// return; the next frame's return in such a cell is the same surface a cell along, not a new
/// obstacle. A real moving obstacle entering free space has had nothing returned next to its new cells
/// in the previous frames. (Longer memories were tried: they also silence an object that starts to
/// move from rest, whose first new cells lie next to where it rested.)
pub(crate) fn appeared_in_free_space(l: &Layers, g: &GridGeometry, i: usize, f: u32) -> bool {
    // Seen free at t−1 and t−2: one crossing is not yet free space (a surface edge-on is crossed by
    // one ray and returned by the next); free space stays free frame after frame.
    if l.class[i] != CellClass::Free as u8 || l.crossed(i, f) & 0b110 != 0b110 {
        return false;
    }
    let mut quiet = true;
    g.for_3x3(i, |j| quiet &= l.hits(j, f) & RECENT == 0);
    quiet
}

/// History bits of frames t−2 and t−1.
const RECENT: u8 = 0b110;

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
        l.record_crossing(i, 2, true);
        l.record_hit(i, 3);
        assert!(appeared_in_free_space(&l, &g, i, 3));
        let mut l = Layers::new(g.len());
        l.class[i] = CellClass::Free as u8;
        l.record_crossing(i, 2, true);
        l.record_hit(i, 3);
        assert!(
            !appeared_in_free_space(&l, &g, i, 3),
            "one crossing is not free space yet"
        );
    }

    #[test]
    fn a_return_next_to_last_frames_return_is_not_moving() {
        // Invariant: a return in the 8-neighbourhood at t−1 (a grazed wall) blocks the moving rule.
        let (g, mut l) = grid();
        let i = 55;
        l.class[i] = CellClass::Free as u8;
        l.record_crossing(i, 1, false);
        l.record_crossing(i, 2, false);
        l.record_hit(i + 11, 2);
        l.record_hit(i, 3);
        assert!(!appeared_in_free_space(&l, &g, i, 3));
    }

    #[test]
    fn a_return_near_a_return_two_frames_ago_is_not_moving() {
        // Invariant: a return next to the cell at t−2 blocks the moving rule; one at t−3 does not.
        let (g, mut l) = grid();
        let i = 55;
        l.class[i] = CellClass::Free as u8;
        l.record_hit(i - 1, 7);
        l.record_crossing(i, 7, true);
        l.record_crossing(i, 8, true);
        l.record_hit(i, 9);
        assert!(!appeared_in_free_space(&l, &g, i, 9));
        let mut l = Layers::new(g.len());
        l.class[i] = CellClass::Free as u8;
        l.record_hit(i - 1, 6);
        l.record_crossing(i, 7, true);
        l.record_crossing(i, 8, true);
        l.record_hit(i, 9);
        assert!(
            appeared_in_free_space(&l, &g, i, 9),
            "three frames ago is long enough"
        );
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
