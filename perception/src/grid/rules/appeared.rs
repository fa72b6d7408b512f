//! Moving obstacles on the ray (Tamura 3.1 as range-image differencing): a return where the previous
//! frame's beams at its bearing went on past it with nothing returned.
//!
//! The cell rule (`moving.rs`) needs the cell seen free in two frames, so it cannot call anything
//! moving that enters space only one frame ever saw: a person walking towards the robot out of the
//! range limit is first returned where the previous frame's rays ran out (the last `clear_tail` of a
//! beam without a return is not counted as seen), and next returned where the previous frame's rays
//! ended on the person itself, a step farther. On the ray both are plain: from the previous sensor
//! position, the beams at the return's bearing reached farther than the return, and nothing was there.
//!
//! Why it does not fire on static surfaces: a static point `p` seen now lies on a surface the previous
//! frame's ray towards `p` could not pass, so the previous range at `p`'s bearing (from the previous
//! sensor position, so the robot's own motion cancels) is at most `|p − previous sensor|`. A wall
//! entering the range limit was farther than the limit from the previous position, which no previous
//! beam reached; a grazed wall returns on the previous beams around `p`'s bearing, one of which lies
//! on its near side. Beams are discrete, so the test asks the two previous beams straddling `p`'s
//! bearing *and* the next one out on each side to have gone on at least `gap` (range noise of both
//! frames) past `p`: a continuous surface through `p` cannot lie beyond `p` on both sides, and one
//! dropped-out return (even on the near side of a grazed wall) does not fire it. Evaluated on rays
//! rather than cells, it needs no cell to have been seen free, and it costs one binary search per
//! return.

use nalgebra::{Point2, Vector2};

use super::super::frame::{BeamEnd, RangeFrame};
use super::super::geometry::GridGeometry;

/// How many median beam steps from a return's bearing the two previous beams straddling it may lie
/// (within one on an even scan): a gap in the previous frame (columns without data) says nothing
/// about the bearings inside it.
const BRACKET_STEPS: f64 = 1.5;

/// Likewise for the next previous beam out on each side (within two on an even scan).
const OUTER_STEPS: f64 = 2.5;

/// Pseudo-angles closer than this may order differently from the bearings they stand for; farther
/// apart they cannot. Rounding moves a pseudo-angle by a few 10⁻¹⁶ and a bearing (`atan2`) by one
/// ulp of π, and a bearing changes at most twice as fast as its pseudo-angle: a margin a million
/// times that leaves no doubt.
const PSEUDO_MARGIN: f64 = 1e-9;

/// What one previous beam saw along its bearing.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Seen {
    /// From the previous sensor position to the beam's end (m).
    to_end: Vector2<f64>,
    /// [`pseudo_angle`] of `to_end`: rises with the bearing, and costs one division.
    pseudo: f64,
    /// Map-frame bearing from the previous sensor position (rad, in (−π, π]); NaN until
    /// [`PreviousBeams::fill_bearings`] fills it in.
    bearing: f64,
    /// How far the beam went with nothing returned before it (m): to its return or its clear end.
    reach: f64,
    /// From how far the beam saw at all (a camera's lowest ray, [`super::super::Beam::seen_from`]).
    seen_from: f64,
}

impl Seen {
    /// Whether the beam went on at least `gap` past a point at `range` with nothing returned, and saw
    /// from nearer than it: the test of [`PreviousBeams::appeared`] short of the bearing's.
    #[inline]
    fn went_past(&self, range: f64, gap: f64) -> bool {
        self.reach >= range + gap && self.seen_from <= range
    }
}

/// The previous frame's beams ordered by bearing from its sensor: what the last frame saw along each
/// bearing, for [`PreviousBeams::appeared`].
///
/// Bearings (`atan2`) and their median step are only worked out once a return passes the test
/// without them (see [`PreviousBeams::appeared`]): most returns of a frame lie on surfaces the
/// previous beams returned from as well, and are turned down by the beams' reaches alone, found by
/// pseudo-angle.
#[derive(Clone, Debug, Default)]
pub(crate) struct PreviousBeams {
    /// The previous frame's sensor position; `None` before the first frame.
    sensor: Option<Point2<f64>>,
    /// Sorted by bearing, ties in frame order.
    beams: Vec<Seen>,
    /// The pseudo-angles of `beams` rise by more than [`PSEUDO_MARGIN`] from beam to beam: their
    /// order is the bearings', and a pseudo-angle search brackets a bearing search.
    by_pseudo: bool,
    /// `beams`' bearings and `step` are filled in.
    exact: bool,
    /// Median angle between bearing-neighbouring beams (rad), once `exact`.
    step: f64,
    /// Reused buffer for the median.
    gaps: Vec<f64>,
    /// Where the last pseudo-angle search ended: returns come in bearing order, so the next one
    /// is usually found a beam or two away.
    hint: usize,
}

impl PreviousBeams {
    /// Keeps `frame` as the previous frame for the next one's test: O(n) for n beams in bearing
    /// order (either way round, or two runs split at the ±π seam), O(n log n) otherwise.
    pub(crate) fn remember(&mut self, frame: &RangeFrame) {
        let s = frame.sensor();
        self.sensor = Some(s);
        self.exact = false;
        self.hint = 0;
        self.beams.clear();
        self.beams.extend(frame.beams().iter().map(|b| {
            let v = b.end - s;
            Seen {
                to_end: v,
                pseudo: pseudo_angle(v),
                bearing: f64::NAN,
                reach: v.norm(),
                seen_from: b.seen_from,
            }
        }));
        if !self.beams.is_sorted_by(|a, b| a.pseudo <= b.pseudo) {
            if self.beams.is_sorted_by(|a, b| a.pseudo >= b.pseudo) {
                self.beams.reverse();
            } else {
                self.beams.sort_by(|a, b| a.pseudo.total_cmp(&b.pseudo));
            }
        }
        self.by_pseudo = self
            .beams
            .windows(2)
            .all(|w| w[1].pseudo - w[0].pseudo > PSEUDO_MARGIN);
        if !self.by_pseudo {
            // Bearings within the margin (repeated directions, a beam of length 0): sort by the
            // bearings themselves, from the frame's order, so that ties keep it.
            self.beams.clear();
            self.beams.extend(frame.beams().iter().map(|b| {
                let v = b.end - s;
                Seen {
                    to_end: v,
                    pseudo: f64::NAN,
                    bearing: v.y.atan2(v.x),
                    reach: v.norm(),
                    seen_from: b.seen_from,
                }
            }));
            self.beams.sort_by(|a, b| a.bearing.total_cmp(&b.bearing));
            self.exact_step();
        }
    }

    /// Fills in the bearings (in pseudo-angle order, which is theirs) and their median step.
    fn fill_bearings(&mut self) {
        if self.exact {
            return;
        }
        for b in &mut self.beams {
            b.bearing = b.to_end.y.atan2(b.to_end.x);
        }
        self.exact_step();
    }

    /// The median angle between bearing-neighbouring beams, from the sorted bearings.
    fn exact_step(&mut self) {
        self.gaps.clear();
        self.gaps
            .extend(self.beams.windows(2).map(|w| w[1].bearing - w[0].bearing));
        self.step = if self.gaps.is_empty() {
            0.0
        } else {
            let mid = self.gaps.len() / 2;
            *self.gaps.select_nth_unstable_by(mid, f64::total_cmp).1
        };
        self.exact = true;
    }

    /// Whether a return at `p` lies at least `gap` inside what the previous frame saw empty along its
    /// bearing: seen from the previous sensor position, the two previous beams straddling `p`'s
    /// bearing and the next one out on each side (all close to that bearing: [`BRACKET_STEPS`],
    /// [`OUTER_STEPS`]) went on at least `gap` past `p` with nothing returned, and saw from nearer
    /// than `p`.
    ///
    /// Decided first without bearings: the pseudo-angle search brackets where `p`'s bearing falls
    /// among the beams' (usually on one place), and if no four beams around any place in the bracket
    /// all went past `p`, it has not appeared. Only otherwise are the bearings worked out.
    pub(crate) fn appeared(&mut self, p: Point2<f64>, gap: f64) -> bool {
        let (Some(s), n) = (self.sensor, self.beams.len()) else {
            return false;
        };
        if n < 3 {
            return false;
        }
        let v = p - s;
        let range = v.norm();
        if !(range > 0.0 && range.is_finite()) {
            return false;
        }
        if self.by_pseudo && !self.may_have_appeared(v, range, gap) {
            return false;
        }
        self.fill_bearings();
        if self.step <= 0.0 {
            return false;
        }
        let bearing = v.y.atan2(v.x);
        let k = self.beams.partition_point(|b| b.bearing < bearing);
        let (step, bracket, outer) = (self.step, BRACKET_STEPS, OUTER_STEPS);
        [(-2, outer), (-1, bracket), (0, bracket), (1, outer)]
            .into_iter()
            .all(|(d, steps)| {
                let b = &self.beams[(k + n).wrapping_add_signed(d) % n];
                angle_between(b.bearing, bearing) <= steps * step && b.went_past(range, gap)
            })
    }

    /// False when no place `k` the bearing of `v` may take among the beams' (the count of beams
    /// below it) has beams `k − 2 ..= k + 1` (around the seam) that all went past `range` + `gap`:
    /// [`Self::appeared`] is false then whatever the bearings. Needs `by_pseudo`.
    fn may_have_appeared(&mut self, v: Vector2<f64>, range: f64, gap: f64) -> bool {
        let q = pseudo_angle(v);
        if q.is_nan() {
            return true;
        }
        let n = self.beams.len();
        // Beams more than the margin below `q` have lower bearings, more than it above higher ones.
        let lo = self.rank(q - PSEUDO_MARGIN);
        let mut hi = lo;
        while hi < n && self.beams[hi].pseudo <= q + PSEUDO_MARGIN {
            hi += 1;
        }
        self.hint = lo;
        // Beam `j` for j in n − 2 ..= 2n + 1: `j mod n` without a division.
        let past = |j: usize| {
            let j = if j >= n { j - n } else { j };
            self.beams[if j >= n { j - n } else { j }].went_past(range, gap)
        };
        (lo..=hi).any(|k| (k + n - 2..k + n + 2).all(past))
    }

    /// How many beams have a pseudo-angle below `x`, searched from the last search's end.
    fn rank(&self, x: f64) -> usize {
        let b = &self.beams;
        let mut k = self.hint.min(b.len());
        // A few beams either way, then a binary search.
        for _ in 0..4 {
            if k < b.len() && b[k].pseudo < x {
                k += 1;
            } else if k > 0 && b[k - 1].pseudo >= x {
                k -= 1;
            } else {
                return k;
            }
        }
        if k < b.len() && b[k].pseudo < x {
            k + b[k..].partition_point(|s| s.pseudo < x)
        } else if k > 0 && b[k - 1].pseudo >= x {
            b[..k].partition_point(|s| s.pseudo < x)
        } else {
            k
        }
    }
}

/// The cells holding a return that appeared this frame, and the frame kept for the next one's test.
#[derive(Clone, Debug, Default)]
pub(crate) struct Appearances {
    previous: PreviousBeams,
    /// Linear indices, sorted, without repeats.
    cells: Vec<u32>,
}

impl Appearances {
    /// Tests every return of `frame` against the previous frame (see [`PreviousBeams::appeared`]),
    /// lists the cells of those that appeared, and keeps `frame` for the next call.
    pub(crate) fn observe(&mut self, frame: &RangeFrame, g: &GridGeometry, gap: f64) {
        self.cells.clear();
        let hits = frame.beams().iter().filter(|b| b.kind == BeamEnd::Hit);
        for b in hits {
            // The ray test first: it turns down most returns, sparing their cells' look-up.
            if self.previous.appeared(b.end, gap)
                && let Some(i) = g.cell_of(b.end).and_then(|c| g.index(c))
            {
                self.cells.push(i as u32);
            }
        }
        self.cells.sort_unstable();
        self.cells.dedup();
        self.previous.remember(frame);
    }

    /// Whether a return in cell `i` appeared in the frame last observed.
    pub(crate) fn contains(&self, i: usize) -> bool {
        u32::try_from(i).is_ok_and(|i| self.cells.binary_search(&i).is_ok())
    }
}

/// A number that rises with the bearing `atan2(v.y, v.x)`: over [−2, 2] as the bearing over
/// [−π, π], with the seam in the same place (the sign of a zero `y` picks its side, as for `atan2`).
/// NaN for a zero or overflowing vector. It is the distance walked along the unit diamond
/// |x| + |y| = 1 from +x, and grows at least half as fast as the bearing.
#[inline]
fn pseudo_angle(v: Vector2<f64>) -> f64 {
    let (x, y) = (v.x, v.y);
    let l1 = x.abs() + y.abs();
    if !(l1 > 0.0 && l1.is_finite()) {
        return f64::NAN;
    }
    let t = y / l1;
    if x >= 0.0 {
        t
    } else if y.is_sign_negative() {
        -2.0 - t
    } else {
        2.0 - t
    }
}

/// The absolute angle between two bearings (rad, in [0, π]), across the ±π seam too.
fn angle_between(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::TAU);
    d.min(std::f64::consts::TAU - d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::Beam;
    use crate::grid::BeamEnd;

    const STEP_DEG: f64 = 0.25;
    const GAP: f64 = 0.06;

    /// A fan of beams from `sensor`, 0.25° apart between bearings `from`..`to` (deg), each ending where
    /// `surface` says (`Some((range, hit))`) or dropped (`None`).
    fn fan(
        sensor: Point2<f64>,
        from: f64,
        to: f64,
        surface: impl Fn(f64) -> Option<(f64, BeamEnd)>,
    ) -> RangeFrame {
        let mut f = RangeFrame::new(sensor).expect("finite");
        let n = ((to - from) / STEP_DEG).round() as usize;
        for k in 0..=n {
            let deg = from + k as f64 * STEP_DEG;
            if let Some((r, kind)) = surface(deg) {
                let b = deg.to_radians();
                let end = sensor + r * nalgebra::Vector2::new(b.cos(), b.sin());
                f.push_beam(Beam {
                    end,
                    kind,
                    seen_from: 0.0,
                });
            }
        }
        f
    }

    fn at(sensor: Point2<f64>, deg: f64, r: f64) -> Point2<f64> {
        let b = deg.to_radians();
        sensor + r * nalgebra::Vector2::new(b.cos(), b.sin())
    }

    #[test]
    fn an_object_inside_the_previous_range_appeared() {
        // Invariant: a return in front of where the previous frame's beams around its bearing ran out
        // (clear to the 5 m limit) or ended (on something a step farther) has appeared; one within the
        // gap of that range, or behind it, has not.
        let s0 = Point2::new(0.0, 0.0);
        let mut prev = PreviousBeams::default();
        // Clear to 5 m everywhere except a person at 4.9 m between 1° and 3°.
        prev.remember(&fan(s0, -20.0, 20.0, |deg| {
            Some(if (1.0..=3.0).contains(&deg) {
                (4.9, BeamEnd::Hit)
            } else {
                (5.0, BeamEnd::Clear)
            })
        }));
        // The robot stepped 2 cm forward; the person stepped 10 cm towards it.
        let s1 = Point2::new(0.02, 0.0);
        assert!(prev.appeared(at(s1, -5.0, 4.8), GAP), "in the clear range");
        assert!(
            prev.appeared(at(s0, 2.0, 4.8), GAP),
            "in front of the person"
        );
        assert!(!prev.appeared(at(s0, 2.0, 4.86), GAP), "within the gap");
        assert!(!prev.appeared(at(s0, -5.0, 5.1), GAP), "beyond the range");
        // Outside the previous fan nothing was seen: entering the field of view is not appearing.
        assert!(!prev.appeared(at(s0, 25.0, 2.0), GAP));
        // Before any previous frame nothing has appeared.
        assert!(!PreviousBeams::default().appeared(at(s0, 0.0, 1.0), GAP));
    }

    #[test]
    fn a_wall_entering_at_the_range_limit_has_not_appeared() {
        // Invariant: a static wall across the view, 5.05 m from the previous position (beyond the 5 m
        // limit, so clear beams to the limit then), returned at 5.0 m now after a 5 cm step, has not
        // appeared: no previous beam reached past it.
        let s0 = Point2::new(0.0, 0.0);
        let wall_x = 5.05;
        let mut prev = PreviousBeams::default();
        prev.remember(&fan(s0, -20.0, 20.0, |deg| {
            let r = wall_x / deg.to_radians().cos();
            Some(if r < 5.0 {
                (r, BeamEnd::Hit)
            } else {
                (5.0, BeamEnd::Clear)
            })
        }));
        let s1 = Point2::new(0.05, 0.0);
        for k in -80..=80 {
            let deg = k as f64 * STEP_DEG + 0.1;
            let r = (wall_x - s1.x) / deg.to_radians().cos();
            if r <= 5.0 {
                assert!(!prev.appeared(at(s1, deg, r), GAP), "bearing {deg}°");
            }
        }
    }

    #[test]
    fn a_grazed_wall_has_not_appeared() {
        // Invariant: along a side wall grazed at a shallow angle (range growing fast with bearing, some
        // previous returns dropped), a return now on the wall, between the previous beams and after the
        // sensor moved, has not appeared: the previous beams on its near side returned before it.
        let s0 = Point2::new(0.0, 0.0);
        let wall_y = 0.6;
        // The wall y = 0.6 seen at bearing b lies at range 0.6 / sin b: 4.9 m at about 7°.
        let surface = |deg: f64| {
            let r = wall_y / deg.to_radians().sin();
            (deg > 0.0).then_some(())?;
            // Every fifth return drops out (grazing beyond the camera's incidence limit).
            let dropped = (deg / STEP_DEG).round() as i64 % 5 == 0;
            Some(if r > 5.0 || dropped {
                (5.0, BeamEnd::Clear)
            } else {
                (r, BeamEnd::Hit)
            })
        };
        let mut prev = PreviousBeams::default();
        prev.remember(&fan(s0, -20.0, 20.0, surface));
        let s1 = Point2::new(0.02, 0.0);
        let mut tested = 0;
        for k in 0..400 {
            // Returns on the wall at x from 1 m to 5 m, from the moved sensor.
            let p = Point2::new(1.0 + k as f64 * 0.01, wall_y);
            if (p - s1).norm() <= 5.0 {
                tested += 1;
                assert!(!prev.appeared(p, GAP), "wall point {p}");
            }
        }
        assert!(tested > 300);
        // The same fan with the wall gone: the points in front of the 5 m limit have appeared.
        prev.remember(&fan(s0, -20.0, 20.0, |_| Some((5.0, BeamEnd::Clear))));
        assert!(prev.appeared(Point2::new(4.0, wall_y), GAP));
    }

    #[test]
    fn a_single_dropped_return_is_not_an_appearance() {
        // Invariant: a return behind which only one previous beam went on (its neighbours returned at
        // the same range) has not appeared; with all three gone on it has.
        let s0 = Point2::new(0.0, 0.0);
        let mut prev = PreviousBeams::default();
        prev.remember(&fan(s0, -5.0, 5.0, |deg| {
            Some(if deg.abs() < 0.1 {
                (8.0, BeamEnd::Clear)
            } else {
                (3.0, BeamEnd::Hit)
            })
        }));
        assert!(!prev.appeared(at(s0, 0.0, 3.0), GAP));
        prev.remember(&fan(s0, -5.0, 5.0, |deg| {
            Some(if deg.abs() < 0.3 {
                (8.0, BeamEnd::Clear)
            } else {
                (3.0, BeamEnd::Hit)
            })
        }));
        assert!(prev.appeared(at(s0, 0.0, 2.9), GAP));
    }

    #[test]
    fn bearings_wrap_across_the_seam_and_the_lowest_ray_counts() {
        // Invariant: a sensor looking along −x (bearings on both sides of ±π) is searched across the
        // seam; a return nearer than where the previous beams began to see has not appeared.
        let s0 = Point2::new(0.0, 0.0);
        let mut prev = PreviousBeams::default();
        prev.remember(&fan(s0, 170.0, 190.0, |_| Some((5.0, BeamEnd::Clear))));
        assert!(prev.appeared(at(s0, 180.0, 3.0), GAP));
        assert!(prev.appeared(at(s0, 179.9, 3.0), GAP));
        let mut f = RangeFrame::new(s0).expect("finite");
        for k in -4..=4 {
            let b = (k as f64 * STEP_DEG).to_radians();
            f.push_beam(Beam {
                end: at(s0, b.to_degrees(), 5.0),
                kind: BeamEnd::Clear,
                seen_from: 2.0,
            });
        }
        prev.remember(&f);
        assert!(prev.appeared(at(s0, 0.0, 3.0), GAP));
        assert!(
            !prev.appeared(at(s0, 0.0, 1.5), GAP),
            "under the lowest ray"
        );
    }

    /// The rule in its straightforward form: every bearing by `atan2`, a sort, a binary search.
    struct Reference {
        sensor: Point2<f64>,
        /// (bearing, reach, seen_from), sorted by bearing.
        beams: Vec<(f64, f64, f64)>,
        step: f64,
    }

    impl Reference {
        fn new(frame: &RangeFrame) -> Self {
            let s = frame.sensor();
            let mut beams: Vec<(f64, f64, f64)> = frame
                .beams()
                .iter()
                .map(|b| {
                    let v = b.end - s;
                    (v.y.atan2(v.x), v.norm(), b.seen_from)
                })
                .collect();
            beams.sort_by(|a, b| a.0.total_cmp(&b.0));
            let mut gaps: Vec<f64> = beams.windows(2).map(|w| w[1].0 - w[0].0).collect();
            let step = if gaps.is_empty() {
                0.0
            } else {
                let mid = gaps.len() / 2;
                *gaps.select_nth_unstable_by(mid, f64::total_cmp).1
            };
            Self {
                sensor: s,
                beams,
                step,
            }
        }

        fn appeared(&self, p: Point2<f64>, gap: f64) -> bool {
            let n = self.beams.len();
            if n < 3 || self.step <= 0.0 {
                return false;
            }
            let v = p - self.sensor;
            let range = v.norm();
            if !(range > 0.0 && range.is_finite()) {
                return false;
            }
            let bearing = v.y.atan2(v.x);
            let k = self.beams.partition_point(|b| b.0 < bearing);
            [
                (-2, OUTER_STEPS),
                (-1, BRACKET_STEPS),
                (0, BRACKET_STEPS),
                (1, OUTER_STEPS),
            ]
            .into_iter()
            .all(|(d, steps)| {
                let (b, reach, seen_from) = self.beams[(k + n).wrapping_add_signed(d) % n];
                angle_between(b, bearing) <= steps * self.step
                    && reach >= range + gap
                    && seen_from <= range
            })
        }
    }

    #[test]
    fn the_fast_form_decides_as_the_straightforward_one() {
        // Invariant: on many seeded random frames (fans either way round, shuffled, across the ±π
        // seam, with gaps, repeated directions and zero-length beams) and returns (on the previous
        // beams' own directions too), the pseudo-angle form decides every return exactly as the
        // atan2-per-beam form.
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let (mut tested, mut fired, mut fast_frames, mut slow_frames) = (0, 0, 0, 0);
        for frame_no in 0..400 {
            let s0 = Point2::new(rng.random_range(-10.0..10.0), rng.random_range(-10.0..10.0));
            let layout = frame_no % 7;
            let n: usize = rng.random_range(3..400);
            let step = [0.25_f64, 0.5, 1.0][rng.random_range(0..3)].to_radians();
            let start = if layout == 6 {
                -std::f64::consts::PI
            } else {
                rng.random_range(-std::f64::consts::PI..std::f64::consts::PI)
            };
            let n = if layout == 6 { 360 } else { n };
            let step = if layout == 6 { 1f64.to_radians() } else { step };
            // Ranges: a few flat stretches with noise, some beams clear at the limit.
            let mut level = rng.random_range(0.5..8.0);
            let mut beams: Vec<Beam> = Vec::new();
            for k in 0..n {
                if rng.random_bool(0.05) {
                    level = rng.random_range(0.5..8.0);
                }
                if layout == 3 && rng.random_bool(0.2) {
                    continue; // a column without data
                }
                let b = start + k as f64 * step;
                let r = level + rng.random_range(-0.02..0.02);
                let clear = rng.random_bool(0.2);
                let seen_from = if rng.random_bool(0.3) {
                    rng.random_range(0.0..1.5)
                } else {
                    0.0
                };
                let end = if layout == 5 && rng.random_bool(0.01) {
                    s0
                } else {
                    s0 + r * nalgebra::Vector2::new(b.cos(), b.sin())
                };
                let kind = if clear { BeamEnd::Clear } else { BeamEnd::Hit };
                beams.push(Beam {
                    end,
                    kind,
                    seen_from,
                });
                if layout == 4 && rng.random_bool(0.05) {
                    // The same direction again, another range.
                    let e = s0 + (end - s0) * rng.random_range(0.5..1.5);
                    beams.push(Beam {
                        end: e,
                        kind,
                        seen_from,
                    });
                }
            }
            match layout {
                1 => beams.reverse(),
                2 => {
                    for k in (1..beams.len()).rev() {
                        beams.swap(k, rng.random_range(0..=k));
                    }
                }
                _ => {}
            }
            let mut frame = RangeFrame::new(s0).expect("finite");
            for &b in &beams {
                frame.push_beam(b);
            }
            let reference = Reference::new(&frame);
            let mut fast = PreviousBeams::default();
            fast.remember(&frame);
            if fast.by_pseudo {
                fast_frames += 1;
            } else {
                slow_frames += 1;
            }
            // Returns of the next frame: from a sensor moved a little (or not at all), inside and
            // around the previous ranges; on previous beams' own directions; anywhere.
            let s1 = if rng.random_bool(0.3) {
                s0
            } else {
                s0 + nalgebra::Vector2::new(
                    rng.random_range(-0.1..0.1),
                    rng.random_range(-0.1..0.1),
                )
            };
            let mut points = Vec::new();
            for k in 0..2 * n {
                let b = start + (k as f64 * 0.5 + rng.random_range(-0.5..0.5)) * step;
                let r = rng.random_range(0.1..9.0);
                points.push(s1 + r * nalgebra::Vector2::new(b.cos(), b.sin()));
            }
            for b in beams.iter().step_by(3) {
                points.push(s0 + (b.end - s0) * rng.random_range(0.2..1.1));
                points.push(b.end);
            }
            for _ in 0..20 {
                points.push(Point2::new(
                    rng.random_range(-20.0..20.0),
                    rng.random_range(-20.0..20.0),
                ));
            }
            points.push(s0);
            if rng.random_bool(0.5) {
                points.reverse();
            }
            for &p in &points {
                let gap = [0.0, 0.06, 0.2][rng.random_range(0..3)];
                let want = reference.appeared(p, gap);
                assert_eq!(
                    fast.appeared(p, gap),
                    want,
                    "frame {frame_no}, {p}, gap {gap}"
                );
                tested += 1;
                fired += usize::from(want);
            }
        }
        assert!(
            tested > 100_000 && fired > 10_000,
            "{tested} tested, {fired} appeared"
        );
        assert!(
            fast_frames > 200 && slow_frames > 20,
            "{fast_frames} fast, {slow_frames} not"
        );
    }

    /// A 6 m × 2 m grid of 5 cm cells with the default rules, lower-left corner at (0, −1).
    fn hallway() -> crate::grid::ObstacleGrid {
        crate::grid::ObstacleGrid::from_extent(Point2::new(0.0, -1.0), [6.0, 2.0], 0.05)
            .expect("valid grid")
    }

    /// Feeds `frames` at 10 Hz and returns, per frame, the grid's classes of the hits.
    fn classes_of_hits(
        grid: &mut crate::grid::ObstacleGrid,
        frames: &[RangeFrame],
    ) -> Vec<Vec<crate::grid::CellClass>> {
        frames
            .iter()
            .enumerate()
            .map(|(k, f)| {
                grid.update(f, k as f64 * 0.1).expect("in order");
                f.beams()
                    .iter()
                    .filter(|b| b.kind == BeamEnd::Hit)
                    .filter_map(|b| grid.class_at(b.end))
                    .collect()
            })
            .collect()
    }

    #[test]
    fn a_grid_calls_a_person_stepping_inside_the_range_moving_at_once() {
        // Invariant: on a grid, a person first returned 0.2 m inside the range limit, where the
        // previous frame (the only one) saw nothing, is Moving in that very frame, by this rule; the
        // cell rule alone leaves it tentative (its cells lie in the previous beams' clear tail, not
        // seen free).
        let s = Point2::new(0.0, 0.0);
        let empty = fan(s, -20.0, 20.0, |_| Some((5.0, BeamEnd::Clear)));
        let person = fan(s, -20.0, 20.0, |deg| {
            Some(if deg.abs() <= 2.0 {
                (4.8, BeamEnd::Hit)
            } else {
                (5.0, BeamEnd::Clear)
            })
        });
        let mut grid = hallway();
        let classes = classes_of_hits(&mut grid, &[empty, person]);
        assert!(!classes[1].is_empty());
        assert!(
            classes[1]
                .iter()
                .all(|&c| c == crate::grid::CellClass::Moving),
            "{:?}",
            classes[1]
        );
        let cell = grid.geometry().cell_of(at(s, 0.0, 4.8)).expect("inside");
        assert_eq!(
            grid.cell(cell).expect("inside").evidence,
            crate::grid::Evidence::Passive(crate::grid::Rule::Appeared)
        );
    }

    #[test]
    fn a_grid_never_calls_walls_moving_as_the_sensor_approaches_or_grazes_them() {
        // Invariant: walking 5 cm a frame towards an end wall (entering the 5 m limit frame by frame)
        // and along a side wall grazed at a few degrees (every seventh return dropped), no return on
        // either wall is ever called Moving.
        let (end_x, side_y) = (5.6, 0.6);
        let frames: Vec<RangeFrame> = (0..30)
            .map(|k| {
                let s = Point2::new(0.1 + 0.05 * k as f64, 0.0);
                fan(s, -20.0, 20.0, |deg| {
                    let b = deg.to_radians();
                    let to_end = (end_x - s.x) / b.cos();
                    let to_side = if b > 0.0 {
                        side_y / b.sin()
                    } else {
                        f64::INFINITY
                    };
                    let r = to_end.min(to_side);
                    let dropped = to_side < to_end && (deg / STEP_DEG).round() as i64 % 7 == 0;
                    Some(if r > 5.0 || dropped {
                        (5.0, BeamEnd::Clear)
                    } else {
                        (r, BeamEnd::Hit)
                    })
                })
            })
            .collect();
        let mut grid = hallway();
        let classes = classes_of_hits(&mut grid, &frames);
        let hits: usize = classes.iter().map(Vec::len).sum();
        assert!(hits > 1000, "both walls are returned: {hits}");
        for (k, c) in classes.iter().enumerate() {
            assert!(
                !c.contains(&crate::grid::CellClass::Moving),
                "frame {k}: {c:?}"
            );
        }
    }
}
