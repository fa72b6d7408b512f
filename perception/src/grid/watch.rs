//! The replanning flag (Lopez-Perez 2.2): watched path cells that turn into obstacles.

use super::ObstacleGrid;
use super::class::CellClass;
use super::geometry::CellIndex;
use super::rules::fsm::raises_replan;

/// Why the executive should replan: the first watched cell that turned into an obstacle since the flag
/// was last taken, and how many did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReplanReason {
    /// The first watched cell that changed.
    pub cell: CellIndex,
    /// Its class before.
    pub was: CellClass,
    /// Its class now (an obstacle class).
    pub became: CellClass,
    /// Robot-clock stamp of the change.
    pub stamp: f64,
    /// How many watched cells changed into an obstacle class since the flag was last taken.
    pub cells: usize,
}

impl ObstacleGrid {
    /// Watches the cells of the executive's current path (replacing the previous path; an empty slice
    /// stops watching). Cells outside the grid are ignored. O(path length): earlier watches are retired
    /// by a generation counter, not swept.
    pub fn set_watched_path(&mut self, cells: &[CellIndex]) {
        self.watch_gen = self.watch_gen.wrapping_add(1);
        if self.watch_gen == 0 {
            // After 2³² paths, reset the stamps once so an old stamp can never match again.
            self.layers.watch.fill(0);
            self.watch_gen = 1;
        }
        for &c in cells {
            if let Some(i) = self.geom.index(c) {
                self.layers.watch[i] = self.watch_gen;
            }
        }
    }

    /// Takes the replanning flag: `Some` when a watched cell turned into an obstacle since the last call.
    pub fn take_replan_flag(&mut self) -> Option<ReplanReason> {
        self.replan.take()
    }

    /// True when linear index `i` is on the watched path.
    pub(crate) fn is_watched(&self, i: usize) -> bool {
        self.watch_gen != 0 && self.layers.watch[i] == self.watch_gen
    }

    /// Raises or extends the flag for a class change at linear index `i`.
    pub(crate) fn check_watch(&mut self, i: usize, old: u8, new: CellClass, stamp: f64) {
        let old = CellClass::from_code(old).unwrap_or(CellClass::Unknown);
        if !raises_replan(old, new) || !self.is_watched(i) {
            return;
        }
        match &mut self.replan {
            Some(r) => r.cells += 1,
            None => {
                if let Some(cell) = self.geom.cell_at(i) {
                    self.replan = Some(ReplanReason {
                        cell,
                        was: old,
                        became: new,
                        stamp,
                        cells: 1,
                    });
                }
            }
        }
    }
}
