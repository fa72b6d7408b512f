//! Clearing obstacles that are seen through: when a stationary (or pushed) cell becomes free.

use super::super::geometry::GridGeometry;
use super::super::layers::Layers;

/// A stationary or actively marked cell is cleared when it was crossed well before the ray's return in
/// this frame and the previous one, and nothing was returned in its 8-neighbourhood in either frame.
/// Grazing rays cross wall cells just before their return (never "well before"), so walls stay walls;
/// a removed object, seen through twice, goes.
pub(crate) fn cleared(l: &Layers, g: &GridGeometry, i: usize, f: u32) -> bool {
    if l.crossed_far_in_frames(i, f, 0b11) != 0b11 {
        return false;
    }
    let mut quiet = true;
    g.for_3x3(i, |j| quiet &= l.hits(j, f) & 0b11 == 0);
    quiet
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::layers::Crossing;
    use nalgebra::Point2;

    #[test]
    fn two_far_crossings_with_nothing_around_clear() {
        // Invariant: cleared iff crossed far at t and t−1 and no return in the 3×3 block at t or t−1.
        let g = GridGeometry::with_cells(Point2::new(0.0, 0.0), 10, 10, 0.05).expect("valid");
        let mut l = Layers::new(g.len());
        l.record_crossing(44, 1, Crossing::Far);
        assert!(!cleared(&l, &g, 44, 1));
        l.record_crossing(44, 2, Crossing::Far);
        assert!(cleared(&l, &g, 44, 2));
        l.record_hit(45, 2);
        assert!(!cleared(&l, &g, 44, 2));
        let mut l = Layers::new(g.len());
        l.record_crossing(44, 1, Crossing::Free);
        l.record_crossing(44, 2, Crossing::Far);
        assert!(!cleared(&l, &g, 44, 2), "a near crossing does not count");
    }
}
