//! What can hide the floor, and which floor is wanted: the rasters a look prediction marches through.
//!
//! Over a window of the grid (the targets' bounding box grown by the far range: no ray that can
//! reach a target leaves it before its targets), each cell holds
//! - a *shadow factor* from its occluder height `h`: `H / (H − h)` for the eye height `H` (∞ for
//!   `h ≥ H`; 1 for no occluder). A cell holding points of a prism has the highest such point's
//!   height; a cell the grid classes Stationary, Movable or Moving with no prism point has unknown
//!   height and blocks (∞). The unseen interior of a prism's hull is no occluder — nobody knows what
//!   is there — and neither are Unknown cells (the targets themselves are Unknown), tentative
//!   returns included.
//! - the cell's target weight (0 for none).
//!
//! A sight line from the eye at `H` to the floor at distance `r` passes above an occluder top at
//! `(d, h)` iff `H·(1 − d/r) > h`, i.e. iff `r > d · H/(H − h)`: every occluder casts a shadow on
//! the floor from its far edge to `d` times its factor, and a ray keeps the farthest shadow end.
//!
//! For ranking many positions cheaply, the same window is kept at a coarse resolution too
//! (`raster.rs`), and a *viewshed* on it: per coarse cell, the target area of the 0.8 m target
//! blocks whose centre it sees through walls ([`SightMap::viewshed`]), cast once from each block.

use nalgebra::Point2;
use nudge_perception::grid::{CellClass, CellIndex, GridGeometry, ObstacleGrid};
use nudge_perception::{CloudFrame, Prism};

use crate::view::coverage::LookCoverage;
use crate::view::raster::{Raster, SightCell};
use crate::view::targets::Targets;

/// Target blocks are this many grid cells square (0.8 m at 5 cm): few enough that a candidate
/// checks its distance to each, fine enough to hug an L-shaped region.
pub(crate) const BLOCK: usize = 16;

/// A square of `BLOCK × BLOCK` grid cells holding targets: where rays must go.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TargetBlock {
    /// Lower-left corner (m from the window's lower-left corner).
    pub min: (f64, f64),
    /// Upper-right corner (m from the window's lower-left corner).
    pub max: (f64, f64),
    /// Sum of weight × cell area of its targets (m²).
    pub area: f64,
}

impl TargetBlock {
    /// Squared distances from `p` (m from the window's corner) to the block's nearest and
    /// farthest points.
    #[inline]
    pub fn distances2(&self, (px, py): (f64, f64)) -> (f64, f64) {
        let gap = |lo: f64, hi: f64, v: f64| (lo - v).max(v - hi).max(0.0);
        let span = |lo: f64, hi: f64, v: f64| (v - lo).abs().max((hi - v).abs());
        let (gx, gy) = (
            gap(self.min.0, self.max.0, px),
            gap(self.min.1, self.max.1, py),
        );
        let (sx, sy) = (
            span(self.min.0, self.max.0, px),
            span(self.min.1, self.max.1, py),
        );
        (gx * gx + gy * gy, sx * sx + sy * sy)
    }
}

/// The occluder and target rasters over the part of a grid a look at the targets can involve,
/// at the grid's resolution and a coarse one, with the ray fans that predictions cast (see the
/// module doc).
#[derive(Clone, Debug)]
pub struct SightMap {
    pub(crate) geom: GridGeometry,
    pub(crate) coverage: LookCoverage,
    /// First grid column and row of the window.
    pub(crate) x0: usize,
    pub(crate) y0: usize,
    /// The window's cells at the grid's resolution, and 4 × 4 of them to a cell.
    pub(crate) fine: Raster,
    pub(crate) coarse: Raster,
    pub(crate) blocks: Vec<TargetBlock>,
    /// Per coarse cell: the target area of the blocks whose centre is in its sight through walls
    /// (m²; see [`Self::viewshed`]).
    pub(crate) vis: Vec<f32>,
    /// Target cells inside the grid, and their weighted area (m²).
    pub(crate) target_cells: usize,
    pub(crate) target_area: f64,
}

/// Grid cells per coarse raster cell edge (20 cm on the 5 cm grid).
pub(crate) const COARSE: usize = 4;

impl SightMap {
    /// The rasters for a look at `targets` (cells outside the grid are ignored) on `grid` among
    /// `prisms`, with `coverage`'s eye height and range. Occluders within `body_radius` (m) of the
    /// eye are taken for the robot's own footprint and ignored (the robot stands there, so a cell
    /// still marked there is stale). `None` when no target lies in the grid.
    pub fn new(
        grid: &ObstacleGrid,
        prisms: &[Prism],
        targets: &Targets,
        coverage: &LookCoverage,
        body_radius: f64,
    ) -> Option<Self> {
        let geom = *grid.geometry();
        let res = geom.resolution();
        let inside: Vec<(CellIndex, f64)> = targets
            .cells()
            .iter()
            .copied()
            .filter(|(c, _)| geom.contains(*c))
            .collect();
        let first = inside.first()?;
        let (mut lo, mut hi) = ((first.0.x, first.0.y), (first.0.x, first.0.y));
        for (c, _) in &inside {
            lo = (lo.0.min(c.x), lo.1.min(c.y));
            hi = (hi.0.max(c.x), hi.1.max(c.y));
        }
        // Grown by the far range and a cell: every ray that can reach a target does so inside.
        let margin = (coverage.far / res).ceil() as i64 + 1;
        let clip = |v: i64, n: usize| v.clamp(0, n as i64 - 1) as usize;
        let x0 = clip(i64::from(lo.0) - margin, geom.width());
        let y0 = clip(i64::from(lo.1) - margin, geom.height());
        let x1 = clip(i64::from(hi.0) + margin, geom.width());
        let y1 = clip(i64::from(hi.1) + margin, geom.height());
        let (w, h) = (x1 - x0 + 1, y1 - y0 + 1);

        // Occluder heights: prism points first (NaN: none), then obstacle classes without points.
        // Occluder tops go straight into the cells' shadow field (NaN: no point yet), which a
        // last pass turns into factors: one window-sized array, not two.
        let mut cells = vec![
            SightCell {
                shadow: f32::NAN,
                weight: 0.0,
            };
            w * h
        ];
        let origin = geom.origin();
        // Window edges in the map frame, to skip prisms (and points) outside it.
        let (wx0, wy0) = (origin.x + x0 as f64 * res, origin.y + y0 as f64 * res);
        let (wx1, wy1) = (wx0 + w as f64 * res, wy0 + h as f64 * res);
        let inv = 1.0 / res;
        for prism in prisms {
            let outside = prism.footprint.iter().all(|p| p.x < wx0)
                || prism.footprint.iter().all(|p| p.x >= wx1)
                || prism.footprint.iter().all(|p| p.y < wy0)
                || prism.footprint.iter().all(|p| p.y >= wy1);
            if outside && prism.points.frame() == CloudFrame::Map {
                continue; // its points lie in its footprint (map-frame clouds only: cheap to trust)
            }
            let map;
            let cloud = if prism.points.frame() == CloudFrame::Map {
                &prism.points
            } else {
                map = prism.points.to_map();
                &map
            };
            let (xs, ys, zs) = (cloud.xs(), cloud.ys(), cloud.zs());
            for ((&x, &y), &z) in xs.iter().zip(ys).zip(zs) {
                // Window coordinates; truncation is the floor where they are not negative (and
                // `floor` is a library call on targets without SSE4.1).
                let gx = (f64::from(x) - wx0) * inv;
                let gy = (f64::from(y) - wy0) * inv;
                if gx >= 0.0 && gy >= 0.0 && gx < w as f64 && gy < h as f64 && z.is_finite() {
                    let t = &mut cells[gy as usize * w + gx as usize].shadow;
                    if t.is_nan() || z > *t {
                        *t = z;
                    }
                }
            }
        }
        let eye = coverage.eye_height;
        let codes = grid.class_codes();
        let obstacle: [bool; 256] = std::array::from_fn(|c| {
            u8::try_from(c)
                .ok()
                .and_then(CellClass::from_code)
                .is_some_and(CellClass::is_obstacle)
        });
        for (wy, row) in cells.chunks_exact_mut(w).enumerate() {
            let at = (y0 + wy) * geom.width() + x0;
            for (c, &code) in row.iter_mut().zip(&codes[at..at + w]) {
                c.shadow = if !c.shadow.is_nan() {
                    shadow_factor(eye, f64::from(c.shadow))
                } else if obstacle[usize::from(code)] {
                    f32::INFINITY // an obstacle cell without points: unknown height, blocks
                } else {
                    1.0
                };
            }
        }
        let bw = w.div_ceil(BLOCK);
        let mut block_area = vec![0.0f64; bw * h.div_ceil(BLOCK)];
        let mut total = 0.0;
        for &(c, weight) in &inside {
            let (wx, wy) = (c.x as usize - x0, c.y as usize - y0);
            cells[wy * w + wx].weight = weight as f32;
            block_area[(wy / BLOCK) * bw + wx / BLOCK] += weight * res * res;
            total += weight * res * res;
        }
        let blocks: Vec<TargetBlock> = block_area
            .iter()
            .enumerate()
            .filter(|(_, a)| **a > 0.0)
            .map(|(k, &area)| {
                let (bx, by) = (k % bw * BLOCK, k / bw * BLOCK);
                let m = |v: usize| v as f64 * res;
                TargetBlock {
                    min: (m(bx), m(by)),
                    max: (m((bx + BLOCK).min(w)), m((by + BLOCK).min(h))),
                    area,
                }
            })
            .collect();
        let fine = Raster::new(
            (w, h, res),
            cells,
            (coverage.near, coverage.far, body_radius),
            1.5,
        );
        let coarse = fine.coarsened(COARSE, 2.0);
        let vis = viewshed(&coarse, &blocks, coverage.far);
        Some(Self {
            geom,
            coverage: *coverage,
            x0,
            y0,
            fine,
            coarse,
            blocks,
            vis,
            target_cells: inside.len(),
            target_area: total,
        })
    }

    /// The occluder height the prediction assumes at `cell` (m): `None` for no occluder (and
    /// outside the window), infinity for an obstacle of unknown height. Heights at or above the eye
    /// read as infinity (they hide everything behind them alike).
    pub fn occluder_height(&self, cell: CellIndex) -> Option<f64> {
        let c = self.fine.cells.get(self.window_index(cell)?)?;
        if c.shadow == 1.0 {
            None
        } else if c.shadow.is_infinite() {
            Some(f64::INFINITY)
        } else {
            // shadow = H / (H − h)  ⇒  h = H · (1 − 1/shadow)
            Some(self.coverage.eye_height * (1.0 - 1.0 / f64::from(c.shadow)))
        }
    }

    /// A quick upper estimate of what a look from `position` can show (m²): the target area of
    /// the blocks (0.8 m squares of targets) whose centre lies within the far range of it with no
    /// obstacle of unknown height or taller than the eye (a wall) in between — lower occluders,
    /// the heading and the near range are left out. One table look-up; for choosing which
    /// positions to predict.
    pub fn viewshed(&self, position: Point2<f64>) -> f64 {
        let (x, y) = self.local(position);
        let r = &self.coarse;
        let (cx, cy) = (x / r.res, y / r.res);
        if !(cx >= 0.0 && cy >= 0.0 && cx < r.w as f64 && cy < r.h as f64) {
            return 0.0;
        }
        self.vis
            .get(cy as usize * r.w + cx as usize)
            .map_or(0.0, |&v| f64::from(v))
    }

    /// The largest [`Self::viewshed`] anywhere (m²).
    pub fn max_viewshed(&self) -> f64 {
        f64::from(self.vis.iter().copied().fold(0.0, f32::max))
    }

    /// Number of target cells inside the grid.
    pub fn target_cells(&self) -> usize {
        self.target_cells
    }

    /// The targets' total weighted area (m²): the most any look can gain.
    pub fn target_area(&self) -> f64 {
        self.target_area
    }

    /// The coverage the predictions use.
    pub fn coverage(&self) -> &LookCoverage {
        &self.coverage
    }

    /// The grid's geometry.
    pub fn geometry(&self) -> &GridGeometry {
        &self.geom
    }

    /// The window's lower-left corner and a point just inside its upper-right one (map frame).
    pub(crate) fn window_bounds(&self) -> (Point2<f64>, Point2<f64>) {
        let res = self.geom.resolution();
        let lo = self.origin();
        let hi = Point2::new(
            lo.x + (self.fine.w as f64 - 0.5) * res,
            lo.y + (self.fine.h as f64 - 0.5) * res,
        );
        (lo, hi)
    }

    /// The window's lower-left corner (map frame).
    pub(crate) fn origin(&self) -> Point2<f64> {
        let res = self.geom.resolution();
        let o = self.geom.origin();
        Point2::new(o.x + self.x0 as f64 * res, o.y + self.y0 as f64 * res)
    }

    /// Index of a grid cell in the fine raster.
    pub(crate) fn window_index(&self, cell: CellIndex) -> Option<usize> {
        let x = (cell.x as usize).checked_sub(self.x0)?;
        let y = (cell.y as usize).checked_sub(self.y0)?;
        (x < self.fine.w && y < self.fine.h).then_some(y * self.fine.w + x)
    }

    /// The grid cell of a fine raster index.
    pub(crate) fn grid_cell(&self, i: usize) -> CellIndex {
        let w = self.fine.w;
        CellIndex::new((self.x0 + i % w) as u32, (self.y0 + i / w) as u32)
    }

    /// A map point relative to the window's lower-left corner (m).
    pub(crate) fn local(&self, p: Point2<f64>) -> (f64, f64) {
        let o = self.origin();
        (p.x - o.x, p.y - o.y)
    }
}

/// Per cell of `coarse`: the area of the target `blocks` whose centre it sees within `far` (m)
/// through no wall (an infinite shadow factor). Sight through walls is symmetric, so each block
/// casts the rays instead of each cell: a fan from its centre, each ray stopped at the first wall,
/// each cell counted once per block.
fn viewshed(coarse: &Raster, blocks: &[TargetBlock], far: f64) -> Vec<f32> {
    let mut vis = vec![0.0f32; coarse.w * coarse.h];
    let mut stamp = vec![u32::MAX; coarse.w * coarse.h];
    let res = coarse.res;
    for (k, b) in blocks.iter().enumerate() {
        let centre = (
            0.5 * (b.min.0 + b.max.0) / res,
            0.5 * (b.min.1 + b.max.1) / res,
        );
        let area = b.area as f32;
        for &dir in &coarse.fan {
            coarse.walk(centre, dir, far / res, |i, c, t0, _, _| {
                // A wall stops the ray (not one in the centre's own cell: the block's targets
                // lie around it).
                if c.shadow.is_infinite() && t0 > 0.0 {
                    return false;
                }
                if let (Some(s), Some(v)) = (stamp.get_mut(i), vis.get_mut(i))
                    && *s != k as u32
                {
                    *s = k as u32;
                    *v += area;
                }
                true
            });
        }
    }
    vis
}

/// `H / (H − h)` as `f32`: 1 at or below the floor, ∞ at or above the eye.
fn shadow_factor(eye: f64, top: f64) -> f32 {
    if top >= eye {
        f32::INFINITY
    } else if top <= 0.0 {
        1.0
    } else {
        (eye / (eye - top)) as f32
    }
}
