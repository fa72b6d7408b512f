//! Reactive avoidance while walking, after Miyazaki et al.: a *search space* ahead of the robot on its
//! path; a person in it stops the walk, and the walk goes on when the space is clear again, or is
//! planned anew when the person stays.
//!
//! Miyazaki's search space is a box 1–2 m ahead of the robot, as wide as the robot, in which any
//! return stops it (their Fig. 5). Here it is the strip of floor the robot's body sweeps along the
//! next [`SEARCH_LENGTH`] of its path, grown by [`SEARCH_MARGIN`] on each side, and what stops the
//! robot is a grid cell in it where motion was seen a moment ago ([`RECENT`]: a frame turned it
//! Moving, or a look saw something come or go there) and that no obstacle stands on but one that
//! may be a person: a person crossing. One who stopped in the way stops the walk as any obstacle
//! does, at the body's safety margin, and is then looked at again. Static things on the path are the grid
//! watch's business (they flag the path and it is planned anew); this is only about what moves.
//!
//! It is consulted only once a look has seen something come or go in the run (people are about):
//! in a still room a walk is what it always was.

use nalgebra::Point2;

use super::Runner;
use crate::record::Observer;
use crate::robot::Robot;

/// How far ahead along the path the search space reaches (m): Miyazaki's 1–2 m, the near end of it,
/// for a robot walking 0.15 m/s (seven seconds of walking, several watch frames).
pub const SEARCH_LENGTH: f64 = 1.0;

/// How much wider than the robot's body the search space is on each side (m): the grid's 5 cm cell
/// twice, so a person's edge a cell off the robot's sweep still counts.
pub const SEARCH_MARGIN: f64 = 0.1;

/// Motion this recent (s of robot time) in the search space stops the walk: two watch frames (a
/// frame a second while walking), so a person just seen crossing counts and one who left does not.
pub const RECENT: f64 = 2.0;

/// How long the robot waits for a person in its way before the walk is planned anew (s): a person
/// crossing at walking pace clears the robot's width in a few seconds; one still there after fifteen
/// is standing, not passing.
pub const PERSON_WAIT: f64 = 15.0;

/// The cells of the search space: those whose centres lie within `half_width` of `path` (its first
/// point is where the robot stands) over its first `length` metres. `cell_of` maps a point to its
/// cell index, `cell_size` is the grid's resolution.
pub fn search_cells(
    path: &[Point2<f64>],
    length: f64,
    half_width: f64,
    cell_size: f64,
    cell_of: impl Fn(Point2<f64>) -> Option<usize>,
) -> Vec<usize> {
    let mut out = Vec::new();
    let mut left = length;
    let step = cell_size / 2.0;
    let reach = (half_width / step).ceil() as i64;
    for pair in path.windows(2) {
        if left <= 0.0 {
            break;
        }
        let (a, b) = (pair[0], pair[1]);
        let along = (b - a).norm();
        if along < 1e-9 {
            continue;
        }
        let dir = (b - a) / along;
        let normal = nalgebra::Vector2::new(-dir.y, dir.x);
        let used = along.min(left);
        let steps = (used / step).ceil() as i64;
        for s in 0..=steps {
            let centre = a + dir * (s as f64 * step).min(used);
            for k in -reach..=reach {
                let offset = (k as f64 * step).clamp(-half_width, half_width);
                if let Some(i) = cell_of(centre + normal * offset) {
                    out.push(i);
                }
            }
        }
        left -= used;
    }
    out.sort_unstable();
    out.dedup();
    out
}

impl<R: Robot, O: Observer> Runner<R, O> {
    /// Whether a look has seen something come or go in this run: people are about.
    pub(crate) fn people_about(&self) -> bool {
        self.world.look_motion.iter().any(|t| t.is_finite())
    }

    /// Whether something moving stands in the search space ahead of the robot on `path` (its first
    /// point where the robot stands).
    pub(crate) fn search_space_occupied(&self, path: &[Point2<f64>]) -> bool {
        let Some(grid) = self.world.grid.as_ref() else {
            return false;
        };
        let geometry = grid.geometry();
        let half_width = self.config.model.body.radius + SEARCH_MARGIN;
        let cells = search_cells(
            path,
            SEARCH_LENGTH,
            half_width,
            geometry.resolution(),
            |p| geometry.cell_of(p).and_then(|c| geometry.index(c)),
        );
        let since = self.robot.elapsed() - RECENT;
        // Cells an obstacle that is no mover stands on are its own (a cart a person left, now at
        // rest, whose cells the grid still holds Moving): walking up to it is what the walk is for.
        let movers = self.movers();
        let still: Vec<&nudge_perception::Prism> = self
            .world
            .prisms
            .iter()
            .filter(|p| !movers.contains(&p.id))
            .collect();
        let half = geometry.resolution() / 2.0;
        cells.iter().any(|&i| {
            let lately = |stamps: &[f64]| stamps.get(i).is_some_and(|&t| t >= since);
            let moved = lately(&self.world.fresh_motion) || lately(&self.world.look_motion);
            moved
                && geometry.cell_at(i).is_some_and(|c| {
                    let centre = geometry.centre(c);
                    !still
                        .iter()
                        .any(|p| super::grid::overlaps_cell(p, centre, half))
                })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_search_space_is_the_strip_the_body_sweeps_over_the_next_metre_of_the_path() {
        // Invariant: the search space holds the cells within the half width of the path's first metre (round a corner too), and none beyond that metre or wider than the half width.
        let size = 0.05;
        let width = 100usize;
        let cell_of = |p: Point2<f64>| {
            let (x, y) = ((p.x / size).floor(), (p.y / size).floor());
            (x >= 0.0 && y >= 0.0 && (x as usize) < width && (y as usize) < width)
                .then(|| y as usize * width + x as usize)
        };
        let centre = |x: f64, y: f64| cell_of(Point2::new(x, y)).expect("in the grid");
        // Straight east from (1, 2.5), 3 m long.
        let path = [Point2::new(1.0, 2.5), Point2::new(4.0, 2.5)];
        let cells = search_cells(&path, 1.0, 0.45, size, cell_of);
        assert!(
            cells.contains(&centre(1.02, 2.52)),
            "where the robot stands"
        );
        assert!(cells.contains(&centre(1.98, 2.52)), "a metre ahead");
        assert!(cells.contains(&centre(1.5, 2.9)), "0.4 m to the side");
        assert!(!cells.contains(&centre(2.2, 2.52)), "beyond the metre");
        assert!(!cells.contains(&centre(1.5, 3.05)), "0.55 m to the side");
        // A corner after half a metre: the second half metre runs north.
        let corner = [
            Point2::new(1.0, 2.5),
            Point2::new(1.5, 2.5),
            Point2::new(1.5, 4.0),
        ];
        let cells = search_cells(&corner, 1.0, 0.2, size, cell_of);
        assert!(
            cells.contains(&centre(1.52, 2.98)),
            "half a metre up the second leg"
        );
        assert!(
            !cells.contains(&centre(1.52, 3.2)),
            "beyond the metre along the bend"
        );
        assert!(
            !cells.contains(&centre(1.9, 2.52)),
            "straight on past the corner"
        );
    }
}
