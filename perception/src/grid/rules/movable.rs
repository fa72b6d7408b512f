//! Movable obstacles (Tamura 3.2): addition, retention and deletion.

use super::super::class::CellClass;
use super::super::evidence::{Rule, pack_rule};
use super::super::geometry::GridGeometry;
use super::super::layers::Layers;

/// Retention (Tamura 3.2.2), own cell: a return in a movable cell stays movable — unless motion is
/// seen next to it in the same frame (decided with [`added`]): then the movable obstacle is being
/// moved (picked up, pulled away) and the return is moving.
pub(crate) fn retained(class: CellClass) -> bool {
    class == CellClass::Movable
}

/// Retention (Tamura 3.2.2), neighbours: a return that has been in place for three frames (`rested`)
/// within three cells (Tamura's ε, 0.15 m) of a cell made movable by addition or own-cell retention
/// joins it (a new face of the same object coming into view, or a return jittering across a cell
/// boundary). A cell joined this way does not pass the label on, so a movable label can never creep
/// along a wall it happens to touch.
pub(crate) fn extended(
    l: &Layers,
    g: &GridGeometry,
    i: usize,
    class: CellClass,
    rested: bool,
) -> bool {
    if !rested || class == CellClass::Stationary {
        return false;
    }
    let sources = [
        pack_rule(Rule::MovableAddition),
        pack_rule(Rule::MovableRetention),
    ];
    let mut near = false;
    // Only a row holding a movable cell can hold a source.
    g.for_square_rows(i, EXTENSION_REACH, |row| {
        if !near && holds(&l.class, row.clone(), MOVABLE) {
            near = row.into_iter().any(|j| {
                l.class[j] == CellClass::Movable as u8 && sources.contains(&l.evidence[j])
            });
        }
    });
    near
}

const MOVABLE: u8 = CellClass::Movable as u8;

/// Whether `bytes[row]` (nothing if out of range) holds `b`: a row of up to eight bytes at once.
#[inline]
fn holds(bytes: &[u8], row: std::ops::RangeInclusive<usize>, b: u8) -> bool {
    let (from, len) = (*row.start(), row.clone().count());
    let Some(cells) = bytes.get(row) else {
        return false;
    };
    match bytes.get(from..).and_then(|c| c.first_chunk::<8>()) {
        // Bytes past the row do not count.
        Some(word) if len <= 8 => equal_bytes(u64::from_le_bytes(*word), b) & first_bytes(len) != 0,
        _ => cells.contains(&b),
    }
}

/// How far (cells, Chebyshev) a movable label extends from a cell found by addition or retention.
pub(crate) const EXTENSION_REACH: usize = 3;

/// True when a movable cell of any kind lies within the extension reach: such a return
/// is never made stationary (it stays tentative), so a movable obstacle's fringe — returns jittering
/// across a cell boundary along its face — cannot turn into a wall.
pub(crate) fn touches_movable(l: &Layers, g: &GridGeometry, i: usize) -> bool {
    let (w, h) = (g.width(), g.height());
    let (x, y) = (i % w, i / w);
    let (x0, x1) = (
        x.saturating_sub(EXTENSION_REACH),
        (x + EXTENSION_REACH).min(w - 1),
    );
    let (y0, y1) = (
        y.saturating_sub(EXTENSION_REACH),
        (y + EXTENSION_REACH).min(h - 1),
    );
    let class = l.class.as_slice();
    let len = (x1 + 1).saturating_sub(x0);
    if len > 8 || y1 * w + x0 + 8 > class.len() {
        let mut near = false;
        g.for_square_rows(i, EXTENSION_REACH, |row| {
            near = near || holds(class, row, MOVABLE);
        });
        return near;
    }
    // One word a row, from the row's first cell of the block; bytes past the block do not count.
    let mut movable = 0;
    for yy in y0..=y1 {
        let a = yy * w + x0;
        let word = class.get(a..).and_then(|c| c.first_chunk::<8>());
        movable |= word.map_or(0, |b| equal_bytes(u64::from_le_bytes(*b), MOVABLE));
    }
    movable & first_bytes(len) != 0
}

/// The top bit of each byte of `v` that equals `b`, and no other bit.
#[inline]
fn equal_bytes(v: u64, b: u8) -> u64 {
    const ONES: u64 = 0x0101_0101_0101_0101;
    const LOW7: u64 = 0x7f7f_7f7f_7f7f_7f7f;
    // A byte of `x` is zero exactly where `v` holds `b`; the carry-free test below sets the top bit
    // of every non-zero byte.
    let x = v ^ (ONES * u64::from(b));
    !(((x & LOW7) + LOW7) | x) & !LOW7
}

/// The bits of the first `n` bytes (n ≤ 8).
#[inline]
fn first_bytes(n: usize) -> u64 {
    if n >= 8 { !0 } else { (1u64 << (8 * n)) - 1 }
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
/// before the ray's return, is free again: the movable obstacle has gone. Guard: no return in its
/// 8-neighbourhood this frame — a ray slipping past an object's corner crosses the corner cell far
/// before its return while the object is still there, returned next to it.
pub(crate) fn deleted(l: &Layers, g: &GridGeometry, i: usize, f: u32) -> bool {
    if l.crossed_far_in_frames(i, f, 1) == 0 {
        return false;
    }
    let mut quiet = true;
    g.for_3x3(i, |j| quiet &= l.hits(j, f) & 1 == 0);
    quiet
}

/// Something has just left the cell: it held a return at t−1 and none now, and a ray crossed it now at
/// least the clear margin before its return, with no return in its 8-neighbourhood now — the
/// deletion test (whatever the cell's class) on a cell returned a frame ago. The back end of a pulled
/// suitcase leaves such cells every frame; a resting object's edge does not (returns stay around it).
pub(crate) fn vacated(l: &Layers, g: &GridGeometry, i: usize, f: u32) -> bool {
    l.hits(i, f) & 0b11 == 0b10 && deleted(l, g, i, f)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::layers::Crossing;
    use nalgebra::Point2;

    fn grid() -> (GridGeometry, Layers) {
        let g = GridGeometry::with_cells(Point2::new(0.0, 0.0), 10, 10, 0.05).expect("valid");
        let l = Layers::new(g.len());
        (g, l)
    }

    #[test]
    fn retention_keeps_movable_and_extends_only_from_added_or_retained_cells() {
        // Invariant: movable stays movable; a resting return within reach of an added/retained cell joins,
        // never a stationary one, and never one near a cell that itself only joined.
        let (g, mut l) = grid();
        assert!(retained(CellClass::Movable));
        assert!(!retained(CellClass::Stationary));
        l.class[44] = CellClass::Movable as u8;
        l.evidence[44] = pack_rule(Rule::MovableAddition);
        assert!(extended(&l, &g, 45, CellClass::Unknown, true));
        assert!(!extended(&l, &g, 45, CellClass::Unknown, false));
        assert!(!extended(&l, &g, 45, CellClass::Stationary, true));
        assert!(extended(&l, &g, 47, CellClass::Unknown, true), "three away");
        assert!(!extended(&l, &g, 48, CellClass::Unknown, true));
        assert!(touches_movable(&l, &g, 77) && !touches_movable(&l, &g, 48));
        l.evidence[44] = pack_rule(Rule::MovableExtension);
        assert!(!extended(&l, &g, 45, CellClass::Unknown, true));
    }

    #[test]
    fn addition_needs_no_motion_nearby() {
        // Invariant: a resting return is added as movable only with no moving return within the radius.
        assert!(added((5, 5), &[], 6.0));
        assert!(added((5, 5), &[(12, 5)], 6.0));
        assert!(!added((5, 5), &[(11, 5)], 6.0));
    }

    #[test]
    fn deletion_needs_a_far_crossing_and_no_return_around() {
        // Invariant: only a crossing well before the return, with no return in the 3×3 block, deletes.
        let (g, mut l) = grid();
        l.record_crossing(44, 4, Crossing::Free);
        assert!(!deleted(&l, &g, 44, 4));
        l.record_crossing(44, 5, Crossing::Far);
        assert!(deleted(&l, &g, 44, 5));
        l.record_hit(45, 5);
        assert!(
            !deleted(&l, &g, 44, 5),
            "a return next to it: a ray past the object's corner"
        );
    }

    #[test]
    fn a_cell_returned_last_frame_and_seen_through_now_is_vacated() {
        // Invariant: vacated iff returned at t−1, not at t, crossed far at t, no return around at t.
        let (g, mut l) = grid();
        l.record_hit(44, 4);
        l.record_crossing(44, 5, Crossing::Far);
        assert!(vacated(&l, &g, 44, 5));
        l.record_hit(34, 5);
        assert!(
            !vacated(&l, &g, 44, 5),
            "a return next to it: the object is still there"
        );
        let (g, mut l) = grid();
        l.record_hit(44, 3);
        l.record_crossing(44, 5, Crossing::Far);
        assert!(!vacated(&l, &g, 44, 5), "returned two frames ago only");
        let (g, mut l) = grid();
        l.record_hit(44, 4);
        l.record_crossing(44, 5, Crossing::Free);
        assert!(!vacated(&l, &g, 44, 5), "crossed just before a return only");
    }

    /// A frame of a wall along y = 0.9 m grazed from (0.1, 0) by beams 0.25° apart: those steeper
    /// than `limit_deg` return 1 cm in front of the wall (in the row below its face, where the
    /// short-biased returns of a grazed wall land), the shallower ones are beyond the incidence limit
    /// and clear up to the wall's foot, where the floor is seen to.
    fn grazed_wall(limit_deg: f64) -> crate::grid::RangeFrame {
        let sensor = Point2::new(0.1, 0.0);
        let mut frame = crate::grid::RangeFrame::new(sensor).expect("finite");
        for k in 0..25 {
            let bearing = 8.0 + 0.25 * f64::from(k);
            let face = if bearing > limit_deg { 0.89 } else { 0.899 };
            let end = Point2::new(sensor.x + face / bearing.to_radians().tan(), face);
            if bearing > limit_deg {
                frame.push_hit(end);
            } else {
                frame.push_clear(end);
            }
        }
        frame
    }

    #[test]
    fn a_wall_grazed_beyond_the_incidence_limit_is_not_vacated() {
        // Invariant: when a grazed wall's last return drops beyond the incidence limit, the clear
        // beam running along the wall's foot does not see the cell of that return vacated, so the
        // wall's returns beside it are not made movable (with a 0.15 m clear tail they were).
        use crate::grid::{GridConfig, ObstacleGrid};
        let geom = GridGeometry::with_cells(Point2::new(0.0, 0.0), 140, 20, 0.05).expect("valid");
        let frames = [grazed_wall(10.1), grazed_wall(10.1), grazed_wall(10.3)];
        let movable_cells = |cfg: GridConfig| {
            let mut grid = ObstacleGrid::new(geom, cfg);
            for (k, frame) in frames.iter().enumerate() {
                grid.update(frame, k as f64 * 0.1).expect("in order");
            }
            let movable = CellClass::Movable.code();
            grid.class_codes().iter().filter(|&&c| c == movable).count()
        };
        assert_eq!(movable_cells(GridConfig::default()), 0);
        let short_tail = GridConfig {
            clear_tail: 0.15,
            ..GridConfig::default()
        };
        assert!(movable_cells(short_tail) > 0, "the frames show the failure");
    }

    #[test]
    fn a_row_holds_a_byte_as_contains_says() {
        // Invariant: holds(bytes, row, b) is bytes[row].contains(&b) (false out of range) for rows of
        // every length and place, the grid's end included, over every byte value next to the row.
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut found = 0;
        for _ in 0..20_000 {
            let n = rng.random_range(1..40);
            let bytes: Vec<u8> = (0..n)
                .map(|_| match rng.random_range(0..4) {
                    0 => rng.random(),
                    k => k as u8 + 1,
                })
                .collect();
            let from = rng.random_range(0..n + 2);
            let to = from + rng.random_range(0..12);
            let b = rng.random_range(0..6);
            let want = bytes.get(from..=to).is_some_and(|c| c.contains(&b));
            assert_eq!(
                holds(&bytes, from..=to, b),
                want,
                "{bytes:?} {from}..={to} {b}"
            );
            found += usize::from(want);
        }
        assert!(found > 3000);
    }

    #[test]
    fn the_word_test_for_movable_neighbours_agrees_with_the_cell_test() {
        // Invariant: touches_movable is "some cell within EXTENSION_REACH (Chebyshev) is Movable",
        // cell by cell, on random class maps of grids of several widths, at every cell, borders too.
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let mut near = 0;
        for (w, h) in [(10, 10), (7, 13), (30, 4), (3, 3), (64, 9)] {
            let g = GridGeometry::with_cells(Point2::new(0.0, 0.0), w, h, 0.05).expect("valid");
            for _ in 0..20 {
                let mut l = Layers::new(g.len());
                let p = rng.random_range(0.0..0.05);
                for c in l.class.iter_mut() {
                    *c = if rng.random_bool(p) {
                        CellClass::Movable as u8
                    } else {
                        rng.random_range(0..5u8).min(2)
                    };
                }
                for i in 0..g.len() {
                    let mut want = false;
                    g.for_square(i, EXTENSION_REACH, |j| {
                        want |= l.class[j] == CellClass::Movable as u8
                    });
                    assert_eq!(touches_movable(&l, &g, i), want, "{w}x{h} cell {i}");
                    near += usize::from(want);
                }
            }
        }
        assert!(near > 1000);
    }
}
