//! The elevation map (Kakiuchi et al. 2010, §IV-C): non-floor points binned into square cells.
//!
//! Each cell keeps its point count, its lowest and highest point (heights above the floor) and the eight
//! extreme points of its xy footprint (along ±x, ±y and both diagonals), from which a cluster's convex
//! hull is built without revisiting every point. Cells with fewer than
//! [`ElevationConfig::min_points_per_cell`] points are measurement error and are not occupied.
//!
//! Storage is sparse: a dense `u32` index over the bounding rows × columns points into a compact list of
//! touched cells, so a 380,000-point look-around costs one pass over the points.

use nalgebra::Point2;
use rayon::prelude::*;

use crate::cloud::ColourCloud;
use crate::error::PerceptionError;

/// Parameters of the elevation map.
#[derive(Clone, Debug, PartialEq)]
pub struct ElevationConfig {
    /// Cell side (m). Default 0.04 (the paper's 40 mm).
    pub cell_size: f64,
    /// Fewest points for a cell to be occupied; sparser cells are measurement error. Default 3.
    pub min_points_per_cell: u32,
    /// Points lower than this above the floor are ignored (m): below-floor returns are noise or
    /// reflections, not obstacles. Default −0.05.
    pub min_height: f64,
    /// Points higher than this above the floor are ignored (m). Default 3.0 (above the 2 m walls).
    pub max_height: f64,
    /// Points farther than this from the map centre given to [`ElevationMap::build`] are ignored (m);
    /// it bounds the grid whatever stray point the sensor returns. Default 12.0.
    pub max_range: f64,
}

impl Default for ElevationConfig {
    fn default() -> Self {
        Self {
            cell_size: 0.04,
            min_points_per_cell: 3,
            min_height: -0.05,
            max_height: 3.0,
            max_range: 12.0,
        }
    }
}

/// Index of a direction in [`Cell::extremes`]: −x, +x, −y, +y, −(x+y), +(x+y), −(x−y), +(x−y).
const EXTREME_DIRS: [[f32; 2]; 8] = [
    [-1.0, 0.0],
    [1.0, 0.0],
    [0.0, -1.0],
    [0.0, 1.0],
    [-1.0, -1.0],
    [1.0, 1.0],
    [-1.0, 1.0],
    [1.0, -1.0],
];

/// One touched cell of the elevation map.
#[derive(Clone, Debug, PartialEq)]
pub struct Cell {
    /// Column (x index) in the map's grid.
    pub col: u32,
    /// Row (y index) in the map's grid.
    pub row: u32,
    /// Points binned into the cell.
    pub count: u32,
    /// Lowest point's height above the floor (m).
    pub z_min: f32,
    /// Highest point's height above the floor (m).
    pub z_max: f32,
    /// The cell's extreme points in the map frame's xy plane, one per direction (−x, +x, −y, +y,
    /// −(x+y), +(x+y), −(x−y), +(x−y)). Their convex hull is the cell's points' hull up to a few mm.
    pub extremes: [[f32; 2]; 8],
}

impl Cell {
    fn new(col: u32, row: u32, x: f32, y: f32, h: f32) -> Self {
        Self {
            col,
            row,
            count: 1,
            z_min: h,
            z_max: h,
            extremes: [[x, y]; 8],
        }
    }

    fn add(&mut self, x: f32, y: f32, h: f32) {
        self.count += 1;
        self.z_min = self.z_min.min(h);
        self.z_max = self.z_max.max(h);
        for (e, d) in self.extremes.iter_mut().zip(EXTREME_DIRS) {
            if x * d[0] + y * d[1] > e[0] * d[0] + e[1] * d[1] {
                *e = [x, y];
            }
        }
    }
}

/// Sentinel for "no cell".
pub const NO_CELL: u32 = u32::MAX;

/// Non-floor points binned into square cells.
#[derive(Clone, Debug, PartialEq)]
pub struct ElevationMap {
    origin: Point2<f64>,
    cell_size: f64,
    cols: usize,
    rows: usize,
    floor_z: f64,
    min_points: u32,
    index: Vec<u32>,
    cells: Vec<Cell>,
    point_cell: Vec<u32>,
}

impl ElevationMap {
    /// Bins the valid points of `cloud` (map frame, floor already removed) into cells.
    ///
    /// Heights are measured from `floor_z` (the floor model's mean height). Points outside
    /// `max_range` of `centre` or outside the height band are ignored. An empty or all-invalid cloud gives
    /// an empty map; a non-finite centre, floor height or config is an error.
    pub fn build(
        cloud: &ColourCloud,
        floor_z: f64,
        centre: Point2<f64>,
        config: &ElevationConfig,
    ) -> Result<Self, PerceptionError> {
        let ok = floor_z.is_finite()
            && centre.x.is_finite()
            && centre.y.is_finite()
            && config.cell_size.is_finite()
            && config.cell_size > 1e-4
            && config.max_range.is_finite()
            && config.max_range > 0.0
            && config.min_height.is_finite()
            && config.max_height.is_finite();
        if !ok {
            return Err(PerceptionError::InvalidInput(format!(
                "elevation map input out of range: floor_z {floor_z}, centre {centre:?}, {config:?}"
            )));
        }
        let cell = config.cell_size;
        let range = config.max_range;
        // The grid covers the square of side 2·max_range around the centre, snapped to cells; only the
        // rows and columns actually touched are stored densely.
        let origin = Point2::new(
            ((centre.x - range) / cell).floor() * cell,
            ((centre.y - range) / cell).floor() * cell,
        );
        let span = (2.0 * range / cell).ceil() as usize + 2;
        let (xs, ys, zs) = (cloud.xs(), cloud.ys(), cloud.zs());
        let (lo, hi) = (config.min_height, config.max_height);
        let range_sq = range * range;
        // Pass 1 (parallel, order-preserving): each point's grid column/row or NO_CELL.
        let grid_pos: Vec<(u32, u32)> = (0..cloud.len())
            .into_par_iter()
            .with_min_len(8192)
            .map(|i| {
                let (x, y, z) = (f64::from(xs[i]), f64::from(ys[i]), f64::from(zs[i]));
                let h = z - floor_z;
                let (dx, dy) = (x - centre.x, y - centre.y);
                let inside = x.is_finite()
                    && y.is_finite()
                    && h.is_finite()
                    && h >= lo
                    && h <= hi
                    && dx * dx + dy * dy <= range_sq;
                if !inside {
                    return (NO_CELL, NO_CELL);
                }
                let c = ((x - origin.x) / cell).floor();
                let r = ((y - origin.y) / cell).floor();
                if c < 0.0 || r < 0.0 || c >= span as f64 || r >= span as f64 {
                    (NO_CELL, NO_CELL)
                } else {
                    (c as u32, r as u32)
                }
            })
            .collect();
        // The touched bounding box keeps the dense index small.
        let (mut c0, mut r0, mut c1, mut r1) = (u32::MAX, u32::MAX, 0u32, 0u32);
        for &(c, r) in &grid_pos {
            if c != NO_CELL {
                c0 = c0.min(c);
                c1 = c1.max(c);
                r0 = r0.min(r);
                r1 = r1.max(r);
            }
        }
        if c0 == u32::MAX {
            return Ok(Self {
                origin,
                cell_size: cell,
                cols: 0,
                rows: 0,
                floor_z,
                min_points: config.min_points_per_cell,
                index: Vec::new(),
                cells: Vec::new(),
                point_cell: vec![NO_CELL; cloud.len()],
            });
        }
        let cols = (c1 - c0 + 1) as usize;
        let rows = (r1 - r0 + 1) as usize;
        let origin = Point2::new(
            origin.x + f64::from(c0) * cell,
            origin.y + f64::from(r0) * cell,
        );
        // Pass 2 (sequential: compact cell order is first-touch order, deterministic).
        let mut index = vec![NO_CELL; cols * rows];
        let mut cells: Vec<Cell> = Vec::new();
        let mut point_cell = vec![NO_CELL; cloud.len()];
        let floor_z32 = floor_z as f32;
        for (i, &(c, r)) in grid_pos.iter().enumerate() {
            if c == NO_CELL {
                continue;
            }
            let (col, row) = (c - c0, r - r0);
            let slot = &mut index[row as usize * cols + col as usize];
            let h = zs[i] - floor_z32;
            if *slot == NO_CELL {
                *slot = cells.len() as u32;
                cells.push(Cell::new(col, row, xs[i], ys[i], h));
            } else {
                cells[*slot as usize].add(xs[i], ys[i], h);
            }
            point_cell[i] = *slot;
        }
        Ok(Self {
            origin,
            cell_size: cell,
            cols,
            rows,
            floor_z,
            min_points: config.min_points_per_cell,
            index,
            cells,
            point_cell,
        })
    }

    /// Map-frame xy of the grid's lower-left corner (m).
    pub fn origin(&self) -> Point2<f64> {
        self.origin
    }

    /// Cell side (m).
    pub fn cell_size(&self) -> f64 {
        self.cell_size
    }

    /// Columns (x) and rows (y) of the grid.
    pub fn dims(&self) -> (usize, usize) {
        (self.cols, self.rows)
    }

    /// The floor height the heights are measured from (map frame, m).
    pub fn floor_z(&self) -> f64 {
        self.floor_z
    }

    /// Every touched cell (occupied or not), in first-touch order.
    pub fn cells(&self) -> &[Cell] {
        &self.cells
    }

    /// True when touched cell `k` holds enough points to count.
    pub fn is_occupied(&self, k: usize) -> bool {
        self.cells
            .get(k)
            .is_some_and(|c| c.count >= self.min_points)
    }

    /// Number of occupied cells.
    pub fn occupied_count(&self) -> usize {
        (0..self.cells.len())
            .filter(|&k| self.is_occupied(k))
            .count()
    }

    /// The touched cell at grid column/row, if any.
    pub fn cell_at(&self, col: i64, row: i64) -> Option<u32> {
        if col < 0 || row < 0 || col as usize >= self.cols || row as usize >= self.rows {
            return None;
        }
        let k = self.index[row as usize * self.cols + col as usize];
        (k != NO_CELL).then_some(k)
    }

    /// For each slot of the cloud the map was built from: its touched cell, or [`NO_CELL`].
    pub fn point_cells(&self) -> &[u32] {
        &self.point_cell
    }

    /// Map-frame centre of grid cell (col, row).
    pub fn cell_centre(&self, col: u32, row: u32) -> Point2<f64> {
        Point2::new(
            self.origin.x + (f64::from(col) + 0.5) * self.cell_size,
            self.origin.y + (f64::from(row) + 0.5) * self.cell_size,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud::CloudFrame;
    use nalgebra::{Isometry3, Point3};

    fn cloud_of(points: &[[f32; 3]]) -> ColourCloud {
        let mut c = ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0);
        for p in points {
            c.push(Point3::new(p[0], p[1], p[2]), [0, 0, 0]);
        }
        c
    }

    #[test]
    fn cells_keep_count_and_height_range_and_sparse_cells_are_not_occupied() {
        // Invariant: a cell records count, min and max height above the floor; a cell under the
        // threshold is touched but not occupied.
        let cloud = cloud_of(&[
            [0.01, 0.01, 0.2],
            [0.02, 0.02, 0.5],
            [0.03, 0.01, 0.3],
            [1.01, 1.01, 0.4],
        ]);
        let map = ElevationMap::build(&cloud, 0.1, Point2::origin(), &ElevationConfig::default())
            .expect("valid input");
        assert_eq!(map.cells().len(), 2);
        let dense = map
            .cells()
            .iter()
            .position(|c| c.count == 3)
            .expect("a 3-point cell");
        let c = &map.cells()[dense];
        assert!((c.z_min - 0.1).abs() < 1e-6 && (c.z_max - 0.4).abs() < 1e-6);
        assert!(map.is_occupied(dense));
        assert_eq!(map.occupied_count(), 1);
    }

    #[test]
    fn stray_far_and_non_finite_points_are_ignored() {
        // Invariant: points out of range, out of the height band or non-finite never make cells.
        let cloud = cloud_of(&[
            [1e30, 0.0, 0.2],
            [f32::NAN, 0.0, 0.2],
            [0.0, 0.0, -1.0],
            [0.0, 0.0, 10.0],
        ]);
        let map = ElevationMap::build(&cloud, 0.0, Point2::origin(), &ElevationConfig::default())
            .expect("valid input");
        assert!(map.cells().is_empty());
        assert!(map.point_cells().iter().all(|&k| k == NO_CELL));
    }
}
