//! One object, one obstacle: merging the pieces perception makes of an object seen from one side or
//! from far, and keeping apart two things that only touch.

use nalgebra::Point2;
use nudge_perception::grid::ObstacleGrid;
use nudge_perception::{ColourCloud, Prism};

use super::config::RunConfig;
use super::floor_index::FloorIndex;
use super::world::{TOP_MARGIN, WorldModel, footprint_box};

impl WorldModel {
    /// Whether floor was seen where the hull of `a` and `b` covers neither (two wall runs meeting at a
    /// corner, seen from inside it; two chairs side by side): they are two things, and their hull would
    /// be a phantom over free floor.
    pub(super) fn floor_between(
        &self,
        a: &Prism,
        b: &Prism,
        floor: &FloorIndex,
        config: &RunConfig,
    ) -> bool {
        let hull = outline_of_both(a, b);
        let outside_both = |q: &Point2<f64>| !a.contains_xy(q) && !b.contains_xy(q);
        let (lo, hi) = footprint_box(&hull);
        let in_gap = |q: &Point2<f64>| hull.contains_xy(q) && outside_both(q);
        let n = config.forget_after_floor_points;
        floor.in_box(lo, hi).filter(|q| in_gap(q)).take(n).count() >= n
            || self.grid.as_ref().is_some_and(|g| {
                free_area_where(g, (lo, hi), |q| {
                    q.x >= lo.x && q.y >= lo.y && q.x <= hi.x && q.y <= hi.y && in_gap(q)
                }) >= MERGE_BLOCKING_FREE_AREA
            })
    }

    /// Merges obstacles that are pieces of one thing: footprints within two grid cells of each other,
    /// height ranges that meet, and no floor seen between them (see [`Self::floor_between`]). A
    /// surface seen obliquely or from far (a wall, a table's top at 4 m) comes out of perception in
    /// pieces whose gaps are where its points thinned out; planning around the pieces is the same as
    /// around the whole, but a push of one piece "runs into" the next. Two obstacles that both carry a
    /// push test's verdict stay apart; a merge keeps the id of the one that has a verdict (else the
    /// older id).
    pub(super) fn merge_fragments(&mut self, floor: &FloorIndex, config: &RunConfig) {
        let gap = self.touching_gap();
        loop {
            let judged = |p: &Prism| self.objects.get(p.id).judgement.is_some();
            let outlines: Vec<Option<nudge_motion::Obstacle>> = self
                .prisms
                .iter()
                .map(|p| nudge_motion::Obstacle::from_prism(p).ok())
                .collect();
            let mut pair = None;
            'search: for i in 0..self.prisms.len() {
                for j in i + 1..self.prisms.len() {
                    let (a, b) = (&self.prisms[i], &self.prisms[j]);
                    let (Some(oa), Some(ob)) = (&outlines[i], &outlines[j]) else {
                        continue;
                    };
                    if (judged(a) && judged(b))
                        || self.objects.apart(a.id, b.id)
                        || self.taller_than_moved(a, b)
                        || self.taller_than_moved(b, a)
                        || !oa.heights_overlap(ob)
                        || !oa.aabb().inflated(SURFACE_GAP).overlaps(ob.aabb())
                    {
                        continue;
                    }
                    let apart = oa.distance_to_obstacle(ob);
                    let hull = outline_of_both(a, b);
                    // Their hull adds no more than a strip of the surface gap along it: pieces of one
                    // run, not two walls meeting at a corner (whose hull is a triangle of floor).
                    let added = area(&hull.footprint) - area(&a.footprint) - area(&b.footprint);
                    if added > SURFACE_GAP * hull.extent() / 2.0 {
                        continue;
                    }
                    // Pieces of one object's surfaces (a table's edge seen from 4 m, floor showing
                    // under its top): points within the sensor's spacing, and together no larger
                    // than an object to push (a chair beside a wall stays a chair).
                    let one_surface = apart <= SURFACE_GAP
                        && hull.extent() <= config.max_candidate_extent
                        && points_within(a, b, SURFACE_GAP);
                    let touching = || apart <= gap && !self.floor_between(a, b, floor, config);
                    // Last, as it sums both point sets: two colours side by side are two things.
                    if (!one_surface && !touching()) || other_colours(a, b, config) {
                        continue;
                    }
                    pair = Some((i, j));
                    break 'search;
                }
            }
            let Some((i, j)) = pair else {
                return;
            };
            let (a, b) = (&self.prisms[i], &self.prisms[j]);
            let id = match (judged(a), judged(b)) {
                (true, _) => a.id,
                (false, true) => b.id,
                _ => a.id.min(b.id),
            };
            self.join(i, j, id);
        }
    }

    /// Takes into the obstacle `id`, about to be moved by a push, the pieces perception made of the
    /// same object's other faces: untested obstacles touching it (within two grid cells) with which
    /// it forms an L that is one object seen from its corner (see [`one_object_l`]), with no floor
    /// the grid saw free inside the L. Before a look shows the object whole, its side seen edge-on
    /// often comes out as a thin obstacle of its own beside the face the robot pushes; moved alone,
    /// the pushed face would leave that side behind where the object no longer stands, in the way of
    /// the pushes that follow.
    pub(super) fn take_in_faces_of(
        &mut self,
        id: nudge_perception::ObjectId,
        robot: &Point2<f64>,
        config: &RunConfig,
    ) {
        let gap = self.touching_gap();
        // No look's floor points are at hand mid-push: only the cells the grid saw free count.
        let no_floor = FloorIndex::new(&ColourCloud::empty(
            nudge_perception::CloudFrame::Map,
            nalgebra::Isometry3::identity(),
            0.0,
        ));
        loop {
            let Some(i) = self.prisms.iter().position(|p| p.id == id) else {
                return;
            };
            let x = &self.prisms[i];
            let Ok(ox) = nudge_motion::Obstacle::from_prism(x) else {
                return;
            };
            let face = self.prisms.iter().enumerate().position(|(j, f)| {
                j != i
                    && self.untouched(f.id)
                    && !self.objects.apart(id, f.id)
                    && nudge_motion::Obstacle::from_prism(f)
                        .is_ok_and(|of| ox.distance_to_obstacle(&of) <= gap)
                    && one_object_l(x, f, robot, config)
                    && !self.floor_between(x, f, &no_floor, config)
                    && !other_colours(x, f, config)
            });
            let Some(j) = face else {
                return;
            };
            self.join(i, j, id);
        }
    }

    /// Whether obstacle `prism` touches another (within [`Self::touching_gap`], at overlapping
    /// heights): an object pushed to rest against something, whose outline a look may have taken
    /// together with it.
    pub(super) fn rests_against_another(&self, prism: &Prism) -> bool {
        let gap = self.touching_gap();
        let Ok(own) = nudge_motion::Obstacle::from_prism(prism) else {
            return false;
        };
        self.prisms.iter().filter(|q| q.id != prism.id).any(|q| {
            nudge_motion::Obstacle::from_prism(q)
                .is_ok_and(|o| own.heights_overlap(&o) && own.distance_to_obstacle(&o) <= gap)
        })
    }

    /// How far apart (m) two obstacles' footprints may lie and still touch: two grid cells, as a
    /// hull's edge runs a cell off the face it was made from, on either side.
    pub(super) fn touching_gap(&self) -> f64 {
        2.0 * self
            .grid
            .as_ref()
            .map_or(MERGE_GAP_FALLBACK, |g| g.geometry().resolution())
    }

    /// Merges obstacle `j` into obstacle `i` under `id` (one of theirs): the hull of both with both
    /// point sets, seen from wherever either was; the other id is recorded as joined to it.
    fn join(&mut self, i: usize, j: usize, id: nudge_perception::ObjectId) {
        let a_id = self.prisms[i].id;
        let b = self.prisms.remove(j);
        let i = if j < i { i - 1 } else { i };
        let a = &self.prisms[i];
        let mut merged = a.merged_with(&b);
        merged.id = id;
        for (_, p, c) in b.points.iter_valid() {
            merged.points.push(p, c);
        }
        self.prisms[i] = merged;
        // The piece whose id goes joins the whole. The second piece's places go to the whole; the
        // first piece's stay with its old id when that is the one that goes, though the whole was
        // seen from them too (a gap kept as it was: handing them on changes runs).
        if id == a_id {
            self.objects.join(b.id, id);
        } else {
            self.objects.learn(b.id).seen_again();
            self.objects.learn(a_id).joined = Some(id);
        }
    }
}

/// Whether two pieces meeting in an L are two faces of one object seen from its corner (a box's side
/// and its far part): together no wider than anything the robot pushes, and both tops in view from
/// `robot` at one height — a top seen is an object's, and one object's faces share it. Two runs of
/// structure meeting at a corner have no top in view (the view ends on them), and a box against a
/// wall's end is lower than the wall.
fn one_object_l(a: &Prism, b: &Prism, robot: &Point2<f64>, config: &RunConfig) -> bool {
    let top_in_view =
        |p: &Prism| p.z_max + TOP_MARGIN < config.top_in_view(super::world::far_side(p, robot));
    outline_of_both(a, b).extent() <= config.max_candidate_extent
        && (a.z_max - b.z_max).abs() <= TOP_MARGIN
        && top_in_view(a)
        && top_in_view(b)
}

impl WorldModel {
    /// Whether `moved` is an object the robot pushed and `other` rises above its top: an object pushed
    /// over the floor keeps its height, so what stands taller beside it is something else (see
    /// [`Self::remember`]).
    fn taller_than_moved(&self, moved: &Prism, other: &Prism) -> bool {
        let known = self.objects.get(moved.id);
        known.ever_moved()
            && !known.settled()
            && other.z_max > moved.z_max + super::world::RESTING_COLUMN
    }
}

/// Whether two overlapping obstacles are two runs of room structure meeting at a corner (a
/// partition and the room's wall): their hull adds more floor than a strip of the surface gap along
/// it, as [`WorldModel::merge_fragments`] asks of pieces that touch, and spans more than
/// `max_extent` (wider than anything the robot would push). Two faces of one object seen from its
/// corner (a cart) also form an L, but their hull is that object, no wider than `max_extent`.
pub(super) fn structure_corner(a: &Prism, b: &Prism, max_extent: f64) -> bool {
    let hull = outline_of_both(a, b);
    let overlap = nudge_perception::prism::convex_intersection_area(&a.footprint, &b.footprint);
    let added = area(&hull.footprint) - area(&a.footprint) - area(&b.footprint) + overlap;
    added > SURFACE_GAP * hull.extent() / 2.0 && hull.extent() > max_extent
}

/// The convex hull of `a`'s and `b`'s footprints as a prism of `a`'s heights with no points: their
/// outline together, to measure and test points against.
fn outline_of_both(a: &Prism, b: &Prism) -> Prism {
    Prism {
        id: a.id,
        footprint: a.merged_footprint(b),
        z_min: a.z_min.min(b.z_min),
        z_max: a.z_max.max(b.z_max),
        points: ColourCloud::empty(
            nudge_perception::CloudFrame::Map,
            nalgebra::Isometry3::identity(),
            0.0,
        ),
    }
}

/// Area of grid cells seen free (m²) whose centres lie in the box `(lo, hi)` and satisfy `keep`.
fn free_area_where(
    grid: &ObstacleGrid,
    (lo, hi): (Point2<f64>, Point2<f64>),
    keep: impl Fn(&Point2<f64>) -> bool,
) -> f64 {
    let geometry = grid.geometry();
    let res = geometry.resolution();
    let (Some(a), Some(b)) = (geometry.cell_of(lo), geometry.cell_of(hi)) else {
        return 0.0;
    };
    let mut free = 0usize;
    for y in a.y..=b.y {
        for x in a.x..=b.x {
            let cell = nudge_perception::grid::CellIndex { x, y };
            if grid.class(cell) == Some(nudge_perception::grid::CellClass::Free)
                && keep(&geometry.centre(cell))
            {
                free += 1;
            }
        }
    }
    free as f64 * res * res
}

/// Points of one surface seen by the range camera lie at most this far apart (m): adjacent pixels
/// 0.25° apart (43.6° over 176 columns) at the camera's 5 m range, on a surface seen at perception's
/// 80° incidence limit, are 5 m × 0.25° / cos 80° ≈ 12.5 cm apart.
const SURFACE_GAP: f64 = 0.125;

/// Whether a point of `a` lies within `within` (3D, m) of a point of `b`: `b`'s points binned in
/// cubes of that side, each of `a`'s checked against the 27 cubes around its own.
fn points_within(a: &Prism, b: &Prism, within: f64) -> bool {
    // Only points near the other's footprint can be near its points.
    let near = |p: &Prism, of: &Prism| -> Vec<[f32; 3]> {
        let (lo, hi) = footprint_box(of);
        p.points
            .iter_valid()
            .filter(|(_, q, _)| {
                let (x, y) = (f64::from(q.x), f64::from(q.y));
                x >= lo.x - within && y >= lo.y - within && x <= hi.x + within && y <= hi.y + within
            })
            .map(|(_, q, _)| [q.x, q.y, q.z])
            .collect()
    };
    let key = |q: &[f32; 3]| {
        let k = |v: f32| (f64::from(v) / within).floor() as i64;
        (k(q[0]), k(q[1]), k(q[2]))
    };
    let (from_a, from_b) = (near(a, b), near(b, a));
    if from_a.is_empty() || from_b.is_empty() {
        return false;
    }
    let mut bins: std::collections::BTreeMap<(i64, i64, i64), Vec<[f32; 3]>> =
        std::collections::BTreeMap::new();
    for q in from_b {
        bins.entry(key(&q)).or_default().push(q);
    }
    let w2 = (within * within) as f32;
    from_a.iter().any(|p| {
        let (i, j, k) = key(p);
        (-1..=1).any(|di| {
            (-1..=1).any(|dj| {
                (-1..=1).any(|dk| {
                    bins.get(&(i + di, j + dj, k + dk)).is_some_and(|pts| {
                        pts.iter().any(|q| {
                            let (dx, dy, dz) = (p[0] - q[0], p[1] - q[1], p[2] - q[2]);
                            dx * dx + dy * dy + dz * dz <= w2
                        })
                    })
                })
            })
        })
    })
}

/// Area of the polygon `f` (m², shoelace; either winding).
pub(super) fn area(f: &[Point2<f64>]) -> f64 {
    let n = f.len();
    (0..n)
        .map(|i| {
            let (a, b) = (f[i], f[(i + 1) % n]);
            a.x * b.y - b.x * a.y
        })
        .sum::<f64>()
        .abs()
        / 2.0
}

/// Gap (m) within which two pieces may be one thing when there is no grid to say its cell size.
const MERGE_GAP_FALLBACK: f64 = 0.05;

/// Free floor (m²) the grid saw between two obstacles that keeps them from merging: a few cells, more
/// than the slivers a hull adds along two overlapping views of one straight face.
const MERGE_BLOCKING_FREE_AREA: f64 = 0.02;

/// Whether `a` and `b` are two things of two colours standing side by side: their points' mean
/// chromaticities differ by more than the camera's colour noise and rounding explain
/// ([`nudge_perception::hue`]), and neither stands over most of the other. Such pieces are two
/// things that touch, never one object seen in parts: a surface's texture changes its brightness,
/// not its chromaticity. Parts of one thing in two colours stand one over the other (a person's
/// clothes, a cushion on a seat): their footprints share more than half the smaller one, where two
/// things side by side share at most the cell-wide strip each hull takes of the other, under half
/// of anything wider than two cells. Always false where perception keeps no colours.
pub(super) fn other_colours(a: &Prism, b: &Prism, config: &RunConfig) -> bool {
    let Some(hue) = config.perception.elevation.hue.as_ref() else {
        return false;
    };
    let shared = nudge_perception::prism::convex_intersection_area(&a.footprint, &b.footprint);
    shared <= 0.5 * a.area().min(b.area()) && !hue.same(&a.colour(), &b.colour())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::runner::world::tests::{config_to, floor, solid};
    use nudge_perception::{ObjectId, Prism};

    #[test]
    fn pieces_of_one_object_merge_and_two_objects_side_by_side_do_not() {
        // Invariant: two pieces of one table's edge seen from far (points 8 cm apart, floor seen under the table beside them) become one obstacle with both pieces' points; a chair 18 cm from the table stays apart; two wall runs meeting at a corner stay two (their hull would be a triangle of floor).
        let config = config_to(Point2::new(13.3, 1.8));
        let robot = Point2::new(3.6, 1.8);
        let left = solid(7, (8.1, 1.2, 8.2, 1.75), 0.72);
        let right = solid(8, (8.1, 1.83, 8.2, 2.4), 0.72);
        let chair = solid(12, (9.05, 0.6, 9.55, 1.1), 0.85);
        let table_back = solid(9, (8.38, 1.2, 8.9, 2.4), 0.72);
        let under = floor(8.25, 1.3, 8.33, 2.3);
        let mut world = WorldModel::default();
        world.remember(
            vec![left.clone(), right.clone(), chair.clone(), table_back],
            &under,
            &robot,
            &config,
        );
        let edge = world
            .prisms
            .iter()
            .find(|p| p.contains_xy(&Point2::new(8.15, 1.5)))
            .expect("the table's edge");
        assert!(
            edge.contains_xy(&Point2::new(8.15, 2.2)),
            "{:?}",
            world.prisms
        );
        assert_eq!(edge.id, ObjectId(7));
        assert_eq!(edge.points.len(), left.points.len() + right.points.len());
        assert!(world.prisms.iter().any(|p| p.id == ObjectId(12)));
        // Two wall runs meeting at a corner, touching, no floor seen between them.
        let mut corner = WorldModel::default();
        let south = solid(20, (4.1, 3.95, 7.4, 4.05), 2.0);
        let east = solid(21, (7.35, 4.05, 7.45, 5.5), 2.0);
        corner.remember(
            vec![south, east],
            &floor(1.0, 1.0, 1.1, 1.1),
            &Point2::new(5.0, 6.0),
            &config,
        );
        assert_eq!(corner.prisms.len(), 2, "{:?}", corner.prisms);
    }

    /// `prism` with every point of colour `rgb`.
    fn recoloured(prism: Prism, rgb: [u8; 3]) -> Prism {
        let mut points = nudge_perception::ColourCloud::empty(
            prism.points.frame(),
            *prism.points.sensor_pose(),
            prism.points.stamp(),
        );
        for (_, p, _) in prism.points.iter_valid() {
            points.push(p, rgb);
        }
        Prism { points, ..prism }
    }

    #[test]
    fn two_touching_things_of_two_colours_stay_two_obstacles() {
        // Invariant: two untested boxes 2 cm apart with no floor seen between them, which merge as one object's pieces when they are of one colour, stay two obstacles when their colours differ by more than the camera's noise explains (two greens a touching-family doorway held abreast).
        let config = config_to(Point2::new(13.3, 1.8));
        let robot = Point2::new(6.0, 1.8);
        let elsewhere = floor(1.0, 1.0, 1.1, 1.1);
        let a = solid(7, (8.1, 1.2, 8.6, 1.75), 0.5);
        let b = solid(8, (8.1, 1.77, 8.6, 2.3), 0.5);
        let look = |a: Prism, b: Prism| {
            let mut world = WorldModel::default();
            world.remember(vec![a, b], &elsewhere, &robot, &config);
            world.prisms.len()
        };
        assert_eq!(
            look(
                recoloured(a.clone(), [61, 204, 72]),
                recoloured(b.clone(), [61, 204, 72])
            ),
            1
        );
        assert_eq!(
            look(recoloured(a, [61, 204, 72]), recoloured(b, [61, 206, 119])),
            2
        );
    }

    #[test]
    fn a_pushed_box_takes_in_its_side_seen_as_a_piece_of_its_own_and_not_the_wall_beside_it() {
        // Invariant: before a push moves an obstacle, an untested piece touching it in an L that is one object seen from its corner (no wider than an object to push, both tops in view at one height) joins it under its id, so the move carries the whole object; a taller piece (a wall's end, its top out of view) and a piece not touching stay where they are.
        let config = config_to(Point2::new(7.2, 1.7));
        let robot = Point2::new(3.55, 2.25);
        let side = solid(7, (4.04, 1.70, 4.11, 2.12), 0.79);
        let far_part = solid(8, (4.04, 2.04, 4.59, 2.47), 0.79);
        let wall_end = solid(9, (4.25, 2.47, 4.40, 3.2), 2.0);
        let apart = solid(10, (4.0, 0.9, 4.5, 1.4), 0.79);
        let mut world = WorldModel {
            prisms: vec![side, far_part.clone(), wall_end.clone(), apart.clone()],
            ..WorldModel::default()
        };
        world.take_in_faces_of(ObjectId(8), &robot, &config);
        assert_eq!(world.prisms.len(), 3, "{:?}", world.prisms);
        let pushed = world
            .prisms
            .iter()
            .find(|p| p.id == ObjectId(8))
            .expect("the pushed box");
        assert!(pushed.contains_xy(&Point2::new(4.07, 1.75)));
        assert!(pushed.contains_xy(&Point2::new(4.3, 1.95)));
        assert_eq!(world.objects.get(ObjectId(7)).joined, Some(ObjectId(8)));
        assert!(world.prisms.contains(&wall_end));
        assert!(world.prisms.contains(&apart));
    }

    #[test]
    fn an_object_rests_against_another_only_within_the_touching_gap() {
        // Invariant: an obstacle rests against another when their footprints lie within the touching gap (5 cm without a grid) at overlapping heights; 12 cm apart, or a shelf above it, it does not.
        let boxed = solid(4, (2.0, 1.0, 2.5, 1.5), 0.7);
        let world = |other: Prism| WorldModel {
            prisms: vec![boxed.clone(), other],
            ..WorldModel::default()
        };
        let against = world(solid(5, (2.54, 0.5, 3.0, 2.0), 2.0));
        assert!(against.rests_against_another(&boxed));
        let apart = world(solid(5, (2.62, 0.5, 3.0, 2.0), 2.0));
        assert!(!apart.rests_against_another(&boxed));
        let mut shelf = solid(5, (2.52, 0.5, 3.0, 2.0), 1.6);
        shelf.z_min = 1.2;
        assert!(!world(shelf).rests_against_another(&boxed));
    }

    #[test]
    fn objects_that_both_carry_a_verdict_never_merge() {
        // Invariant: two touching obstacles that both have a push test's verdict stay two; a piece touching one with a verdict joins it under that id.
        let config = config_to(Point2::new(6.2, 1.8));
        let a = solid(3, (2.0, 1.0, 2.5, 1.5), 0.8);
        let b = solid(4, (2.52, 1.0, 3.0, 1.5), 0.8);
        let mut world = WorldModel {
            prisms: vec![a.clone(), b.clone()],
            ..WorldModel::default()
        };
        world
            .objects
            .judge(ObjectId(3), nudge_perception::grid::Verdict::Static, 1);
        world
            .objects
            .judge(ObjectId(4), nudge_perception::grid::Verdict::Movable, 2);
        world.merge_fragments(&FloorIndex::new(&floor(0.1, 0.1, 0.2, 0.2)), &config);
        assert_eq!(world.prisms.len(), 2);
        let mut one = WorldModel {
            prisms: vec![solid(2, (2.0, 1.0, 2.5, 1.5), 0.8), b],
            ..WorldModel::default()
        };
        one.objects
            .judge(ObjectId(4), nudge_perception::grid::Verdict::Movable, 1);
        one.merge_fragments(&FloorIndex::new(&floor(0.1, 0.1, 0.2, 0.2)), &config);
        assert_eq!(one.prisms.len(), 1);
        assert_eq!(one.prisms[0].id, ObjectId(4));
    }
}
