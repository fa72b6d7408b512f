//! What the run has seen of each obstacle: how much of its outline and from where, and whether the
//! grid still holds it (returns there) or has seen all of its floor free.

use nalgebra::Point2;
use nudge_perception::Prism;
use nudge_perception::seen_through::FLOOR_BAND;

use super::world::{WorldModel, footprint_box};

impl WorldModel {
    /// How much of `prism`'s outline has been seen (0 to 1), and from where: the share of points
    /// every grid cell along its footprint's edges whose cell a cell and a half outwards was seen
    /// (its floor, or a return there), or lies inside another obstacle (it cannot be seen and does not
    /// matter); and the places the looks that showed it were taken from.
    pub fn outline_seen(&self, prism: &Prism) -> (f64, &[Point2<f64>]) {
        let from = self.objects.get(prism.id).seen_from.as_slice();
        let Some(grid) = &self.grid else {
            return (0.0, from);
        };
        let geometry = grid.geometry();
        let step = geometry.resolution();
        let f = &prism.footprint;
        let (mut seen, mut all) = (0usize, 0usize);
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            let edge = b - a;
            let len = edge.norm();
            if len <= 0.0 {
                continue;
            }
            // Counter-clockwise footprint: outwards is the edge turned clockwise.
            let out = nalgebra::Vector2::new(edge.y, -edge.x) / len;
            let n = (len / step).ceil() as usize;
            for j in 0..n {
                let p = a + edge * ((j as f64 + 0.5) / n as f64) + out * (1.5 * step);
                all += 1;
                let inside_other = self
                    .prisms
                    .iter()
                    .any(|q| q.id != prism.id && q.contains_xy(&p));
                let observed = geometry
                    .cell_of(p)
                    .and_then(|c| geometry.index(c))
                    .is_some_and(|i| self.memory.seen(grid, i));
                seen += usize::from(inside_other || observed);
            }
        }
        let share = if all == 0 {
            0.0
        } else {
            seen as f64 / all as f64
        };
        (share, from)
    }

    /// Whether the grid holds an obstacle class (Stationary, Movable, Moving) in a cell `prism`'s
    /// footprint overlaps, away from every cell `moved` marks (near motion ever seen): something
    /// that does not move by itself still returns there.
    pub(super) fn grid_holds_returns(&self, prism: &Prism, moved: Option<&[bool]>) -> bool {
        self.cells_under(prism).iter().any(|(i, class)| {
            class.is_some_and(nudge_perception::grid::CellClass::is_obstacle)
                && !moved.is_some_and(|m| m.get(*i).copied().unwrap_or(false))
        })
    }

    /// The indices and classes of the grid cells `prism`'s footprint overlaps (empty without a grid).
    fn cells_under(
        &self,
        prism: &Prism,
    ) -> Vec<(usize, Option<nudge_perception::grid::CellClass>)> {
        let Some(grid) = &self.grid else {
            return Vec::new();
        };
        let geometry = grid.geometry();
        self.cells_overlapped(prism)
            .into_iter()
            .filter_map(|cell| Some((geometry.index(cell)?, grid.class(cell))))
            .collect()
    }

    /// The grid cells `prism`'s footprint overlaps (empty without a grid).
    fn cells_overlapped(&self, prism: &Prism) -> Vec<nudge_perception::grid::CellIndex> {
        let Some(grid) = &self.grid else {
            return Vec::new();
        };
        let geometry = grid.geometry();
        let half = geometry.resolution() / 2.0;
        let (lo, hi) = footprint_box(prism);
        let (Some(a), Some(b)) = (geometry.cell_of(lo), geometry.cell_of(hi)) else {
            return Vec::new();
        };
        let mut out = Vec::new();
        for y in a.y..=b.y {
            for x in a.x..=b.x {
                let cell = nudge_perception::grid::CellIndex { x, y };
                if super::grid::overlaps_cell(prism, geometry.centre(cell), half) {
                    out.push(cell);
                }
            }
        }
        out
    }

    /// Whether the grid's frames after `since` looked where `prism` stood and found it gone: their
    /// rays crossed at least half of the cells its footprint overlaps, and none of those cells held a
    /// return after `since`. A person who is still there returns the rays that reach them; one hidden
    /// behind something is not crossed, and stays.
    pub(super) fn grid_saw_it_gone(&self, prism: &Prism, since: f64) -> bool {
        let Some(grid) = &self.grid else {
            return false;
        };
        let cells = self.cells_overlapped(prism);
        let after = |t: Option<f64>| t.is_some_and(|t| t > since);
        let crossed = cells
            .iter()
            .filter(|c| after(grid.last_crossed(**c)))
            .count();
        !cells.is_empty() && 2 * crossed >= cells.len() && !self.grid_saw_it_there(prism, since)
    }

    /// Whether a frame after `since` (the robot's clock) returned from a cell `prism`'s footprint
    /// overlaps: something stood there then.
    pub(super) fn grid_saw_it_there(&self, prism: &Prism, since: f64) -> bool {
        let Some(grid) = &self.grid else {
            return false;
        };
        self.cells_overlapped(prism)
            .iter()
            .any(|c| grid.last_hit(*c).is_some_and(|t| t > since))
    }

    /// Whether floor was seen, after `since` (robot time let pass), in at least half of the grid
    /// cells `prism`'s footprint overlaps. An object still standing there hides the floor under it,
    /// its rim's cells aside; a smear of something that passed does not.
    pub(super) fn floor_seen_since(&self, prism: &Prism, since: f64) -> bool {
        let Some(grid) = &self.grid else {
            return false;
        };
        let geometry = grid.geometry();
        let cells = self.cells_overlapped(prism);
        let bare = cells
            .iter()
            .filter_map(|c| geometry.index(*c))
            .filter(|&i| self.memory.floor_seen.get(i).is_some_and(|&t| t > since))
            .count();
        !cells.is_empty() && 2 * bare >= cells.len()
    }

    /// The share of the grid cells whose centres `prism`'s footprint holds that the grid saw Free
    /// (0 without a grid or such cells, see [`seen_free`]) and that lie behind the obstacle's own
    /// surface as seen from where the last look was taken ([`SurfaceProfile`]): floor it saw
    /// through or on before, where the obstacle now stands. What lies in front of the surface the
    /// look saw is not where anything stands: the hull of a thin face seen face on reaches over a cell
    /// of the floor in front of it (`two-boxes-in-doorway` seed 13 with the push test below tipping:
    /// a jamb found again as a 9 cm sliver, 38 % of it over such cells, was taken for a person come
    /// to stand there, and the clearing stroke beside it waited for them to leave). The floor a
    /// person stands on lies behind the front of their body.
    pub(super) fn free_share(&self, prism: &Prism) -> f64 {
        let Some(grid) = &self.grid else {
            return 0.0;
        };
        let geometry = grid.geometry();
        let (lo, hi) = footprint_box(prism);
        let (Some(a), Some(b)) = (geometry.cell_of(lo), geometry.cell_of(hi)) else {
            return 0.0;
        };
        let profile = self
            .looks
            .last()
            .map(|eye| SurfaceProfile::new(prism, *eye));
        let half_cell = geometry.resolution() / 2.0;
        let (mut inside, mut free) = (0usize, 0usize);
        for y in a.y..=b.y {
            for x in a.x..=b.x {
                let cell = nudge_perception::grid::CellIndex { x, y };
                let centre = geometry.centre(cell);
                if prism.contains_xy(&centre) {
                    inside += 1;
                    let in_front = profile
                        .as_ref()
                        .is_some_and(|p| p.in_front(centre, half_cell));
                    free += usize::from(seen_free(grid, cell) && !in_front);
                }
            }
        }
        free as f64 / inside.max(1) as f64
    }

    /// Whether the grid holds every cell `prism`'s footprint overlaps Free: it saw floor all over
    /// where the obstacle was (a sliver left where an object stood before a push, too small to hold
    /// the look's floor points that forget larger ones).
    pub(super) fn grid_sees_free(&self, prism: &Prism) -> bool {
        let classes = self.cells_under(prism);
        !classes.is_empty()
            && classes
                .iter()
                .all(|(_, c)| *c == Some(nudge_perception::grid::CellClass::Free))
    }
}

/// Whether `grid` holds `cell` Free from what its frames saw: by a passive rule, or, where the robot's
/// own push freed it (active evidence: the pushed object's old footprint and the edge cells its hull
/// stood off them), once a frame crossed it after the push. The edge cells of a box pushed out of a
/// doorway include the jamb's end beside it, where no ray passes: a look that then finds the jamb
/// standing there has not seen it arrive (`two-boxes-in-doorway` seed 12 with the push test below
/// tipping waited for the jamb as for a person until the waits ran out).
fn seen_free(
    grid: &nudge_perception::grid::ObstacleGrid,
    cell: nudge_perception::grid::CellIndex,
) -> bool {
    use nudge_perception::grid::{CellClass, Evidence};
    grid.cell(cell).is_some_and(|c| {
        c.class == CellClass::Free
            && (!matches!(c.evidence, Evidence::Active { .. })
                || grid
                    .last_crossed(cell)
                    .zip(c.last_seen)
                    .is_some_and(|(crossed, seen)| crossed >= seen))
    })
}

/// Points of an obstacle asked about for its [`SurfaceProfile`], at most: evenly spread, a few per
/// centimetre of a person's or a jamb's width at the ranges a look sees them.
const PROFILE_SAMPLE: usize = 400;

/// An obstacle's surface as seen from one place: the bearing and range of its points above the floor
/// band (an even sample), in the floor plane.
struct SurfaceProfile {
    eye: Point2<f64>,
    points: Vec<(f64, f64)>,
}

impl SurfaceProfile {
    /// The profile of `prism`'s points as seen from `eye`.
    fn new(prism: &Prism, eye: Point2<f64>) -> Self {
        let cloud = &prism.points;
        let above: Vec<usize> = (0..cloud.len())
            .filter(|&i| cloud.point(i).is_some_and(|p| p.z >= FLOOR_BAND))
            .collect();
        let step = above.len().div_ceil(PROFILE_SAMPLE).max(1);
        let points = above
            .iter()
            .step_by(step)
            .filter_map(|&i| cloud.point(i))
            .map(|p| {
                let d = Point2::new(f64::from(p.x), f64::from(p.y)) - eye;
                (d.y.atan2(d.x), d.norm())
            })
            .collect();
        Self { eye, points }
    }

    /// Whether the point `centre` (of a cell `half_cell` across from its middle to a side) lies
    /// nearer the eye than every point of the surface in its direction (within the angle the cell
    /// spans): the look saw past it to the surface, so nothing of the obstacle stands there. False
    /// where no point lies in its direction.
    fn in_front(&self, centre: Point2<f64>, half_cell: f64) -> bool {
        let d = centre - self.eye;
        let range = d.norm();
        if range <= half_cell {
            return false;
        }
        let bearing = d.y.atan2(d.x);
        let spread = (half_cell / range).atan();
        let nearest = self
            .points
            .iter()
            .filter(|(b, _)| {
                let off = (b - bearing + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                    - std::f64::consts::PI;
                off.abs() <= spread
            })
            .map(|(_, r)| *r)
            .fold(f64::INFINITY, f64::min);
        nearest.is_finite() && range < nearest
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::runner::unseen::SeenMemory;
    use crate::runner::world::tests::{config_to, floor, prism};
    use nalgebra::{Isometry3, Point3};
    use nudge_perception::grid::{GridGeometry, ObstacleGrid};
    use nudge_perception::{CloudFrame, ColourCloud};

    /// A run's configuration and an empty grid of 5 cm cells over a 4 m × 2 m room.
    fn room_4_by_2() -> (crate::runner::config::RunConfig, GridGeometry, ObstacleGrid) {
        let config = config_to(Point2::new(5.0, 1.0));
        let geometry = GridGeometry::new(Point2::origin(), [4.0, 2.0], 0.05).expect("a grid");
        let grid = ObstacleGrid::new(geometry, config.grid.rules);
        (config, geometry, grid)
    }

    /// A world model over `grid` that has seen nothing yet.
    fn seen_world(geometry: GridGeometry, grid: ObstacleGrid) -> WorldModel {
        WorldModel {
            memory: SeenMemory::new(geometry.len()),
            grid: Some(grid),
            ..WorldModel::default()
        }
    }

    #[test]
    fn an_obstacle_seen_from_one_side_has_a_quarter_of_its_outline_seen() {
        // Invariant: the outline seen is the share of a footprint's edges whose floor just outside was seen, or that lie against another obstacle; a box whose west side alone was seen has a quarter of it, with a neighbour against its east side a half, with everything round it seen all of it; the places it was seen from are those of the looks that showed it.
        let (config, geometry, grid) = room_4_by_2();
        let mut world = seen_world(geometry, grid);
        let object = prism(1, 2.0, 0.5, 2.5, 1.0);
        let west = floor(1.5, 0.3, 1.95, 1.2);
        world.memory.saw(&geometry, &west);
        world.prisms = vec![object.clone()];
        let (share, from) = world.outline_seen(&object);
        assert!((share - 0.25).abs() < 0.05, "{share}");
        assert!(from.is_empty());
        world.prisms.push(prism(2, 2.55, 0.3, 3.0, 1.2));
        let (share, _) = world.outline_seen(&object);
        assert!((share - 0.5).abs() < 0.05, "{share}");
        world.memory.saw(&geometry, &floor(1.5, 0.0, 3.5, 1.9));
        let (share, _) = world.outline_seen(&object);
        assert!((share - 1.0).abs() < 1e-9, "{share}");
        let mut looked = WorldModel::default();
        looked.remember(
            vec![object.clone()],
            &floor(0.1, 0.1, 0.2, 0.2),
            &Point2::new(0.6, 0.75),
            &config,
        );
        looked.remember(
            vec![object.clone()],
            &floor(0.1, 0.1, 0.2, 0.2),
            &Point2::new(1.2, 1.6),
            &config,
        );
        assert_eq!(
            looked.outline_seen(&looked.prisms[0]).1,
            &[Point2::new(0.6, 0.75), Point2::new(1.2, 1.6)]
        );
    }

    #[test]
    fn the_free_share_of_an_obstacle_is_the_floor_the_grid_saw_free_under_it() {
        // Invariant: an obstacle's free share is the share of its footprint's cell centres the grid saw Free — none where the robot's push freed the floor and no ray crossed it since, all of it there once a frame saw the floor empty, none over floor it never saw, half for one half over each.
        use nudge_perception::ObjectId;
        use nudge_perception::grid::{Footprint, Verdict};
        let (_, _, mut grid) = room_4_by_2();
        let was = prism(9, 1.0, 0.5, 2.0, 1.5).footprint;
        let now = prism(9, 3.2, 0.5, 3.8, 1.5).footprint;
        grid.mark_object(
            ObjectId(9),
            Footprint::Polygon(&was),
            Verdict::Movable,
            1,
            1.0,
        )
        .expect("marked");
        grid.object_moved(
            ObjectId(9),
            Footprint::Polygon(&was),
            Footprint::Polygon(&now),
            2.0,
        )
        .expect("moved");
        let world = |grid: &ObstacleGrid| WorldModel {
            grid: Some(grid.clone()),
            ..WorldModel::default()
        };
        // Freed by the push alone, the floor was not seen: nothing arrived on it.
        let unseen = world(&grid).free_share(&prism(1, 1.2, 0.7, 1.8, 1.3));
        assert_eq!(unseen, 0.0);
        // A fan of beams from (0.05, 1.0) across the old footprint to a wall at x = 2.05 sees it.
        let mut frame =
            nudge_perception::grid::RangeFrame::new(Point2::new(0.05, 1.0)).expect("a frame");
        for k in 0..=200 {
            frame.push_hit(Point2::new(2.05, f64::from(k) * 0.01));
        }
        grid.update(&frame, 3.0).expect("updated");
        let world = world(&grid);
        let on_free = world.free_share(&prism(1, 1.2, 0.7, 1.8, 1.3));
        let never_seen = world.free_share(&prism(2, 2.2, 0.7, 2.8, 1.3));
        let half = world.free_share(&prism(3, 1.7, 0.7, 2.3, 1.3));
        assert!((on_free - 1.0).abs() < 1e-9, "{on_free}");
        assert_eq!(never_seen, 0.0);
        assert!((half - 0.5).abs() < 0.1, "{half}");
        assert_eq!(
            WorldModel::default().free_share(&prism(1, 1.2, 0.7, 1.8, 1.3)),
            0.0
        );
    }

    #[test]
    fn floor_in_front_of_the_surface_a_look_saw_is_not_floor_an_obstacle_came_onto() {
        // Invariant: the free share that says an obstacle arrived leaves out the Free cells that lie in front of the obstacle's own surface as seen from where the last look was taken (the hull of a thin face seen face on reaches over the floor before it), and keeps those behind it (where a body seen from the front stands).
        let (_, geometry, mut grid) = room_4_by_2();
        let mut frame =
            nudge_perception::grid::RangeFrame::new(Point2::new(0.05, 1.0)).expect("a frame");
        for k in 0..=200 {
            frame.push_hit(Point2::new(3.55, f64::from(k) * 0.01));
        }
        grid.update(&frame, 3.0).expect("updated");
        let mut world = seen_world(geometry, grid);
        // Points on a plane facing the eye at x = `face`, over y 0.8..1.2, 0.1..1.0 m up.
        let with_face = |mut p: Prism, face: f32| {
            for i in 0..20u8 {
                for j in 0..10u8 {
                    let point =
                        Point3::new(face, 0.8 + 0.02 * f32::from(i), 0.1 + 0.1 * f32::from(j));
                    p.points.push(point, [90, 90, 90]);
                }
            }
            p
        };
        // A jamb's face at x = 2.0, its hull reaching 10 cm over the floor before it.
        let jamb = with_face(prism(1, 1.9, 0.8, 2.0, 1.2), 2.0);
        // A body whose front the look saw at x = 1.2, standing over 1.2..1.5.
        let body = with_face(prism(2, 1.2, 0.8, 1.5, 1.2), 1.2);
        let unlooked = world.free_share(&jamb);
        assert!(
            (unlooked - 1.0).abs() < 1e-9,
            "no look to judge from: {unlooked}"
        );
        world.looks.push(Point2::new(0.05, 1.0));
        let jamb_share = world.free_share(&jamb);
        let body_share = world.free_share(&body);
        assert_eq!(jamb_share, 0.0, "its cells all lie before its face");
        assert!(
            (body_share - 1.0).abs() < 1e-9,
            "its cells lie behind its front: {body_share}"
        );
    }

    #[test]
    fn a_place_looked_through_since_a_detection_with_no_return_there_is_gone() {
        // Invariant: an obstacle counts as gone once frames after its detection crossed at least half of its cells and none returned from them; frames that return from it keep it, frames that never crossed it prove nothing, and frames before the detection do not count.
        use nudge_perception::grid::RangeFrame;
        let (_, _, mut grid) = room_4_by_2();
        let person = prism(1, 2.0, 0.8, 2.4, 1.2);
        // A fan of beams from (0.5, 1.0) across the person's place, to a wall at x = 3.9.
        let scan = |hit_person: bool| {
            let mut frame = RangeFrame::new(Point2::new(0.5, 1.0)).expect("a frame");
            for k in -20..=20 {
                let y = 1.0 + f64::from(k) * 0.02;
                let x = if hit_person && (0.8..=1.2).contains(&y) {
                    2.0
                } else {
                    3.9
                };
                frame.push_hit(Point2::new(x, y));
            }
            frame
        };
        grid.update(&scan(true), 1.0).expect("updated");
        let world = |grid: &ObstacleGrid| WorldModel {
            grid: Some(grid.clone()),
            ..WorldModel::default()
        };
        assert!(
            !world(&grid).grid_saw_it_gone(&person, 0.5),
            "returned from"
        );
        assert!(
            !world(&grid).grid_saw_it_gone(&person, 1.5),
            "not looked at since"
        );
        let mut still_there = grid.clone();
        still_there.update(&scan(true), 2.0).expect("updated");
        assert!(
            !world(&still_there).grid_saw_it_gone(&person, 1.5),
            "still returns"
        );
        grid.update(&scan(false), 2.0).expect("updated");
        assert!(
            world(&grid).grid_saw_it_gone(&person, 1.5),
            "looked through"
        );
        assert!(
            !world(&grid).grid_saw_it_gone(&person, 0.5),
            "the return at 1 s"
        );
        assert!(
            !WorldModel::default().grid_saw_it_gone(&person, 1.5),
            "no grid"
        );
    }

    #[test]
    fn floor_seen_bare_under_an_obstacle_after_the_look_that_showed_it_proves_it_gone() {
        // Invariant: an obstacle's floor counts as seen bare after a moment only when frames after that moment put floor returns in at least half of the cells it overlaps: floor seen before it, or all around it but not under it (what an object still standing there leaves), does not count, nor do returns above the floor band.
        let (_, geometry, grid) = room_4_by_2();
        let mut world = seen_world(geometry, grid);
        let low = prism(1, 2.0, 0.5, 2.3, 0.8);
        let band = 0.05;
        let around = floor(1.5, 0.2, 2.8, 1.2);
        let mut around_only = ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0);
        for (_, p, rgb) in around.iter_valid() {
            let q = Point2::new(f64::from(p.x), f64::from(p.y));
            if low.distance_xy(&q) > 0.06 {
                around_only.push(p, rgb);
            }
        }
        world.memory.saw_floor(&geometry, &around_only, band, 5.0);
        assert!(
            !world.floor_seen_since(&low, 4.0),
            "the object hid its floor"
        );
        let mut raised = ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0);
        for (_, p, rgb) in around.iter_valid() {
            raised.push(Point3::new(p.x, p.y, 0.3), rgb);
        }
        world.memory.saw_floor(&geometry, &raised, band, 6.0);
        assert!(
            !world.floor_seen_since(&low, 4.0),
            "returns 0.3 m up are no floor"
        );
        world.memory.saw_floor(&geometry, &around, band, 7.0);
        assert!(
            world.floor_seen_since(&low, 6.5),
            "floor seen under it at 7 s"
        );
        assert!(!world.floor_seen_since(&low, 7.0), "not after 7 s");
    }

    #[test]
    fn floor_in_a_sensor_frame_cloud_is_found_in_the_map() {
        // Invariant: a cloud in the sensor frame lands its floor in the map cells under it: returns 1.2 m below a sensor 1.2 m up are floor, returns 0.5 m below it are not.
        let (_, geometry, grid) = room_4_by_2();
        let mut world = seen_world(geometry, grid);
        let pose = Isometry3::translation(2.0, 1.0, 1.2);
        let mut cloud = ColourCloud::empty(CloudFrame::Sensor, pose, 0.0);
        for i in 0..20 {
            for j in 0..20 {
                let (x, y) = (
                    -0.2 + 0.02 * f32::from(i as u8),
                    -0.2 + 0.02 * f32::from(j as u8),
                );
                cloud.push(Point3::new(x, y, -0.5), [100, 100, 100]);
            }
        }
        let object = prism(1, 1.85, 0.85, 2.15, 1.15);
        world.memory.saw_floor(&geometry, &cloud, 0.05, 1.0);
        assert!(!world.floor_seen_since(&object, 0.0));
        let mut floor_cloud = ColourCloud::empty(CloudFrame::Sensor, pose, 0.0);
        for (_, p, rgb) in cloud.iter_valid() {
            floor_cloud.push(Point3::new(p.x, p.y, -1.2), rgb);
        }
        world.memory.saw_floor(&geometry, &floor_cloud, 0.05, 2.0);
        assert!(world.floor_seen_since(&object, 1.5));
    }
}
