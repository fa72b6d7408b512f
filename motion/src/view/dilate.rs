//! A convex footprint grown by a disc, cut into the runs of lattice cells whose centres it holds.
//!
//! The disc-grown footprint `P ⊕ D(r)` of a convex polygon is the *offset polygon* — each edge
//! moved `r` outwards, consecutive ones joined by a chord across the vertex — together with a disc
//! on each vertex (which covers the sliver between a chord and its arc); it is convex, so a row of
//! centres meets it in one interval, the hull of the intervals the row cuts from those parts. That is exact — the cells are those whose centre is within `r` of the footprint — and
//! costs O(vertices) per row, with no per-cell distance query. (A disc stencil stamped around the
//! rasterised footprint costs a stencil per boundary cell and is exact only to a cell; a distance
//! transform sweeps the whole lattice.)

use nalgebra::{Point2, Vector2};

/// Calls `run(y, x0, x1)` for every lattice row `y` (of a lattice of `dims = (cols, rows)` cells of
/// edge `cell`, lower-left corner `origin`) with the columns `x0..=x1` of the cells whose centre
/// lies within `reach` of the convex polygon `poly` (boundary included). Nothing for fewer than
/// three vertices or a non-finite vertex or reach.
pub(crate) fn dilated_rows(
    poly: &[Point2<f64>],
    reach: f64,
    origin: Point2<f64>,
    cell: f64,
    dims: (usize, usize),
    mut run: impl FnMut(usize, usize, usize),
) {
    let (cols, rows) = dims;
    let finite = poly.iter().all(|p| p.x.is_finite() && p.y.is_finite());
    if poly.len() < 3 || !finite || !(reach.is_finite() && reach >= 0.0) || cols == 0 || rows == 0 {
        return;
    }
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in poly {
        lo = lo.min(p.y);
        hi = hi.max(p.y);
    }
    // Rows whose centre y lies within [lo − reach, hi + reach].
    let first = ((lo - reach - origin.y) / cell - 0.5).ceil().max(0.0);
    let last = ((hi + reach - origin.y) / cell - 0.5).floor();
    if last < first {
        return;
    }
    let last = (last as usize).min(rows - 1);
    // The offset polygon: each edge moved `reach` along its outward normal (the right-hand one of
    // a counter-clockwise polygon, the left-hand one of a clockwise one).
    let n = poly.len();
    let turn: f64 = (0..n)
        .map(|i| poly[i].coords.perp(&poly[(i + 1) % n].coords))
        .sum();
    let side = if turn < 0.0 { -1.0 } else { 1.0 };
    let mut offset: Vec<Point2<f64>> = Vec::with_capacity(2 * n);
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        let d = b - a;
        let len = d.norm();
        if len > 0.0 {
            let out = Vector2::new(d.y, -d.x) * (side * reach / len);
            offset.extend([a + out, b + out]);
        }
    }
    for y in first as usize..=last {
        let yc = origin.y + (y as f64 + 0.5) * cell;
        let mut span = Span::EMPTY;
        // The offset polygon holds the footprint itself.
        span.add(convex_cut(&offset, yc));
        for p in poly {
            let dy = yc - p.y;
            let h2 = reach * reach - dy * dy;
            if h2 >= 0.0 {
                let h = h2.sqrt();
                span.add(Some((p.x - h, p.x + h)));
            }
        }
        if span.lo > span.hi {
            continue;
        }
        let x0 = ((span.lo - origin.x) / cell - 0.5).ceil().max(0.0);
        let x1 = ((span.hi - origin.x) / cell - 0.5).floor();
        if x1 < x0 || x0 >= cols as f64 {
            continue;
        }
        run(y, x0 as usize, (x1 as usize).min(cols - 1));
    }
}

/// An interval of x, possibly empty.
struct Span {
    lo: f64,
    hi: f64,
}

impl Span {
    const EMPTY: Span = Span {
        lo: f64::INFINITY,
        hi: f64::NEG_INFINITY,
    };

    fn add(&mut self, part: Option<(f64, f64)>) {
        if let Some((a, b)) = part {
            self.lo = self.lo.min(a);
            self.hi = self.hi.max(b);
        }
    }
}

/// The x interval where the horizontal line at `y` meets the convex polygon `poly`, if it does.
fn convex_cut(poly: &[Point2<f64>], y: f64) -> Option<(f64, f64)> {
    let mut span = Span::EMPTY;
    let n = poly.len();
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if (a.y - y) * (b.y - y) > 0.0 {
            continue; // both ends on one side
        }
        if a.y == b.y {
            span.add(Some((a.x.min(b.x), a.x.max(b.x))));
        } else {
            let x = a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y);
            span.add(Some((x, x)));
        }
    }
    (span.lo <= span.hi).then_some((span.lo, span.hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance from `p` to the convex polygon `poly` (0 inside).
    fn distance(poly: &[Point2<f64>], p: Point2<f64>) -> f64 {
        let n = poly.len();
        let side = |i: usize| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            (b - a).perp(&(p - a))
        };
        let inside = (0..n).all(|i| side(i) >= 0.0) || (0..n).all(|i| side(i) <= 0.0);
        if inside {
            return 0.0;
        }
        (0..n)
            .map(|i| {
                let (a, b) = (poly[i], poly[(i + 1) % n]);
                let ab = b - a;
                let t = ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
                (p - (a + ab * t)).norm()
            })
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn the_rows_hold_exactly_the_centres_within_reach() {
        // Invariant: a centre is in a run iff its distance to the (counter-clockwise, convex)
        // footprint is at most the reach (to 1e-9 m), for rotated boxes, triangles and slivers of
        // either orientation, reaches from 0 to half a metre, footprints crossing the lattice's
        // edges.
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut r = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let (origin, cell, dims) = (Point2::new(-0.3, 0.2), 0.1, (40, 30));
        for case in 0..300 {
            let c = Point2::new(-0.5 + r() * 4.5, -0.2 + r() * 3.5);
            let k = 3 + case % 5;
            let (rx, ry) = (0.02 + r() * 0.8, 0.01 + r() * 0.6);
            let turn = r() * std::f64::consts::TAU;
            let poly: Vec<Point2<f64>> = (0..k)
                .map(|i| {
                    let a = std::f64::consts::TAU * i as f64 / k as f64;
                    let (x, y) = (rx * a.cos(), ry * a.sin());
                    c + Vector2::new(
                        x * turn.cos() - y * turn.sin(),
                        x * turn.sin() + y * turn.cos(),
                    )
                })
                .collect();
            let mut poly = poly;
            if case % 2 == 1 {
                poly.reverse(); // clockwise
            }
            let reach = if case % 7 == 0 { 0.0 } else { r() * 0.5 };
            let mut inside = vec![false; dims.0 * dims.1];
            dilated_rows(&poly, reach, origin, cell, dims, |y, x0, x1| {
                for x in x0..=x1 {
                    inside[y * dims.0 + x] = true;
                }
            });
            for y in 0..dims.1 {
                for x in 0..dims.0 {
                    let p = origin + Vector2::new((x as f64 + 0.5) * cell, (y as f64 + 0.5) * cell);
                    let d = distance(&poly, p);
                    if (d - reach).abs() > 1e-9 {
                        assert_eq!(inside[y * dims.0 + x], d < reach, "case {case} ({x}, {y})");
                    }
                }
            }
        }
    }
}
