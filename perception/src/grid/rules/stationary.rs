//! Stationary obstacles (Tamura 3.3, Chen 2.3–2.4): temporarily stationary at t, t−1 and t−2.

use super::super::geometry::GridGeometry;
use super::super::layers::Layers;

/// What the 3 × 3 block around a return says about whether it is in place.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct InPlace {
    /// The "in place" test of the movable rules, after Chen's three maps on raw returns: some return
    /// in the block in at least two of the frames t−1, t−2, t−3. (Two of three rather than both of
    /// t−1 and t−2, so that a surface returned only every other frame — seen edge-on — still counts
    /// as in place.)
    pub rested: bool,
    /// Tamura eqs. (8)–(11) on the grid, with Chen's 8-neighbour rule against localisation noise:
    /// some cell of the block held a temporarily stationary return at t−1, and some at t−2. (The
    /// return at t is the one being classified.)
    pub three_frames: bool,
}

/// Both tests of [`InPlace`] for a return at `i` in frame `f`, from one pass over the block that
/// reads each cell's returns once, its own row first, and stops as soon as both hold: a surface in
/// place has returned into the return's own row of the block frame after frame (nine returns in ten
/// in an office scan stop there).
pub(crate) fn in_place(l: &Layers, g: &GridGeometry, i: usize, f: u32) -> InPlace {
    let settled = |hits: u8, ts: u8| InPlace {
        rested: (hits & 0b1110).count_ones() >= 2,
        three_frames: ts & 0b110 == 0b110,
    };
    let (w, h) = (g.width(), g.height());
    let (x, y) = (i % w, i / w);
    let (x0, x1) = (x.saturating_sub(1), (x + 1).min(w - 1));
    // The block's rows: own, below, above (those in the grid).
    let rows = [Some(y), y.checked_sub(1), Some(y + 1)];
    let (mut hits, mut ts) = (0u8, 0u8);
    for yy in rows.into_iter().flatten().filter(|&yy| yy < h) {
        for j in yy * w + x0..=yy * w + x1 {
            hits |= l.hits(j, f);
            ts |= l.ts(j, f);
        }
        let p = settled(hits, ts);
        if p.rested && p.three_frames {
            return p;
        }
    }
    settled(hits, ts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point2;

    fn three_frames(l: &Layers, g: &GridGeometry, i: usize, f: u32) -> bool {
        in_place(l, g, i, f).three_frames
    }

    fn returned_around(l: &Layers, g: &GridGeometry, i: usize, f: u32) -> bool {
        in_place(l, g, i, f).rested
    }

    /// [`InPlace::three_frames`] as first written: the whole block, every time.
    fn three_frames_reference(l: &Layers, g: &GridGeometry, i: usize, f: u32) -> bool {
        let mut seen = 0u8;
        g.for_3x3(i, |j| seen |= l.ts(j, f));
        seen & 0b110 == 0b110
    }

    /// [`InPlace::rested`] as first written.
    fn returned_around_reference(l: &Layers, g: &GridGeometry, i: usize, f: u32) -> bool {
        let mut seen = 0u8;
        g.for_3x3(i, |j| seen |= l.hits(j, f));
        (seen & 0b1110).count_ones() >= 2
    }

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

    #[test]
    fn the_one_pass_test_agrees_with_both_tests() {
        // Invariant: in_place gives both tests as first written, for every cell of random histories
        // (returns and temporarily stationary marks over eight frames, on the border too).
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let g = GridGeometry::with_cells(Point2::new(0.0, 0.0), 10, 10, 0.05).expect("valid");
        let (mut rested, mut stationary) = (0, 0);
        for _ in 0..200 {
            let mut l = Layers::new(g.len());
            let density = rng.random_range(0.05..0.9);
            for f in 1..=8 {
                for i in 0..g.len() {
                    if rng.random_bool(density) {
                        l.record_hit(i, f);
                        if rng.random_bool(0.7) {
                            l.mark_ts(i);
                        }
                    }
                }
            }
            for f in 8..=9 {
                for i in 0..g.len() {
                    let want = InPlace {
                        rested: returned_around_reference(&l, &g, i, f),
                        three_frames: three_frames_reference(&l, &g, i, f),
                    };
                    assert_eq!(in_place(&l, &g, i, f), want, "cell {i}, frame {f}");
                    rested += usize::from(want.rested);
                    stationary += usize::from(want.three_frames);
                }
            }
        }
        assert!(rested > 1000 && stationary > 1000 && rested < 39_000 && stationary < 39_000);
    }
}
