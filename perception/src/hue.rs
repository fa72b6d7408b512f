//! Telling touching surfaces apart by their colour.
//!
//! A surface's shades (a darker stripe, a leg in shadow, a texture's patches) change a return's
//! brightness but hardly its *chromaticity*, its colour over its brightness `(r, g, b) / (r + g + b)`.
//! Two things that touch (a red box against a grey wall, a blue chair against a brown sideboard)
//! differ in chromaticity wherever they differ in hue. So returns are summed per colour, and two sums
//! are one surface's colour when their chromaticities differ by no more than the camera's colour
//! noise explains:
//!
//! - each channel of a return carries noise σ (8-bit counts, the robot's camera's `colour_noise`);
//!   a chromaticity channel `c = r / S` then carries at most `√2 σ / S` (`S = r + g + b`), and the
//!   mean of `n` returns of brightness `S̄` at most `√2 σ / (S̄ √n)`;
//! - every reading is rounded to a whole count per channel, and a shade of a surface's colour is
//!   rounded again: at most one count per channel over the brightness, `1 / S̄`, on each side;
//! - sums are one colour when every channel differs by at most `k` times the combined noise plus
//!   both rounding terms. `k` = 4 ([`HueSplit::sigmas`]): a surface's own returns are split at one
//!   comparison in 16,000 per channel.
//!
//! A black surface (brightness near zero) has no chromaticity to speak of: its noise term grows
//! without bound, and it fits any colour. Grey things (walls, the floor, a grey cabinet) share one
//! chromaticity and are not told apart by colour: what tells them apart is a gap, or a push.

/// How colour tells surfaces apart.
#[derive(Clone, Debug, PartialEq)]
pub struct HueSplit {
    /// Noise σ of each colour channel of a return (8-bit counts): the robot's camera's.
    pub noise: f64,
    /// How many times the combined noise two sums of one surface's colour may differ by.
    pub sigmas: f64,
    /// Most colours an elevation cell keeps apart; a return that fits none of them when the cell
    /// has this many joins the nearest. Four: the corner where a box, a chair, a wall and another
    /// box meet in 4 cm.
    pub layers: usize,
}

impl Default for HueSplit {
    /// The paper's SR-4000 with its colour cameras: 3 counts of noise per channel.
    fn default() -> Self {
        Self {
            noise: 3.0,
            sigmas: 4.0,
            layers: 4,
        }
    }
}

/// Returns' colours summed: their mean chromaticity and brightness.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ColourSum {
    /// Per channel, the sum of the returns' values.
    pub rgb: [f32; 3],
    /// How many returns.
    pub count: u32,
}

impl ColourSum {
    /// The sum of one return of colour `c`.
    pub fn of(c: [u8; 3]) -> Self {
        Self {
            rgb: c.map(f32::from),
            count: 1,
        }
    }

    /// Adds a return of colour `c`.
    pub fn add(&mut self, c: [u8; 3]) {
        for (s, v) in self.rgb.iter_mut().zip(c) {
            *s += f32::from(v);
        }
        self.count += 1;
    }

    /// The sum of all channels.
    fn total(&self) -> f32 {
        self.rgb[0] + self.rgb[1] + self.rgb[2]
    }

    /// Mean chromaticity `(r, g, b) / (r + g + b)`; `None` for black or empty.
    pub fn chroma(&self) -> Option<[f32; 3]> {
        let t = self.total();
        (t > 0.0).then(|| self.rgb.map(|v| v / t))
    }

    /// Mean brightness `r + g + b` of the returns (0–765).
    pub fn brightness(&self) -> f32 {
        if self.count == 0 {
            0.0
        } else {
            self.total() / self.count as f32
        }
    }
}

/// A sum's chromaticity with its noise and rounding terms worked out once, for the many
/// comparisons labelling makes between neighbouring cells ([`HueSplit::same_summary`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HueSummary {
    /// Mean chromaticity; `None` for black or empty.
    chroma: Option<[f32; 3]>,
    /// Squared noise of each chromaticity channel: `(√2 σ √n / T)²`.
    variance: f32,
    /// Rounding: one count per channel over the mean brightness, `n / T`.
    rounding: f32,
}

impl HueSplit {
    /// `sum`'s chromaticity, noise and rounding, for [`Self::same_summary`].
    pub fn summary(&self, sum: &ColourSum) -> HueSummary {
        let t = sum.total();
        let n = sum.count.max(1) as f32;
        let spread = std::f32::consts::SQRT_2 * self.noise as f32 * n.sqrt() / t;
        HueSummary {
            chroma: sum.chroma(),
            variance: spread * spread,
            rounding: n / t,
        }
    }

    /// [`Self::same`] on two summaries.
    #[inline]
    pub fn same_summary(&self, a: &HueSummary, b: &HueSummary) -> bool {
        let (Some(ca), Some(cb)) = (a.chroma, b.chroma) else {
            return true;
        };
        let differ = (0..3)
            .map(|k| (ca[k] - cb[k]).abs())
            .fold(0.0_f32, f32::max);
        let beyond = differ - a.rounding - b.rounding;
        let k = self.sigmas as f32;
        beyond <= 0.0 || beyond * beyond <= k * k * (a.variance + b.variance)
    }

    /// Whether `a` and `b` are one surface's colour (see the module doc). Black or empty sums fit
    /// anything.
    pub fn same(&self, a: &ColourSum, b: &ColourSum) -> bool {
        self.excess(a, b) <= 0.0
    }

    /// Whether one return of colour `rgb` is `sum`'s colour: [`Self::same`] for the sum of that one
    /// return, worked out without a division (every return of a look-around asks it). Both sides
    /// of `|r / S − R / T| ≤ k √(2σ²/S² + 2σ²n/T²) + 1/S + n/T` times `S T`.
    #[inline]
    pub fn fits(&self, sum: &ColourSum, rgb: [u8; 3]) -> bool {
        let c = rgb.map(f32::from);
        let s = c[0] + c[1] + c[2];
        let t = sum.total();
        if s <= 0.0 || t <= 0.0 {
            return true;
        }
        let n = sum.count.max(1) as f32;
        let allowed = self.sigmas as f32
            * std::f32::consts::SQRT_2
            * self.noise as f32
            * (t * t + n * s * s).sqrt()
            + t
            + n * s;
        (0..3).all(|k| (c[k] * t - sum.rgb[k] * s).abs() <= allowed)
    }

    /// By how much the largest channel of the two chromaticities differs beyond what noise and
    /// rounding explain (≤ 0: one colour). Black or empty sums: −∞.
    pub fn excess(&self, a: &ColourSum, b: &ColourSum) -> f32 {
        let (Some(ca), Some(cb)) = (a.chroma(), b.chroma()) else {
            return f32::NEG_INFINITY;
        };
        // Per channel: √2 σ √n / T for the mean of n returns summing to T; one count in S̄.
        let spread = |s: &ColourSum| {
            let (t, n) = (s.total(), s.count.max(1) as f32);
            (
                std::f32::consts::SQRT_2 * self.noise as f32 * n.sqrt() / t,
                n / t,
            )
        };
        let ((sa, qa), (sb, qb)) = (spread(a), spread(b));
        let allowed = self.sigmas as f32 * sa.hypot(sb) + qa + qb;
        let differ = (0..3)
            .map(|k| (ca[k] - cb[k]).abs())
            .fold(0.0_f32, f32::max);
        differ - allowed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sum_of(colours: &[[u8; 3]]) -> ColourSum {
        let mut s = ColourSum::default();
        for &c in colours {
            s.add(c);
        }
        s
    }

    #[test]
    fn a_surfaces_shades_are_one_colour_and_a_grey_wall_is_another() {
        // Invariant: a red box's full colour and its 60 % shade (each rounded, with ±3 counts of noise) are one colour; the box's returns and a grey wall's are not; black fits anything.
        let split = HueSplit::default();
        let red = sum_of(&[[200, 60, 40], [203, 57, 41], [197, 62, 38]]);
        let shade = sum_of(&[[120, 36, 24], [118, 38, 25], [122, 35, 23]]);
        let wall = sum_of(&[[225, 222, 210], [222, 224, 208]]);
        assert!(split.same(&red, &shade));
        assert!(split.same(&ColourSum::of([201, 61, 39]), &red));
        assert!(!split.same(&red, &wall));
        assert!(!split.same(&ColourSum::of([120, 36, 24]), &wall));
        assert!(split.same(&ColourSum::of([0, 0, 0]), &wall));
        for (a, b) in [
            (red, shade),
            (red, wall),
            (shade, wall),
            (wall, ColourSum::default()),
        ] {
            assert_eq!(
                split.same_summary(&split.summary(&a), &split.summary(&b)),
                split.same(&a, &b),
                "{a:?} {b:?}"
            );
        }
        // One return against a sum: the division-free test agrees with the general one.
        for (sum, rgb) in [
            (red, [201, 61, 39]),
            (red, [120, 36, 24]),
            (wall, [120, 36, 24]),
            (shade, [225, 222, 210]),
            (wall, [0, 0, 0]),
        ] {
            assert_eq!(
                split.fits(&sum, rgb),
                split.same(&sum, &ColourSum::of(rgb)),
                "{sum:?} {rgb:?}"
            );
        }
    }

    #[test]
    fn two_blues_apart_in_hue_are_told_apart_once_enough_returns_are_summed() {
        // Invariant: two cells of 40 returns each, one [40, 70, 170] and one [40, 110, 170] with noise, are different colours; a single dim return of either is not told apart from the other (its noise is too large).
        let split = HueSplit::default();
        let wobble = |c: [u8; 3], k: u8| c.map(|v| v + (k % 3));
        let a = sum_of(
            &(0..40)
                .map(|k| wobble([40, 70, 170], k))
                .collect::<Vec<_>>(),
        );
        let b = sum_of(
            &(0..40)
                .map(|k| wobble([40, 110, 170], k))
                .collect::<Vec<_>>(),
        );
        assert!(!split.same(&a, &b));
        assert!(split.same(&ColourSum::of([4, 9, 17]), &b));
    }
}
