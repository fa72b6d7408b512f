//! Stationary obstacles (Tamura 3.3, Chen 2.3–2.4): temporarily stationary at t, t−1 and t−2.

use super::super::geometry::GridGeometry;
use super::super::layers::Layers;

/// Tamura eqs. (8)–(11) on the grid, with Chen's 8-neighbour rule against localisation noise: some
/// cell of the 3 × 3 block around `i` held a temporarily stationary return at t−1, and some at t−2.
/// (The return at t is the one being classified.)
pub(crate) fn three_frames(l: &Layers, g: &GridGeometry, i: usize, f: u32) -> bool {
    let mut seen = 0u8;
    g.for_3x3(i, |j| seen |= l.ts(j, f));
    seen & 0b110 == 0b110
}

/// "In place" test of the movable rules, after Chen's three maps on raw returns: some return in the
/// 3 × 3 block in at least two of the frames t−1, t−2, t−3. (Two of three rather than both of t−1 and
/// t−2, so that a surface returned only every other frame — seen edge-on — still counts as in place.)
pub(crate) fn returned_around(l: &Layers, g: &GridGeometry, i: usize, f: u32) -> bool {
    let mut seen = 0u8;
    g.for_3x3(i, |j| seen |= l.hits(j, f));
    (seen & 0b1110).count_ones() >= 2
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

    fn ts_hit(l: &mut Layers, i: usize, f: u32) {
        l.record_hit(i, f);
        l.mark_ts(i);
    }

    #[test]
    fn three_frames_in_the_same_cell_is_stationary() {
        // Invariant: temporarily stationary at t−2 and t−1 in the cell ⇒ the return at t is stationary.
        let (g, mut l) = grid();
        ts_hit(&mut l, 44, 1);
        ts_hit(&mut l, 44, 2);
        l.record_hit(44, 3);
        assert!(three_frames(&l, &g, 44, 3));
    }

    #[test]
    fn eight_neighbours_absorb_one_cell_of_jitter() {
        // Invariant (Chen 2.4): returns wandering by one cell between frames still count.
        let (g, mut l) = grid();
        ts_hit(&mut l, 43, 1);
        ts_hit(&mut l, 55, 2);
        l.record_hit(44, 3);
        assert!(three_frames(&l, &g, 44, 3));
        // Two cells away is not the neighbourhood.
        let (g, mut l) = (g, Layers::new(100));
        ts_hit(&mut l, 42, 1);
        ts_hit(&mut l, 44, 2);
        l.record_hit(44, 3);
        assert!(!three_frames(&l, &g, 44, 3));
    }

    #[test]
    fn a_gap_frame_or_a_moving_return_breaks_the_chain() {
        // Invariant: missing t−1 (or t−1's return not temporarily stationary) ⇒ not stationary.
        let (g, mut l) = grid();
        ts_hit(&mut l, 44, 1);
        l.record_hit(44, 3);
        assert!(!three_frames(&l, &g, 44, 3));
        let mut l = Layers::new(100);
        ts_hit(&mut l, 44, 1);
        l.record_hit(44, 2); // returned but classified moving: no ts bit
        l.record_hit(44, 3);
        assert!(!three_frames(&l, &g, 44, 3));
        assert!(returned_around(&l, &g, 44, 3));
    }
}
