//! A coarse planning lattice over the obstacle grid: where the robot may stand and walk, and at
//! what cost.
//!
//! A lattice cell is `factor × factor` grid cells (default 2: 10 cm on the 5 cm grid). Each holds a
//! *weight*: 0 blocks it, any other value multiplies the cost of stepping into it (1 = ordinary
//! floor). Callers with their own rules fill the weights themselves ([`Lattice::open`] with
//! [`Lattice::set_weight`], or [`Lattice::from_weights`]); [`Lattice::observed_floor`] is the
//! planner's rule — free of obstacles by the robot's radius plus a clearance
//! ([`Lattice::block_obstacles`]), and standing on floor the grid has seen free
//! ([`Lattice::keep_observed_floor`]). Distances and paths come from [`Lattice::distances`].

use nalgebra::Point2;
use nudge_perception::grid::{CellClass, GridGeometry, ObstacleGrid};

use crate::validity::Validity;
use crate::view::dilate::dilated_rows;
use crate::view::geodesic::DistanceField;

/// Why a lattice could not be built or searched.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum LatticeError {
    /// The lattice factor is 0.
    #[error("a lattice cell must hold at least one grid cell")]
    ZeroFactor,
    /// The weights do not have one entry per lattice cell.
    #[error("{got} weights for a lattice of {expected} cells")]
    WrongLength {
        /// Entries given.
        got: usize,
        /// Lattice cells.
        expected: usize,
    },
    /// A position is outside the lattice or not finite.
    #[error("position ({x}, {y}) is outside the lattice")]
    Outside {
        /// x (m).
        x: f64,
        /// y (m).
        y: f64,
    },
    /// A radius or clearance is negative or not finite.
    #[error("radius and clearance must be finite and not negative")]
    BadClearance,
}

/// A lattice cell's column (`x`) and row (`y`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct LatticeCell {
    /// Column, growing with map x.
    pub x: u32,
    /// Row, growing with map y.
    pub y: u32,
}

impl LatticeCell {
    /// The cell at column `x`, row `y`.
    pub const fn new(x: u32, y: u32) -> Self {
        Self { x, y }
    }
}

/// The planning lattice: cells of `factor × factor` grid cells, each with a step weight (0: blocked).
#[derive(Clone, Debug, PartialEq)]
pub struct Lattice {
    origin: Point2<f64>,
    cell: f64,
    factor: usize,
    cols: usize,
    rows: usize,
    /// Weights with a blocked border of one cell all round (`(cols + 2) × (rows + 2)`, row-major),
    /// so that a search reads its neighbours without bounds tests.
    padded: Vec<u8>,
}

impl Lattice {
    /// A lattice over `grid` with cells of `factor × factor` grid cells (the last column and row
    /// may reach past the grid), every cell of weight 1.
    pub fn open(grid: &GridGeometry, factor: usize) -> Result<Self, LatticeError> {
        if factor == 0 {
            return Err(LatticeError::ZeroFactor);
        }
        let cols = grid.width().div_ceil(factor);
        let rows = grid.height().div_ceil(factor);
        let mut padded = vec![0u8; (cols + 2) * (rows + 2)];
        for y in 0..rows {
            let row = (y + 1) * (cols + 2) + 1;
            padded[row..row + cols].fill(1);
        }
        Ok(Self {
            origin: grid.origin(),
            cell: grid.resolution() * factor as f64,
            factor,
            cols,
            rows,
            padded,
        })
    }

    /// A lattice over `grid` with the given weights, one per lattice cell, row-major (0: blocked).
    pub fn from_weights(
        grid: &GridGeometry,
        factor: usize,
        weights: &[u8],
    ) -> Result<Self, LatticeError> {
        let mut l = Self::open(grid, factor)?;
        if weights.len() != l.len() {
            return Err(LatticeError::WrongLength {
                got: weights.len(),
                expected: l.len(),
            });
        }
        for (y, row) in weights.chunks_exact(l.cols).enumerate() {
            let at = (y + 1) * (l.cols + 2) + 1;
            l.padded[at..at + l.cols].copy_from_slice(row);
        }
        Ok(l)
    }

    /// The planner's lattice: cells where the robot's disc, grown by `clearance`, meets no blocking
    /// obstacle of `validity` and stays inside its walls ([`Self::block_obstacles`]), and that
    /// stand on floor the grid has seen free, or lie within the robot's radius of `robot` (it
    /// stands there) ([`Self::keep_observed_floor`]). Every open cell has weight 1, so a cost is a
    /// walking distance.
    pub fn observed_floor(
        grid: &ObstacleGrid,
        validity: &Validity,
        factor: usize,
        clearance: f64,
        robot: Point2<f64>,
    ) -> Result<Self, LatticeError> {
        Self::seen_floor(grid, None, validity, factor, clearance, robot)
    }

    /// [`Self::observed_floor`], counting as floor also the grid cells whose bit is set in
    /// `also_floor` (bit `i % 64` of word `i / 64` for grid cell `i`): floor seen by other means
    /// than the grid's frames (a look-around's steep views, which the grid leaves out; where the
    /// robot stood).
    pub fn seen_floor(
        grid: &ObstacleGrid,
        also_floor: Option<&[u64]>,
        validity: &Validity,
        factor: usize,
        clearance: f64,
        robot: Point2<f64>,
    ) -> Result<Self, LatticeError> {
        let mut l = Self::open(grid.geometry(), factor)?;
        l.block_obstacles(validity, clearance)?;
        let weights = also_floor.map(|_| l.padded.clone());
        l.keep_observed_floor(grid, robot, validity.robot().radius)?;
        if let (Some(extra), Some(before)) = (also_floor, weights) {
            l.reopen_seen(grid, extra, &before);
        }
        Ok(l)
    }

    /// Puts back the weight `before` had for every cell that the floor rule blocked but that stands
    /// on floor when the cells set in `extra` count as Free too (at least half its grid cells).
    fn reopen_seen(&mut self, grid: &ObstacleGrid, extra: &[u64], before: &[u8]) {
        let geom = grid.geometry();
        let (w, h, k) = (geom.width(), geom.height(), self.factor);
        let codes = grid.class_codes();
        let free = CellClass::Free.code();
        let bit = |i: usize| {
            extra
                .get(i / 64)
                .is_some_and(|word| word & (1 << (i % 64)) != 0)
        };
        for ly in 0..self.rows {
            for lx in 0..self.cols {
                let at = (ly + 1) * (self.cols + 2) + lx + 1;
                if self.padded[at] != 0 || before[at] == 0 {
                    continue;
                }
                let (mut n, mut floor) = (0usize, 0usize);
                for gy in ly * k..((ly + 1) * k).min(h) {
                    for gx in lx * k..((lx + 1) * k).min(w) {
                        let i = gy * w + gx;
                        n += 1;
                        floor += usize::from(codes[i] == free || bit(i));
                    }
                }
                if 2 * floor >= n {
                    self.padded[at] = before[at];
                }
            }
        }
    }

    /// Blocks every cell whose centre lies within the robot's radius plus `clearance` of a blocking
    /// obstacle of `validity` (exactly: each footprint grown by that disc is cut row by row), or
    /// closer than that to its walls. Obstacles the robot passes under or steps over are not in
    /// `validity.obstacles()`, so they block nothing here either.
    pub fn block_obstacles(
        &mut self,
        validity: &Validity,
        clearance: f64,
    ) -> Result<(), LatticeError> {
        let reach = validity.robot().radius + clearance;
        if !(clearance.is_finite() && clearance >= 0.0 && reach.is_finite()) {
            return Err(LatticeError::BadClearance);
        }
        let (cols, rows) = (self.cols, self.rows);
        let walls = validity.walls();
        let (lo, hi) = (walls.min(), walls.max());
        // Centres inside the walls shrunk by the reach, per axis: a column or row range each.
        let span = |a: f64, b: f64, origin: f64, n: usize| -> (usize, usize) {
            let first = ((a + reach - origin) / self.cell - 0.5).ceil().max(0.0);
            let last = ((b - reach - origin) / self.cell - 0.5).floor();
            if last < first || last < 0.0 {
                return (1, 0);
            }
            (first as usize, (last as usize).min(n.saturating_sub(1)))
        };
        let (x0, x1) = span(lo.x, hi.x, self.origin.x, cols);
        let (y0, y1) = span(lo.y, hi.y, self.origin.y, rows);
        for y in 0..rows {
            let row = (y + 1) * (cols + 2) + 1;
            let cells = &mut self.padded[row..row + cols];
            if y < y0 || y > y1 || x0 > x1 || x0 >= cols {
                cells.fill(0);
                continue;
            }
            cells[..x0].fill(0);
            if x1 + 1 < cols {
                cells[x1 + 1..].fill(0);
            }
        }
        for o in validity.obstacles() {
            dilated_rows(
                o.footprint(),
                reach,
                self.origin,
                self.cell,
                (cols, rows),
                |y, x0, x1| {
                    let row = (y + 1) * (cols + 2) + 1;
                    self.padded[row + x0..=row + x1].fill(0);
                },
            );
        }
        Ok(())
    }

    /// Blocks every cell that does not stand on floor the grid has seen free: at least half of
    /// its grid cells (in the grid) Free — so a cell across a floor/obstacle border counts by its
    /// majority, and a lone cell the scans missed in open floor does not cut a corridor. Cells
    /// whose centre lies within `radius` of `robot` stay as they are: the robot stands there.
    pub fn keep_observed_floor(
        &mut self,
        grid: &ObstacleGrid,
        robot: Point2<f64>,
        radius: f64,
    ) -> Result<(), LatticeError> {
        if !(radius.is_finite() && radius >= 0.0) {
            return Err(LatticeError::BadClearance);
        }
        let geom = grid.geometry();
        let (w, h, k) = (geom.width(), geom.height(), self.factor);
        let codes = grid.class_codes();
        let free = CellClass::Free.code();
        // The cells the robot stands on keep their weights: saved here, put back at the end.
        let mut under_robot = Vec::new();
        let near = |v: f64, o: f64| ((v - o) / self.cell).floor().max(0.0) as usize;
        let (x0, x1) = (
            near(robot.x - radius, self.origin.x),
            near(robot.x + radius, self.origin.x),
        );
        let (y0, y1) = (
            near(robot.y - radius, self.origin.y),
            near(robot.y + radius, self.origin.y),
        );
        for y in y0..=y1.min(self.rows.saturating_sub(1)) {
            for x in x0..=x1.min(self.cols.saturating_sub(1)) {
                let c = LatticeCell::new(x as u32, y as u32);
                if (self.centre(c) - robot).norm() <= radius {
                    under_robot.push((c, self.weight(c)));
                }
            }
        }
        let cols = self.cols;
        // Per grid column, the Free cells among the lattice row's grid rows: a byte compare and
        // add per cell, which the compiler vectorises (bytes count up to 255 rows; taller lattice
        // cells count in parts).
        let mut column = vec![0u8; w];
        let mut count = vec![0u32; cols];
        for ly in 0..self.rows {
            let (gy0, gy1) = (ly * k, ((ly + 1) * k).min(h));
            let at = (ly + 1) * (cols + 2) + 1;
            let weights = &mut self.padded[at..at + cols];
            if k == 2 && gy1 - gy0 == 2 {
                // The default lattice, whole rows: at least 2 of the 4 cells Free.
                let (r0, r1) = (&codes[gy0 * w..gy1 * w - w], &codes[gy1 * w - w..gy1 * w]);
                for ((c, &a), &b) in column.iter_mut().zip(r0).zip(r1) {
                    *c = u8::from(a == free) + u8::from(b == free);
                }
                for (wt, pair) in weights.iter_mut().zip(column.chunks_exact(2)) {
                    if pair[0] + pair[1] < 2 {
                        *wt = 0;
                    }
                }
                if w % 2 == 1 && column[w - 1] < 1 {
                    weights[cols - 1] = 0; // the last, half lattice cell: 1 of 2
                }
                continue;
            }
            count.fill(0);
            for part in (gy0..gy1).step_by(255) {
                column.fill(0);
                for gy in part..(part + 255).min(gy1) {
                    let row = &codes[gy * w..(gy + 1) * w];
                    for (c, &b) in column.iter_mut().zip(row) {
                        *c += u8::from(b == free);
                    }
                }
                for (n, part) in count.iter_mut().zip(column.chunks(k)) {
                    *n += part.iter().map(|&c| u32::from(c)).sum::<u32>();
                }
            }
            let rows_in = gy1 - gy0;
            for (lx, (wt, &c)) in weights.iter_mut().zip(&count).enumerate() {
                let cols_in = (w - lx * k).min(k);
                // At least half: 2·count ≥ cells.
                if (2 * c as usize) < rows_in * cols_in {
                    *wt = 0;
                }
            }
        }
        for (c, weight) in under_robot {
            self.set_weight(c, weight);
        }
        Ok(())
    }

    /// Number of columns.
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.cols * self.rows
    }

    /// Always false: a lattice over a grid has at least one cell.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Edge length of a lattice cell (m).
    pub fn cell_size(&self) -> f64 {
        self.cell
    }

    /// Grid cells per lattice cell edge.
    pub fn factor(&self) -> usize {
        self.factor
    }

    /// Lower-left corner of cell (0, 0): the grid's origin.
    pub fn origin(&self) -> Point2<f64> {
        self.origin
    }

    /// The cell containing map point `p`, `None` outside (or for a non-finite point).
    pub fn cell_of(&self, p: Point2<f64>) -> Option<LatticeCell> {
        let x = ((p.x - self.origin.x) / self.cell).floor();
        let y = ((p.y - self.origin.y) / self.cell).floor();
        let inside = x >= 0.0 && y >= 0.0 && x < self.cols as f64 && y < self.rows as f64;
        inside.then(|| LatticeCell::new(x as u32, y as u32))
    }

    /// Centre of `cell` in the map frame.
    pub fn centre(&self, cell: LatticeCell) -> Point2<f64> {
        Point2::new(
            self.origin.x + (f64::from(cell.x) + 0.5) * self.cell,
            self.origin.y + (f64::from(cell.y) + 0.5) * self.cell,
        )
    }

    /// The weight of `cell` (0: blocked; also 0 outside the lattice).
    pub fn weight(&self, cell: LatticeCell) -> u8 {
        self.padded_index(cell).map_or(0, |i| self.padded[i])
    }

    /// Whether the robot may stand in `cell`.
    pub fn is_passable(&self, cell: LatticeCell) -> bool {
        self.weight(cell) != 0
    }

    /// Sets the weight of `cell` (0 blocks it); ignored outside the lattice.
    pub fn set_weight(&mut self, cell: LatticeCell, weight: u8) {
        if let Some(i) = self.padded_index(cell) {
            self.padded[i] = weight;
        }
    }

    /// Least-cost distances from `start` over the open cells (see [`DistanceField`]).
    pub fn distances(&self, start: Point2<f64>) -> Result<DistanceField<'_>, LatticeError> {
        let cell = self.cell_of(start).ok_or(LatticeError::Outside {
            x: start.x,
            y: start.y,
        })?;
        Ok(DistanceField::search(self, start, cell, |_, _| true))
    }

    /// [`Self::distances`], stopped where `go_on(cost)` — called with each cell's cost as it is
    /// settled, in increasing cost — returns false: cells of higher cost then read as not reached.
    pub fn distances_until(
        &self,
        start: Point2<f64>,
        mut go_on: impl FnMut(u32) -> bool,
    ) -> Result<DistanceField<'_>, LatticeError> {
        let cell = self.cell_of(start).ok_or(LatticeError::Outside {
            x: start.x,
            y: start.y,
        })?;
        Ok(DistanceField::search(self, start, cell, |_, c| go_on(c)))
    }

    /// [`Self::distances_until`] with each settled cell's padded index.
    pub(crate) fn distances_indexed(
        &self,
        start: Point2<f64>,
        go_on: impl FnMut(usize, u32) -> bool,
    ) -> Result<DistanceField<'_>, LatticeError> {
        let cell = self.cell_of(start).ok_or(LatticeError::Outside {
            x: start.x,
            y: start.y,
        })?;
        Ok(DistanceField::search(self, start, cell, go_on))
    }

    /// Index of `cell` in the padded weights.
    pub(crate) fn padded_index(&self, cell: LatticeCell) -> Option<usize> {
        let (x, y) = (cell.x as usize, cell.y as usize);
        (x < self.cols && y < self.rows).then(|| (y + 1) * (self.cols + 2) + x + 1)
    }

    /// The cell at a padded index (`None` on the border or past the end).
    pub(crate) fn cell_at_padded(&self, i: usize) -> Option<LatticeCell> {
        let w = self.cols + 2;
        let (x, y) = (i % w, i / w);
        (x >= 1 && y >= 1 && x <= self.cols && y <= self.rows)
            .then(|| LatticeCell::new((x - 1) as u32, (y - 1) as u32))
    }

    /// Number of padded indices.
    pub(crate) fn padded_len(&self) -> usize {
        self.padded.len()
    }

    /// The padded weights and the padded row length.
    pub(crate) fn padded(&self) -> (&[u8], usize) {
        (&self.padded, self.cols + 2)
    }
}
