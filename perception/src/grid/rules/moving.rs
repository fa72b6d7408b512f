//! Moving obstacles (Tamura 3.1): a return where the previous frame saw free space.

use super::super::class::CellClass;
use super::super::geometry::{GridGeometry, floor};
use super::super::layers::Layers;

/// Tamura 3.1: the cell holds a return now and was in the visible area of one of the last three
/// frames (V_{t−1}, V_{t−2} or V_{t−3}) as free space beyond doubt: crossed at least the clear margin
/// before a return (or along a beam without one), not merely the free gap.
///
/// Why the clear margin: a ray grazing a surface at angle α runs inside the surface's row of cells for
/// `cell / sin α` before its return — 0.29 m for 5 cm cells at the [`GRAZING_LIMIT_DEG`] — and noisy
/// returns of that surface land in those cells. A crossing nearer its return than that can be a ray
/// running along a wall just beside the cell a later return of the same wall lands in (a wall coming
/// out from behind an obstacle is seen so, crossed a few centimetres before its return in frame after
/// frame); a crossing the clear margin (0.3 m) before its return cannot. One such crossing suffices:
/// the cell was empty then, so anything in it now has arrived since, whichever frame saw it empty. The
/// last three frames rather than the last one: a cell is often not seen at t−1 (in the shadow of the
/// mover itself as it walks away from the sensor, or between the fanned beams at the image's edge).
///
/// Guard (Chen 2.4's 8-neighbourhood, over two frames): nothing was returned in the cell's
/// 8-neighbourhood at t−1 or t−2, nor within `quiet` cells (see [`quiet_radius`]) unless farther from
/// the sensor (`sensor`: its continuous grid coordinates) than the cell. A ray grazing a surface
/// crosses the surface's cells between its returns, which lie up to `range · beam step / sin α` apart
/// along it; the next frame's return in such a cell is the same surface a little along, and one of
/// the previous returns lies within half that spacing, on the near side or the far side — a surface
/// receding from the sensor has returns on both. A real moving obstacle entering free space has had
/// nothing returned next to its new cells in the previous frames, and nothing nearer the sensor within
/// the quiet radius: what it left behind lies farther away when it comes towards the sensor (stepping
/// 10 cm a frame, more than the 8-neighbourhood) and to the side of its path otherwise. (Longer
/// memories were tried: they also silence an object that starts to move from rest, whose first new
/// cells lie next to where it rested.)
pub(crate) fn appeared_in_free_space(
    l: &Layers,
    g: &GridGeometry,
    i: usize,
    f: u32,
    quiet: usize,
    sensor: (f64, f64),
) -> bool {
    if l.class[i] != CellClass::Free as u8 || l.crossed_far_in_frames(i, f, SEEN_FREE) == 0 {
        return false;
    }
    let w = g.width();
    let (x, y) = ((i % w) as f64, (i / w) as f64);
    let range2 = |x: f64, y: f64| (x + 0.5 - sensor.0).powi(2) + (y + 0.5 - sensor.1).powi(2);
    let own = range2(x, y);
    let mut calm = true;
    g.for_square(i, quiet.max(1), |j| {
        if l.hits(j, f) & RECENT == 0 {
            return;
        }
        let (jx, jy) = ((j % w) as f64, (j / w) as f64);
        let neighbour = (jx - x).abs() <= 1.0 && (jy - y).abs() <= 1.0;
        calm &= !neighbour && range2(jx, jy) > own;
    });
    calm
}

/// Something has entered a cell last seen free: its class is Free (the last thing the grid saw there
/// was a ray going through), and nothing was returned in its 8-neighbourhood at t−1 or t−2, so it is
/// not a surface returned next to it jittering across a cell boundary (Chen 2.4's neighbourhood). A
/// static surface cannot do that; a moving obstacle can, and one that came to rest. The moving rule
/// misses it when the cell was seen free too long ago or too near a ray's return — a suitcase pulled
/// out of the shadow of the person pulling it enters cells nobody saw for frames. Whether it moves
/// or rests is the rest test's question (motion seen near it in the same frame).
pub(crate) fn entered_free_cell(l: &Layers, g: &GridGeometry, i: usize, f: u32) -> bool {
    if l.class[i] != CellClass::Free as u8 {
        return false;
    }
    let mut calm = true;
    g.for_3x3(i, |j| calm &= l.hits(j, f) & RECENT == 0);
    calm
}

/// The steepest a surface can be grazed and still return (degrees from the surface): an SR4000-like
/// camera returns nothing beyond 80° incidence, a laser scanner little beyond.
pub(crate) const GRAZING_LIMIT_DEG: f64 = 10.0;

/// The widest quiet neighbourhood, in cells (9 × 9).
const MAX_QUIET: usize = 4;

/// How many cells around a return at `range` (m) the moving rule asks to have been quiet, for beams
/// `beam_step` (rad) apart on a grid of `resolution` (m) cells.
///
/// Along a surface, neighbouring beams return `range · beam_step / sin α` apart, α the grazing angle,
/// at least [`GRAZING_LIMIT_DEG`]: about 13 cm at 5 m for a 0.25° camera, where the cells are 5 cm. A
/// return on a surface returned last frame lies within half that spacing of one of last frame's
/// returns, so the quiet neighbourhood must reach that far — and at least one cell (Chen's
/// 8-neighbourhood), capped at [`MAX_QUIET`] cells.
pub(crate) fn quiet_radius(range: f64, beam_step: f64, resolution: f64) -> usize {
    // ceil(x) = −floor(−x), bit for bit; the inline floor spares a library call per return.
    let cells = -floor(-(half_spacing(range, beam_step) / resolution));
    if cells.is_finite() {
        (cells as usize).clamp(1, MAX_QUIET)
    } else {
        1
    }
}

/// [`quiet_radius`] for one frame's beam step and grid: the ranges at which it steps up are found
/// once, so that a return costs three compares instead of two dependent divisions.
#[derive(Clone, Copy, Debug)]
pub(crate) struct QuietRadii {
    beam_step: f64,
    resolution: f64,
    /// `up[m − 1]`: the greatest range whose radius is at most `m` (within `0..=limit`).
    up: [f64; MAX_QUIET - 1],
    /// Ranges `0..=limit` are looked up; others (and NaN) computed.
    limit: f64,
}

impl QuietRadii {
    /// Ranges beyond this (m) are computed, not looked up.
    const LIMIT: f64 = 1e9;

    /// The radii of a frame whose beams are `beam_step` apart, on cells of `resolution`.
    pub(crate) fn new(beam_step: f64, resolution: f64) -> Self {
        let mut radii = Self {
            beam_step,
            resolution,
            up: [0.0; MAX_QUIET - 1],
            limit: -1.0,
        };
        // quiet_radius is monotone in the range where each rounding step is (a non-negative step
        // over positive divisors) and finite: there, its radius exceeds m exactly beyond the
        // greatest range whose cell count is at most m.
        let radius = |r: f64| quiet_radius(r, beam_step, resolution);
        let counts = |r: f64| {
            let c = half_spacing(r, beam_step) / resolution;
            c.is_finite().then_some(c)
        };
        if !(beam_step >= 0.0
            && beam_step.is_finite()
            && resolution > 0.0
            && counts(Self::LIMIT).is_some())
        {
            return radii;
        }
        for m in 1..MAX_QUIET {
            // The estimate, then float by float to the last range at most m (a step or two).
            let guess = m as f64 * resolution / half_spacing(1.0, beam_step);
            let mut r = if guess.is_finite() {
                guess.clamp(0.0, Self::LIMIT)
            } else {
                Self::LIMIT
            };
            let within = |r: f64| radius(r) <= m;
            let mut steps = 0;
            while !within(r) && r > 0.0 && steps < 64 {
                r = f64::from_bits(r.to_bits() - 1);
                steps += 1;
            }
            loop {
                let next = f64::from_bits(r.to_bits() + 1);
                if next > Self::LIMIT || !within(next) || steps >= 64 {
                    break;
                }
                r = next;
                steps += 1;
            }
            if steps >= 64 || !within(r) {
                return radii; // not found near the estimate: compute every radius
            }
            radii.up[m - 1] = r;
        }
        radii.limit = Self::LIMIT;
        radii
    }

    /// `quiet_radius(range, beam_step, resolution)`, bit for bit.
    #[inline]
    pub(crate) fn of(&self, range: f64) -> usize {
        if range >= 0.0 && range <= self.limit {
            1 + self.up.iter().filter(|&&u| range > u).count()
        } else {
            quiet_radius(range, self.beam_step, self.resolution)
        }
    }
}

/// Half the along-surface spacing (m) of returns `beam_step` apart at `range` at the grazing limit.
#[inline]
fn half_spacing(range: f64, beam_step: f64) -> f64 {
    range * beam_step / (2.0 * GRAZING_LIMIT_DEG.to_radians().sin())
}

/// History bits of frames t−2 and t−1.
const RECENT: u8 = 0b110;

/// History bits of the frames whose visible area counts for the moving rule: t−1, t−2 and t−3.
const SEEN_FREE: u8 = 0b1110;

/// The cell lies within `moving_step` of a cell that was moving at t−1 (stamped at the start of the
/// frame from the previous frame's moving cells).
pub(crate) fn near_previous_motion(l: &Layers, i: usize, f: u32) -> bool {
    l.near_moving[i] == f
}

/// The cell lies within `moving_step` of a cell that was moving at t−1 and had not been at t−2 but
/// something nearby had (*confirmed* motion: moving two frames running, and on into a new cell), or of
/// a cell something has just left.
pub(crate) fn near_confirmed_motion(l: &Layers, i: usize, f: u32) -> bool {
    l.near_confirmed[i] == f
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::layers::Crossing;
    use nalgebra::Point2;

    /// A sensor far below the 10 × 10 test grid.
    const FAR_SENSOR: (f64, f64) = (5.0, -1000.0);

    fn grid() -> (GridGeometry, Layers) {
        let g = GridGeometry::with_cells(Point2::new(0.0, 0.0), 10, 10, 0.05).expect("valid");
        let l = Layers::new(g.len());
        (g, l)
    }

    #[test]
    fn a_return_in_last_frames_free_space_is_moving() {
        // Invariant: a cell crossed the clear margin before a return (far) in one of the last frames,
        // returned now with nothing returned around it before ⇒ moving; crossings nearer their return
        // than the clear margin, in any number of frames, are not enough (a grazed surface's own cells).
        let (g, mut l) = grid();
        let i = 55;
        l.class[i] = CellClass::Free as u8;
        l.record_crossing(i, 2, Crossing::Far);
        l.record_hit(i, 3);
        assert!(appeared_in_free_space(&l, &g, i, 3, 1, FAR_SENSOR));
        let mut l = Layers::new(g.len());
        l.class[i] = CellClass::Free as u8;
        l.record_crossing(i, 1, Crossing::Free);
        l.record_crossing(i, 2, Crossing::Free);
        l.record_hit(i, 3);
        assert!(
            !appeared_in_free_space(&l, &g, i, 3, 1, FAR_SENSOR),
            "seen free only within the clear margin of a return"
        );
    }

    #[test]
    fn a_wall_coming_out_from_behind_an_obstacle_is_not_moving() {
        // Invariant: rays that graze a wall past an occluder's corner cross the wall's own row of cells
        // a few centimetres before their returns (Free, never Far) frame after frame; the wall's first
        // return in such a cell, nearer the sensor than its returns so far and two cells from them, is
        // not moving.
        let (g, mut l) = grid();
        let i = 52; // row 5, column 2; the sensor far to the left along the row
        l.class[i] = CellClass::Free as u8;
        for f in 1..=3 {
            l.record_crossing(i, f, Crossing::Free);
            l.record_hit(i + 2, f);
            l.record_hit(i + 3, f);
        }
        l.record_hit(i, 4);
        assert!(!appeared_in_free_space(&l, &g, i, 4, 1, (-100.0, 5.5)));
    }

    #[test]
    fn a_return_next_to_last_frames_return_is_not_moving() {
        // Invariant: a return in the 8-neighbourhood at t−1 (a grazed wall) blocks the moving rule.
        let (g, mut l) = grid();
        let i = 55;
        l.class[i] = CellClass::Free as u8;
        l.record_crossing(i, 1, Crossing::Far);
        l.record_crossing(i, 2, Crossing::Far);
        l.record_hit(i + 11, 2);
        l.record_hit(i, 3);
        assert!(!appeared_in_free_space(&l, &g, i, 3, 1, FAR_SENSOR));
    }

    #[test]
    fn a_return_near_a_return_two_frames_ago_is_not_moving() {
        // Invariant: a return next to the cell at t−2 blocks the moving rule; one at t−3 does not.
        let (g, mut l) = grid();
        let i = 55;
        l.class[i] = CellClass::Free as u8;
        l.record_hit(i - 1, 7);
        l.record_crossing(i, 7, Crossing::Far);
        l.record_crossing(i, 8, Crossing::Far);
        l.record_hit(i, 9);
        assert!(!appeared_in_free_space(&l, &g, i, 9, 1, FAR_SENSOR));
        let mut l = Layers::new(g.len());
        l.class[i] = CellClass::Free as u8;
        l.record_hit(i - 1, 6);
        l.record_crossing(i, 7, Crossing::Far);
        l.record_crossing(i, 8, Crossing::Far);
        l.record_hit(i, 9);
        assert!(
            appeared_in_free_space(&l, &g, i, 9, 1, FAR_SENSOR),
            "three frames ago is long enough"
        );
    }

    #[test]
    fn free_space_seen_more_than_three_frames_ago_does_not_count() {
        // Invariant: a far crossing at t−3 (the cell unseen at t−2 and t−1: in the mover's own shadow,
        // between fanned beams) makes a return at t moving; one at t−4 does not; nor does a cell that
        // is not Free (unknown).
        let (g, mut l) = grid();
        let i = 55;
        l.class[i] = CellClass::Free as u8;
        l.record_crossing(i, 2, Crossing::Far);
        l.record_hit(i, 5);
        assert!(appeared_in_free_space(&l, &g, i, 5, 1, FAR_SENSOR));
        let mut l = Layers::new(g.len());
        l.class[i] = CellClass::Free as u8;
        l.record_crossing(i, 1, Crossing::Far);
        l.record_hit(i, 5);
        assert!(!appeared_in_free_space(&l, &g, i, 5, 1, FAR_SENSOR));
        l.class[i] = CellClass::Unknown as u8;
        l.record_crossing(i, 4, Crossing::Far);
        assert!(!appeared_in_free_space(&l, &g, i, 5, 1, FAR_SENSOR));
    }

    #[test]
    fn a_grazed_wall_needs_a_wider_quiet_neighbourhood_far_away() {
        // Invariant: the quiet radius covers half the along-surface beam spacing at the grazing limit
        // (at least one cell, at most four); a return two cells from last frame's return is moving with
        // the 8-neighbourhood, and with the radius for a 0.25° camera at 4.5 m only if that return lies
        // farther from the sensor.
        let step = 0.25_f64.to_radians();
        assert_eq!(quiet_radius(0.5, step, 0.05), 1);
        assert_eq!(quiet_radius(4.5, step, 0.05), 2);
        assert_eq!(quiet_radius(50.0, step, 0.05), 4);
        assert_eq!(quiet_radius(f64::NAN, step, 0.05), 1);
        let (g, mut l) = grid();
        let i = 55;
        l.class[i] = CellClass::Free as u8;
        l.record_crossing(i, 1, Crossing::Far);
        l.record_crossing(i, 2, Crossing::Far);
        l.record_hit(i + 2, 2);
        l.record_hit(i, 3);
        let quiet = quiet_radius(4.5, step, 0.05);
        assert!(appeared_in_free_space(&l, &g, i, 3, 1, FAR_SENSOR));
        // Sensor to the right: last frame's return two cells nearer it blocks; to the left (the return
        // lies behind the cell, as for something coming towards the sensor) it does not.
        assert!(!appeared_in_free_space(&l, &g, i, 3, quiet, (20.0, 5.5)));
        assert!(appeared_in_free_space(&l, &g, i, 3, quiet, (-10.0, 5.5)));
    }

    #[test]
    fn a_return_in_a_cell_last_seen_free_with_no_surface_beside_it_has_entered() {
        // Invariant: entered iff the cell is Free and nothing was returned in its 3×3 block at t−1 or
        // t−2 (a return there three frames ago does not count); a cell not Free has not been entered.
        let (g, mut l) = grid();
        let i = 55;
        l.class[i] = CellClass::Free as u8;
        l.record_hit(i + 1, 2);
        l.record_hit(i, 5);
        assert!(entered_free_cell(&l, &g, i, 5));
        l.record_hit(i - 11, 3);
        assert!(
            !entered_free_cell(&l, &g, i, 5),
            "a return beside it at t−2"
        );
        let (g, mut l) = grid();
        l.class[i] = CellClass::Unknown as u8;
        l.record_hit(i, 5);
        assert!(!entered_free_cell(&l, &g, i, 5));
    }

    #[test]
    fn looked_up_radii_are_the_computed_ones() {
        // Invariant: QuietRadii::of equals quiet_radius bit for bit for every range (at and either
        // side of each step, negative, huge, infinite, NaN) and every beam step and resolution
        // (zero, tiny, huge, negative and NaN steps included).
        let mut r = crate::grid::test_rng::uniform(0x853c_49e6_748f_ea9b_u64);
        let mut steps = vec![0.0, 1e-300, 1e300, -0.01, f64::NAN, f64::INFINITY];
        steps.extend((0..200).map(|_| (0.01 + r() * 2.0_f64).to_radians()));
        let mut looked_up = 0;
        for (n, &step) in steps.iter().enumerate() {
            let resolution = [0.05, 0.01, 0.1, 1e-300, 0.02 + r() * 0.2][n % 5];
            let radii = QuietRadii::new(step, resolution);
            looked_up += usize::from(radii.limit > 0.0);
            let mut ranges = vec![0.0, -0.0, -1.0, 1e12, f64::INFINITY, f64::NAN, 1e9];
            ranges.extend((0..300).map(|_| r() * 40.0));
            for &u in &radii.up {
                let bits = u.to_bits();
                ranges.extend((bits.saturating_sub(3)..bits + 4).map(f64::from_bits));
            }
            for range in ranges {
                assert_eq!(
                    radii.of(range),
                    quiet_radius(range, step, resolution),
                    "range {range:e} step {step:e} resolution {resolution:e}"
                );
            }
        }
        assert!(looked_up > 150, "only {looked_up} frames looked radii up");
    }

    #[test]
    fn a_near_crossing_is_not_free_space() {
        // Invariant: crossings within the free gap of their return (recorded Near) do not make the cell
        // last frames' free space.
        let (g, mut l) = grid();
        let i = 55;
        l.class[i] = CellClass::Free as u8;
        l.record_crossing(i, 1, Crossing::Near);
        l.record_crossing(i, 2, Crossing::Near);
        l.record_hit(i, 3);
        assert!(!appeared_in_free_space(&l, &g, i, 3, 1, FAR_SENSOR));
    }
}
