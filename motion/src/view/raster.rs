//! One resolution of the sight rasters: per cell a shadow factor and a target weight, the fan of
//! rays cast over it, and the march of one ray with its running shadow end.
//!
//! The planner keeps two: the grid's own cells, and a coarse copy (4 × 4 cells into one, the
//! largest shadow factor and the mean weight, so it blocks at least what the fine one does and
//! holds the same target area) with rays 2 of its cells apart at the far range, whose rays take
//! some 20 times fewer steps in all, for ranking many candidate positions before the few best are
//! predicted on the fine one.

/// One raster cell: how far its occluder throws a shadow, and what seeing its floor is worth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SightCell {
    /// `H / (H − h)` for occluder height `h` and eye height `H` (1: none; ∞: blocks all beyond).
    pub shadow: f32,
    /// Target weight per unit of this raster's cell area (0: not a target).
    pub weight: f32,
}

/// Sight cells over the window at one resolution, with the rays cast through them.
#[derive(Clone, Debug)]
pub(crate) struct Raster {
    /// Columns and rows.
    pub w: usize,
    pub h: usize,
    /// Cell edge (m).
    pub res: f64,
    /// Row-major cells.
    pub cells: Vec<SightCell>,
    /// Unit ray directions, evenly over the circle from bearing 0.
    pub fan: Vec<(f64, f64)>,
    /// The coverage's near and far range, and the robot's body radius, in cells.
    pub near: f64,
    pub far: f64,
    pub body: f64,
}

impl Raster {
    /// A raster of `cells` (`w × h`, edge `res` m) for a coverage of `near..far` m and a body of
    /// `body` m radius, with rays `gap` cells apart at the far range (1.5 on the grid's own cells:
    /// every cell there is crossed by a ray or lies within a cell of two, and area sums stay
    /// within a few per cent).
    pub fn new(
        (w, h, res): (usize, usize, f64),
        cells: Vec<SightCell>,
        (near, far, body): (f64, f64, f64),
        gap: f64,
    ) -> Self {
        let rays = ((std::f64::consts::TAU * far / (gap * res)).ceil() as usize).max(8);
        let fan = (0..rays)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / rays as f64;
                (a.cos(), a.sin())
            })
            .collect();
        Self {
            w,
            h,
            res,
            cells,
            fan,
            near: near / res,
            far: far / res,
            body: body.max(0.0) / res,
        }
    }

    /// This raster with `k × k` cells merged into one — the largest shadow factor (it hides at
    /// least what any of them hides) and the mean weight (the same target area) — with rays `gap`
    /// of its cells apart at the far range.
    pub fn coarsened(&self, k: usize, gap: f64) -> Self {
        let k = k.max(1);
        let (w, h) = (self.w.div_ceil(k), self.h.div_ceil(k));
        let mut cells = vec![
            SightCell {
                shadow: 1.0,
                weight: 0.0,
            };
            w * h
        ];
        // Row by row: the k fine rows of a coarse row fold into one row of the fine width, whose
        // k-cell runs then fold into the coarse cells.
        let mut fold = vec![
            SightCell {
                shadow: 1.0,
                weight: 0.0,
            };
            self.w
        ];
        for (out, rows) in cells.chunks_exact_mut(w).zip(self.cells.chunks(k * self.w)) {
            fold.copy_from_slice(&rows[..self.w]);
            for row in rows.chunks_exact(self.w).skip(1) {
                for (f, c) in fold.iter_mut().zip(row) {
                    f.shadow = f.shadow.max(c.shadow);
                    f.weight += c.weight;
                }
            }
            for (o, part) in out.iter_mut().zip(fold.chunks(k)) {
                for c in part {
                    o.shadow = o.shadow.max(c.shadow);
                    o.weight += c.weight;
                }
            }
        }
        let area = (k * k) as f32;
        for c in &mut cells {
            c.weight /= area;
        }
        let res = self.res * k as f64;
        Self::new(
            (w, h, res),
            cells,
            (
                self.near * self.res,
                self.far * self.res,
                self.body * self.res,
            ),
            gap,
        )
    }

    /// Marches the ray from `p` (raster cells) along unit `dir` up to `end` (cells) and returns
    /// its sum of weight · r · Δs over the target cells it sees — those whose stretch of the ray
    /// has its midpoint `r` within `near..far` and beyond the shadow of the occluders before them
    /// — calling `seen` with each one's index.
    #[inline(always)]
    pub fn march(
        &self,
        p: (f64, f64),
        dir: (f64, f64),
        end: f64,
        mut seen: impl FnMut(usize),
    ) -> f64 {
        let (near, end) = (self.near, end.min(self.far));
        let mut sum = 0.0;
        self.walk(p, dir, end, |i, c, t0, t1, shadow| {
            let mid = 0.5 * (t0 + t1);
            if c.weight > 0.0 && mid >= near && mid > shadow {
                sum += f64::from(c.weight) * mid * (t1 - t0);
                seen(i);
            }
            true
        });
        sum
    }

    /// Walks the cells the ray from `p` along unit `dir` crosses up to `end` (cells; Amanatides–
    /// Woo), calling `visit(i, cell, t0, t1, shadow)` with each cell's index, the stretch of the
    /// ray in it and the farthest shadow end of the occluders crossed before it. Occluders within
    /// the body radius are the robot's own footprint and ignored. Stops when `visit` returns false,
    /// at `end`, at the raster's edge, or when a shadow reaches `end` (nothing beyond is visible).
    #[inline(always)]
    pub fn walk(
        &self,
        (px, py): (f64, f64),
        (dx, dy): (f64, f64),
        end: f64,
        mut visit: impl FnMut(usize, SightCell, f64, f64, f64) -> bool,
    ) {
        let (w, h) = (self.w as isize, self.h as isize);
        // Not negative (NaN fails too), so truncation is the floor (`floor` is a library call on
        // targets without SSE4.1).
        if !(px >= 0.0 && py >= 0.0) {
            return;
        }
        let (mut ix, mut iy) = (px as isize, py as isize);
        if ix >= w || iy >= h {
            return;
        }
        let axis = |d: f64, p: f64, i: isize| -> (isize, f64, f64) {
            if d > 0.0 {
                (1, 1.0 / d, (i as f64 + 1.0 - p) / d)
            } else if d < 0.0 {
                (-1, -1.0 / d, (p - i as f64) / -d)
            } else {
                (0, f64::INFINITY, f64::INFINITY)
            }
        };
        let (sx, delta_x, mut tx) = axis(dx, px, ix);
        let (sy, delta_y, mut ty) = axis(dy, py, iy);
        let body = self.body;
        let (mut t0, mut shadow) = (0.0f64, 0.0f64);
        loop {
            let t1 = tx.min(ty).min(end);
            let i = (iy * w + ix) as usize;
            let Some(&c) = self.cells.get(i) else {
                return;
            };
            if !visit(i, c, t0, t1, shadow) {
                return;
            }
            if t1 > body {
                // ∞ · t1 is ∞ for t1 > 0.
                shadow = shadow.max(t1 * f64::from(c.shadow));
            }
            if t1 >= end || shadow >= end {
                return;
            }
            if tx <= ty {
                ix += sx;
                t0 = tx;
                tx += delta_x;
                if ix < 0 || ix >= w {
                    return;
                }
            } else {
                iy += sy;
                t0 = ty;
                ty += delta_y;
                if iy < 0 || iy >= h {
                    return;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn open(w: usize, h: usize) -> Raster {
        let cells = vec![
            SightCell {
                shadow: 1.0,
                weight: 1.0,
            };
            w * h
        ];
        Raster::new((w, h, 0.05), cells, (0.0, 10.0, 0.0), 1.5)
    }

    #[test]
    fn an_open_ray_sums_the_area_of_the_annulus_it_crosses() {
        // Invariant: over open floor of weight 1 the fan's sums times Δθ·res² are the area of the
        // disc the rays reach (π r², to 2 %), and the coarse copy gives the same.
        let r = open(200, 200);
        let centre = (100.0, 100.0);
        let n = r.fan.len();
        let sum: f64 = r
            .fan
            .iter()
            .map(|&d| r.march(centre, d, 80.0, |_| {}))
            .sum();
        let area = sum * std::f64::consts::TAU / n as f64 * r.res * r.res;
        let want = std::f64::consts::PI * 4.0 * 4.0;
        assert!((area / want - 1.0).abs() < 0.02, "{area} vs {want}");
        let c = r.coarsened(4, 1.5);
        let sum: f64 = c
            .fan
            .iter()
            .map(|&d| c.march((25.0, 25.0), d, 20.0, |_| {}))
            .sum();
        let area = sum * std::f64::consts::TAU / c.fan.len() as f64 * c.res * c.res;
        assert!((area / want - 1.0).abs() < 0.02, "{area} vs {want}");
    }

    #[test]
    fn an_occluder_shades_to_its_factor_times_its_far_edge() {
        // Invariant: along +x, an occluder cell of factor f whose far edge is at d hides the cells
        // whose midpoint is at most f·d; those beyond are seen; an infinite one ends the ray.
        let mut r = open(60, 3);
        r.cells[60 + 10].shadow = 2.0; // far edge at 10.5 from p = 0.5
        let mut seen = Vec::new();
        r.march((0.5, 1.5), (1.0, 0.0), 60.0, |i| seen.push(i % 60));
        let hidden: Vec<usize> = (0..60).filter(|x| !seen.contains(x)).collect();
        assert_eq!(
            hidden,
            (11..=21).collect::<Vec<_>>(),
            "midpoints 10.5..21 hidden"
        );
        r.cells[60 + 30].shadow = f32::INFINITY;
        let mut last = 0;
        r.march((0.5, 1.5), (1.0, 0.0), 60.0, |i| last = i % 60);
        assert_eq!(last, 30, "the wall cell is seen, nothing after it");
    }
}
