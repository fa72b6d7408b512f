//! 2D ray traversal: every cell a segment passes through, in order (Amanatides & Woo 1987).
//!
//! The segment is first clipped to the grid (Liang–Barsky), then walked one cell boundary at a time:
//! `t_max_x`/`t_max_y` hold the segment parameter of the next vertical/horizontal boundary, and the
//! smaller one says which way to step. Conventions:
//! - the last cell is the one *containing* the end point (the same cell [`GridGeometry::cell_of`] gives
//!   for a return), so a ray and its return agree on the hit cell;
//! - a segment that passes exactly through a cell corner steps diagonally: the two cells that share only
//!   that corner point are not visited (they are touched in a point, not crossed);
//! - a start point on a cell boundary, heading into the lower cell, starts in the lower cell.
//!
//! Cost is O(cells crossed); no allocation.

use nalgebra::Point2;

use super::geometry::{CellIndex, GridGeometry, floor};
use super::layers::Crossing;

/// One visited cell and the segment parameter (0 at the start, 1 at the end) where the segment leaves it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayCell {
    /// The cell.
    pub cell: CellIndex,
    /// Where the segment leaves the cell, as a fraction of the whole segment (1 for the last cell).
    pub t_exit: f64,
}

/// Iterator over the cells a segment crosses, from start to end.
#[derive(Clone, Debug)]
pub struct Traversal {
    x: i64,
    y: i64,
    step_x: i64,
    step_y: i64,
    t_max_x: f64,
    t_max_y: f64,
    t_delta_x: f64,
    t_delta_y: f64,
    /// Boundaries crossed per unit of segment parameter along x and y (`|dx|`, `|dy|`): the
    /// reciprocals of the deltas, for counting boundaries without a division.
    per_t: (f64, f64),
    end_x: i64,
    end_y: i64,
    t_end: f64,
    remaining: u64,
}

/// Tolerance (in segment parameter, 0..1) under which two boundary crossings count as one corner.
const CORNER_EPS: f64 = 1e-12;

impl Traversal {
    /// The cells of `geom` crossed by the segment `from → to` (map frame). Parts outside the grid are
    /// skipped; a segment entirely outside, or with a non-finite end, yields nothing.
    pub fn new(geom: &GridGeometry, from: Point2<f64>, to: Point2<f64>) -> Self {
        let (ax, ay) = geom.grid_coords(from);
        let (bx, by) = geom.grid_coords(to);
        Self::in_grid_units(ax, ay, bx, by, geom.width() as f64, geom.height() as f64)
    }

    /// [`Self::new`] from both ends' continuous grid coordinates
    /// ([`GridGeometry::grid_coords`]), for callers that have them already.
    pub(crate) fn between(geom: &GridGeometry, (ax, ay): (f64, f64), (bx, by): (f64, f64)) -> Self {
        Self::in_grid_units(ax, ay, bx, by, geom.width() as f64, geom.height() as f64)
    }

    fn empty() -> Self {
        Self {
            x: 0,
            y: 0,
            step_x: 0,
            step_y: 0,
            t_max_x: f64::INFINITY,
            t_max_y: f64::INFINITY,
            t_delta_x: f64::INFINITY,
            t_delta_y: f64::INFINITY,
            per_t: (0.0, 0.0),
            end_x: 0,
            end_y: 0,
            t_end: 0.0,
            remaining: 0,
        }
    }

    /// Traversal in continuous grid coordinates of a `w × h` grid.
    fn in_grid_units(ax: f64, ay: f64, bx: f64, by: f64, w: f64, h: f64) -> Self {
        let (dx, dy) = (bx - ax, by - ay);
        // Both ends in the grid (the common case: a sensor on the map looking at it): no clipping.
        // Liang–Barsky would find every bound at or beyond the segment's ends — rounding is monotone,
        // so e.g. (w − ax) / dx ≥ 1 when bx ≤ w — and give (±0, 1), so a start a + t0·d = a (but
        // for the sign of a zero, which changes no cell).
        let inside = |a: f64, b: f64, n: f64| 0.0 <= a && a <= n && 0.0 <= b && b <= n;
        let (sx, sy, t1) = if inside(ax, bx, w) && inside(ay, by, h) {
            (ax, ay, 1.0)
        } else if !(ax.is_finite() && ay.is_finite() && bx.is_finite() && by.is_finite()) {
            return Self::empty();
        } else if let Some((t0, t1)) = clip(ax, ay, dx, dy, w, h) {
            (ax + t0 * dx, ay + t0 * dy, t1)
        } else {
            return Self::empty();
        };
        Self::from_start(ax, ay, dx, dy, (sx, sy, t1), w, h)
    }

    /// The traversal of `a + t·d` in a `w × h` grid from its in-grid start `(sx, sy)` up to
    /// parameter `t1`, where the segment leaves the grid or ends.
    fn from_start(
        ax: f64,
        ay: f64,
        dx: f64,
        dy: f64,
        (sx, sy, t1): (f64, f64, f64),
        w: f64,
        h: f64,
    ) -> Self {
        let (ex, ey) = (ax + t1 * dx, ay + t1 * dy);
        let start = |s: f64, d: f64, n: f64| -> i64 {
            let f = floor(s);
            let c = if d < 0.0 && f == s { f - 1.0 } else { f };
            c.clamp(0.0, n - 1.0) as i64
        };
        let x = start(sx, dx, w);
        let y = start(sy, dy, h);
        let end_x = floor(ex).clamp(0.0, w - 1.0) as i64;
        let end_y = floor(ey).clamp(0.0, h - 1.0) as i64;
        let axis = |c: i64, d: f64, a: f64| -> (i64, f64, f64) {
            if d > 0.0 {
                (1, ((c + 1) as f64 - a) / d, 1.0 / d)
            } else if d < 0.0 {
                (-1, (c as f64 - a) / d, -1.0 / d)
            } else {
                (0, f64::INFINITY, f64::INFINITY)
            }
        };
        let (step_x, t_max_x, t_delta_x) = axis(x, dx, ax);
        let (step_y, t_max_y, t_delta_y) = axis(y, dy, ay);
        let remaining = (end_x - x).unsigned_abs() + (end_y - y).unsigned_abs() + 1;
        Self {
            x,
            y,
            step_x,
            step_y,
            t_max_x,
            t_max_y,
            t_delta_x,
            t_delta_y,
            per_t: (dx.abs(), dy.abs()),
            end_x,
            end_y,
            t_end: t1,
            remaining,
        }
    }
}

/// Where along a beam (segment parameter, 0..1) its cells change kind, by their exit parameter:
/// up to `seen` not seen at all, up to `far` crossed far before the return, up to `free` crossed free,
/// beyond that crossed near the return.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cuts {
    pub seen: f64,
    pub free: f64,
    pub far: f64,
}

impl Cuts {
    #[inline]
    pub(crate) fn kind(&self, t_exit: f64) -> Option<Crossing> {
        if t_exit <= self.seen {
            None
        } else if t_exit <= self.far {
            Some(Crossing::Far)
        } else if t_exit <= self.free {
            Some(Crossing::Free)
        } else {
            Some(Crossing::Near)
        }
    }

    /// [`Self::kind`] as a level bit ([`Crossing::level`]; 0 for an unseen cell).
    #[inline]
    pub(crate) fn level(&self, t_exit: f64) -> u8 {
        self.kind(t_exit).map_or(0, Crossing::level)
    }
}

impl Traversal {
    /// Walks the same cells as the iterator, stopping before `stop` if it comes, and calls
    /// `cell(i, level)` for each with its linear index and [`Cuts::level`] (0 for an unseen cell).
    /// Cells outside the grid end the walk. Returns the linear indices of the first and last cell
    /// walked, if any (the last may be one step further, still in the grid, when floating point
    /// ends the walk early): the cells' columns and rows run monotonically between them.
    ///
    /// The kind is monotone along the ray, so it is only re-evaluated once the exit parameter passes
    /// the next cut. In the common case — the stop cell, if any, is the end cell, and the end cell
    /// lies inside the grid's border — a step checks nothing else: the step budget alone says when
    /// the walk is at its last cell (each step towards the end cell spends one, a corner two), and
    /// the walk cannot leave the grid. The step itself is the iterator's, with the segment
    /// parameters in fixed point (2⁻⁵² units, saturated far beyond 1): integer comparisons.
    pub(crate) fn for_each_cell(
        self,
        geom: &GridGeometry,
        stop: Option<CellIndex>,
        cuts: &Cuts,
        skippable: Option<(f64, f64)>,
        mut cell: impl FnMut(usize, u8),
    ) -> Option<(usize, usize)> {
        let (w, h) = (geom.width() as i64, geom.height() as i64);
        let (ex, ey) = (self.end_x, self.end_y);
        let interior = |x: i64, y: i64, m: i64| x >= m && y >= m && x < w - m && y < h - m;
        let stop_at_end = stop.is_none_or(|c| (i64::from(c.x), i64::from(c.y)) == (ex, ey));
        if self.remaining == 0
            || !stop_at_end
            || !interior(ex, ey, 2)
            || !interior(self.x, self.y, 0)
        {
            return self.for_each_cell_checked(geom, stop, cuts, cell);
        }
        let (dix, diy) = (self.step_x, self.step_y * w);
        let t_end = self.t_end;
        let mut i = self.y * w + self.x;
        let first = i;
        let mut remaining = self.remaining;
        let (mut a, mut b) = (fixed(self.t_max_x), fixed(self.t_max_y));
        let (da, db) = (fixed(self.t_delta_x), fixed(self.t_delta_y));
        let eps = fixed(CORNER_EPS);
        let exit = |a: i64, b: i64| {
            let ab = a.min(b) as f64 / ONE;
            if ab < t_end { ab } else { t_end }
        };
        // The level holds until the exit parameter passes `cut`; min(a, b, t_end) > cut is tested
        // as a > cut && b > cut, with cuts at or beyond t_end never passed. In fixed point, as
        // running maxima (so that the kind is the number of them passed).
        let fold = |c: f64| if c < t_end { fixed(c) } else { i64::MAX };
        let c1 = cuts.seen;
        let c2 = c1.max(cuts.far);
        let c3 = c2.max(cuts.free);
        let passes = [fold(c1), fold(c2), fold(c3), i64::MAX];
        let levels = [
            0,
            Crossing::Far.level(),
            Crossing::Free.level(),
            Crossing::Near.level(),
        ];
        let at = |a: i64, b: i64| {
            let m = a.min(b);
            let k = usize::from(m > passes[0])
                + usize::from(m > passes[1])
                + usize::from(m > passes[2]);
            (levels[k], passes[k])
        };
        let (mut level, mut cut) = at(a, b);
        // The skippable stretch, as a cut of its own: once a cell's exit passes its start, the
        // walk jumps to the cell holding its end.
        let (mut skip_from, skip_to) = match skippable {
            Some((t1, t2)) if t1 < t2 && t2 < t_end && da >= 1 << 20 && db >= 1 << 20 => {
                (fixed(t1), fixed(t2))
            }
            _ => (i64::MAX, 0),
        };
        let step = |i: i64, a: i64, b: i64, remaining: u64| {
            if a < b - eps {
                (i + dix, a + da, b, remaining)
            } else if b < a - eps {
                (i + diy, a, b + db, remaining)
            } else {
                // Through a corner: one diagonal step covers two boundaries.
                (i + dix + diy, a + da, b + db, remaining - 1)
            }
        };
        let mut next = cut.min(skip_from);
        while remaining > 1 {
            if a > next && b > next {
                if a > cut && b > cut {
                    (level, cut) = at(a, b);
                }
                if a > skip_from && b > skip_from {
                    skip_from = i64::MAX;
                    // Past the stretch: as many boundaries of each axis as lie before its end.
                    let (kx, ky) = (
                        boundaries_before(a, da, skip_to, self.per_t.0 / ONE),
                        boundaries_before(b, db, skip_to, self.per_t.1 / ONE),
                    );
                    if kx + ky + 1 < remaining as i64 {
                        cell(i as usize, level);
                        i += kx * dix + ky * diy;
                        a += kx * da;
                        b += ky * db;
                        remaining -= (kx + ky) as u64;
                        // The level only changes if the stretch held a cut (not the near field's).
                        if a > cut && b > cut {
                            (level, cut) = at(a, b);
                        }
                    }
                }
                next = cut.min(skip_from);
                if remaining <= 1 {
                    break;
                }
                if skip_from == i64::MAX && level > Crossing::Far.level() {
                    // The last few cells before the return, crossed free or near: each cell's
                    // level from its own exit, and no loop exit per cut (each one mispredicted).
                    while remaining > 1 {
                        cell(i as usize, at(a, b).0);
                        remaining -= 1;
                        (i, a, b, remaining) = step(i, a, b, remaining);
                    }
                    break;
                }
            }
            cell(i as usize, level);
            remaining -= 1;
            (i, a, b, remaining) = step(i, a, b, remaining);
        }
        // The last cell: the end cell (not walked if it is the stop cell), or where the budget ran
        // out if floating point stepped past it.
        let end = ey * w + ex;
        if remaining == 1 && !(i == end && stop.is_some()) {
            let t = if i == end { t_end.max(0.0) } else { exit(a, b) };
            cell(i as usize, cuts.level(t));
        }
        Some((first as usize, i as usize))
    }

    /// [`Self::for_each_cell`] for any walk: every step checks the stop cell, the end cell and the
    /// grid's bounds.
    fn for_each_cell_checked(
        mut self,
        geom: &GridGeometry,
        stop: Option<CellIndex>,
        cuts: &Cuts,
        mut cell: impl FnMut(usize, u8),
    ) -> Option<(usize, usize)> {
        let (w, h) = (geom.width() as i64, geom.height() as i64);
        let stop = stop.map_or(-1, |c| i64::from(c.y) * w + i64::from(c.x));
        let end = self.end_y * w + self.end_x;
        let t_end = self.t_end;
        let (mut first, mut last) = (None, None);
        while self.remaining > 0 && (0..w).contains(&self.x) && (0..h).contains(&self.y) {
            let i = self.y * w + self.x;
            if i == stop {
                break;
            }
            let at_end = i == end;
            let t_exit = if at_end {
                t_end.max(0.0)
            } else {
                let (a, b) = (self.t_max_x, self.t_max_y);
                let ab = if a < b { a } else { b };
                if ab < t_end { ab } else { t_end }
            };
            cell(i as usize, cuts.level(t_exit));
            first = first.or(Some(i as usize));
            last = Some(i as usize);
            if at_end {
                break;
            }
            self.remaining -= 1;
            self.step();
        }
        first.zip(last)
    }

    /// One Amanatides–Woo step to the next cell.
    #[inline]
    fn step(&mut self) {
        let (a, b) = (self.t_max_x, self.t_max_y);
        // Segment parameters live in [0, 1], so an absolute tolerance decides corner crossings.
        if a < b - CORNER_EPS {
            self.x += self.step_x;
            self.t_max_x += self.t_delta_x;
        } else if b < a - CORNER_EPS {
            self.y += self.step_y;
            self.t_max_y += self.t_delta_y;
        } else {
            // Through a corner: one diagonal step covers two boundaries.
            self.x += self.step_x;
            self.t_max_x += self.t_delta_x;
            self.y += self.step_y;
            self.t_max_y += self.t_delta_y;
            self.remaining = self.remaining.saturating_sub(1);
        }
    }
}

/// How many of the boundaries `start`, `start + step`, … (fixed point, `step > 0`) lie before
/// `end`, given `per_step ≈ 1 / step`.
fn boundaries_before(start: i64, step: i64, end: i64, per_step: f64) -> i64 {
    if end <= start {
        return 0;
    }
    // The count is the quotient's ceiling: a float estimate, truncated and one up (no library
    // call), made exact by integer checks (off by rounding only). A multiplication: a division
    // here waited on the divider.
    let mut k = ((end - start) as f64 * per_step) as i64 + 1;
    let at = |k: i64| start.saturating_add(k.saturating_mul(step));
    while at(k) < end {
        k += 1;
    }
    while k > 0 && at(k - 1) >= end {
        k -= 1;
    }
    k
}

/// One in the walk's fixed point.
const ONE: f64 = (1_u64 << 52) as f64;

/// A non-negative segment parameter in fixed point, saturated at 2⁶⁰ (far beyond the segment's 1:
/// such a boundary is never crossed, and sums of two stay in range).
fn fixed(t: f64) -> i64 {
    // In the parameter's own units: 2⁶⁰ fixed-point units are 2⁸. (Comparing `t` itself with 2⁶⁰
    // let parameters from 2¹¹ up convert to i64::MAX, and a step of that overflows.)
    const MAX: f64 = (1_u64 << 60) as f64 / ONE;
    if t < MAX { (t * ONE) as i64 } else { 1 << 60 }
}

/// Liang–Barsky clip of `a + t·d`, t ∈ [0,1], to the box [0,w]×[0,h]; `None` when nothing is inside.
fn clip(ax: f64, ay: f64, dx: f64, dy: f64, w: f64, h: f64) -> Option<(f64, f64)> {
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for (p, q) in [(-dx, ax), (dx, w - ax), (-dy, ay), (dy, h - ay)] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then_some((t0, t1))
}

impl Iterator for Traversal {
    type Item = RayCell;

    #[inline]
    fn next(&mut self) -> Option<RayCell> {
        if self.remaining == 0 {
            return None;
        }
        let cell = CellIndex::new(self.x as u32, self.y as u32);
        if self.x == self.end_x && self.y == self.end_y {
            self.remaining = 0;
            return Some(RayCell {
                cell,
                t_exit: self.t_end.max(0.0),
            });
        }
        self.remaining -= 1;
        // Compare-and-select rather than `f64::min`, whose NaN handling costs: nothing here is NaN.
        let (a, b) = (self.t_max_x, self.t_max_y);
        let ab = if a < b { a } else { b };
        let t_exit = if ab < self.t_end { ab } else { self.t_end };
        self.step();
        Some(RayCell { cell, t_exit })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cells(ax: f64, ay: f64, bx: f64, by: f64) -> Vec<(i64, i64)> {
        Traversal::in_grid_units(ax, ay, bx, by, 10.0, 10.0)
            .map(|c| (c.cell.x as i64, c.cell.y as i64))
            .collect()
    }

    /// [`Traversal::in_grid_units`] as first written: every segment through Liang–Barsky.
    fn always_clipped(ax: f64, ay: f64, bx: f64, by: f64, w: f64, h: f64) -> Traversal {
        if !(ax.is_finite() && ay.is_finite() && bx.is_finite() && by.is_finite()) {
            return Traversal::empty();
        }
        let (dx, dy) = (bx - ax, by - ay);
        let Some((t0, t1)) = clip(ax, ay, dx, dy, w, h) else {
            return Traversal::empty();
        };
        let start = (ax + t0 * dx, ay + t0 * dy, t1);
        Traversal::from_start(ax, ay, dx, dy, start, w, h)
    }

    /// Every field of a traversal, floats by their bits.
    fn fields(t: &Traversal) -> [u64; 12] {
        [
            t.x as u64,
            t.y as u64,
            t.step_x as u64,
            t.step_y as u64,
            t.t_max_x.to_bits(),
            t.t_max_y.to_bits(),
            t.t_delta_x.to_bits(),
            t.t_delta_y.to_bits(),
            t.end_x as u64,
            t.end_y as u64,
            t.t_end.to_bits(),
            t.remaining,
        ]
    }

    #[test]
    fn segments_inside_the_grid_skip_the_clip_and_walk_the_same() {
        // Invariant: a traversal set up without the clip for segments inside the grid is, field for
        // field and bit for bit, the one set up through Liang–Barsky — for ends inside, on the border
        // (±0 too), just outside and far outside, axis-aligned and not.
        let (w, h) = (40.0, 30.0);
        let mut r = super::super::test_rng::xorshift(0x1f2e_3d4c_u64);
        let mut coord = |n: f64| {
            let u = (r() % 1_000_000) as f64 / 1_000_000.0;
            match r() % 8 {
                0 => 0.0,
                1 => -0.0,
                2 => n,
                3 => (u * n).round(),
                4 => u * (n + 2.0) - 1.0,
                5 => u * 200.0 - 100.0,
                _ => u * n,
            }
        };
        let mut inside = 0;
        for _ in 0..200_000 {
            let (ax, ay, bx, by) = (coord(w), coord(h), coord(w), coord(h));
            let got = Traversal::in_grid_units(ax, ay, bx, by, w, h);
            let want = always_clipped(ax, ay, bx, by, w, h);
            assert_eq!(fields(&got), fields(&want), "{ax} {ay} -> {bx} {by}");
            let within = |a: f64, b: f64, n: f64| (0.0..=n).contains(&a) && (0.0..=n).contains(&b);
            inside += usize::from(within(ax, bx, w) && within(ay, by, h));
        }
        assert!(inside > 50_000);
    }

    #[test]
    fn far_boundaries_saturate_and_jumps_count_them_without_overflow() {
        // Invariant: parameters beyond 2⁸ segment lengths are one saturated fixed-point value,
        // sums of two of them stay in range, and counting boundaries before a point past such a
        // step ends (one boundary).
        assert_eq!(fixed(1e6), 1 << 60);
        assert_eq!(fixed(f64::INFINITY), 1 << 60);
        assert_eq!(fixed(3000.0), 1 << 60);
        assert!(fixed(255.0) < 1 << 60);
        assert!(fixed(1e6).checked_add(fixed(1e6)).is_some());
        assert_eq!(
            boundaries_before(fixed(0.25), fixed(1e6), fixed(0.5), 1e-6 / ONE),
            1
        );
        assert_eq!(
            boundaries_before(fixed(0.25), fixed(0.1), fixed(0.5), 10.0 / ONE),
            3
        );
        assert_eq!(
            boundaries_before(fixed(0.75), fixed(0.1), fixed(0.5), 10.0 / ONE),
            0
        );
    }

    #[test]
    fn axis_aligned_rays_visit_their_row_or_column() {
        // Invariant: a ray along +x, −x, +y or −y visits exactly the cells between its end cells.
        assert_eq!(
            cells(0.5, 2.5, 4.5, 2.5),
            vec![(0, 2), (1, 2), (2, 2), (3, 2), (4, 2)]
        );
        assert_eq!(
            cells(4.5, 2.5, 1.2, 2.5),
            vec![(4, 2), (3, 2), (2, 2), (1, 2)]
        );
        assert_eq!(
            cells(3.5, 0.2, 3.5, 3.9),
            vec![(3, 0), (3, 1), (3, 2), (3, 3)]
        );
        assert_eq!(cells(3.5, 3.9, 3.5, 1.0), vec![(3, 3), (3, 2), (3, 1)]);
    }

    #[test]
    fn diagonal_through_corners_steps_diagonally() {
        // Invariant: a 45° ray through cell corners visits only the diagonal cells.
        assert_eq!(
            cells(0.5, 0.5, 3.5, 3.5),
            vec![(0, 0), (1, 1), (2, 2), (3, 3)]
        );
        assert_eq!(
            cells(3.5, 3.5, 0.5, 0.5),
            vec![(3, 3), (2, 2), (1, 1), (0, 0)]
        );
        assert_eq!(
            cells(0.5, 3.5, 3.5, 0.5),
            vec![(0, 3), (1, 2), (2, 1), (3, 0)]
        );
        // Starting exactly on a corner, heading down-left: the first cell is the lower-left one.
        assert_eq!(cells(3.0, 3.0, 0.5, 0.5), vec![(2, 2), (1, 1), (0, 0)]);
    }

    #[test]
    fn shallow_ray_visits_the_supercover_cells_in_order() {
        // Invariant: a ray from (0.5,0.5) to (4.5,2.5) (slope 1/2) crosses x=1,y=1,x=2 ... in that order.
        // Boundaries: x=1 at t=.125, y=1 at t=.25, x=2 at t=.375, x=3 at t=.625, y=2 at t=.75, x=4 at .875;
        // the crossings of y=1 and y=2 fall between x crossings, so no corner is hit.
        assert_eq!(
            cells(0.5, 0.5, 4.5, 2.5),
            vec![(0, 0), (1, 0), (1, 1), (2, 1), (3, 1), (3, 2), (4, 2)]
        );
    }

    #[test]
    fn exit_parameters_grow_and_end_at_one() {
        // Invariant: t_exit is non-decreasing along the ray and 1 in the end cell.
        let ts: Vec<f64> = Traversal::in_grid_units(0.5, 0.5, 4.5, 2.5, 10.0, 10.0)
            .map(|c| c.t_exit)
            .collect();
        assert!(ts.windows(2).all(|w| w[0] <= w[1]));
        assert_eq!(ts.last().copied(), Some(1.0));
        assert!((ts[0] - 0.125).abs() < 1e-12);
    }

    #[test]
    fn segments_are_clipped_to_the_grid() {
        // Invariant: parts outside the grid are skipped; a segment wholly outside yields nothing.
        assert_eq!(cells(-3.5, 1.5, 2.5, 1.5), vec![(0, 1), (1, 1), (2, 1)]);
        assert_eq!(cells(8.5, 1.5, 14.0, 1.5), vec![(8, 1), (9, 1)]);
        assert!(cells(-3.0, -1.0, -1.0, -5.0).is_empty());
        assert!(cells(f64::NAN, 1.0, 2.0, 2.0).is_empty());
        assert_eq!(cells(2.5, 2.5, 2.5, 2.5), vec![(2, 2)]);
    }

    #[test]
    fn every_step_moves_to_a_neighbouring_cell() {
        // Invariant: consecutive cells differ by one step in x, y or both, and the walk ends in the
        // end point's cell, for many random-looking rays.
        let mut next = super::super::test_rng::xorshift(0x2545_f491_u64);
        let mut r = || (next() % 10_000) as f64 / 1000.0;
        for _ in 0..2000 {
            let (ax, ay, bx, by) = (r(), r(), r(), r());
            let v = cells(ax, ay, bx, by);
            // On a boundary, heading into the lower cell, the walk starts in the lower cell.
            let first = |a: f64, b: f64| {
                let f = a.floor();
                (if b < a && f == a { f - 1.0 } else { f }).max(0.0) as i64
            };
            assert_eq!(v.first().copied(), Some((first(ax, bx), first(ay, by))));
            assert_eq!(
                v.last().copied(),
                Some((bx.floor() as i64, by.floor() as i64))
            );
            for w in v.windows(2) {
                let (ddx, ddy) = ((w[1].0 - w[0].0).abs(), (w[1].1 - w[0].1).abs());
                assert!(
                    ddx <= 1 && ddy <= 1 && ddx + ddy >= 1,
                    "{ax} {ay} {bx} {by}: {v:?}"
                );
            }
        }
    }

    #[test]
    fn the_cell_walk_gives_exactly_the_iterators_cells_with_their_kinds() {
        // Invariant: for_each_cell reports the iterator's in-grid cells up to (not including) the stop
        // cell, each once, with the kind of its own exit parameter, within the box of the cells it returns.
        let geom =
            GridGeometry::with_cells(nalgebra::Point2::new(0.0, 0.0), 40, 30, 1.0).expect("valid");
        let mut next = super::super::test_rng::xorshift(0x9e37_79b9_u64);
        let mut r = |m: f64| (next() % 100_000) as f64 / 100_000.0 * m;
        for n in 0..20_000 {
            let a = if n % 11 == 0 {
                Point2::new(r(40.0).round() * 0.5, r(30.0).round() * 0.5)
            } else {
                Point2::new(r(50.0) - 5.0, r(40.0) - 5.0)
            };
            // Some rays axis-aligned, from or to cell corners (also on the grid's border), most
            // anywhere.
            let b = match n % 5 {
                0 => Point2::new(a.x + r(20.0) - 10.0, a.y),
                1 => Point2::new((a.x + 7.0).floor(), (a.y + 7.0).floor()),
                2 if n % 7 == 0 => Point2::new((r(60.0) - 10.0).round(), (r(50.0) - 10.0).round()),
                3 => Point2::new(
                    a.x + (r(20.0) - 10.0).round(),
                    a.y + (r(20.0) - 10.0).round(),
                ),
                _ => Point2::new(r(50.0) - 5.0, r(40.0) - 5.0),
            };
            let cuts = Cuts {
                seen: r(0.4) - 0.1,
                free: r(1.2),
                far: r(1.2),
            };
            let all: Vec<RayCell> = Traversal::new(&geom, a, b).collect();
            let stop = (n % 3 == 0)
                .then(|| all.get(all.len() * 2 / 3).map(|c| c.cell))
                .flatten();
            let mut expected: Vec<(usize, Option<Crossing>)> = all
                .iter()
                .take_while(|c| Some(c.cell) != stop)
                // Float drift can carry the iterator one step out of the grid at the very end.
                .filter(|c| c.cell.x < 40 && c.cell.y < 30)
                .map(|c| {
                    (
                        c.cell.y as usize * 40 + c.cell.x as usize,
                        cuts.kind(c.t_exit),
                    )
                })
                .filter(|(_, k)| k.is_some())
                .collect();
            expected.sort_by_key(|e| e.0);
            let mut got = Vec::new();
            let rows =
                Traversal::new(&geom, a, b).for_each_cell(&geom, stop, &cuts, None, |i, level| {
                    if level != 0 {
                        let kinds = [Crossing::Far, Crossing::Free, Crossing::Near];
                        got.push((i, kinds.into_iter().find(|k| k.level() == level)));
                    }
                });
            if let Some((first, last)) = rows {
                let span = |f: fn(usize) -> usize| {
                    let (a, b) = (f(first), f(last));
                    a.min(b)..=a.max(b)
                };
                let (cols, rows) = (span(|i| i % 40), span(|i| i / 40));
                assert!(
                    got.iter()
                        .all(|(i, _)| cols.contains(&(i % 40)) && rows.contains(&(i / 40)))
                );
            } else {
                assert!(got.is_empty());
            }
            got.sort_by_key(|e| e.0);
            assert_eq!(got, expected, "{a:?} -> {b:?}, {cuts:?}, stop {stop:?}");
        }
    }
}
