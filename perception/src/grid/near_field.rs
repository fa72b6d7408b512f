//! The dense near field of a scan: where the beams lie so close together that every cell between
//! them is crossed by one, filled a grid row at a time instead of walked beam by beam.
//!
//! Why this is exact: a cell whose points all lie within `r` of the sensor subtends an angle of at
//! least `1 / r` (cell units): it holds a disk of diameter 1 whose centre is nearer than `r`. So
//! when no two neighbouring beams of a fan are more than `Δ` apart in bearing, every cell nearer
//! than `1 / Δ` whose bearings overlap the fan's has some beam's bearing strictly inside its own:
//! that beam crosses it, and a cell no beam's bearing enters is crossed by none. Nearer than the
//! reach (its return less the clear margin, or the end of its walk) of every beam that can cross
//! such a cell, and farther than every beam's `seen_from`, each beam that crosses it crosses it
//! *far*. So the cells of the annulus `r_in ..= r_out` that overlap the fan are exactly the cells
//! the walks would mark far there, and nothing else, and each beam only needs walking up to `r_in`
//! plus a cell diagonal and from `r_out` less one (the walk jumps in between): a cell crossed only
//! in between lies wholly inside the annulus.
//!
//! A 361-beam scan at 0.5° is that dense out to 5.7 m: about three quarters of a 180° scan's
//! steps in an office lie there. The fan is cut into parts of under 120°, each with its own outer
//! radius, so that "overlaps the part" is three half-plane tests per cell (in front of the part,
//! past its first bearing, short of its last), each linear along a row.
//!
//! Two cuts of the fan: coarse parts, as wide and as even as 120° allows (a 180° scan: two of
//! 90°), and fine parts, cut also where the bound the near returns put on the radius changes (a
//! chair 4.7 m away shortens the beams around it, not a whole part's). A part costs a fill of
//! every row it reaches, so a fine part is only filled where it reaches farther than the coarse
//! parts it overlaps, and only in the rows it reaches from there out. Each beam skips as far as
//! the fill reaches along it: on the office scan, 62 300 steps become 16 200, and the fill
//! covers 480 rows (counted in session 7). Every filled cell lies in a part whose own bound holds
//! for it, so the union is exact too.

use std::hint::select_unpredictable;

use nalgebra::Vector2;
use wide::f64x2;

#[cfg(doc)]
use super::frame::Beam;
use super::geometry::GridGeometry;

/// Nearest the sensor the fill may start (cells): nearer, a cell subtends so much that the
/// half-plane tests below would not describe its bearings (see [`inner_radius`]).
const MIN_INNER: f64 = 2.0;

/// How near the sensor the fill of parts up to `half` (radians) either side of their middle
/// bearing may start: a cell that overlaps such a part lies under `half` off its middle bearing
/// plus the most a cell spans from `r` out, `2·asin(√½ / r)`; from where that stays under 90°,
/// all its corners lie in front of the sensor (what the fill's first half-plane test asks). For
/// parts of 90°, 1.85 cells; of 120°, 2.73.
fn inner_radius(half: f64) -> f64 {
    let spare = (std::f64::consts::FRAC_PI_2 - half) / 2.0;
    if spare <= 0.0 {
        return f64::INFINITY;
    }
    (std::f64::consts::FRAC_1_SQRT_2 / spare.sin() * (1.0 + 1e-3)).max(MIN_INNER)
}

/// Whether direction `d` lies under 120° from `first` (with a margin): within one part.
fn within_part(first: Vector2<f64>, d: Vector2<f64>) -> bool {
    let c = first.dot(&d);
    c > 0.0 || c * c < (0.25 - SLACK) * first.norm_squared() * d.norm_squared()
}

/// The annulus must be at least this deep (cells) for the fill to save walking.
const MIN_DEPTH: f64 = 4.0;

/// Safety factor on the density bound (floating point in the gaps and the fill's own bounds).
const SLACK: f64 = 1e-6;

/// One beam of a frame as the near field sees it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Reach {
    /// Direction from the sensor (any length but zero).
    pub direction: Vector2<f64>,
    /// The beam's length (m): from the sensor to its end.
    pub length: f64,
    /// Nearer than this (m) the beam sees nothing ([`Beam::seen_from`]).
    pub seen_from: f64,
    /// Up to this distance (m) every cell the beam crosses is crossed far: its return less the
    /// clear margin, or the end of its walk.
    pub far_to: f64,
}

/// One part of a fan: a run of beams less than 120° wide, with the radius out to which its cells
/// are filled.
#[derive(Clone, Copy, Debug)]
struct Part {
    /// Its first and last beam (indices into the frame's beams).
    beams: (usize, usize),
    /// Its first and last bearing, counter-clockwise (unit vectors).
    first: Vector2<f64>,
    last: Vector2<f64>,
    /// Outer radius (cells); the part is not filled unless it exceeds the inner one enough.
    r_out: f64,
    /// Nearer than this (cells) other parts fill the part's cells already: only the rows its
    /// wedge reaches from there out are filled.
    r_from: f64,
}

impl Part {
    /// Whether the part's annulus, from `r_in` out, is deep enough to fill.
    fn filled(&self, r_in: f64) -> bool {
        let depth = self.r_out - r_in;
        self.r_out.is_finite() && depth > MIN_DEPTH + 2.0 * std::f64::consts::SQRT_2
    }
}

/// The annulus of a frame's dense fan (see the module).
#[derive(Clone, Debug, Default)]
pub(crate) struct NearField {
    /// The sensor (grid units).
    sensor: (f64, f64),
    /// Inner radius (cells), the same for every part.
    r_in: f64,
    /// The parts filled: the fan's coarse parts, in beam order, each sharing its edge beams with
    /// its neighbours, then the fine parts that reach farther than the coarse ones they lie in.
    parts: Vec<Part>,
    /// How far out (cells) the fill reaches along each beam.
    filled_to: Vec<f64>,
}

/// A fine part is cut where the beams' bound from near returns changes by more than this
/// (cells)… (4, 8 and 12 measured within 2 µs of each other on the office scan.)
const STEP: f64 = 8.0;

/// …once it holds this many beams.
const MIN_PART_BEAMS: usize = 4;

impl NearField {
    /// The near field of beams `reach` (in bearing order, either way round) from `sensor`, or `None`
    /// when they are not a fan dense enough to save walking.
    ///
    /// Each part's outer radius is the least of its density bound (`1 / Δ` for its widest gap Δ)
    /// and the reach of every beam that could cross one of its cells beyond that beam's reach: a
    /// cell whose nearest point is `ρ` away spans at most `2·asin(√½ / ρ)` of bearing, so a beam
    /// whose reach is `R` can only cross cells of parts within `2·asin(√½ / (R − √2))` of its
    /// bearing beyond `R`. The coarse parts are all filled; a fine part only if it reaches `STEP`
    /// beyond the coarse parts it overlaps, and only from their radius (`r_from`) out. Each beam
    /// records how far the fill reaches along it: the least over the fine parts holding it.
    pub(crate) fn of(
        geom: &GridGeometry,
        sensor: nalgebra::Point2<f64>,
        reach: &[Reach],
    ) -> Option<Self> {
        let n = reach.len();
        if n < 2 {
            return None;
        }
        let res = geom.resolution();
        // Bearing order: every turn from one beam to the next the same way, each under 90°; the
        // gaps' sines.
        let ccw = reach[0].direction.perp(&reach[1].direction) > 0.0;
        // Squared sines: no square root per beam. All gaps, then whether every one was valid: a
        // loop without an exit per beam (an invalid fan is rare, and computing on costs nothing).
        let mut valid = true;
        let gaps: Vec<f64> = reach
            .windows(2)
            .map(|w| {
                let (a, b) = (w[0].direction, w[1].direction);
                let (cross, dot) = (a.perp(&b), a.dot(&b));
                let norms = a.norm_squared() * b.norm_squared();
                valid &= norms > 0.0 && dot > 0.0 && (cross > 0.0) == ccw && cross != 0.0;
                (cross * cross / norms).min(1.0)
            })
            .collect();
        if !valid {
            return None;
        }
        let narrowest = gaps.iter().copied().fold(1.0, f64::min).sqrt().asin();
        let seen = reach.iter().map(|r| r.seen_from).fold(0.0, f64::max) / res;
        // How far out each beam's cells may be filled as far as the returns go: a beam whose reach
        // is `R` can only cross cells within `spread` of its bearing beyond `R`, so it bounds the
        // beams within `within` of it (only a beam short of the density bound can matter).
        let dense = (1.0 - SLACK) / narrowest;
        let mut bound = vec![f64::INFINITY; n];
        for (k, r) in reach.iter().enumerate() {
            let far = r.far_to / res;
            if far >= dense {
                continue;
            }
            let spread = if far - std::f64::consts::SQRT_2 > std::f64::consts::FRAC_1_SQRT_2 {
                2.0 * (std::f64::consts::FRAC_1_SQRT_2 / (far - std::f64::consts::SQRT_2)).asin()
            } else {
                std::f64::consts::PI
            };
            // Never NaN: spread is positive and finite, and the min drops an infinite quotient.
            let within = ceil_int((spread / narrowest).min(n as f64)) as usize + 1;
            let (lo, hi) = (k.saturating_sub(within), (k + within).min(n - 1));
            for b in &mut bound[lo..=hi] {
                *b = select_unpredictable(far < *b, far, *b);
            }
        }
        // Plain compares: nothing here is NaN (a NaN reach fails `far >= dense` and is skipped).
        let levels: Vec<f64> = bound
            .iter()
            .map(|&b| if b < dense { b } else { dense })
            .collect();
        let level = |k: usize| levels[k];
        // Coarse parts, as wide as 120° allows (the fill visits every part's rows), and fine ones,
        // also cut where the bound changes by more than `STEP`, so that a near return only
        // shortens the beams around it.
        let split = |fine: bool, most: usize| {
            let unit = |k: usize| reach[k].direction.normalize();
            let mut parts = Vec::new();
            let mut start = 0;
            while start + 1 < n {
                let first = reach[start].direction;
                let mut end = start + 1;
                let (mut low, mut high) = min_max(level(start), level(end));
                while end + 1 < n && end - start < most && {
                    let d = reach[end + 1].direction;
                    let next = level(end + 1);
                    within_part(first, d)
                        && (!fine || end - start < MIN_PART_BEAMS || {
                            let (lo, hi) = min_max(low, next);
                            let (_, hi) = min_max(hi, high);
                            hi - lo <= STEP
                        })
                } {
                    end += 1;
                    (low, high) = (min_max(low, level(end)).0, min_max(high, level(end)).1);
                }
                let widest = gaps[start..end]
                    .iter()
                    .copied()
                    .fold(0.0, f64::max)
                    .sqrt()
                    .asin();
                let (a, b) = (unit(start), unit(end));
                let (first, last) = if ccw { (a, b) } else { (b, a) };
                parts.push(Part {
                    beams: (start, end),
                    first,
                    last,
                    r_out: ((1.0 - SLACK) / widest).min(low),
                    r_from: 0.0,
                });
                start = end;
            }
            parts
        };
        // The coarse parts as even as their count allows: a sliver of a part left at the end
        // would cost as many rows as a whole one.
        let mut parts = split(false, n);
        if parts.len() > 1 {
            let even = split(false, (n - 1).div_ceil(parts.len()));
            if even.len() == parts.len() {
                parts = even;
            }
        }
        let coarse = parts.len();
        let fine = split(true, n);
        let half = parts
            .iter()
            .chain(&fine)
            .map(|p| p.first.dot(&p.last).clamp(-1.0, 1.0).acos() / 2.0)
            .fold(0.0, f64::max);
        let r_in = (seen + SLACK).max(inner_radius(half));
        let mut filled_to = vec![f64::INFINITY; n];
        for mut part in fine {
            let (b0, b1) = part.beams;
            // Filled by the coarse parts it overlaps (unless one of them is not filled at all).
            part.r_from = parts[..coarse]
                .iter()
                .filter(|p| p.beams.0 <= b1 && p.beams.1 >= b0)
                .map(|p| if p.filled(r_in) { p.r_out } else { 0.0 })
                .fold(f64::INFINITY, f64::min);
            let reaches = if part.r_out > part.r_from + STEP && part.filled(r_in.max(part.r_from)) {
                parts.push(part);
                part.r_out
            } else {
                part.r_from
            };
            for f in &mut filled_to[b0..=b1] {
                *f = f.min(reaches);
            }
        }
        if !parts[..coarse].iter().any(|p| p.filled(r_in)) {
            return None;
        }
        Some(Self {
            sensor: geom.grid_coords(sensor),
            r_in,
            parts,
            filled_to,
        })
    }

    /// The distances (m) from the sensor between which beam `k` needs no walking, if any: from the
    /// inner radius plus a cell diagonal to as far as the fill reaches along it, less one.
    pub(crate) fn skipped(&self, k: usize, resolution: f64) -> Option<(f64, f64)> {
        let d = std::f64::consts::SQRT_2 + SLACK;
        let (near, far) = (self.r_in + d, self.filled_to.get(k)? - d);
        (far - near > MIN_DEPTH).then_some((near * resolution, far * resolution))
    }

    /// Calls `run(y, x0, x1)` for runs of cells `x0..=x1` of row `y` that the fill marks far (each
    /// cell at least once; parts of the fan overlap at their shared edges).
    pub(crate) fn fill(&self, geom: &GridGeometry, mut run: impl FnMut(usize, usize, usize)) {
        let (sx, sy) = self.sensor;
        let (w, h) = (geom.width() as i64, geom.height() as f64);
        let r_in = self.r_in;
        for part in &self.parts {
            let (f, l, r_out) = (part.first, part.last, part.r_out);
            if !part.filled(r_in.max(part.r_from)) {
                continue;
            }
            let m = f + l; // the part's middle bearing (not normalised: only its sign is used)
            let planes = [
                // All corners in front of the part (its middle bearing): min over corners m · c > 0.
                HalfPlane::new(m.x, m.x < 0.0, m.y, m.y < 0.0),
                // Some corner strictly counter-clockwise of its first bearing: max f × c > 0.
                HalfPlane::new(-f.y, f.y <= 0.0, f.x, f.x >= 0.0),
                // Some corner strictly clockwise of its last bearing: max −(l × c) > 0.
                HalfPlane::new(l.y, l.y >= 0.0, -l.x, l.x <= 0.0),
            ];
            // The rows the part's wedge reaches from `r_from` out (a cell more each way: cells
            // overlap it; and two cells nearer: a cell whose far corner lies beyond `r_from` may
            // overlap the wedge only nearer).
            let within = |d: Vector2<f64>| f.perp(&d) >= 0.0 && d.perp(&l) >= 0.0;
            let near = (part.r_from - 2.0).max(0.0);
            let ends = [near * f.y, near * l.y, r_out * f.y, r_out * l.y];
            let up = if within(Vector2::y()) {
                r_out
            } else {
                ends.iter().copied().fold(f64::NEG_INFINITY, f64::max)
            };
            let down = if within(-Vector2::y()) {
                -r_out
            } else {
                ends.iter().copied().fold(f64::INFINITY, f64::min)
            };
            let y0 = (floor_of(sy + down) - 1.0).max(0.0);
            let y1 = (floor_of(sy + up) + 1.0).min(h - 1.0);
            // Two rows at a time: the bounds are float arithmetic (two square roots, five
            // floors), lane for lane the same as one row's; only the runs are emitted one by one.
            let (r_out2, r_in2) = (f64x2::splat(r_out * r_out), f64x2::splat(r_in * r_in));
            let (sx2, sy2) = (f64x2::splat(sx), f64x2::splat(sy));
            let one = f64x2::splat(1.0);
            let mut y = y0;
            while y <= y1 {
                let ya = f64x2::new([y, y + 1.0]) - sy2;
                let yb = ya + one;
                let y_far = ya.abs().fast_max(yb.abs());
                let inside = y_far.simd_lt(f64x2::splat(r_out)).to_bitmask();
                if inside == 0 {
                    y += 2.0;
                    continue;
                }
                // All four corners within r_out (the lanes outside are not emitted).
                let half = (r_out2 - y_far * y_far).fast_max(f64x2::ZERO).sqrt();
                let mut lo = ceil_lanes(sx2 - half);
                let mut hi = floor_lanes(sx2 + half) - one;
                for plane in &planes {
                    (lo, hi) = plane.clip(lo, hi, ya, yb, sx2);
                }
                let lo = lo.fast_max(f64x2::ZERO).to_array();
                let hi = hi.fast_min(f64x2::splat(w as f64 - 1.0)).to_array();
                // Nearest point at least r_in away: a hole around the sensor's column.
                let straddles = ya.simd_le(f64x2::ZERO) & yb.simd_ge(f64x2::ZERO);
                let y_near = straddles.select(f64x2::ZERO, ya.abs().fast_min(yb.abs()));
                let holed = y_near.simd_lt(f64x2::splat(r_in)).to_bitmask();
                let v = (r_in2 - y_near * y_near).fast_max(f64x2::ZERO).sqrt();
                let hole_hi = (floor_lanes(sx2 - v) - one).to_array();
                let hole_lo = ceil_lanes(sx2 + v).to_array();
                for lane in 0..2 {
                    let row = y + lane as f64;
                    if row > y1 || inside >> lane & 1 == 0 {
                        continue;
                    }
                    let (lo, hi) = (lo[lane] as i64, hi[lane] as i64);
                    if holed >> lane & 1 == 0 {
                        emit(row as usize, lo, hi, &mut run);
                    } else {
                        let (hole_hi, hole_lo) = (hole_hi[lane] as i64, hole_lo[lane] as i64);
                        emit(row as usize, lo, hi.min(hole_hi), &mut run);
                        emit(row as usize, lo.max(hole_lo), hi, &mut run);
                    }
                }
                y += 2.0;
            }
        }
    }
}

/// One of a part's conditions on the cells of a row: `a·X + c·Y > 0` for the cell's corner column
/// X (its right edge when `right`, else its left) and corner row Y (its upper edge when `upper`),
/// both relative to the sensor: linear along the row, so it bounds the row's cells on one side.
#[derive(Clone, Copy, Debug)]
struct HalfPlane {
    a: f64,
    /// `1 / a` (0 when `a` is).
    inv_a: f64,
    right: f64,
    c: f64,
    upper: bool,
}

impl HalfPlane {
    fn new(a: f64, right: bool, c: f64, upper: bool) -> Self {
        Self {
            a,
            inv_a: if a != 0.0 { 1.0 / a } else { 0.0 },
            right: if right { 1.0 } else { 0.0 },
            c,
            upper,
        }
    }

    /// Narrows cells `lo..=hi` (as floats) of two rows whose cells' lower and upper edges are
    /// `ya` and `yb` (relative to the sensor) to those meeting the condition, lane by lane.
    #[inline]
    fn clip(&self, lo: f64x2, hi: f64x2, ya: f64x2, yb: f64x2, sx: f64x2) -> (f64x2, f64x2) {
        let b = f64x2::splat(self.c) * if self.upper { yb } else { ya };
        // a·(x + right − sx) + b > 0  ⇔  x > or < sx − right − b / a.
        let at = sx - f64x2::splat(self.right) - b * f64x2::splat(self.inv_a);
        // NaN only from an infinite sensor coordinate or 1 / a: no bound (as a float bound's max
        // and min would ignore it).
        let known = at.simd_eq(at);
        if self.a > 0.0 {
            let bound = floor_lanes(at) + f64x2::splat(1.0);
            (known.select(lo.fast_max(bound), lo), hi)
        } else if self.a < 0.0 {
            let bound = ceil_lanes(at) - f64x2::splat(1.0);
            (lo, known.select(hi.fast_min(bound), hi))
        } else {
            let keep = b.simd_gt(f64x2::ZERO) | !known;
            (
                keep.select(lo, f64x2::splat(1.0)),
                keep.select(hi, f64x2::ZERO),
            )
        }
    }
}

/// [`floor_int`] lane by lane, as floats (integers): the same rounding, in two lanes at once.
#[inline]
fn floor_lanes(x: f64x2) -> f64x2 {
    const ROUND: f64 = 6_755_399_441_055_744.0;
    let x = x.fast_max(f64x2::splat(-1e15)).fast_min(f64x2::splat(1e15));
    let r = (x + f64x2::splat(ROUND)) - f64x2::splat(ROUND);
    r - (r.simd_gt(x) & f64x2::splat(1.0))
}

/// [`ceil_int`] lane by lane, as floats.
#[inline]
fn ceil_lanes(x: f64x2) -> f64x2 {
    -floor_lanes(-x)
}

/// `x.floor()` for the fill's bounds, without a library call, a branch (the grid's own `floor`
/// branches on the sign and fraction, which a row's bounds make unpredictable) or a conversion.
/// Exact for |x| < 10¹⁵; a bound beyond that lies outside any grid and is clamped to it anyway.
fn floor_of(x: f64) -> f64 {
    // Adding and taking away 1.5·2⁵² rounds to the nearest integer (exactly, for |x| < 2⁵¹);
    // one less if that rounded up.
    const ROUND: f64 = 6_755_399_441_055_744.0;
    let x = x.clamp(-1e15, 1e15);
    let r = (x + ROUND) - ROUND;
    r - f64::from(u8::from(r > x))
}

/// `x.ceil()`, likewise.
#[cfg(test)]
fn ceil(x: f64) -> f64 {
    -floor_of(-x)
}

/// [`floor_of`] as an integer: `x` clamped to ±10¹⁵ and floored, with integer compares and
/// selects where the float's `r > x` would be an unpredictable branch. Exact for every `x` but NaN
/// (meaningless then: the callers rule it out). No float-to-integer conversion, whose saturation
/// and NaN checks cost more than the floor: the rounded value's bits are the integer.
#[inline]
fn floor_int(x: f64) -> i64 {
    // Adding 1.5·2⁵² rounds to the nearest integer and lands in [2⁵², 2⁵³), where consecutive
    // integers have consecutive bit patterns.
    const ROUND: f64 = 6_755_399_441_055_744.0;
    let x = x.clamp(-1e15, 1e15);
    let m = x + ROUND;
    let nearest = m.to_bits() as i64 - ROUND.to_bits() as i64;
    nearest - i64::from(m - ROUND > x)
}

/// `x.ceil()` as an integer, likewise.
#[inline]
fn ceil_int(x: f64) -> i64 {
    -floor_int(-x)
}

/// The lesser and the greater of two numbers that are not NaN. Selects, not a branch: along a
/// fan the bounds go up and down as the returns do.
#[inline]
fn min_max(a: f64, b: f64) -> (f64, f64) {
    let less = a < b;
    (
        select_unpredictable(less, a, b),
        select_unpredictable(less, b, a),
    )
}

/// Calls `run` for cells `lo..=hi` of `row` if there are any.
#[inline]
fn emit(row: usize, lo: i64, hi: i64, run: &mut impl FnMut(usize, usize, usize)) {
    if lo <= hi && hi >= 0 {
        run(row, lo.max(0) as usize, hi as usize);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point2;

    /// The fill as it was with float row bounds (before `floor_int`): the oracle.
    fn fill_before(
        near: &NearField,
        geom: &GridGeometry,
        mut run: impl FnMut(usize, usize, usize),
    ) {
        let (sx, sy) = near.sensor;
        let (w, h) = (geom.width() as f64, geom.height() as f64);
        let r_in = near.r_in;
        for part in &near.parts {
            let (f, l, r_out) = (part.first, part.last, part.r_out);
            if !part.filled(r_in) {
                continue;
            }
            let m = f + l; // the part's middle bearing (not normalised: only its sign is used)
            let planes = [
                // All corners in front of the part (its middle bearing): min over corners m · c > 0.
                HalfPlane::new(m.x, m.x < 0.0, m.y, m.y < 0.0),
                // Some corner strictly counter-clockwise of its first bearing: max f × c > 0.
                HalfPlane::new(-f.y, f.y <= 0.0, f.x, f.x >= 0.0),
                // Some corner strictly clockwise of its last bearing: max −(l × c) > 0.
                HalfPlane::new(l.y, l.y >= 0.0, -l.x, l.x <= 0.0),
            ];
            // The rows the part's wedge reaches (a cell more each way: cells overlap it).
            let within = |d: Vector2<f64>| f.perp(&d) >= 0.0 && d.perp(&l) >= 0.0;
            let up = if within(Vector2::y()) {
                1.0
            } else {
                f.y.max(l.y).max(0.0)
            };
            let down = if within(-Vector2::y()) {
                -1.0
            } else {
                f.y.min(l.y).min(0.0)
            };
            let y0 = (floor_of(sy + r_out * down) - 1.0).max(0.0);
            let y1 = (floor_of(sy + r_out * up) + 1.0).min(h - 1.0);
            let mut y = y0;
            while y <= y1 {
                let (ya, yb) = (y - sy, y + 1.0 - sy);
                let y_far = ya.abs().max(yb.abs());
                if y_far < r_out {
                    // All four corners within r_out.
                    let half = (r_out * r_out - y_far * y_far).sqrt();
                    let mut lo = ceil(sx - half);
                    let mut hi = floor_of(sx + half) - 1.0;
                    for plane in &planes {
                        (lo, hi) = clip_before(plane, lo, hi, ya, yb, sx);
                    }
                    lo = lo.max(0.0);
                    hi = hi.min(w - 1.0);
                    // Nearest point at least r_in away: a hole around the sensor's column.
                    let y_near = if ya <= 0.0 && yb >= 0.0 {
                        0.0
                    } else {
                        ya.abs().min(yb.abs())
                    };
                    let row = y as usize;
                    if y_near >= r_in {
                        emit_before(row, lo, hi, &mut run);
                    } else {
                        let v = (r_in * r_in - y_near * y_near).sqrt();
                        emit_before(row, lo, hi.min(floor_of(sx - v) - 1.0), &mut run);
                        emit_before(row, lo.max(ceil(sx + v)), hi, &mut run);
                    }
                }
                y += 1.0;
            }
        }
    }

    fn clip_before(plane: &HalfPlane, lo: f64, hi: f64, ya: f64, yb: f64, sx: f64) -> (f64, f64) {
        let b = plane.c * if plane.upper { yb } else { ya };
        // a·(x + right − sx) + b > 0  ⇔  x > or < sx − right − b / a.
        let at = sx - plane.right - b * plane.inv_a;
        if plane.a > 0.0 {
            (lo.max(floor_of(at) + 1.0), hi)
        } else if plane.a < 0.0 {
            (lo, hi.min(ceil(at) - 1.0))
        } else if b > 0.0 {
            (lo, hi)
        } else {
            (1.0, 0.0)
        }
    }

    fn emit_before(row: usize, lo: f64, hi: f64, run: &mut impl FnMut(usize, usize, usize)) {
        if lo <= hi && hi >= 0.0 {
            run(row, lo.max(0.0) as usize, hi as usize);
        }
    }

    #[test]
    fn a_fan_with_one_bad_gap_anywhere_has_no_near_field() {
        // Invariant: NearField::of is None when any neighbouring pair of beams (first, middle or
        // last) turns the other way, is 90° or more apart, repeats a bearing or has a zero
        // direction, and Some for the same dense fan without it.
        let geom = GridGeometry::with_cells(Point2::new(0.0, 0.0), 400, 400, 0.05).expect("valid");
        let sensor = Point2::new(10.0, 10.0);
        let fan = |n: usize| -> Vec<Reach> {
            (0..n)
                .map(|k| {
                    let a = -1.5 + 3.0 * k as f64 / (n - 1) as f64;
                    Reach {
                        direction: Vector2::new(a.cos(), a.sin()) * 6.0,
                        length: 6.0,
                        seen_from: 0.0,
                        far_to: 5.8,
                    }
                })
                .collect()
        };
        let good = fan(361);
        assert!(NearField::of(&geom, sensor, &good).is_some());
        for at in [1, 180, 360] {
            let mut bad = good.clone();
            bad[at].direction = good[at - 1].direction; // a repeated bearing
            assert!(
                NearField::of(&geom, sensor, &bad).is_none(),
                "repeat at {at}"
            );
            let mut bad = good.clone();
            bad[at].direction = Vector2::zeros();
            assert!(NearField::of(&geom, sensor, &bad).is_none(), "zero at {at}");
            let mut bad = good.clone();
            bad.swap(at - 1, at); // turns back
            assert!(NearField::of(&geom, sensor, &bad).is_none(), "swap at {at}");
            let mut bad = good.clone();
            bad[at].direction = -good[at - 1].direction; // 90° or more
            assert!(NearField::of(&geom, sensor, &bad).is_none(), "wide at {at}");
        }
    }

    #[test]
    fn a_part_filled_from_a_radius_marks_every_cell_reaching_beyond_it() {
        // Invariant: a part filled only from `r_from` out (deep enough there to be filled at all)
        // marks a subset of the cells the whole part marks, and among them every one whose far
        // corner lies at `r_from` or beyond.
        let geom = GridGeometry::with_cells(Point2::new(0.0, 0.0), 300, 300, 0.05).expect("valid");
        let mut r = super::super::test_rng::uniform(0x1234_5678_9abc_def1_u64);
        let cells = |near: &NearField| {
            let mut set = std::collections::BTreeSet::new();
            near.fill(&geom, |y, x0, x1| set.extend((x0..=x1).map(|x| (x, y))));
            set
        };
        let mut checked = 0;
        for case in 0..400 {
            let (sx, sy) = (100.0 + r() * 100.0, 100.0 + r() * 100.0);
            let theta = r() * std::f64::consts::TAU;
            let width = r() * 1.5;
            let unit = |a: f64| Vector2::new(a.cos(), a.sin());
            let r_out = 20.0 + r() * 120.0;
            let part = Part {
                beams: (0, 1),
                first: unit(theta),
                last: unit(theta + width),
                r_out,
                r_from: 0.0,
            };
            let near = |part: Part| NearField {
                sensor: (sx, sy),
                r_in: 2.0,
                parts: vec![part],
                filled_to: Vec::new(),
            };
            let whole = cells(&near(part));
            let r_from = r() * r_out;
            let banded = Part { r_from, ..part };
            if !banded.filled(r_from.max(2.0)) {
                continue; // too thin a band to fill: never kept
            }
            let band = cells(&near(banded));
            assert!(band.is_subset(&whole), "case {case}");
            for &(x, y) in &whole {
                let far_x = (x as f64 - sx).abs().max((x as f64 + 1.0 - sx).abs());
                let far_y = (y as f64 - sy).abs().max((y as f64 + 1.0 - sy).abs());
                if far_x.hypot(far_y) >= r_from {
                    assert!(band.contains(&(x, y)), "case {case}: cell {x}, {y}");
                    checked += 1;
                }
            }
        }
        assert!(checked > 100_000, "only {checked} cells checked");
    }

    #[test]
    fn integer_row_bounds_give_the_runs_the_float_bounds_gave() {
        // Invariant: fill emits exactly the runs, in the same order, that the float-bounded fill
        // it replaced did, for parts of any bearing (axis-aligned ones too), width and radii, and
        // sensors inside, beside and far outside the grid (infinitely far included).
        let geom = GridGeometry::with_cells(Point2::new(0.0, 0.0), 230, 170, 0.05).expect("valid");
        let mut r = super::super::test_rng::uniform(0x2545_f491_4f6c_dd1d_u64);
        let mut runs = 0;
        for case in 0..3000 {
            let sensor = match case % 10 {
                0 => (-40.0 + r() * 310.0, -40.0 + r() * 250.0),
                1 => (1e300 * (r() - 0.5), 85.0),
                2 => (f64::INFINITY, 50.0 + r() * 60.0),
                3 => (115.0, f64::NEG_INFINITY),
                4 => ((r() * 230.0).floor(), (r() * 170.0).floor()),
                _ => (r() * 230.0, r() * 170.0),
            };
            let r_in = 2.0 + r() * 8.0;
            let mut parts = Vec::new();
            for _ in 0..1 + (r() * 4.0) as usize {
                let (theta, width) = if r() < 0.3 {
                    // Exactly along an axis, and exactly 0° to 90° wide.
                    let k = (r() * 4.0).floor() * std::f64::consts::FRAC_PI_2;
                    (k, (r() * 3.0).floor() * 0.5 * std::f64::consts::FRAC_PI_4)
                } else {
                    (r() * std::f64::consts::TAU, r() * 1.55)
                };
                let unit = |a: f64| {
                    // Exact axes where the angle is a multiple of 90°.
                    let (c, s) = (a.cos(), a.sin());
                    let snap = |v: f64| if v.abs() < 1e-12 { 0.0 } else { v };
                    Vector2::new(snap(c), snap(s))
                };
                parts.push(Part {
                    beams: (0, 1),
                    first: unit(theta),
                    last: unit(theta + width),
                    r_out: r_in + r() * 160.0,
                    r_from: 0.0,
                });
            }
            let near = NearField {
                sensor,
                r_in,
                parts,
                filled_to: Vec::new(),
            };
            let (mut got, mut want) = (Vec::new(), Vec::new());
            near.fill(&geom, |y, x0, x1| got.push((y, x0, x1)));
            fill_before(&near, &geom, |y, x0, x1| want.push((y, x0, x1)));
            assert_eq!(got, want, "case {case}: {near:?}");
            runs += got.len();
        }
        assert!(runs > 100_000, "only {runs} runs compared");
    }
}
