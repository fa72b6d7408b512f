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

    /// Robot-clock stamp of the latest frame with a return in `cell` (something stood there at a
    /// height the grid counts); `None` outside the grid or for a cell no frame returned from.
    pub fn last_hit(&self, cell: CellIndex) -> Option<f64> {
        let l = &self.layers;
        let frame = l.track[self.idx(cell)?].hit_frame as usize;
        l.stamps.get(frame).copied().filter(|t| t.is_finite())
    }

    /// Robot-clock stamp of the latest frame whose rays crossed `cell` (on their way to a return
    /// beyond it, or to one in it); `None` outside the grid or for a cell no ray crossed.
    pub fn last_crossed(&self, cell: CellIndex) -> Option<f64> {
        let l = &self.layers;
        let frame = l.visible.last_crossed(self.idx(cell)?) as usize;
        l.stamps.get(frame).copied().filter(|t| t.is_finite())
    }

    /// Whether `cell` was ever observed: crossed by a ray (however near its return), holding a
    /// return, or given a verdict — exactly when [`Self::age`] is `Some`. False outside the grid.
    pub fn observed(&self, cell: CellIndex) -> bool {
        self.idx(cell).is_some_and(|i| {
            self.layers
                .observed
                .get(i / 64)
                .is_some_and(|w| w >> (i % 64) & 1 != 0)
        })
    }

    /// Every cell's [`Self::observed`] as a bitset: bit `i % 64` of word `i / 64` is the cell with
    /// row-major linear index `i` (as in [`Self::class_codes`]); bits past the last cell are 0.
    /// Kept up to date by every update and verdict, so reading it costs nothing.
    pub fn observed_words(&self) -> &[u64] {
        &self.layers.observed
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

#[cfg(test)]
mod tests {
    use super::super::test_rng::uniform;
    use super::super::{
        Beam, BeamEnd, CellIndex, Footprint, GridConfig, GridGeometry, ObstacleGrid, RangeFrame,
        Verdict,
    };
    use crate::prism::ObjectId;
    use nalgebra::{Point2, Vector2};

    /// Asserts that the bitset says observed exactly where `last_seen` (and `age`) is `Some`, and
    /// that no bit past the last cell is set.
    fn assert_bitset_is_last_seen(grid: &ObstacleGrid, what: &str) {
        let geom = grid.geometry();
        for i in 0..geom.len() {
            let c = geom.cell_at(i).expect("in grid");
            let seen = grid.cell(c).expect("in grid").last_seen.is_some();
            let bit = grid.observed_words()[i / 64] >> (i % 64) & 1 == 1;
            assert_eq!(bit, seen, "{what}: cell {i}");
            assert_eq!(grid.observed(c), seen, "{what}: cell {i}");
            assert_eq!(grid.age(c, 1e6).is_some(), seen, "{what}: cell {i}");
            // The latest return and the latest crossing are observations: never after the last one.
            let last = grid.cell(c).and_then(|info| info.last_seen);
            for t in [grid.last_hit(c), grid.last_crossed(c)]
                .into_iter()
                .flatten()
            {
                assert!(last.is_some_and(|l| l >= t), "{what}: cell {i}");
            }
        }
        let words = grid.observed_words();
        assert_eq!(words.len(), geom.len().div_ceil(64));
        if !geom.len().is_multiple_of(64) {
            let last = words[words.len() - 1];
            assert_eq!(last >> (geom.len() % 64), 0, "{what}: bits past the end");
        }
        assert!(!grid.observed(CellIndex::new(geom.width() as u32, 0)));
    }

    #[test]
    fn the_observed_bitset_is_exactly_the_cells_with_a_last_seen() {
        // Invariant: after any sequence of random scans (fans of every width and density, returns
        // and clear beams, blind zones, beams leaving the grid, sensors inside and outside it),
        // push-test marks and moves, a cell's observed bit is set iff its `last_seen` is `Some`,
        // and its latest return and latest crossing are never after its `last_seen`.
        let mut r = uniform(0x510e_527f_ade6_82d1_u64);
        for scene in 0..24 {
            let (w, h) = (40 + (r() * 200.0) as usize, 30 + (r() * 150.0) as usize);
            let geom =
                GridGeometry::with_cells(Point2::new(-1.0, 2.0), w, h, 0.05).expect("valid grid");
            let mut grid = ObstacleGrid::new(geom, GridConfig::default());
            let size = Vector2::new(w as f64 * 0.05, h as f64 * 0.05);
            let mut sensor = Point2::new(-1.0 + r() * size.x, 2.0 + r() * size.y);
            if scene % 6 == 5 {
                sensor.x -= 1.0; // outside the grid, looking in
            }
            let frames = 1 + (r() * 12.0) as usize;
            for k in 0..frames {
                let n = 10 + (r() * 400.0) as usize;
                let span = 0.2 + r() * 6.0;
                let yaw = r() * std::f64::consts::TAU;
                let blind = if r() < 0.5 { 0.0 } else { r() * 1.5 };
                let mut frame = RangeFrame::new(sensor).expect("finite");
                for b in 0..n {
                    let a = yaw + span * b as f64 / n as f64;
                    let range = 0.05 + r() * 9.0;
                    frame.push_beam(Beam {
                        end: sensor + Vector2::new(a.cos(), a.sin()) * range,
                        kind: if r() < 0.6 {
                            BeamEnd::Hit
                        } else {
                            BeamEnd::Clear
                        },
                        seen_from: blind * r(),
                    });
                }
                grid.update(&frame, k as f64 * 0.1).expect("in order");
                if r() < 0.2 {
                    let c = Point2::new(-1.0 + r() * size.x, 2.0 + r() * size.y);
                    let square = [
                        c,
                        c + Vector2::new(0.3, 0.0),
                        c + Vector2::new(0.3, 0.3),
                        c + Vector2::new(0.0, 0.3),
                    ];
                    let id = ObjectId(k as u32);
                    grid.mark_object(
                        id,
                        Footprint::Polygon(&square),
                        Verdict::Movable,
                        1,
                        0.1 * k as f64,
                    )
                    .expect("valid mark");
                    if r() < 0.5 {
                        let moved = square.map(|p| p + Vector2::new(0.5, 0.2));
                        grid.object_moved(
                            id,
                            Footprint::Polygon(&square),
                            Footprint::Polygon(&moved),
                            0.1 * k as f64,
                        )
                        .expect("marked before");
                    }
                }
                assert_bitset_is_last_seen(&grid, &format!("scene {scene} frame {k}"));
                sensor += Vector2::new(r() - 0.5, r() - 0.5) * 0.4;
            }
        }
    }
}
