//! Predicting what one look-around from a position shows of the targets, and the heading that
//! shows the most.
//!
//! Rays leave the eye evenly over the full circle (about 1.5 cells apart at the far range; see
//! [`SightMap::rays`]), but only those whose bearing meets the box around the target blocks
//! inside `near..far` are cast. Each is marched cell by cell through the window (Amanatides–Woo) from the eye, keeping
//! the farthest shadow end of the occluders crossed so far (see `sight.rs`), so a step is O(1): a
//! target cell whose stretch of the ray has its midpoint `r` inside `near..far` and beyond the
//! shadow is seen, and adds its weight times the floor area its stretch stands for, `r · Δθ · Δs`,
//! to the ray's bin. A ray stops at the far range, past its farthest target block, at the window's
//! edge, or when a shadow reaches that far (a wall). The heading is the centre of the window of
//! `2 · half_angle` of bins with the largest sum (a circular sliding window); among windows with
//! the same sum, the middle one of the longest run of them, so a look centres what it sees.
//!
//! The same march over the coarse raster (`raster.rs`) gives a cheap estimate for ranking many
//! positions ([`SightMap::estimate`]).

use nalgebra::Point2;
use nudge_perception::grid::CellIndex;

use crate::view::raster::Raster;
use crate::view::sight::SightMap;

/// What a look-around from one position is predicted to show.
#[derive(Clone, Debug, PartialEq)]
pub struct LookPrediction {
    /// The heading to face (rad, map frame, in `(−π, π]`).
    pub heading: f64,
    /// The weighted target area predicted visible (m²).
    pub gain: f64,
    /// The target cells predicted seen, sorted row-major, deduplicated.
    pub seen: Vec<CellIndex>,
}

/// Buffers a prediction reuses from one position to the next.
#[derive(Clone, Debug, Default)]
pub struct Scratch {
    /// Per ray of the fan: its target sum (weight · r · Δs, cells²).
    bins: Vec<f64>,
    /// Per ray of the fan: whether it can meet a target block.
    cast: Vec<bool>,
    /// Prefix sums of the bins over two turns.
    prefix: Vec<f64>,
    /// Per window start: whether its sum is (within rounding) the best.
    good: Vec<bool>,
    /// The position and raster (true: the fine one) the buffers hold, and the window found.
    held: Option<(f64, f64, bool, Window)>,
}

/// The heading window chosen from a position's bins.
#[derive(Clone, Copy, Debug)]
struct Window {
    start: usize,
    len: usize,
    heading: f64,
    /// Its bin sum.
    sum: f64,
    /// How far the rays need to go (cells).
    end: f64,
}

impl SightMap {
    /// Number of rays over the full circle (at the grid's resolution).
    pub fn rays(&self) -> usize {
        self.fine.fan.len()
    }

    /// The best heading and its predicted gain (m²) for a look-around from `position`: as
    /// [`Self::predict`] without listing the cells.
    pub fn gain_at(&self, position: Point2<f64>) -> (f64, f64) {
        self.gain_with(&mut Scratch::default(), position)
    }

    /// [`Self::gain_at`] with buffers reused from call to call.
    pub fn gain_with(&self, scratch: &mut Scratch, position: Point2<f64>) -> (f64, f64) {
        self.heading_gain(&self.fine, scratch, position)
    }

    /// A cheap estimate of [`Self::gain_at`] (heading, m²) on the coarse raster: 4 × 4 cells to
    /// one, each hiding what any of its cells hides, rays 16 times fewer steps in all. For ranking
    /// positions; it errs low where a gap is narrower than a coarse cell.
    pub fn estimate(&self, scratch: &mut Scratch, position: Point2<f64>) -> (f64, f64) {
        self.heading_gain(&self.coarse, scratch, position)
    }

    fn heading_gain(&self, r: &Raster, scratch: &mut Scratch, position: Point2<f64>) -> (f64, f64) {
        match self.window(r, scratch, position) {
            Some(w) => (w.heading, w.sum * area_scale(r)),
            None => (0.0, 0.0),
        }
    }

    /// The look-around from `position` that shows the most target area: its heading, the weighted
    /// area it is predicted to show (m²) and the target cells it is predicted to see.
    pub fn predict(&self, position: Point2<f64>) -> LookPrediction {
        self.predict_with(&mut Scratch::default(), position)
    }

    /// [`Self::predict`] with buffers reused from call to call (and the rays already cast, when
    /// the last call with them was [`Self::gain_with`] at the same position).
    pub fn predict_with(&self, scratch: &mut Scratch, position: Point2<f64>) -> LookPrediction {
        let r = &self.fine;
        let Some(w) = self.window(r, scratch, position) else {
            return LookPrediction {
                heading: 0.0,
                gain: 0.0,
                seen: Vec::new(),
            };
        };
        let n = r.fan.len();
        let p = self.at(r, position);
        let mut seen = Vec::new();
        let mut sum = 0.0;
        for k in (w.start..w.start + w.len).map(|k| k % n) {
            if scratch.cast[k] {
                sum += r.march(p, r.fan[k], w.end, |i| seen.push(i));
            }
        }
        seen.sort_unstable();
        seen.dedup();
        // Raster indices are row-major in the window, so also in the grid.
        let seen = seen.into_iter().map(|i| self.grid_cell(i)).collect();
        LookPrediction {
            heading: w.heading,
            gain: sum * area_scale(r),
            seen,
        }
    }

    /// Whether the floor at the centre of `cell` is in sight from an eye above `position`, whatever
    /// the heading and range: no occluder crossed before it throws its shadow that far. False
    /// outside the window.
    pub fn floor_visible(&self, position: Point2<f64>, cell: CellIndex) -> bool {
        let r = &self.fine;
        let Some(target) = self.window_index(cell) else {
            return false;
        };
        let p = self.at(r, position);
        let q = self.at(r, self.geom.centre(cell));
        let (dx, dy) = (q.0 - p.0, q.1 - p.1);
        let len = dx.hypot(dy);
        if len == 0.0 {
            return true; // the eye stands above it
        }
        let mut visible = false;
        r.walk(
            p,
            (dx / len, dy / len),
            len + 1.0,
            |i, _, t0, t1, shadow| {
                if i == target {
                    visible = 0.5 * (t0 + t1) > shadow;
                    false
                } else {
                    true
                }
            },
        );
        visible
    }

    /// Whether some target block lies at a distance within `near..far` of `position` (else no
    /// look from there can see a target).
    pub fn within_reach(&self, position: Point2<f64>) -> bool {
        let p = self.local(position);
        let (near, far) = (self.coverage.near, self.coverage.far);
        self.blocks.iter().any(|b| {
            let (nearest, farthest) = b.distances2(p);
            nearest <= far * far && farthest >= near * near
        })
    }

    /// A map point in raster `r`'s cells.
    fn at(&self, r: &Raster, p: Point2<f64>) -> (f64, f64) {
        let (x, y) = self.local(p);
        (x / r.res, y / r.res)
    }

    /// Fills the scratch bins with each cast ray's target sum from `position` on raster `r` and
    /// picks the heading window. `None` outside the window.
    fn window(&self, r: &Raster, s: &mut Scratch, position: Point2<f64>) -> Option<Window> {
        let fine = std::ptr::eq(r, &self.fine);
        if let Some((x, y, f, w)) = s.held
            && x == position.x
            && y == position.y
            && f == fine
        {
            return Some(w);
        }
        s.held = None;
        let p = self.at(r, position);
        if !(p.0 >= 0.0 && p.1 >= 0.0 && p.0 < r.w as f64 && p.1 < r.h as f64) {
            return None;
        }
        let n = r.fan.len();
        let end = self.rays_from(position, n, &mut s.cast) / r.res;
        s.bins.clear();
        s.bins.resize(n, 0.0);
        for (k, bin) in s.bins.iter_mut().enumerate() {
            if s.cast[k] {
                *bin = r.march(p, r.fan[k], end, |_| {});
            }
        }
        let (start, len, heading) = best_window(
            &s.bins,
            self.coverage.half_angle,
            &mut s.prefix,
            &mut s.good,
        );
        let sum = s.prefix[start + len] - s.prefix[start];
        let w = Window {
            start,
            len,
            heading,
            sum: sum.max(0.0),
            end,
        };
        s.held = Some((position.x, position.y, fine, w));
        Some(w)
    }

    /// Marks in `cast` which of a fan of `n` rays from `position` can meet a target block at a
    /// distance in `near..far`: the bearings of the box around those blocks; returns how far the
    /// rays need to go (m).
    fn rays_from(&self, position: Point2<f64>, n: usize, cast: &mut Vec<bool>) -> f64 {
        let (px, py) = self.local(position);
        let (near, far) = (self.coverage.near, self.coverage.far);
        cast.clear();
        cast.resize(n, false);
        let mut end: f64 = 0.0;
        let (mut lo, mut hi) = (
            (f64::INFINITY, f64::INFINITY),
            (f64::NEG_INFINITY, f64::NEG_INFINITY),
        );
        // Squared distances: no square root per block.
        for b in &self.blocks {
            let (nearest, farthest) = b.distances2((px, py));
            if nearest > far * far || farthest < near * near {
                continue;
            }
            end = end.max(farthest);
            lo = (lo.0.min(b.min.0), lo.1.min(b.min.1));
            hi = (hi.0.max(b.max.0), hi.1.max(b.max.1));
        }
        if end == 0.0 {
            return 0.0;
        }
        let end = end.sqrt().min(far);
        if px >= lo.0 && px <= hi.0 && py >= lo.1 && py <= hi.1 {
            cast.fill(true);
            return end;
        }
        // The box's bearings about its centre's: it does not hold p, so they span < π.
        let pi = std::f64::consts::PI;
        let centre = (0.5 * (lo.1 + hi.1) - py).atan2(0.5 * (lo.0 + hi.0) - px);
        let (mut from, mut to) = (0.0f64, 0.0f64);
        for (x, y) in [(lo.0, lo.1), (hi.0, lo.1), (hi.0, hi.1), (lo.0, hi.1)] {
            let mut d = (y - py).atan2(x - px) - centre;
            if d > pi {
                d -= 2.0 * pi;
            } else if d < -pi {
                d += 2.0 * pi;
            }
            from = from.min(d);
            to = to.max(d);
        }
        // One ray more each side: a box narrower than the ray spacing still gets one.
        let step = std::f64::consts::TAU / n as f64;
        let k0 = ((centre + from) / step).floor() as i64;
        let k1 = ((centre + to) / step).ceil() as i64;
        for k in k0..=k1.min(k0 + n as i64 - 1) {
            cast[k.rem_euclid(n as i64) as usize] = true;
        }
        end
    }
}

/// Square metres per bin unit of raster `r` (bins sum weight · r · Δs in cells², per ray of width
/// Δθ).
fn area_scale(r: &Raster) -> f64 {
    std::f64::consts::TAU / r.fan.len() as f64 * r.res * r.res
}

/// The circular window of bins spanning `2 · half_angle` with the largest sum: (first bin,
/// length, heading at its centre in `(−π, π]`). Among windows within rounding of the best sum, the
/// middle of the longest run (the first such run); a window of the whole circle faces the bins'
/// weighted mean bearing.
fn best_window(
    bins: &[f64],
    half_angle: f64,
    prefix: &mut Vec<f64>,
    good: &mut Vec<bool>,
) -> (usize, usize, f64) {
    let n = bins.len();
    let step = std::f64::consts::TAU / n as f64;
    let len = ((2.0 * half_angle / step).round() as usize).clamp(1, n);
    let wrap = |a: f64| a.sin().atan2(a.cos());
    prefix.clear();
    prefix.push(0.0);
    let mut acc = 0.0;
    for k in 0..2 * n {
        acc += bins[k % n];
        prefix.push(acc);
    }
    if len == n {
        let (s, c) = bins.iter().enumerate().fold((0.0, 0.0), |(s, c), (k, &b)| {
            let a = k as f64 * step;
            (s + b * a.sin(), c + b * a.cos())
        });
        let heading = if s == 0.0 && c == 0.0 {
            0.0
        } else {
            s.atan2(c)
        };
        return (0, n, heading);
    }
    let best = (0..n)
        .map(|s| prefix[s + len] - prefix[s])
        .fold(0.0, f64::max);
    let tol = 1e-9 * prefix[n].max(f64::MIN_POSITIVE);
    good.clear();
    good.extend((0..n).map(|s| prefix[s + len] - prefix[s] >= best - tol));
    // Runs of good windows, read from just after a window that is not good (none: all are).
    let start = match good.iter().position(|&g| !g) {
        Some(k) => k + 1,
        None => {
            let centre = (n - 1) as f64 / 2.0;
            return (0, len, wrap((centre + (len - 1) as f64 / 2.0) * step));
        }
    };
    let (mut best_run, mut run) = ((0usize, 0usize), (0usize, 0usize));
    for j in 0..n {
        let k = (start + j) % n;
        if good[k] {
            if run.1 == 0 {
                run.0 = k;
            }
            run.1 += 1;
            if run.1 > best_run.1 {
                best_run = run;
            }
        } else {
            run.1 = 0;
        }
    }
    let first = best_run.0 + (best_run.1 - 1) / 2;
    let centre = first as f64 + if best_run.1 % 2 == 0 { 0.5 } else { 0.0 };
    let heading = wrap((centre + (len - 1) as f64 / 2.0) * step);
    (first % n, len, heading)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_window_centres_on_the_bins_it_sums() {
        // Invariant: the best window holds the heaviest arc; with room to spare on both sides it
        // is centred on the arc's run of equally good windows, across the ±π seam too.
        let n = 360;
        let mut bins = vec![0.0; n];
        for b in &mut bins[170..=190] {
            *b = 1.0;
        }
        let (mut prefix, mut good) = (Vec::new(), Vec::new());
        let (start, len, heading) = best_window(&bins, 30f64.to_radians(), &mut prefix, &mut good);
        assert_eq!(len, 60);
        let sum: f64 = (start..start + len).map(|k| bins[k % n]).sum();
        assert_eq!(sum, 21.0);
        assert!(
            (heading.abs() - 180f64.to_radians()).abs() < 1.01f64.to_radians(),
            "{heading}"
        );
        let mut seam = vec![0.0; n];
        for k in (350..360).chain(0..10) {
            seam[k] = 1.0;
        }
        seam[5] = 3.0;
        let (_, _, heading) = best_window(&seam, 20f64.to_radians(), &mut prefix, &mut good);
        assert!(heading.abs() < 1.01f64.to_radians(), "{heading}");
        let (_, len, _) = best_window(&seam, 4.0, &mut prefix, &mut good);
        assert_eq!(len, n);
    }
}
