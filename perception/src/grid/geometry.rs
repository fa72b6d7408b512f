//! The grid frame: where the grid lies in the map, how big its cells are, and cell indices.
//!
//! Cell `(x, y)` covers `[origin.x + x·res, origin.x + (x+1)·res) × [origin.y + y·res, origin.y + (y+1)·res)`
//! in the map frame. Cells are stored row-major: linear index `y · width + x`.

use nalgebra::Point2;

use super::GridError;

/// Default cell size: 50 mm (Chen et al. use 5 cm cells for an 800 × 600 grid).
pub const DEFAULT_RESOLUTION: f64 = 0.05;

/// Largest number of cells a grid may hold (2^28, about 16 km² at 5 cm): linear indices fit in `u32`.
pub const MAX_CELLS: usize = 1 << 28;

/// A cell's column (`x`) and row (`y`) in the grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct CellIndex {
    /// Column, growing with map x.
    pub x: u32,
    /// Row, growing with map y.
    pub y: u32,
}

impl CellIndex {
    /// The cell at column `x`, row `y`.
    pub const fn new(x: u32, y: u32) -> Self {
        Self { x, y }
    }
}

/// Placement and size of a grid in the map frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridGeometry {
    origin: Point2<f64>,
    resolution: f64,
    width: usize,
    height: usize,
}

impl GridGeometry {
    /// A grid whose lower-left corner is `origin`, covering at least `extent` (x, y) metres with square
    /// cells of `resolution` metres (the cell count is rounded up).
    pub fn new(origin: Point2<f64>, extent: [f64; 2], resolution: f64) -> Result<Self, GridError> {
        if !(resolution.is_finite() && resolution > 0.0) {
            return Err(GridError::BadResolution(resolution));
        }
        if !(origin.x.is_finite() && origin.y.is_finite()) {
            return Err(GridError::BadExtent);
        }
        let cells = |e: f64| -> Result<usize, GridError> {
            if !(e.is_finite() && e > 0.0) {
                return Err(GridError::BadExtent);
            }
            let n = (e / resolution - 1e-9).ceil();
            if n > MAX_CELLS as f64 {
                return Err(GridError::TooLarge);
            }
            Ok((n as usize).max(1))
        };
        let (width, height) = (cells(extent[0])?, cells(extent[1])?);
        if width.checked_mul(height).is_none_or(|n| n > MAX_CELLS) {
            return Err(GridError::TooLarge);
        }
        Ok(Self {
            origin,
            resolution,
            width,
            height,
        })
    }

    /// A grid covering the rectangle `min..max` (map frame) plus `margin` metres on every side, as for a
    /// scenario's room (e.g. the 6.0 × 3.6 m kakiuchi room with a 0.5 m margin).
    pub fn from_rect(
        min: Point2<f64>,
        max: Point2<f64>,
        margin: f64,
        resolution: f64,
    ) -> Result<Self, GridError> {
        if !(margin.is_finite() && margin >= 0.0) {
            return Err(GridError::BadExtent);
        }
        let origin = Point2::new(min.x - margin, min.y - margin);
        Self::new(
            origin,
            [max.x - min.x + 2.0 * margin, max.y - min.y + 2.0 * margin],
            resolution,
        )
    }

    /// A grid of exactly `width × height` cells with its lower-left corner at `origin`.
    pub fn with_cells(
        origin: Point2<f64>,
        width: usize,
        height: usize,
        resolution: f64,
    ) -> Result<Self, GridError> {
        if width == 0 || height == 0 {
            return Err(GridError::BadExtent);
        }
        Self::new(
            origin,
            [width as f64 * resolution, height as f64 * resolution],
            resolution,
        )
    }

    /// Lower-left corner of cell (0, 0) in the map frame (m).
    pub fn origin(&self) -> Point2<f64> {
        self.origin
    }

    /// Cell edge length (m).
    pub fn resolution(&self) -> f64 {
        self.resolution
    }

    /// Number of columns.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Number of rows.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.width * self.height
    }

    /// Always false: a grid has at least one cell.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The cell containing map point `p`, or `None` outside the grid (or for a non-finite point).
    pub fn cell_of(&self, p: Point2<f64>) -> Option<CellIndex> {
        let gx = floor((p.x - self.origin.x) / self.resolution);
        let gy = floor((p.y - self.origin.y) / self.resolution);
        self.cell_checked(gx, gy)
    }

    /// The cell at (possibly out-of-range, possibly fractional) grid coordinates, floored.
    pub(crate) fn cell_checked(&self, gx: f64, gy: f64) -> Option<CellIndex> {
        // NaN fails both comparisons, so it is rejected here too.
        let inside = gx >= 0.0 && gy >= 0.0 && gx < self.width as f64 && gy < self.height as f64;
        inside.then(|| CellIndex::new(gx as u32, gy as u32))
    }

    /// Centre of `cell` in the map frame.
    pub fn centre(&self, cell: CellIndex) -> Point2<f64> {
        Point2::new(
            self.origin.x + (cell.x as f64 + 0.5) * self.resolution,
            self.origin.y + (cell.y as f64 + 0.5) * self.resolution,
        )
    }

    /// True when `cell` lies inside the grid.
    pub fn contains(&self, cell: CellIndex) -> bool {
        (cell.x as usize) < self.width && (cell.y as usize) < self.height
    }

    /// Row-major linear index of `cell`, or `None` outside the grid.
    pub fn index(&self, cell: CellIndex) -> Option<usize> {
        self.contains(cell)
            .then(|| cell.y as usize * self.width + cell.x as usize)
    }

    /// The cell at a row-major linear index, or `None` past the end.
    pub fn cell_at(&self, index: usize) -> Option<CellIndex> {
        (index < self.len())
            .then(|| CellIndex::new((index % self.width) as u32, (index / self.width) as u32))
    }

    /// Map point to continuous grid coordinates (cell units, cell (0,0) spans [0,1)²).
    pub(crate) fn grid_coords(&self, p: Point2<f64>) -> (f64, f64) {
        (
            (p.x - self.origin.x) / self.resolution,
            (p.y - self.origin.y) / self.resolution,
        )
    }

    /// Linear indices of the (up to 8) in-grid neighbours of linear index `i`, plus `i` itself.
    #[inline]
    pub(crate) fn for_3x3(&self, i: usize, mut f: impl FnMut(usize)) {
        let (w, h) = (self.width, self.height);
        let (x, y) = (i % w, i / w);
        let (x0, x1) = (x.saturating_sub(1), (x + 1).min(w - 1));
        let (y0, y1) = (y.saturating_sub(1), (y + 1).min(h - 1));
        for yy in y0..=y1 {
            let row = yy * w;
            for xx in x0..=x1 {
                f(row + xx);
            }
        }
    }

    /// Calls `f` with the in-grid linear indices within `r` cells (Chebyshev) of linear index `i`,
    /// one row's contiguous range at a time.
    #[inline]
    pub(crate) fn for_square_rows(
        &self,
        i: usize,
        r: usize,
        mut f: impl FnMut(std::ops::RangeInclusive<usize>),
    ) {
        let (w, h) = (self.width, self.height);
        let (x, y) = (i % w, i / w);
        let (x0, x1) = (x.saturating_sub(r), (x + r).min(w - 1));
        let (y0, y1) = (y.saturating_sub(r), (y + r).min(h - 1));
        for yy in y0..=y1 {
            f(yy * w + x0..=yy * w + x1);
        }
    }

    /// Calls `f` with every in-grid linear index within `r` cells (Chebyshev) of linear index `i`.
    #[inline]
    pub(crate) fn for_square(&self, i: usize, r: usize, mut f: impl FnMut(usize)) {
        let (w, h) = (self.width, self.height);
        let (x, y) = (i % w, i / w);
        let (x0, x1) = (x.saturating_sub(r), (x + r).min(w - 1));
        let (y0, y1) = (y.saturating_sub(r), (y + r).min(h - 1));
        for yy in y0..=y1 {
            let row = yy * w;
            for xx in x0..=x1 {
                f(row + xx);
            }
        }
    }
}

/// `x.floor()`, inline: without SSE4.1 the standard one is a library call, and the grid floors
/// two coordinates per beam end and four per ray. Exact for every `f64` (the integer conversion is
/// only used where it is exact).
#[inline]
pub(crate) fn floor(x: f64) -> f64 {
    // 1.5·2⁵²: adding and taking it away rounds |x| < 2⁵¹ to the nearest integer, exactly.
    const ROUND: f64 = 6_755_399_441_055_744.0;
    if x.abs() < 2_251_799_813_685_248.0 {
        // One less if that rounded up; the floor has x's sign (−0 stays −0, (−1, 0) gives −1).
        // Neither a conversion (with its saturation checks) nor a branch on the fraction.
        let r = (x + ROUND) - ROUND;
        (r - f64::from(u8::from(r > x))).copysign(x)
    } else if x.abs() < 4_503_599_627_370_496.0 {
        // |x| < 2⁵²: the truncation is exact, and one below it when x is negative and fractional;
        // an integer (also −0) is its own floor.
        let t = x as i64 as f64;
        if t > x {
            t - 1.0
        } else if t < x {
            t
        } else {
            x
        }
    } else {
        // Already an integer, infinite or NaN.
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kakiuchi_room_with_margin_has_the_expected_cell_count() {
        // Invariant: a 6.0 × 3.6 m room with 0.5 m margins at 5 cm gives 140 × 92 cells.
        let g = GridGeometry::from_rect(
            Point2::new(0.0, 0.0),
            Point2::new(6.0, 3.6),
            0.5,
            DEFAULT_RESOLUTION,
        )
        .expect("valid room");
        assert_eq!((g.width(), g.height()), (140, 92));
        assert_eq!(
            g.cell_of(Point2::new(-0.5, -0.5)),
            Some(CellIndex::new(0, 0))
        );
        assert_eq!(
            g.cell_of(Point2::new(6.49, 4.09)),
            Some(CellIndex::new(139, 91))
        );
        assert_eq!(g.cell_of(Point2::new(6.51, 0.0)), None);
        assert_eq!(g.cell_of(Point2::new(f64::NAN, 0.0)), None);
    }

    #[test]
    fn bad_geometry_is_an_error() {
        // Invariant: zero, negative or non-finite sizes are refused, never a panic.
        let o = Point2::new(0.0, 0.0);
        assert!(GridGeometry::new(o, [1.0, 1.0], 0.0).is_err());
        assert!(GridGeometry::new(o, [-1.0, 1.0], 0.05).is_err());
        assert!(GridGeometry::new(o, [f64::INFINITY, 1.0], 0.05).is_err());
        assert!(GridGeometry::new(o, [1e9, 1e9], 0.05).is_err());
        assert!(GridGeometry::with_cells(o, 0, 3, 0.05).is_err());
    }

    #[test]
    fn index_and_cell_at_are_inverse() {
        // Invariant: linear indices are row-major and round-trip.
        let g = GridGeometry::with_cells(Point2::new(0.0, 0.0), 7, 5, 0.1).expect("valid");
        for i in 0..g.len() {
            let c = g.cell_at(i).expect("in range");
            assert_eq!(g.index(c), Some(i));
        }
        assert_eq!(g.index(CellIndex::new(2, 3)), Some(3 * 7 + 2));
        assert_eq!(g.index(CellIndex::new(7, 0)), None);
        assert_eq!(g.cell_at(35), None);
    }

    #[test]
    fn the_inline_floor_is_the_standard_floor() {
        // Invariant: floor(x) is bit for bit x.floor(), for integers, halves, tiny and huge values,
        // both signs, infinities (NaN stays NaN).
        let mut xs = vec![
            0.0, -0.0, 0.5, -0.5, 1.0, -1.0, 1e-300, -1e-300, 2.5e15, -2.5e15,
        ];
        xs.extend([
            4.5e15,
            -4.5e15,
            1e300,
            -1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ]);
        xs.extend((0..1000).map(|k| (k as f64 - 500.0) * 0.37 + 1e-9 * k as f64));
        xs.extend([
            f64::MAX,
            f64::MIN,
            4_503_599_627_370_495.5,
            -4_503_599_627_370_495.5,
        ]);
        for x in xs {
            assert_eq!(floor(x).to_bits(), x.floor().to_bits(), "{x}");
        }
        assert!(floor(f64::NAN).is_nan());
    }

    #[test]
    fn the_rounding_floor_matches_the_truncating_one() {
        // Invariant: floor (round to nearest through 1.5·2⁵², less one when that rounded up, with
        // x's sign) is bit for bit the truncating floor it replaced, over random bit patterns and
        // magnitudes of both signs, halves, integers, their neighbouring floats, and ±2⁵¹, ±2⁵².
        fn before(x: f64) -> f64 {
            if x.abs() < 4_503_599_627_370_496.0 {
                let t = x as i64 as f64;
                if t > x {
                    t - 1.0
                } else if t < x {
                    t
                } else {
                    x
                }
            } else {
                x
            }
        }
        let mut next = super::super::test_rng::xorshift(0x6a09_e667_f3bc_c909_u64);
        let mut xs = Vec::new();
        for e in [2_251_799_813_685_248.0, 4_503_599_627_370_496.0, 0.5, 0.0] {
            xs.extend([e, -e, e + 0.5, -e - 0.5, e - 0.5, 0.5 - e]);
        }
        for _ in 0..20_000 {
            let s = next();
            let scaled = (s >> 11) as f64 / (1u64 << 53) as f64 * 2e3 - 1e3;
            for v in [
                f64::from_bits(s),
                scaled,
                scaled.round(),
                scaled.round() + 0.5,
                scaled * 1e-300,
                scaled * 2.3e12,
            ] {
                xs.extend([
                    v,
                    f64::from_bits(v.to_bits() ^ 1),
                    f64::from_bits(v.to_bits() ^ 2),
                ]);
            }
        }
        for x in xs {
            let (a, b) = (floor(x), before(x));
            assert!(
                a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                "{x:e}"
            );
        }
    }
}
