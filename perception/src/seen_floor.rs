//! Floor seen free in one look: the elevation map's cells where the floor showed, nothing stood, and
//! the space above was in view.
//!
//! Prism building needs it to tell two things that make the same L of occupied cells apart: two wall
//! runs meeting at a corner, seen from inside the corner, and two faces of a cart. Inside the corner
//! the sensor sees the floor (the triangle between the walls is free); behind the cart's faces the
//! floor is hidden. So a cell counts as seen free when it holds at least a few floor points, nothing
//! else was seen in it or near it (floor under a table top is not free), and the sightline from the
//! sensor to the column above it, up to the height asked about, passes no occupied cell: the floor
//! under a chair's seat shows below the chair's back, but the seat behind the back is hidden, and
//! floor seen there says nothing about the seat. A ray to the floor only proves the space it crossed
//! empty; the column above the floor inside a corner is proved empty by the rays that cross it on
//! their way to the walls.
//!
//! The raster lies on the elevation map's grid, so a cluster's hull (built from the map's cells)
//! never reaches past it and "free" and "occupied" are judged cell for cell.

use nalgebra::{Point2, Point3};
use rayon::prelude::*;

use crate::cloud::ColourCloud;
use crate::elevation::ElevationMap;

/// Cells of an [`ElevationMap`]'s grid where the floor was seen and nothing stood.
#[derive(Clone, Debug, PartialEq)]
pub struct SeenFloor {
    origin: Point2<f64>,
    cell_size: f64,
    cols: usize,
    rows: usize,
    free: Vec<bool>,
    free_count: usize,
    /// Height range (above the floor) of each occupied cell, `None` elsewhere: the occluders.
    solid: Vec<Option<(f32, f32)>>,
    /// The sensor's xy and height above the floor, when known.
    eye: Option<(Point2<f64>, f64)>,
    floor_z: f64,
}

impl SeenFloor {
    /// No floor seen anywhere on `map`'s grid (every hull is then accepted as it is).
    pub fn none(map: &ElevationMap) -> Self {
        let (cols, rows) = map.dims();
        Self {
            origin: map.origin(),
            cell_size: map.cell_size(),
            cols,
            rows,
            free: vec![false; cols * rows],
            free_count: 0,
            solid: Vec::new(),
            eye: None,
            floor_z: map.floor_z(),
        }
    }

    /// The same floor, seen from `eye` (the sensor's position in the map frame): a free cell then
    /// counts only where the sightline to the column above it is clear (see the module doc). An eye
    /// not above the floor, or not finite, is ignored.
    pub fn seen_from(mut self, eye: Point3<f64>) -> Self {
        let height = eye.z - self.floor_z;
        if height > 0.0 && eye.x.is_finite() && eye.y.is_finite() && height.is_finite() {
            self.eye = Some((Point2::new(eye.x, eye.y), height));
        }
        self
    }

    /// Bins the points of `cloud` flagged in `is_floor` (map frame; the floor model's verdict on the
    /// cloud `map` was built from, see [`crate::FloorModel::non_floor_and_flags`]) on `map`'s grid: a
    /// cell is seen free when it holds at least `min_points` floor points and no cell within
    /// `clearance` cells of it (Chebyshev distance) holds any other point. Points off the grid or not
    /// finite are ignored, and so are slots past the shorter of the cloud and the flags.
    ///
    /// The clearance keeps a compact object's own edge out of the free floor: the floor seen between a
    /// chair's legs beside an inset seat, or under the seat's edge where the seat showed only one or
    /// two points per cell, lies next to what was seen of the chair.
    pub fn build(
        cloud: &ColourCloud,
        is_floor: &[bool],
        map: &ElevationMap,
        min_points: u32,
        clearance: u32,
    ) -> Self {
        let mut seen = Self::none(map);
        if seen.free.is_empty() {
            return seen;
        }
        // f32 is exact enough to bin a floor point: an error of a micrometre at a cell boundary
        // moves one point of many into the next cell.
        let (ox, oy) = (seen.origin.x as f32, seen.origin.y as f32);
        let per_metre = (1.0 / seen.cell_size) as f32;
        let (cols, rows, size) = (seen.cols as i64, seen.rows as i64, seen.free.len());
        let width = seen.cols;
        let (xs, ys) = (cloud.xs(), cloud.ys());
        let n = xs.len().min(ys.len()).min(is_floor.len());
        // Counts per cell, binned in parallel over large chunks and summed: integer sums, so the
        // result does not depend on the thread count.
        const CHUNK: usize = 1 << 16;
        let counts = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|chunk| {
                let mut counts = vec![0u32; size];
                let slots = chunk * CHUNK..((chunk + 1) * CHUNK).min(n);
                let points = xs[slots.clone()].iter().zip(&ys[slots.clone()]);
                for ((&x, &y), _) in points.zip(&is_floor[slots]).filter(|(_, f)| **f) {
                    // Truncation of the index plus one, less one, is the floor of the index for
                    // every index above −1, and below −1 it stays negative; NaN truncates to 0 and
                    // goes to −1, off the grid.
                    let c = ((x - ox) * per_metre + 1.0) as i64 - 1;
                    let r = ((y - oy) * per_metre + 1.0) as i64 - 1;
                    if (0..cols).contains(&c) && (0..rows).contains(&r) {
                        let k = r as usize * width + c as usize;
                        counts[k] = counts[k].saturating_add(1);
                    }
                }
                counts
            })
            .reduce_with(|mut a, b| {
                for (x, y) in a.iter_mut().zip(b) {
                    *x = x.saturating_add(y);
                }
                a
            })
            .unwrap_or_else(|| vec![0u32; size]);
        // Cells near anything but floor: every touched cell grown by the clearance.
        let mut near = vec![false; seen.free.len()];
        let reach = clearance as usize;
        for c in map.cells() {
            let (col, row) = (c.col as usize, c.row as usize);
            let last_col = col.saturating_add(reach).min(seen.cols - 1);
            for r in row.saturating_sub(reach)..=row.saturating_add(reach).min(seen.rows - 1) {
                let line = r * seen.cols;
                near[line + col.saturating_sub(reach)..=line + last_col].fill(true);
            }
        }
        seen.solid = vec![None; seen.free.len()];
        for (k, c) in map.cells().iter().enumerate() {
            if map.is_occupied(k) {
                seen.solid[c.row as usize * seen.cols + c.col as usize] = Some((c.z_min, c.z_max));
            }
        }
        for (k, (&n, &near)) in counts.iter().zip(&near).enumerate() {
            if n >= min_points.max(1) && !near {
                seen.free[k] = true;
                seen.free_count += 1;
            }
        }
        seen
    }

    /// Number of cells seen free.
    pub fn free_cells(&self) -> usize {
        self.free_count
    }

    /// Area (m²) of the cells seen free whose centres lie inside the convex CCW `polygon` (map frame)
    /// and, when the eye is known ([`SeenFloor::seen_from`]), whose column was in view from the floor
    /// up to `up_to` (m above the floor). A degenerate polygon (fewer than three vertices) covers
    /// nothing.
    pub fn free_area_in(&self, polygon: &[Point2<f64>], up_to: f64) -> f64 {
        if polygon.len() < 3 || self.free_count == 0 {
            return 0.0;
        }
        let (lo, hi) = polygon.iter().fold(
            (
                Point2::new(f64::INFINITY, f64::INFINITY),
                Point2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
            ),
            |(lo, hi), p| (lo.inf(p), hi.sup(p)),
        );
        // Cells whose centre may fall inside the box: centre = origin + (i + ½)·cell.
        let index_range = |lo: f64, hi: f64, origin: f64, n: usize| {
            let first = ((lo - origin) / self.cell_size - 0.5).ceil().max(0.0);
            let last = ((hi - origin) / self.cell_size - 0.5).floor();
            if !(first.is_finite() && last.is_finite()) || last < first || first >= n as f64 {
                return 0..0;
            }
            first as usize..(last as usize + 1).min(n)
        };
        let cols = index_range(lo.x, hi.x, self.origin.x, self.cols);
        let rows = index_range(lo.y, hi.y, self.origin.y, self.rows);
        let mut n = 0usize;
        for row in rows {
            let y = self.origin.y + (row as f64 + 0.5) * self.cell_size;
            for col in cols.clone() {
                if self.free[row * self.cols + col] {
                    let x = self.origin.x + (col as f64 + 0.5) * self.cell_size;
                    let centre = Point2::new(x, y);
                    if inside_convex(polygon, &centre)
                        && self.column_in_view(&centre, (col, row), up_to)
                    {
                        n += 1;
                    }
                }
            }
        }
        n as f64 * self.cell_size * self.cell_size
    }
}

impl SeenFloor {
    /// Whether the sightlines from the eye to the column above `centre` (cell `own`), from the floor
    /// up to `up_to`, pass no occupied cell. An occupied cell spanning heights `[lo, hi]` a fraction
    /// `t` of the way to the column hides the heights `z` whose ray passes it within that span:
    /// `e + t·(z − e) ∈ [lo, hi]` with `e` the eye's height. True when the eye is unknown.
    fn column_in_view(&self, centre: &Point2<f64>, own: (usize, usize), up_to: f64) -> bool {
        let Some((eye, e)) = self.eye else {
            return true;
        };
        let d = centre - eye;
        let length = d.norm();
        // Half-cell steps visit every cell the sightline crosses but for corner clips.
        let steps = (2.0 * length / self.cell_size).ceil();
        if !steps.is_finite() || steps < 2.0 {
            return true;
        }
        let steps = steps as usize;
        for i in 1..steps {
            let t = i as f64 / steps as f64;
            let q = eye + d * t;
            let c = ((q.x - self.origin.x) / self.cell_size).floor();
            let r = ((q.y - self.origin.y) / self.cell_size).floor();
            if c < 0.0 || r < 0.0 || c >= self.cols as f64 || r >= self.rows as f64 {
                continue;
            }
            let (c, r) = (c as usize, r as usize);
            if (c, r) == own {
                continue;
            }
            if let Some((lo, hi)) = self.solid[r * self.cols + c] {
                let hidden_from = e - (e - f64::from(lo)) / t;
                let hidden_to = e - (e - f64::from(hi)) / t;
                if hidden_to > 0.0 && hidden_from < up_to {
                    return false;
                }
            }
        }
        true
    }
}

/// True when `p` lies inside the convex CCW polygon (boundary included).
fn inside_convex(polygon: &[Point2<f64>], p: &Point2<f64>) -> bool {
    let n = polygon.len();
    (0..n).all(|i| {
        let (a, b) = (polygon[i], polygon[(i + 1) % n]);
        (b - a).perp(&(p - a)) >= 0.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud::CloudFrame;
    use crate::elevation::ElevationConfig;
    use nalgebra::{Isometry3, Point3};

    fn cloud_of(points: impl IntoIterator<Item = [f32; 3]>) -> ColourCloud {
        let mut c = ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0);
        for p in points {
            c.push(Point3::new(p[0], p[1], p[2]), [150, 150, 140]);
        }
        c
    }

    /// Every slot of `cloud` flagged floor.
    fn all(cloud: &ColourCloud) -> Vec<bool> {
        vec![true; cloud.len()]
    }

    /// Points on a square lattice of `step` over `[x0, x1) × [y0, y1)` at height `z`.
    fn lattice(x0: f32, x1: f32, y0: f32, y1: f32, z: f32, step: f32) -> Vec<[f32; 3]> {
        let (nx, ny) = (
            ((x1 - x0) / step).round() as usize,
            ((y1 - y0) / step).round() as usize,
        );
        (0..nx * ny)
            .map(|k| {
                let (i, j) = (k % nx, k / nx);
                [
                    x0 + step * (i as f32 + 0.5),
                    y0 + step * (j as f32 + 0.5),
                    z,
                ]
            })
            .collect()
    }

    /// A 0.4 m table top at 0.7 m over x 0..0.4 and three points at 0.7 m in the cell at (0.78, 0.38),
    /// with floor seen under the top, over x 0.4..0.8 × y 0.2..0.4 and one lone point at (0.61, 0.11).
    fn table_and_floor() -> (ElevationMap, ColourCloud) {
        let top = lattice(0.0, 0.4, 0.0, 0.4, 0.7, 0.01);
        let corner = [[0.79, 0.39, 0.7]; 3];
        let obstacles = cloud_of(top.iter().copied().chain(corner));
        let map = ElevationMap::build(
            &obstacles,
            0.0,
            Point2::origin(),
            &ElevationConfig::default(),
        )
        .expect("valid input");
        let mut floor = lattice(0.0, 0.4, 0.0, 0.4, 0.0, 0.01);
        floor.extend(lattice(0.4, 0.8, 0.2, 0.4, 0.0, 0.01));
        floor.push([0.61, 0.11, 0.0]);
        (map, cloud_of(floor))
    }

    fn square(x0: f64, x1: f64, y0: f64, y1: f64) -> Vec<Point2<f64>> {
        vec![
            Point2::new(x0, y0),
            Point2::new(x1, y0),
            Point2::new(x1, y1),
            Point2::new(x0, y1),
        ]
    }

    #[test]
    fn floor_under_or_beside_an_object_is_not_free_and_sparse_floor_is_not_evidence() {
        // Invariant: a cell counts free only with the minimum of floor points and nothing else seen within the clearance: floor under a table top is not free, and with a clearance of one cell neither is the ring of floor cells around anything seen.
        let (map, floor) = table_and_floor();
        let cell = 0.04 * 0.04;
        // No clearance: the 10 × 5 cells of floor beside the table less the corner's cell.
        let seen = SeenFloor::build(&floor, &all(&floor), &map, 3, 0);
        assert_eq!(seen.free_area_in(&square(0.0, 0.4, 0.0, 0.4), 0.0), 0.0);
        let free = seen.free_area_in(&square(0.4, 0.8, 0.0, 0.4), 0.0);
        assert!((free - 49.0 * cell).abs() < 1e-9, "free {free}");
        assert_eq!(seen.free_cells(), 49);
        // One cell of clearance: the column beside the table and the 2 × 2 cells by the corner go.
        let seen = SeenFloor::build(&floor, &all(&floor), &map, 3, 1);
        assert_eq!(seen.free_cells(), 41);
        // The lone floor point is evidence only when one point is enough.
        assert_eq!(
            SeenFloor::build(&floor, &all(&floor), &map, 1, 0).free_cells(),
            50
        );
        assert_eq!(
            SeenFloor::none(&map).free_area_in(&square(0.4, 0.8, 0.0, 0.4), 0.0),
            0.0
        );
    }

    #[test]
    fn floor_behind_an_occluder_counts_only_where_the_column_above_was_in_view() {
        // Invariant: with the eye known, floor seen below a panel (a chair's back, 0.45-0.85 m) does not count free up to the panel's height, since the space above it was hidden, while floor in plain view does; without the eye both count.
        let mut obstacles: Vec<[f32; 3]> = lattice(0.0, 0.04, 0.0, 0.6, 0.45, 0.01);
        obstacles.extend(lattice(0.0, 0.04, 0.0, 0.6, 0.85, 0.01));
        // Something far off, so that the grid reaches past the open floor.
        obstacles.extend([[0.7, 1.1, 0.5]; 3]);
        let map = ElevationMap::build(
            &cloud_of(obstacles),
            0.0,
            Point2::origin(),
            &ElevationConfig::default(),
        )
        .expect("valid input");
        let mut floor = lattice(0.12, 0.52, 0.08, 0.52, 0.0, 0.01);
        floor.extend(lattice(0.12, 0.52, 0.8, 1.0, 0.0, 0.01));
        let (behind, open) = (square(0.12, 0.52, 0.08, 0.52), square(0.12, 0.52, 0.8, 1.0));
        let floor = cloud_of(floor);
        let blind = SeenFloor::build(&floor, &all(&floor), &map, 3, 1);
        let cell = 0.04 * 0.04;
        assert!((blind.free_area_in(&behind, 0.85) - 110.0 * cell).abs() < 1e-9);
        assert!((blind.free_area_in(&open, 0.85) - 50.0 * cell).abs() < 1e-9);
        let seen = blind.seen_from(Point3::new(-1.0, 0.3, 1.4));
        assert_eq!(seen.free_area_in(&behind, 0.85), 0.0);
        assert!((seen.free_area_in(&open, 0.85) - 50.0 * cell).abs() < 1e-9);
        assert_eq!(seen.free_area_in(&open[..2], 0.85), 0.0);
    }
}
