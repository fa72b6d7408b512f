//! Active evidence: the executive's push-test verdicts, which outrank the passive rules.

use nalgebra::Point2;

use super::class::CellClass;
use super::evidence::{MAX_PUSH_TEST, pack_active};
use super::geometry::CellIndex;
use super::raster::polygon_cells;
use super::{GridError, ObjectRecord, ObstacleGrid};
use crate::prism::ObjectId;

/// What a push test concluded about an object.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Verdict {
    /// It did not move under the push force limit (wrist force said "static").
    Static,
    /// It moved (colour ICP saw the displacement).
    Movable,
}

impl Verdict {
    fn class(self) -> CellClass {
        match self {
            Verdict::Static => CellClass::Stationary,
            Verdict::Movable => CellClass::Movable,
        }
    }
}

/// The cells an object covers: given directly, or as a footprint polygon in the map frame (for
/// example a [`crate::Prism`]'s `footprint`), rasterised to the cells it covers or whose centre it
/// contains.
#[derive(Clone, Copy, Debug)]
pub enum Footprint<'a> {
    /// These cells (out-of-grid cells are ignored).
    Cells(&'a [CellIndex]),
    /// This polygon (map frame, either orientation, first vertex not repeated).
    Polygon(&'a [Point2<f64>]),
}

impl ObstacleGrid {
    pub(crate) fn footprint_indices(&self, fp: Footprint<'_>) -> Vec<usize> {
        match fp {
            Footprint::Cells(cells) => {
                let mut v: Vec<usize> = cells.iter().filter_map(|&c| self.idx(c)).collect();
                v.sort_unstable();
                v.dedup();
                v
            }
            Footprint::Polygon(poly) => polygon_cells(&self.geom, poly),
        }
    }

    /// Marks `id`'s cells with a push test's verdict: Stationary for [`Verdict::Static`], Movable for
    /// [`Verdict::Movable`], with evidence `Active { object: id, push_test }`, stamped `now`. Returns how
    /// many cells were marked. A later mark of the same object replaces the earlier verdict on its cells.
    pub fn mark_object(
        &mut self,
        id: ObjectId,
        footprint: Footprint<'_>,
        verdict: Verdict,
        push_test: u32,
        now: f64,
    ) -> Result<usize, GridError> {
        check_ids(id, push_test, now)?;
        let cells = self.footprint_indices(footprint);
        let record = self.objects.entry(id).or_insert(ObjectRecord {
            verdict,
            push_test,
            cells: Vec::new(),
        });
        record.verdict = verdict;
        record.push_test = push_test;
        // Earlier cells of this object get the new verdict too.
        let mut all: Vec<u32> = record.cells.clone();
        all.extend(cells.iter().map(|&i| i as u32));
        all.sort_unstable();
        all.dedup();
        record.cells = all.clone();
        for &i in &all {
            let i = i as usize;
            let mine =
                self.layers.object[i] == id.0 && self.layers.class[i] != CellClass::Free as u8;
            if mine || cells.binary_search(&i).is_ok() {
                self.write_active(i, id, verdict.class(), push_test, now);
            }
        }
        Ok(cells.len())
    }

    /// A confirmed push moved `id` from `old` to `new`: every cell of the old footprint (and any other
    /// cell still carrying `id`) becomes Free — even where no background has been seen behind it, the
    /// push is the evidence — then the new footprint becomes Movable. Both with evidence
    /// `Active { object: id, push_test }` of the object's last mark, stamped `now`.
    pub fn object_moved(
        &mut self,
        id: ObjectId,
        old: Footprint<'_>,
        new: Footprint<'_>,
        now: f64,
    ) -> Result<(), GridError> {
        let Some(record) = self.objects.get(&id) else {
            return Err(GridError::UnknownObject(id));
        };
        let push_test = record.push_test;
        check_ids(id, push_test, now)?;
        let mut old_cells = self.footprint_indices(old);
        old_cells.extend(
            record
                .cells
                .iter()
                .map(|&i| i as usize)
                .filter(|&i| self.layers.object[i] == id.0),
        );
        let new_cells = self.footprint_indices(new);
        for &i in &old_cells {
            self.write_active(i, id, CellClass::Free, push_test, now);
        }
        for &i in &new_cells {
            self.write_active(i, id, CellClass::Movable, push_test, now);
        }
        if let Some(r) = self.objects.get_mut(&id) {
            r.verdict = Verdict::Movable;
            r.cells = new_cells.iter().map(|&i| i as u32).collect();
        }
        Ok(())
    }

    /// The verdict and push test last recorded for `id`.
    pub fn verdict(&self, id: ObjectId) -> Option<(Verdict, u32)> {
        self.objects.get(&id).map(|r| (r.verdict, r.push_test))
    }

    fn write_active(&mut self, i: usize, id: ObjectId, class: CellClass, push_test: u32, now: f64) {
        let old = self.layers.set_class(i, class as u8);
        self.layers.object[i] = id.0;
        self.layers.evidence[i] = pack_active(push_test);
        self.layers.marked_at[i] = now;
        self.layers.mark_observed(i);
        self.check_watch(i, old, class, now);
    }
}

fn check_ids(id: ObjectId, push_test: u32, now: f64) -> Result<(), GridError> {
    if id.0 == u32::MAX {
        return Err(GridError::ReservedObjectId(id));
    }
    if push_test > MAX_PUSH_TEST {
        return Err(GridError::PushTestTooLarge(push_test));
    }
    if !now.is_finite() {
        return Err(GridError::NonFinite);
    }
    Ok(())
}
