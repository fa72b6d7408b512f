//! From clusters to prisms: convex footprint in xy, height range, the cluster's coloured points.
//!
//! The footprint is the convex hull (parry2d's `transformation::convex_hull`) of the cells' extreme
//! points (see [`crate::elevation::Cell::extremes`]), which equals the hull of the cluster's points to
//! within a few millimetres at a fraction of the cost.
//!
//! **Walls.** A convex hull is a good obstacle only for a compact cluster. The room's walls, joined at
//! the corners, are one cluster whose hull would cover the whole room. So a cluster whose hull area
//! exceeds [`PrismConfig::max_hull_fill_ratio`] times its occupied-cell area is cut in two across its
//! longer side, each half re-labelled into connected pieces, and each piece treated the same way until
//! it is compact (a straight wall run: hull ≈ cells) or small ([`PrismConfig::min_split_extent`]). A
//! U of three walls becomes straight wall segments plus small corner pieces; a chair or a table, whose
//! hull is about its cells, is never cut.
//!
//! **Corners.** The fill ratio cannot tell two wall runs meeting at a corner from two faces of a cart:
//! both are an L of occupied cells whose hull is a triangle over the space between the arms. What tells
//! them apart is the floor: inside a wall corner seen from within the room the sensor sees free floor,
//! while behind a cart's faces the floor is hidden. So a piece whose hull covers more than
//! [`PrismConfig::max_seen_floor_area`] of floor seen free ([`SeenFloor`]) is cut again, whatever its
//! size, along the column or row boundary that leaves the least hull area on the two sides: for an L
//! that is the boundary at the inner corner, so a corner becomes one prism per arm and no prism over
//! the floor between them. A cart's L (no floor seen inside) stays one prism.
//!
//! Heights are measured from the floor. `z_max` is the height of the piece's top surface: the median
//! of the robust tops ([`crate::elevation::Cell::z_top`]) of the cells within
//! [`PrismConfig::top_band`] of the highest. The highest single point would be the surface plus the
//! largest of thousands of noise draws (a 1 cm mat would be 3 cm tall), the highest cell median the
//! surface plus a few millimetres; the median over the top surface is unbiased. `z_min` is the lowest
//! point (above zero for an overhang such as a shelf or a pipe): erring low there only makes the
//! overhang count as an obstacle sooner. A 1 cm mat gives a prism 1 cm tall (its cells are "low" and
//! cluster apart, see [`crate::segment`]).

use std::collections::HashSet;

use nalgebra::Point2;
use parry2d::math::Vector2 as GVec2;

use crate::cloud::{CloudFrame, ColourCloud};
use crate::elevation::{ElevationMap, NO_CELL};
use crate::prism::{ObjectId, Prism, polygon_area};
use crate::seen_floor::SeenFloor;
use crate::segment::{Cluster, Connectivity, components};

/// Parameters of prism building.
#[derive(Clone, Debug, PartialEq)]
pub struct PrismConfig {
    /// A cluster whose hull area exceeds this many times its occupied-cell area is split. Default 2.0
    /// (compact furniture is about 1; an L of two 1 m wall runs is about 6).
    pub max_hull_fill_ratio: f64,
    /// Pieces whose longer side is shorter than this (m) are not split further. Default 0.4.
    pub min_split_extent: f64,
    /// Greatest number of successive splits of one cluster, counted apart for the halvings of a
    /// sprawling cluster and for the cuts of a piece over floor seen free (a corner reached after many
    /// halvings of the room's walls must still be cut). Default 12.
    pub max_split_depth: u32,
    /// Smallest footprint thickness (m): a cluster whose points are collinear, one spot, or a hull
    /// narrower than this (a flat face seen without noise) gets a footprint this thick around them.
    /// Default 0.02, half the elevation map's 4 cm cell.
    pub min_thickness: f64,
    /// Connectivity used to re-label the halves of a split cluster. Default 8.
    pub connectivity: Connectivity,
    /// Two pieces of different clusters merge when their footprints' intersection covers at least this
    /// fraction of the smaller one: a chair leg seen apart from its seat (the seat's corner hidden)
    /// lies inside the chair's footprint and is the chair, not a second object. Default 0.5.
    pub merge_min_overlap: f64,
    /// A piece with a footprint smaller than this (m²) is a fragment: a leg, an edge seen alone.
    /// Default 0.01 (a 10 × 10 cm patch).
    pub fragment_area: f64,
    /// A fragment closer than this (m) to a piece of another cluster joins it (the nearest). Default
    /// 0.1: a chair leg below a hidden seat corner joins the chair; two objects a robot could pass
    /// between (≥ 0.7 m) never merge.
    pub fragment_gap: f64,
    /// Pieces no higher than this (m) are low (mats; see [`crate::segment::SegmentConfig::low_height`])
    /// and never merge with tall ones, so a mat never lends its area to furniture. Default 0.05.
    pub low_height: f32,
    /// Cells whose robust top lies within this (m) of a piece's highest make up its top surface, whose
    /// median height is the prism's top. Default 0.03: three times the vertical range noise of a
    /// near surface, well under the 40 cm between a chair's seat and the top of its back.
    pub top_band: f32,
    /// A piece whose footprint covers more floor seen free than this (m²) is cut again (see the
    /// module doc). Default 0.004: more than two cells of the 4 cm elevation map, so that a stray
    /// cell or two of floor-coloured noise never cuts an object. In the simulated rooms (five
    /// scenarios, some sixty look-arounds each) no chair or table covers a single cell of floor seen
    /// free (the floor under a seat hidden by the chair's back or by a table is not in view up to the
    /// seat), while a wall corner 0.25 m or more on a side covers three cells or more.
    pub max_seen_floor_area: f64,
    /// Floor cells within this many cells of anything else seen do not count as seen free (see
    /// [`SeenFloor::build`]). Default 1: the 4 cm next to a chair's legs, seat edge or a wall's foot.
    pub seen_floor_clearance: u32,
}

impl Default for PrismConfig {
    fn default() -> Self {
        Self {
            max_hull_fill_ratio: 2.0,
            min_split_extent: 0.4,
            max_split_depth: 12,
            min_thickness: 0.02,
            connectivity: Connectivity::Eight,
            merge_min_overlap: 0.5,
            fragment_area: 0.01,
            fragment_gap: 0.1,
            low_height: 0.05,
            top_band: 0.03,
            max_seen_floor_area: 0.004,
            seen_floor_clearance: 1,
        }
    }
}

/// Builds one prism per compact piece of each cluster; ids are `0..n` in build order (see
/// [`crate::prism::track_ids`] for ids stable across looks).
///
/// `cloud` must be the cloud `map` was built from (its points are gathered through
/// [`ElevationMap::point_cells`]); points in sparse cells are not kept. `seen` is the floor the same
/// look saw free on `map`'s grid ([`SeenFloor::none`] when unknown: hulls are then never cut for it).
pub fn build_prisms(
    cloud: &ColourCloud,
    map: &ElevationMap,
    clusters: &[Cluster],
    seen: &SeenFloor,
    config: &PrismConfig,
) -> Vec<Prism> {
    let mut pieces: Vec<(Vec<u32>, Vec<Point2<f64>>)> = Vec::new();
    let mut roots: Vec<usize> = Vec::new();
    for (root, cluster) in clusters.iter().enumerate() {
        let first = pieces.len();
        let depth = Depth::default();
        split_into_compact(map, seen, cluster.cells.clone(), config, depth, &mut pieces);
        if pieces.len() - first > 1 {
            // Pieces of a cut cluster overlap by one cell across each cut, so that the wall they
            // came from stays closed (no gap between two hulls where the points were continuous).
            // Not where that grows a hull over floor seen free: one arm of a corner grown by a cell
            // of the other would be a thin triangle over the floor between them, and the arms
            // overlap at the corner cell anyway.
            let root: HashSet<u32> = cluster.cells.iter().copied().collect();
            for (cells, hull) in &mut pieces[first..] {
                let grown = grow_within(map, cells, &root);
                let grown_hull = footprint_of(map, &grown, config.min_thickness);
                let top = piece_top(map, &grown);
                if seen.free_area_in(&grown_hull, top) <= seen.free_area_in(hull, top) {
                    *hull = grown_hull;
                }
            }
        }
        roots.resize(pieces.len(), root);
    }
    merge_nested(map, &mut pieces, &roots, config);
    // Which piece each touched cell belongs to, to gather points in one pass.
    let mut cell_piece = vec![NO_CELL; map.cells().len()];
    for (p, (cells, _)) in pieces.iter().enumerate() {
        for &k in cells {
            cell_piece[k as usize] = p as u32;
        }
    }
    let mut counts = vec![0usize; pieces.len()];
    for &k in map.point_cells() {
        if k != NO_CELL && cell_piece[k as usize] != NO_CELL {
            counts[cell_piece[k as usize] as usize] += 1;
        }
    }
    let mut clouds: Vec<ColourCloud> = counts
        .iter()
        .map(|&n| {
            ColourCloud::with_capacity(CloudFrame::Map, *cloud.sensor_pose(), cloud.stamp(), n)
        })
        .collect();
    for (i, &k) in map.point_cells().iter().enumerate() {
        if k == NO_CELL {
            continue;
        }
        let piece = cell_piece[k as usize];
        if piece != NO_CELL
            && let Some(p) = cloud.point(i)
        {
            clouds[piece as usize].push(p, cloud.colours()[i]);
        }
    }
    pieces
        .into_iter()
        .zip(clouds)
        .enumerate()
        .map(|(n, ((cells, footprint), points))| {
            let cs = map.cells();
            let z_min = cells
                .iter()
                .map(|&k| cs[k as usize].z_min)
                .fold(f32::INFINITY, f32::min);
            let tops: Vec<f32> = cells.iter().map(|&k| cs[k as usize].z_top).collect();
            let z_max = top_surface(&tops, config.top_band);
            Prism {
                id: ObjectId(n as u32),
                footprint,
                z_min: f64::from(z_min).max(0.0),
                z_max: f64::from(z_max).max(0.0),
                points,
            }
        })
        .collect()
}

/// The height of a cluster's top surface from its cells' robust tops: the median of the cell tops
/// within `band` of the highest. The highest cell top alone is the surface plus the largest of many
/// cells' noise (a few millimetres on a flat top); the median over the cells that make up the top
/// surface is unbiased, while cells of a lower part (a chair's seat below its back) are left out.
fn top_surface(tops: &[f32], band: f32) -> f32 {
    let highest = tops.iter().copied().fold(f32::NEG_INFINITY, f32::max);
    let mut surface: Vec<f32> = tops
        .iter()
        .copied()
        .filter(|&t| t >= highest - band)
        .collect();
    if surface.is_empty() {
        return highest;
    }
    let mid = surface.len() / 2;
    *surface.select_nth_unstable_by(mid, f32::total_cmp).1
}

/// Merges pieces of different clusters (and the same height class) whose footprints mostly overlap,
/// until none do. Deterministic: pairs are scanned in index order and the merged piece takes the lower
/// index.
fn merge_nested(
    map: &ElevationMap,
    pieces: &mut Vec<(Vec<u32>, Vec<Point2<f64>>)>,
    roots: &[usize],
    config: &PrismConfig,
) {
    let cells = map.cells();
    let is_low = |piece: &[u32]| {
        piece
            .iter()
            .all(|&k| cells[k as usize].z_max <= config.low_height)
    };
    let mut roots = roots.to_vec();
    'again: loop {
        for i in 0..pieces.len() {
            for j in i + 1..pieces.len() {
                if roots[i] == roots[j] || is_low(&pieces[i].0) != is_low(&pieces[j].0) {
                    continue;
                }
                let (a, b) = (&pieces[i].1, &pieces[j].1);
                let smaller = polygon_area(a).abs().min(polygon_area(b).abs());
                if smaller <= 0.0 {
                    continue;
                }
                let inter = crate::prism::convex_intersection_area(a, b);
                let fragment_near =
                    smaller < config.fragment_area && polygon_distance(a, b) <= config.fragment_gap;
                if inter >= config.merge_min_overlap * smaller || fragment_near {
                    let (cells_j, _) = pieces.remove(j);
                    roots.remove(j);
                    pieces[i].0.extend(cells_j);
                    pieces[i].1 = footprint_of(map, &pieces[i].0, config.min_thickness);
                    continue 'again;
                }
            }
        }
        break;
    }
}

/// Smallest distance between two convex polygons (0 when they overlap).
fn polygon_distance(a: &[Point2<f64>], b: &[Point2<f64>]) -> f64 {
    if crate::prism::convex_intersection_area(a, b) > 0.0 {
        return 0.0;
    }
    let point_to_edges = |p: &Point2<f64>, poly: &[Point2<f64>]| {
        (0..poly.len())
            .map(|i| {
                let (s, e) = (poly[i], poly[(i + 1) % poly.len()]);
                let d = e - s;
                let t = if d.norm_squared() > 0.0 {
                    ((p - s).dot(&d) / d.norm_squared()).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                (p - (s + d * t)).norm()
            })
            .fold(f64::INFINITY, f64::min)
    };
    let ab = a
        .iter()
        .map(|p| point_to_edges(p, b))
        .fold(f64::INFINITY, f64::min);
    let ba = b
        .iter()
        .map(|p| point_to_edges(p, a))
        .fold(f64::INFINITY, f64::min);
    ab.min(ba)
}

/// How many splits led to a piece: halvings for the fill ratio, cuts for the floor seen free.
#[derive(Clone, Copy, Debug, Default)]
struct Depth {
    halvings: u32,
    cuts: u32,
}

/// Cuts `cells` until every piece is compact and covers no more than a sliver of floor seen free;
/// pushes (cells, hull) pieces.
fn split_into_compact(
    map: &ElevationMap,
    seen: &SeenFloor,
    cells: Vec<u32>,
    config: &PrismConfig,
    depth: Depth,
    out: &mut Vec<(Vec<u32>, Vec<Point2<f64>>)>,
) {
    let hull = footprint_of(map, &cells, config.min_thickness);
    let cell_area = map.cell_size() * map.cell_size();
    let occupied = cells.len() as f64 * cell_area;
    let all = map.cells();
    let (mut c0, mut c1, mut r0, mut r1) = (u32::MAX, 0, u32::MAX, 0);
    for &k in &cells {
        let c = &all[k as usize];
        c0 = c0.min(c.col);
        c1 = c1.max(c.col);
        r0 = r0.min(c.row);
        r1 = r1.max(c.row);
    }
    let (w, h) = (c1.saturating_sub(c0) + 1, r1.saturating_sub(r0) + 1);
    let extent = f64::from(w.max(h)) * map.cell_size();
    let compact = polygon_area(&hull) <= config.max_hull_fill_ratio * occupied;
    let max = config.max_split_depth;
    let (halves, next) = if !compact && extent >= config.min_split_extent && depth.halvings < max {
        let halves: (Vec<u32>, Vec<u32>) = if w >= h {
            let mid = c0 + w / 2;
            cells.iter().partition(|&&k| all[k as usize].col < mid)
        } else {
            let mid = r0 + h / 2;
            cells.iter().partition(|&&k| all[k as usize].row < mid)
        };
        let next = Depth {
            halvings: depth.halvings + 1,
            ..depth
        };
        (halves, next)
    } else if depth.cuts < max
        && seen.free_area_in(&hull, piece_top(map, &cells)) > config.max_seen_floor_area
    {
        let halves = least_hull_cut(map, &cells).unwrap_or((cells, Vec::new()));
        let next = Depth {
            cuts: depth.cuts + 1,
            ..depth
        };
        (halves, next)
    } else {
        ((cells, Vec::new()), depth)
    };
    if halves.1.is_empty() {
        out.push((halves.0, hull));
        return;
    }
    for half in [halves.0, halves.1] {
        for piece in components(map, &half, config.connectivity) {
            split_into_compact(map, seen, piece, config, next, out);
        }
    }
}

/// The highest point of the cells (m above the floor): the height up to which the floor inside a
/// piece's hull must have been in view to count as free.
fn piece_top(map: &ElevationMap, cells: &[u32]) -> f64 {
    let all = map.cells();
    let top = cells
        .iter()
        .map(|&k| all[k as usize].z_max)
        .fold(0.0f32, f32::max);
    f64::from(top)
}

/// The cut of `cells` between two adjacent columns, or two adjacent rows, that leaves the least total
/// hull area on its two sides, as (below the cut, above it); `None` for a single cell.
///
/// Hull areas of every prefix and suffix come from one monotone-chain sweep each way over the cells'
/// extreme points (the chains after the first k points bound the hull of those points), so every
/// candidate cut costs the length of two chains, not two hulls.
fn least_hull_cut(map: &ElevationMap, cells: &[u32]) -> Option<(Vec<u32>, Vec<u32>)> {
    let all = map.cells();
    let mut best: Option<(f64, bool, u32)> = None;
    for by_row in [false, true] {
        // (line index, along, across): columns sweep along x, rows along y.
        let mut pts: Vec<(u32, f64, f64)> = cells
            .iter()
            .flat_map(|&k| {
                let c = &all[k as usize];
                let line = if by_row { c.row } else { c.col };
                c.extremes.iter().map(move |e| {
                    let (x, y) = (f64::from(e[0]), f64::from(e[1]));
                    if by_row { (line, y, x) } else { (line, x, y) }
                })
            })
            .collect();
        pts.sort_by(|a, b| {
            a.0.cmp(&b.0)
                .then(a.1.total_cmp(&b.1))
                .then(a.2.total_cmp(&b.2))
        });
        let below = prefix_hull_areas(pts.iter());
        let mut above = prefix_hull_areas(pts.iter().rev());
        above.reverse();
        // below[i]: hull of the lines up to the i-th distinct line; above[i]: of the lines from it.
        for i in 1..below.len() {
            let total = below[i - 1].1 + above[i].1;
            if best.is_none_or(|(t, _, _)| total < t) {
                best = Some((total, by_row, above[i].0));
            }
        }
    }
    let (_, by_row, first_above) = best?;
    Some(cells.iter().partition(|&&k| {
        let c = &all[k as usize];
        (if by_row { c.row } else { c.col }) < first_above
    }))
}

/// For points sorted by (line, along, across) — or that order reversed — the area of the hull of the
/// points seen so far at the end of each line, as (line, area), in sweep order.
fn prefix_hull_areas<'a>(points: impl Iterator<Item = &'a (u32, f64, f64)>) -> Vec<(u32, f64)> {
    let cross = |o: (f64, f64), a: (f64, f64), b: (f64, f64)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    // Both chains run from the first point to the latest; the hull is the lower chain out and the
    // upper chain back, so its doubled area is the lower chain's shoelace sum less the upper's.
    let shoelace = |chain: &[(f64, f64)]| {
        chain
            .windows(2)
            .map(|w| w[0].0 * w[1].1 - w[1].0 * w[0].1)
            .sum::<f64>()
    };
    let mut lower: Vec<(f64, f64)> = Vec::new();
    let mut upper: Vec<(f64, f64)> = Vec::new();
    let mut out: Vec<(u32, f64)> = Vec::new();
    let mut points = points.peekable();
    while let Some(&(line, a, b)) = points.next() {
        let p = (a, b);
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], p) <= 0.0 {
            lower.pop();
        }
        lower.push(p);
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], p) >= 0.0 {
            upper.pop();
        }
        upper.push(p);
        if points.peek().is_none_or(|next| next.0 != line) {
            out.push((line, 0.5 * (shoelace(&lower) - shoelace(&upper)).abs()));
        }
    }
    out
}

/// `cells` plus their 8-neighbours that belong to `root`.
fn grow_within(map: &ElevationMap, cells: &[u32], root: &HashSet<u32>) -> Vec<u32> {
    let all = map.cells();
    let mut seen: HashSet<u32> = cells.iter().copied().collect();
    let mut grown = cells.to_vec();
    for &k in cells {
        let c = &all[k as usize];
        for dr in -1..=1 {
            for dc in -1..=1 {
                for n in map.layers_at(i64::from(c.col) + dc, i64::from(c.row) + dr) {
                    if root.contains(&n) && seen.insert(n) {
                        grown.push(n);
                    }
                }
            }
        }
    }
    grown
}

/// Counter-clockwise convex footprint of the cells' extreme points, thickened when degenerate.
fn footprint_of(map: &ElevationMap, cells: &[u32], min_thickness: f64) -> Vec<Point2<f64>> {
    let all = map.cells();
    let pts: Vec<GVec2> = cells
        .iter()
        .flat_map(|&k| {
            all[k as usize]
                .extremes
                .iter()
                .map(|e| GVec2::new(e[0], e[1]))
        })
        .collect();
    convex_footprint(&pts, min_thickness)
}

/// Convex hull (parry2d) of xy points as a CCW f64 polygon; a degenerate set (one spot, a line) gets a
/// rectangle `min_thickness` thick around it. Empty input gives an empty polygon.
pub(crate) fn convex_footprint(pts: &[GVec2], min_thickness: f64) -> Vec<Point2<f64>> {
    let Some(first) = pts.first() else {
        return Vec::new();
    };
    let distinct = pts.iter().any(|p| (*p - *first).length_squared() > 1e-12);
    let hull: Vec<Point2<f64>> = if distinct {
        parry2d::transformation::convex_hull(pts)
            .into_iter()
            .map(|v| Point2::new(f64::from(v.x), f64::from(v.y)))
            .collect()
    } else {
        vec![Point2::new(f64::from(first.x), f64::from(first.y))]
    };
    let hull = drop_close_vertices(hull, 1e-3);
    let half = 0.5 * min_thickness;
    // A hull with more area than the minimum thickness times its bounding box's diagonal is wider
    // than that thickness (its length is at most the diagonal): most hulls stop here, without the
    // quadratic search for their long axis below.
    let area = polygon_area(&hull);
    let (lo_x, hi_x) = hull
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, h), p| (l.min(p.x), h.max(p.x)));
    let (lo_y, hi_y) = hull
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, h), p| (l.min(p.y), h.max(p.y)));
    if hull.len() >= 3 && area > min_thickness * (hi_x - lo_x).hypot(hi_y - lo_y) {
        return hull;
    }
    // The hull's long axis: the segment between its two farthest vertices.
    let (mut a, mut b) = (hull[0], hull[0]);
    for p in &hull {
        for q in &hull {
            if (p - q).norm_squared() > (a - b).norm_squared() {
                (a, b) = (*p, *q);
            }
        }
    }
    let d = b - a;
    let len = d.norm();
    let (u, v) = if len > 1e-9 {
        let u = d / len;
        (u, nalgebra::Vector2::new(-u.y, u.x))
    } else {
        (nalgebra::Vector2::x(), nalgebra::Vector2::y())
    };
    // How far the hull reaches to either side of that axis. A flat face seen without noise (a wall
    // head-on, a board) has a hull a few millimetres wide and metres long, with area enough to pass
    // an area test, but no planner can use it: parry2d's convex polygon merges edges whose normals
    // differ by under √ε_f32 and collapses such a sliver to a segment. So thinness is judged by width.
    let (lo, hi) = hull.iter().fold((0.0f64, 0.0f64), |(lo, hi), p| {
        let off = (p - a).dot(&v);
        (lo.min(off), hi.max(off))
    });
    if hull.len() >= 3 && area > min_thickness * min_thickness * 0.25 && hi - lo >= min_thickness {
        return hull;
    }
    // Degenerate: the long axis (or the spot), thickened about the hull's middle.
    let a = a + v * (0.5 * (lo + hi));
    let b = a + d;
    let (a, b) = (a - u * half, b + u * half);
    vec![a - v * half, b - v * half, b + v * half, a + v * half]
}

/// Removes vertices closer than `eps` to the previously kept one (and the last if it nears the first).
fn drop_close_vertices(hull: Vec<Point2<f64>>, eps: f64) -> Vec<Point2<f64>> {
    let mut out: Vec<Point2<f64>> = Vec::with_capacity(hull.len());
    for p in hull {
        if out.last().is_none_or(|q| (p - q).norm() >= eps) {
            out.push(p);
        }
    }
    while out.len() > 1
        && out
            .last()
            .zip(out.first())
            .is_some_and(|(a, b)| (a - b).norm() < eps)
    {
        out.pop();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elevation::ElevationConfig;
    use crate::segment::{SegmentConfig, label};
    use nalgebra::{Isometry3, Point3};

    /// Points every 2 cm over `[x0, x1) × [y0, y1)` at heights 0.1..1.0 m: a block seen all round.
    fn block(x0: f32, x1: f32, y0: f32, y1: f32) -> Vec<[f32; 3]> {
        lattice(x0, x1, y0, y1)
            .flat_map(|(x, y)| (1..=10).map(move |k| [x, y, 0.1 * k as f32]))
            .collect()
    }

    /// Cell-centred points every 2 cm over `[x0, x1) × [y0, y1)`.
    fn lattice(x0: f32, x1: f32, y0: f32, y1: f32) -> impl Iterator<Item = (f32, f32)> {
        let (nx, ny) = (
            ((x1 - x0) / 0.02).round() as usize,
            ((y1 - y0) / 0.02).round() as usize,
        );
        (0..nx * ny).map(move |k| {
            let (i, j) = ((k % nx) as f32, (k / nx) as f32);
            (x0 + 0.02 * i + 0.01, y0 + 0.02 * j + 0.01)
        })
    }

    fn cloud_of(points: impl IntoIterator<Item = [f32; 3]>) -> ColourCloud {
        let mut c = ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0);
        for p in points {
            c.push(Point3::new(p[0], p[1], p[2]), [200, 196, 186]);
        }
        c
    }

    /// An L of two 12 cm thick runs, 0.6 m on a side: one along x (y 0..0.12), one along y
    /// (x 0.48..0.6). Its cells fill half its hull, so the fill ratio alone keeps it whole.
    fn l_shape() -> ColourCloud {
        let mut points = block(0.0, 0.6, 0.0, 0.12);
        points.extend(block(0.48, 0.6, 0.12, 0.6));
        cloud_of(points)
    }

    /// Prisms of `obstacles` with the floor seen at `floor` (at floor height), default settings, seen
    /// by a sensor 1.4 m high in front of the L's open side.
    fn prisms_of(obstacles: &ColourCloud, floor: &[(f32, f32)]) -> (Vec<Prism>, SeenFloor) {
        let map = ElevationMap::build(
            obstacles,
            0.0,
            Point2::origin(),
            &ElevationConfig::default(),
        )
        .expect("valid input");
        let floor = cloud_of(floor.iter().map(|&(x, y)| [x, y, 0.0]));
        let config = PrismConfig::default();
        let is_floor = vec![true; floor.len()];
        let seen = SeenFloor::build(&floor, &is_floor, &map, 3, config.seen_floor_clearance)
            .seen_from(Point3::new(-0.3, 1.0, 1.4));
        let clusters = label(&map, &SegmentConfig::default());
        assert_eq!(clusters.len(), 1, "the L is one cluster");
        (
            build_prisms(obstacles, &map, &clusters, &seen, &config),
            seen,
        )
    }

    /// The prisms whose footprint contains `p`.
    fn covering(prisms: &[Prism], p: (f64, f64)) -> Vec<u32> {
        let p = Point2::new(p.0, p.1);
        prisms
            .iter()
            .filter(|q| q.contains_xy(&p))
            .map(|q| q.id.0)
            .collect()
    }

    #[test]
    fn a_wall_corner_with_floor_seen_inside_becomes_one_prism_per_arm() {
        // Invariant: an L of two runs whose hull covers floor seen free is cut at the corner: two prisms, each over its own run's points, and none over the floor between the runs.
        let walls = l_shape();
        // The floor shows everywhere around the walls, the triangle between the arms included.
        let floor: Vec<(f32, f32)> = lattice(-0.4, 1.0, -0.4, 1.0)
            .filter(|&(x, y)| {
                let on_x_run = x < 0.6 && y < 0.12;
                let on_y_run = (0.48..0.6).contains(&x) && y < 0.6;
                !on_x_run && !on_y_run
            })
            .collect();
        let (prisms, seen) = prisms_of(&walls, &floor);
        assert_eq!(prisms.len(), 2, "{prisms:?}");
        let (along_x, along_y) = (
            covering(&prisms, (0.1, 0.06)),
            covering(&prisms, (0.54, 0.5)),
        );
        assert_eq!(along_x.len(), 1);
        assert_eq!(along_y.len(), 1);
        assert_ne!(along_x, along_y, "each run is its own prism");
        for p in &prisms {
            let pts: Vec<_> = p.points.iter_valid().map(|(_, q, _)| q).collect();
            assert!(!pts.is_empty());
            assert!(
                pts.iter()
                    .all(|q| p.contains_xy(&Point2::new(f64::from(q.x), f64::from(q.y))))
            );
            // Over its own run: all along x (y < 0.12) or all along y (x ≥ 0.48), but for the
            // corner's cells, which the two runs share.
            let on_x = pts.iter().filter(|q| q.y < 0.12 && q.x < 0.44).count();
            let on_y = pts.iter().filter(|q| q.x >= 0.48 && q.y >= 0.16).count();
            assert!(
                on_x == 0 || on_y == 0,
                "a prism over both runs: {on_x} and {on_y} points"
            );
            let free = seen.free_area_in(&p.footprint, p.z_max);
            assert!(
                free <= PrismConfig::default().max_seen_floor_area,
                "{free} m² of floor"
            );
        }
        // The middle of the free triangle is under no prism.
        assert!(covering(&prisms, (0.25, 0.3)).is_empty());
    }

    #[test]
    fn an_l_with_the_floor_inside_hidden_stays_one_prism() {
        // Invariant: the same L with no floor seen inside its hull (two faces of a cart: the floor behind them is hidden) stays one prism over all its points.
        let faces = l_shape();
        let floor: Vec<(f32, f32)> = lattice(-0.4, 1.0, -0.4, 1.0)
            .filter(|&(x, y)| !(x < 0.6 && y < 0.6))
            .collect();
        let (prisms, _) = prisms_of(&faces, &floor);
        assert_eq!(prisms.len(), 1, "{prisms:?}");
        assert_eq!(prisms[0].points.len(), faces.len());
        assert_eq!(covering(&prisms, (0.25, 0.3)), vec![0]);
    }

    #[test]
    fn the_top_surface_is_the_median_of_the_cells_near_the_highest() {
        // Invariant: the prism top is the median of the cell tops within the band of the highest (a flat top's noise averages out) and lower parts (a seat under a back) do not pull it down.
        let flat = [0.009, 0.010, 0.011, 0.0105, 0.0095];
        assert!((top_surface(&flat, 0.03) - 0.010).abs() < 1e-6);
        let chair = [0.45, 0.45, 0.46, 0.44, 0.85, 0.84, 0.86];
        assert!((top_surface(&chair, 0.03) - 0.85).abs() < 1e-6);
        assert_eq!(top_surface(&[0.7], 0.03), 0.7);
    }

    #[test]
    fn degenerate_point_sets_get_a_thin_ccw_footprint() {
        // Invariant: one spot or collinear points give a valid CCW polygon of the minimum thickness.
        let spot = vec![GVec2::new(1.0, 1.0); 5];
        let f = convex_footprint(&spot, 0.02);
        assert_eq!(f.len(), 4);
        assert!((polygon_area(&f) - 0.0004).abs() < 1e-9);
        let line: Vec<GVec2> = (0..10).map(|i| GVec2::new(i as f32 * 0.1, 0.0)).collect();
        let f = convex_footprint(&line, 0.02);
        assert!(polygon_area(&f) > 0.0);
        assert!((polygon_area(&f) - 0.92 * 0.02).abs() < 1e-6);
        assert!(convex_footprint(&[], 0.02).is_empty());
    }

    #[test]
    fn a_flat_face_seen_without_noise_gets_a_footprint_a_planner_can_use() {
        // Invariant: a hull narrower than the minimum thickness, however long, comes out that thick
        // and still covers every point, so parry2d makes it a polygon (the far wall of the fake
        // robot's door room, 3 mm by 2.8 m, had aborted a run: "footprint without area").
        let wall = [
            (6.001_481_5, 1.828_825_4),
            (6.000_175_5, 3.185_128_7),
            (6.000_072_5, 3.193_128),
            (5.999_798_3, 3.157_821_2),
            (5.998_512, 1.805_677_9),
            (5.999_797_3, 0.461_834_9),
            (6.000_156_4, 0.409_477_4),
            (6.000_195, 0.434_358_5),
            (6.001_467_7, 1.746_856_1),
        ];
        let pts: Vec<GVec2> = wall.iter().map(|&(x, y)| GVec2::new(x, y)).collect();
        let f = convex_footprint(&pts, 0.02);
        let xs = f.iter().map(|p| p.x);
        let width = xs.clone().fold(f64::MIN, f64::max) - xs.fold(f64::MAX, f64::min);
        assert!((width - 0.02).abs() < 1e-4, "width {width}");
        for p in &pts {
            let q = Point2::new(f64::from(p.x), f64::from(p.y));
            let inside =
                (0..f.len()).all(|i| (f[(i + 1) % f.len()] - f[i]).perp(&(q - f[i])) >= -1e-6);
            assert!(inside, "{q} outside {f:?}");
        }
        let local: Vec<GVec2> = f
            .iter()
            .map(|p| GVec2::new((p.x - 6.0) as f32, (p.y - 1.8) as f32))
            .collect();
        assert!(parry2d::shape::ConvexPolygon::from_convex_hull(&local).is_some());
    }
}
