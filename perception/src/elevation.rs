//! The elevation map (Kakiuchi et al. 2010, §IV-C): non-floor points binned into square cells.
//!
//! Each cell keeps its point count, its lowest and highest point (heights above the floor), a robust
//! height of its top and the eight extreme points of its xy footprint (along ±x, ±y and both
//! diagonals), from which a cluster's convex hull is built without revisiting every point. Cells with
//! fewer than [`ElevationConfig::min_points_per_cell`] points are measurement error and are not occupied.
//!
//! **Robust top.** Range noise (σ ≈ 4–10 mm in the room) scatters a flat surface's points above and
//! below it, so a cell's highest point sits a few σ above the surface, and the highest of a cluster's
//! thousands of points higher still: a 1 cm mat's highest point is near 3 cm. A cell's top is therefore
//! the median of its points within [`ElevationConfig::top_band`] of its highest point: on a flat top
//! that is the surface itself (the median of noise is zero); on a sloped or vertical face that reaches
//! the cell's top it lies at most half the band below it.
//!
//! Storage is sparse: a dense `u32` index over the bounding rows × columns points into a compact list of
//! touched cells, so a 380,000-point look-around costs one pass over the points.

use nalgebra::Point2;
use rayon::prelude::*;

use crate::cloud::ColourCloud;
use crate::error::PerceptionError;
use crate::hue::{ColourSum, HueSplit, HueSummary};

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
    /// A cell's robust top ([`Cell::z_top`]) is the median of its points at most this far below its
    /// highest point (m). Default 0.03: wider than the spread of a flat top's points at the room's
    /// ranges (±2.5σ of the ≈ 5 mm vertical noise), so a flat top's median is the surface itself,
    /// and small enough that a vertical face's median stays within 15 mm of its upper edge.
    pub top_band: f64,
    /// Colours a cell keeps apart ([`crate::hue`]): the returns of a cell that differ in
    /// chromaticity beyond the camera's colour noise go into cells of their own at the same place
    /// (its *layers*), so that a red box flush against a grey wall shares no cell with it. `None`:
    /// one cell per place, whatever its colours.
    pub hue: Option<HueSplit>,
}

impl Default for ElevationConfig {
    fn default() -> Self {
        Self {
            cell_size: 0.04,
            min_points_per_cell: 3,
            min_height: -0.05,
            max_height: 3.0,
            max_range: 12.0,
            top_band: 0.03,
            hue: Some(HueSplit::default()),
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
    /// Robust height of the cell's top above the floor (m): the median of its points within
    /// [`ElevationConfig::top_band`] of [`Cell::z_max`]. Noise lifts the highest point a few σ above
    /// the surface; this median stays on it.
    pub z_top: f32,
    /// The cell's extreme points in the map frame's xy plane, one per direction (−x, +x, −y, +y,
    /// −(x+y), +(x+y), −(x−y), +(x−y)). Their convex hull is the cell's points' hull up to a few mm.
    pub extremes: [[f32; 2]; 8],
    /// The colours of its points, summed.
    pub colour: ColourSum,
    /// The next cell at the same place (another colour), or [`NO_CELL`].
    next_layer: u32,
}

impl Cell {
    fn new(col: u32, row: u32, x: f32, y: f32, h: f32, rgb: [u8; 3]) -> Self {
        Self {
            col,
            row,
            count: 1,
            z_min: h,
            z_max: h,
            z_top: h,
            extremes: [[x, y]; 8],
            colour: ColourSum::of(rgb),
            next_layer: NO_CELL,
        }
    }

    fn add(&mut self, x: f32, y: f32, h: f32, rgb: [u8; 3]) {
        self.colour.add(rgb);
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
    hue: Option<HueSplit>,
    /// Per cell, its colour's summary (empty without a hue split).
    hues: Vec<HueSummary>,
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
            && config.max_height.is_finite()
            && config.top_band.is_finite()
            && config.top_band >= 0.0;
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
                // Truncation is the floor for the non-negative values kept (and, unlike
                // `f64::floor` on a baseline x86-64 build, no library call per point).
                let c = (x - origin.x) / cell;
                let r = (y - origin.y) / cell;
                if c >= 0.0 && r >= 0.0 && c < span as f64 && r < span as f64 {
                    (c as u32, r as u32)
                } else {
                    (NO_CELL, NO_CELL)
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
                hue: config.hue.clone(),
                hues: Vec::new(),
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
        let colours = cloud.colours();
        for (i, &(c, r)) in grid_pos.iter().enumerate() {
            if c == NO_CELL {
                continue;
            }
            let (col, row) = (c - c0, r - r0);
            let slot = &mut index[row as usize * cols + col as usize];
            let h = zs[i] - floor_z32;
            let rgb = colours[i];
            let k = if *slot == NO_CELL {
                *slot = cells.len() as u32;
                cells.push(Cell::new(col, row, xs[i], ys[i], h, rgb));
                *slot
            } else {
                match layer_for(&cells, *slot, rgb, config.hue.as_ref()) {
                    Some(k) => {
                        cells[k as usize].add(xs[i], ys[i], h, rgb);
                        k
                    }
                    None => {
                        // A colour of its own at this place: a new layer, linked after the last.
                        let k = cells.len() as u32;
                        let mut last = *slot;
                        while cells[last as usize].next_layer != NO_CELL {
                            last = cells[last as usize].next_layer;
                        }
                        cells[last as usize].next_layer = k;
                        cells.push(Cell::new(col, row, xs[i], ys[i], h, rgb));
                        k
                    }
                }
            };
            point_cell[i] = k;
        }
        robust_tops(
            &mut cells,
            &point_cell,
            zs,
            floor_z32,
            config.top_band as f32,
        );
        Ok(Self {
            origin,
            cell_size: cell,
            cols,
            rows,
            floor_z,
            min_points: config.min_points_per_cell,
            hues: config.hue.as_ref().map_or_else(Vec::new, |hue| {
                cells.iter().map(|c| hue.summary(&c.colour)).collect()
            }),
            index,
            cells,
            point_cell,
            hue: config.hue.clone(),
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

    /// Every touched cell at grid column/row, one per colour kept apart there (see
    /// [`ElevationConfig::hue`]), first touched first.
    pub fn layers_at(&self, col: i64, row: i64) -> impl Iterator<Item = u32> + '_ {
        let mut next = self.cell_at(col, row).unwrap_or(NO_CELL);
        std::iter::from_fn(move || {
            let k = next;
            (k != NO_CELL).then(|| {
                next = self.cells[k as usize].next_layer;
                k
            })
        })
    }

    /// Whether touched cells `a` and `b` hold one surface's colour: always, when the map keeps no
    /// colours apart.
    pub fn same_colour(&self, a: u32, b: u32) -> bool {
        match (
            &self.hue,
            self.hues.get(a as usize),
            self.hues.get(b as usize),
        ) {
            (Some(hue), Some(ha), Some(hb)) => hue.same_summary(ha, hb),
            _ => true,
        }
    }

    /// The first touched cell at grid column/row, if any (the others there hold other colours:
    /// [`Self::layers_at`]).
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

/// The layer at the place whose first cell is `first` that a return of colour `rgb` joins: the first
/// of one colour with it; when none is and the place holds [`HueSplit::layers`] already, the
/// nearest in colour; `None` when it starts a layer of its own. Without a hue split, the first.
fn layer_for(cells: &[Cell], first: u32, rgb: [u8; 3], hue: Option<&HueSplit>) -> Option<u32> {
    let Some(hue) = hue else {
        return Some(first);
    };
    let (mut k, mut layers) = (first, 0);
    while k != NO_CELL {
        if hue.fits(&cells[k as usize].colour, rgb) {
            return Some(k);
        }
        layers += 1;
        k = cells[k as usize].next_layer;
    }
    if layers < hue.layers {
        return None;
    }
    // Every layer taken and none of its colour: the nearest (the rare corner of many colours).
    let point = ColourSum::of(rgb);
    let mut nearest = (f32::INFINITY, first);
    let mut k = first;
    while k != NO_CELL {
        let excess = hue.excess(&cells[k as usize].colour, &point);
        if excess < nearest.0 {
            nearest = (excess, k);
        }
        k = cells[k as usize].next_layer;
    }
    Some(nearest.1)
}

/// Sets every cell's [`Cell::z_top`]: the median of its points' heights within `band` of its highest.
///
/// The heights are gathered per cell by a counting sort over `point_cell` (one pass, in point order, so
/// the result does not depend on anything but the points).
fn robust_tops(cells: &mut [Cell], point_cell: &[u32], zs: &[f32], floor_z: f32, band: f32) {
    let mut start = vec![0usize; cells.len() + 1];
    for &k in point_cell {
        if k != NO_CELL {
            start[k as usize + 1] += 1;
        }
    }
    for k in 0..cells.len() {
        start[k + 1] += start[k];
    }
    let mut fill = start.clone();
    let mut heights = vec![0.0f32; start[cells.len()]];
    for (&k, &z) in point_cell.iter().zip(zs) {
        if k != NO_CELL {
            heights[fill[k as usize]] = z - floor_z;
            fill[k as usize] += 1;
        }
    }
    let mut band_heights: Vec<f32> = Vec::new();
    for (k, cell) in cells.iter_mut().enumerate() {
        let lowest_kept = cell.z_max - band;
        band_heights.clear();
        band_heights.extend(
            heights[start[k]..start[k + 1]]
                .iter()
                .copied()
                .filter(|&h| h >= lowest_kept),
        );
        let mid = band_heights.len() / 2;
        if mid < band_heights.len() {
            let (_, median, _) = band_heights.select_nth_unstable_by(mid, f32::total_cmp);
            cell.z_top = *median;
        }
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

    /// Seeded Gaussian draws of standard deviation `sigma` (Box–Muller).
    fn gaussians(n: usize, sigma: f32, seed: u64) -> Vec<f32> {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        (0..n)
            .map(|_| {
                let u: f32 = 1.0 - rng.random::<f32>();
                let t: f32 = rng.random::<f32>() * std::f32::consts::TAU;
                sigma * (-2.0 * u.ln()).sqrt() * t.cos()
            })
            .collect()
    }

    #[test]
    fn a_flat_noisy_top_has_its_robust_top_on_the_surface_not_at_the_highest_point() {
        // Invariant: on a flat 1 cm top with σ = 5 mm of height noise, every cell's z_top is within
        // 5 mm of 1 cm while the highest points stand well above it.
        let noise = gaussians(1600, 0.005, 7);
        let points: Vec<[f32; 3]> = (0..1600)
            .map(|k| {
                let (i, j) = (k / 40, k % 40);
                let (x, y) = (0.005 * i as f32 + 0.001, 0.005 * j as f32 + 0.001);
                [x, y, 0.01 + noise[k]]
            })
            .collect();
        let map = ElevationMap::build(
            &cloud_of(&points),
            0.0,
            Point2::origin(),
            &ElevationConfig::default(),
        )
        .expect("valid input");
        let highest = map.cells().iter().map(|c| c.z_max).fold(0.0, f32::max);
        assert!(highest > 0.018, "the noise reaches {highest}");
        for c in map.cells() {
            assert!((c.z_top - 0.01).abs() < 0.005, "cell top {}", c.z_top);
        }
    }

    #[test]
    fn a_vertical_face_keeps_its_robust_top_within_half_the_band_of_its_edge() {
        // Invariant: a cell holding a vertical face from 0.45 to 0.85 m (a chair back seen from the
        // front) has z_top below z_max by at most half the top band, and never above it.
        let points: Vec<[f32; 3]> = (0..=80)
            .map(|k| [0.02, 0.02, 0.45 + 0.005 * k as f32])
            .collect();
        let config = ElevationConfig::default();
        let map = ElevationMap::build(&cloud_of(&points), 0.0, Point2::origin(), &config)
            .expect("valid input");
        let c = &map.cells()[0];
        assert!((c.z_max - 0.85).abs() < 1e-5);
        assert!(c.z_top <= c.z_max && c.z_max - c.z_top <= 0.5 * config.top_band as f32 + 1e-5);
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
