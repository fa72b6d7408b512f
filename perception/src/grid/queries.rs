//! Reading the grid: classes, objects, ages, paths.

use nalgebra::Point2;

use super::ObstacleGrid;
use super::class::CellClass;
use super::evidence::{Evidence, is_active, unpack};
use super::geometry::CellIndex;
use super::raster::path_cells;
use crate::prism::ObjectId;

/// Everything the grid knows about one cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellInfo {
    /// The class.
    pub class: CellClass,
    /// The object the cell belongs to (only for obstacle cells the executive marked).
    pub object: Option<ObjectId>,
    /// Robot-clock stamp of the last observation or verdict, `None` if never.
    pub last_seen: Option<f64>,
    /// Why the cell has its class.
    pub evidence: Evidence,
}

impl ObstacleGrid {
    /// The class of `cell`, `None` outside the grid.
    pub fn class(&self, cell: CellIndex) -> Option<CellClass> {
        let i = self.idx(cell)?;
        CellClass::from_code(self.layers.class[i])
    }

    /// The class at map point `p`, `None` outside the grid.
    pub fn class_at(&self, p: Point2<f64>) -> Option<CellClass> {
        self.class(self.geom.cell_of(p)?)
    }

    /// Everything about `cell`, `None` outside the grid.
    pub fn cell(&self, cell: CellIndex) -> Option<CellInfo> {
        let i = self.idx(cell)?;
        let l = &self.layers;
        let class = CellClass::from_code(l.class[i])?;
        let slot = l.object_at(i);
        let seen = l.last_seen(i);
        Some(CellInfo {
            class,
            object: if class.is_obstacle() { slot } else { None },
            last_seen: seen.is_finite().then_some(seen),
            evidence: unpack(l.evidence[i], slot),
        })
    }

    /// Seconds between the cell's last observation (or verdict) and `now`; `None` outside the grid or
    /// for a cell never observed. Negative if `now` is before the observation.
    pub fn age(&self, cell: CellIndex, now: f64) -> Option<f64> {
        let seen = self.layers.last_seen(self.idx(cell)?);
        seen.is_finite().then_some(now - seen)
    }

    /// The cells currently held by `id` (marked by a push test and still an obstacle), sorted.
    pub fn object_cells(&self, id: ObjectId) -> Vec<CellIndex> {
        let Some(r) = self.objects.get(&id) else {
            return Vec::new();
        };
        let l = &self.layers;
        let mut v: Vec<u32> = r
            .cells
            .iter()
            .copied()
            .filter(|&i| {
                let i = i as usize;
                l.object[i] == id.0
                    && is_active(l.evidence[i])
                    && CellClass::from_code(l.class[i]).is_some_and(CellClass::is_obstacle)
            })
            .collect();
        v.sort_unstable();
        v.dedup();
        v.into_iter()
            .filter_map(|i| self.geom.cell_at(i as usize))
            .collect()
    }

    /// The cells a robot of `radius` sweeps along the polyline `path` (every cell within `radius` of
    /// it), sorted row-major, deduplicated. Empty for an empty path, a non-finite point or a negative
    /// radius.
    pub fn cells_along_path(&self, path: &[Point2<f64>], radius: f64) -> Vec<CellIndex> {
        path_cells(&self.geom, path, radius)
            .into_iter()
            .filter_map(|i| self.geom.cell_at(i))
            .collect()
    }

    /// The classes along a path (see [`Self::cells_along_path`]), as (cell, class) pairs.
    pub fn classes_along_path(
        &self,
        path: &[Point2<f64>],
        radius: f64,
    ) -> Vec<(CellIndex, CellClass)> {
        path_cells(&self.geom, path, radius)
            .into_iter()
            .filter_map(|i| {
                let c = self.geom.cell_at(i)?;
                Some((c, CellClass::from_code(self.layers.class[i])?))
            })
            .collect()
    }

    /// Number of cells of each class, indexed by class code. A full sweep: for reports, not per frame.
    pub fn class_counts(&self) -> [usize; 5] {
        let mut n = [0usize; 5];
        for &c in &self.layers.class {
            if let Some(slot) = n.get_mut(c as usize) {
                *slot += 1;
            }
        }
        n
    }
}
