//! Rasterising footprints and paths into cells.

use nalgebra::Point2;

use super::geometry::{CellIndex, GridGeometry};
use super::traversal::Traversal;

/// Linear indices of the cells a polygon (map frame, any orientation, first vertex not repeated)
/// covers: cells whose centre is inside (even–odd rule) plus every cell its edges cross, so thin or
/// small polygons still get their cells. Sorted, no duplicates; empty for fewer than 3 finite vertices.
pub(crate) fn polygon_cells(g: &GridGeometry, poly: &[Point2<f64>]) -> Vec<usize> {
    if poly.len() < 3 || poly.iter().any(|p| !(p.x.is_finite() && p.y.is_finite())) {
        return Vec::new();
    }
    let mut out = Vec::new();
    for k in 0..poly.len() {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        out.extend(Traversal::new(g, a, b).filter_map(|c| g.index(c.cell)));
    }
    let Some((x0, y0, x1, y1)) = cell_bounds(g, poly.iter().copied(), 0.0) else {
        out.sort_unstable();
        out.dedup();
        return out;
    };
    for y in y0..=y1 {
        for x in x0..=x1 {
            let c = CellIndex::new(x, y);
            if inside(poly, g.centre(c))
                && let Some(i) = g.index(c)
            {
                out.push(i);
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// Linear indices of the cells a disc of `radius` sweeps along the polyline `path`: every cell whose
/// square lies within `radius` of a path segment (exact segment–square distance). Sorted, deduplicated.
pub(crate) fn path_cells(g: &GridGeometry, path: &[Point2<f64>], radius: f64) -> Vec<usize> {
    let finite = path.iter().all(|p| p.x.is_finite() && p.y.is_finite());
    if path.is_empty() || !finite || !(radius.is_finite() && radius >= 0.0) {
        return Vec::new();
    }
    let segments: Vec<(Point2<f64>, Point2<f64>)> = if path.len() == 1 {
        vec![(path[0], path[0])]
    } else {
        path.windows(2).map(|w| (w[0], w[1])).collect()
    };
    let mut out = Vec::new();
    let h = g.resolution() / 2.0;
    for (a, b) in segments {
        out.extend(Traversal::new(g, a, b).filter_map(|c| g.index(c.cell)));
        let Some((x0, y0, x1, y1)) = cell_bounds(g, [a, b].into_iter(), radius) else {
            continue;
        };
        for y in y0..=y1 {
            for x in x0..=x1 {
                let c = CellIndex::new(x, y);
                let centre = g.centre(c);
                if segment_square_distance(a, b, centre, h) <= radius
                    && let Some(i) = g.index(c)
                {
                    out.push(i);
                }
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// In-grid cell range of the bounding box of `pts` grown by `pad`; `None` when it misses the grid.
fn cell_bounds(
    g: &GridGeometry,
    pts: impl Iterator<Item = Point2<f64>>,
    pad: f64,
) -> Option<(u32, u32, u32, u32)> {
    let (mut lo, mut hi) = (
        Point2::new(f64::INFINITY, f64::INFINITY),
        Point2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
    );
    for p in pts {
        lo = Point2::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Point2::new(hi.x.max(p.x), hi.y.max(p.y));
    }
    let (ax, ay) = g.grid_coords(Point2::new(lo.x - pad, lo.y - pad));
    let (bx, by) = g.grid_coords(Point2::new(hi.x + pad, hi.y + pad));
    let (w, h) = (g.width() as f64, g.height() as f64);
    if bx < 0.0 || by < 0.0 || ax >= w || ay >= h || !(ax <= bx && ay <= by) {
        return None;
    }
    let c = |v: f64, n: f64| v.floor().clamp(0.0, n - 1.0) as u32;
    Some((c(ax, w), c(ay, h), c(bx, w), c(by, h)))
}

/// Even–odd point-in-polygon test.
fn inside(poly: &[Point2<f64>], p: Point2<f64>) -> bool {
    let mut odd = false;
    let mut j = poly.len() - 1;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[j]);
        if (a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x {
            odd = !odd;
        }
        j = i;
    }
    odd
}

/// Distance from segment `a–b` to the axis-aligned square of half-size `h` around `c` (0 if they meet).
pub(crate) fn segment_square_distance(
    a: Point2<f64>,
    b: Point2<f64>,
    c: Point2<f64>,
    h: f64,
) -> f64 {
    let in_square = |p: Point2<f64>| (p.x - c.x).abs() <= h && (p.y - c.y).abs() <= h;
    let corners = [
        Point2::new(c.x - h, c.y - h),
        Point2::new(c.x + h, c.y - h),
        Point2::new(c.x + h, c.y + h),
        Point2::new(c.x - h, c.y + h),
    ];
    if in_square(a) || in_square(b) {
        return 0.0;
    }
    for k in 0..4 {
        if segments_cross(a, b, corners[k], corners[(k + 1) % 4]) {
            return 0.0;
        }
    }
    // Disjoint convex sets: the closest pair involves a vertex of one of them.
    let to_square = |p: Point2<f64>| {
        let dx = ((p.x - c.x).abs() - h).max(0.0);
        let dy = ((p.y - c.y).abs() - h).max(0.0);
        dx.hypot(dy)
    };
    let d_ends = to_square(a).min(to_square(b));
    corners
        .iter()
        .map(|&q| point_segment_distance(q, a, b))
        .fold(d_ends, f64::min)
}

fn point_segment_distance(p: Point2<f64>, a: Point2<f64>, b: Point2<f64>) -> f64 {
    let ab = b - a;
    let l2 = ab.norm_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(&ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + t * ab)).norm()
}

fn segments_cross(a: Point2<f64>, b: Point2<f64>, c: Point2<f64>, d: Point2<f64>) -> bool {
    let orient = |p: Point2<f64>, q: Point2<f64>, r: Point2<f64>| {
        (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x)
    };
    let (d1, d2) = (orient(c, d, a), orient(c, d, b));
    let (d3, d4) = (orient(a, b, c), orient(a, b, d));
    ((d1 > 0.0) != (d2 > 0.0)) && ((d3 > 0.0) != (d4 > 0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn g() -> GridGeometry {
        GridGeometry::with_cells(Point2::new(0.0, 0.0), 10, 10, 1.0).expect("valid")
    }

    #[test]
    fn a_square_footprint_covers_its_cells_and_no_more() {
        // Invariant: a polygon lying within cells 2..4 × 3..5 and covering their centres gives those 9.
        let poly = [
            Point2::new(2.2, 3.2),
            Point2::new(4.8, 3.2),
            Point2::new(4.8, 5.8),
            Point2::new(2.2, 5.8),
        ];
        let cells = polygon_cells(&g(), &poly);
        let mut want: Vec<usize> = (3..=5)
            .flat_map(|y| (2..=4).map(move |x| y * 10 + x))
            .collect();
        want.sort_unstable();
        assert_eq!(cells, want);
    }

    #[test]
    fn a_thin_polygon_still_gets_the_cells_it_crosses() {
        // Invariant: a sliver with no cell centre inside still marks the cells its edges cross.
        let poly = [
            Point2::new(1.1, 1.1),
            Point2::new(3.9, 1.1),
            Point2::new(3.9, 1.2),
        ];
        assert_eq!(polygon_cells(&g(), &poly), vec![11, 12, 13]);
        assert!(polygon_cells(&g(), &poly[..2]).is_empty());
    }

    #[test]
    fn path_cells_grow_with_the_robot_radius() {
        // Invariant: radius 0 gives the traversal; radius r adds exactly the cells within r of the path.
        let path = [Point2::new(0.5, 5.5), Point2::new(9.5, 5.5)];
        let thin = path_cells(&g(), &path, 0.0);
        assert_eq!(thin, (50..60).collect::<Vec<_>>());
        // Rows 4 and 6 are 0.5 from the path, rows 3 and 7 are 1.5 away.
        let wide = path_cells(&g(), &path, 0.6);
        assert_eq!(wide, (40..70).collect::<Vec<_>>());
        let wider = path_cells(&g(), &path, 1.4);
        assert_eq!(wider.len(), 30, "rows 3 and 7 are 1.5 away");
    }

    #[test]
    fn segment_square_distance_is_exact() {
        // Invariant: distance is 0 on contact, else the true gap (axis and corner cases).
        let c = Point2::new(0.0, 0.0);
        let d = |ax, ay, bx, by| {
            segment_square_distance(Point2::new(ax, ay), Point2::new(bx, by), c, 0.5)
        };
        assert_eq!(d(-2.0, 0.0, 2.0, 0.0), 0.0);
        assert!((d(-2.0, 1.5, 2.0, 1.5) - 1.0).abs() < 1e-12);
        assert!((d(1.5, 1.5, 3.0, 3.0) - 2f64.sqrt()).abs() < 1e-12);
        assert!((d(-1.0, 3.0, 3.0, -1.0) - 1.0 / 2f64.sqrt()).abs() < 1e-9);
    }
}
