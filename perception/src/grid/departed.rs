//! Forgetting what stood on cells a look found gone.
//!
//! The passive rules classify a cell from the returns of the frames whose rays reach it, and only a
//! ray crossing the cell changes it again. A person who stood still long enough reads as
//! Stationary; when they walk away from behind a chair, no ray from the robot's side of the chair
//! ever crosses their cells again, and the grid would hold a wall there for the rest of the run. A
//! look-around sees more than the grid's frames: its views look through where the person's body was
//! above the chair (`crate::seen_through`). What it found gone is forgotten here too.

use super::evidence::is_active;
use super::layers::NO_OBJECT;
use super::{CellClass, Footprint, ObstacleGrid};

impl ObstacleGrid {
    /// Something that stood on `footprint` has gone: a look-around saw through where it stood.
    /// Its cells that passive rules hold occupied go back to Unknown, their return histories
    /// cleared, so the next frames that reach them classify them afresh. Not Free: the floor under
    /// them may still be hidden. Cells with a push test's verdict keep it: that evidence is the
    /// robot's own. Returns how many cells were forgotten; `now` stamps the path watch.
    pub fn departed(&mut self, footprint: Footprint<'_>, now: f64) -> usize {
        let mut forgotten = 0;
        for i in self.footprint_indices(footprint) {
            let l = &self.layers;
            let occupied = CellClass::from_code(l.class[i]).is_some_and(CellClass::is_obstacle);
            if !occupied || is_active(l.evidence[i]) {
                continue;
            }
            let old = self.layers.set_class(i, CellClass::Unknown as u8);
            self.layers.object[i] = NO_OBJECT;
            self.layers.evidence[i] = 0;
            self.layers.track[i] = Default::default();
            self.check_watch(i, old, CellClass::Unknown, now);
            forgotten += 1;
        }
        forgotten
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{GridGeometry, RangeFrame, Verdict};
    use crate::prism::ObjectId;
    use nalgebra::Point2;

    #[test]
    fn a_departed_footprint_forgets_passive_cells_and_keeps_verdicts() {
        // Invariant: a cell the passive rules hold occupied under a departed footprint goes back to Unknown; cells a push test marked keep their verdict, and free or unknown cells stay as they are.
        let geometry = GridGeometry::new(Point2::new(0.0, 0.0), [1.0, 1.0], 0.1).expect("grid");
        let mut grid = ObstacleGrid::new(geometry, Default::default());
        let square = |x0: f64, x1: f64| {
            vec![
                Point2::new(x0, 0.0),
                Point2::new(x1, 0.0),
                Point2::new(x1, 1.0),
                Point2::new(x0, 1.0),
            ]
        };
        let tested = square(0.0, 0.5);
        grid.mark_object(
            ObjectId(3),
            Footprint::Polygon(&tested),
            Verdict::Static,
            1,
            1.0,
        )
        .expect("mark");
        // A still thing the frames saw in place for a few frames: the passive rules call it
        // Stationary.
        let spot = Point2::new(0.75, 0.55);
        for k in 0..8 {
            let mut frame = RangeFrame::new(Point2::new(0.75, 0.05)).expect("frame");
            frame.push_hit(spot);
            grid.update(&frame, f64::from(k)).expect("update");
        }
        let cell = grid.geometry().cell_of(spot).expect("in the grid");
        let class = |g: &ObstacleGrid| g.cell(cell).map(|c| c.class);
        assert_eq!(class(&grid), Some(CellClass::Stationary));
        let before = grid.class_codes().to_vec();
        assert_eq!(grid.departed(Footprint::Polygon(&square(0.0, 1.0)), 9.0), 1);
        assert_eq!(
            class(&grid),
            Some(CellClass::Unknown),
            "the still thing is forgotten"
        );
        let tested_cell = grid
            .geometry()
            .cell_of(Point2::new(0.25, 0.5))
            .expect("cell");
        assert_eq!(
            grid.cell(tested_cell).map(|c| c.class),
            Some(CellClass::Stationary)
        );
        let changed = before
            .iter()
            .zip(grid.class_codes())
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(changed, 1, "only the passive cell changed");
    }
}
