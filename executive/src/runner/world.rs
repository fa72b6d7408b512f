//! What the runner knows of the world between commands: the latest look, the obstacles, the plans.

use nalgebra::{Isometry3, Point2};
use nudge_motion::{Bounds, Path, Problem, PushPlan, Validity};
use nudge_perception::grid::ObstacleGrid;
use nudge_perception::{ColourCloud, FloorModel, ObjectId, Prism};

use super::config::RunConfig;
use super::floor_index::FloorIndex;
use super::object::Objects;
use super::unseen::SeenMemory;

/// The runner's world model.
#[derive(Clone, Debug, Default)]
pub(crate) struct WorldModel {
    /// Clouds of the latest look-around.
    pub views: Vec<ColourCloud>,
    /// Obstacles of the latest detection.
    pub prisms: Vec<Prism>,
    /// The id the next obstacle never seen before takes: ids are never handed out twice in a run, so
    /// what the run holds about a forgotten obstacle (a verdict, a wait, an arrival) never passes to
    /// a new one (perception numbers fresh obstacles on from the highest id it is shown).
    pub next_id: u32,
    /// The path being walked.
    pub path: Option<Path>,
    /// The push plan being executed.
    pub push_plan: Option<PushPlan>,
    /// Corners of the box around every point observed so far (map frame): planning stays inside what
    /// was seen, so it never routes through space no sensor has looked at.
    pub seen: Option<(Point2<f64>, Point2<f64>)>,
    /// The floor learnt at the first look (the floor does not change).
    pub floor: Option<FloorModel>,
    /// The obstacle-type grid: every frame taken lands in it (`None` if it could not be made).
    pub grid: Option<ObstacleGrid>,
    /// Where the hand last ended a stroke in contact with an object (map frame): that object's face on
    /// the push line, measured rather than perceived.
    pub touched: Option<(nudge_perception::ObjectId, Point2<f64>)>,
    /// What the run has learnt of each object it has numbered (verdicts, pushes, arrivals, where
    /// it was seen from), by id: an obstacle a later detection overlaps takes its id, and with it
    /// everything known of the object (see [`Self::remember`]).
    pub objects: Objects,
    /// Per grid cell, when the last look or walk frame that left it Moving came in, as robot time let
    /// pass ([`super::watchdog::Watchdog::elapsed`], NaN: never): that time only runs forward, so a
    /// clock that steps back an hour cannot make old motion count as lately for an hour. Frames of
    /// the robot's own pushes do not count: that motion is its own doing.
    pub last_motion: Vec<f64>,
    /// What the run has seen besides the grid's observations, and what it gave up asking about.
    pub memory: SeenMemory,
    /// Where each look-around was taken from (map frame).
    pub looks: Vec<Point2<f64>>,
    /// How long the last look-around took (robot time, s): what the view planner weighs a look at.
    pub look_time: f64,
    /// Whether the robot has walked off the goal to look closer at what may have been people (see
    /// `recheck.rs`): it does so on one arrival only.
    pub looked_closer: bool,
    /// Per grid cell, when a look-around last saw something come or go there (a point departed or
    /// arrived: see [`nudge_perception::seen_through`]), as robot time let pass (NaN: never). Unlike
    /// the grid's Moving cells, which a surface coming into view as the robot walks can raise in a
    /// room where nothing moves, this evidence is three-dimensional and silent in still rooms: what
    /// stands on such cells may be a person, and is never push-tested.
    pub look_motion: Vec<f64>,
    /// Per grid cell, when a frame last turned it Moving, as robot time let pass (NaN: never): motion
    /// seen at that moment, where [`Self::last_motion`] is renewed every frame a cell stays Moving
    /// (the grid keeps a cell a person walked through Moving until a ray crosses it again).
    pub fresh_motion: Vec<f64>,
    /// Where the last walk ended blocked, facing the way it walked (see the runner's `plan_to`).
    pub blocked_at: Option<nalgebra::Isometry2<f64>>,
    /// The cells the viewpoint chosen last is predicted to show.
    pub view_cells: Option<Vec<usize>>,
    /// The cells the viewpoint the robot arrived at is predicted to show: after its look, those still
    /// unseen count a failed look.
    pub pending_view: Option<Vec<usize>>,
    /// The push sequences the last sequence search considered, each with what stopped it (empty when
    /// it found one).
    pub sequences: Vec<nudge_motion::PairRecord>,
    /// Obstacles forgotten since the last detection was reported because a look saw through where
    /// they stood (see [`crate::Event::ObjectsDetected`]). Not those forgotten for being out of
    /// sight: a person no look shows may still stand in the way beyond it.
    pub forgotten: usize,
}

/// Clearances tried when planning, as fractions of the configured one, largest first: where the robot
/// already stands closer than that to something (after a push, where a walk stopped short, in a tight
/// room), less.
const CLEARANCE_FRACTIONS: [f64; 3] = [1.0, 0.5, 0.0];

/// Points higher than this are ignored when growing the seen box (m): ceilings, not rooms.
const SEEN_MAX_HEIGHT: f32 = 2.5;

impl WorldModel {
    /// Gives the obstacles of a new detection that no remembered obstacle's id matched (perception's
    /// fresh ids) ids never used before in the run (see [`Self::next_id`]).
    pub fn number_fresh(&mut self, detected: &mut [Prism]) {
        for p in detected.iter_mut() {
            if !self.prisms.iter().any(|q| q.id == p.id) {
                p.id = self.fresh_id();
            }
        }
    }

    /// An id never used before in the run (see [`Self::next_id`]): past every id handed out and
    /// every id an obstacle holds.
    fn fresh_id(&mut self) -> ObjectId {
        let used = self.prisms.iter().map(|p| p.id.0 + 1).max().unwrap_or(0);
        self.next_id = self.next_id.max(used);
        let id = ObjectId(self.next_id);
        self.next_id = self.next_id.saturating_add(1);
        id
    }

    /// Grows the seen box by the valid points of `cloud` (map frame).
    pub fn see(&mut self, cloud: &ColourCloud) {
        for (_, p, _) in cloud.iter_valid() {
            if p.z > SEEN_MAX_HEIGHT {
                continue;
            }
            let q = Point2::new(f64::from(p.x), f64::from(p.y));
            self.seen = Some(match self.seen {
                Some((lo, hi)) => (lo.inf(&q), hi.sup(&q)),
                None => (q, q),
            });
        }
    }

    /// The planning bounds: the grid's area (paths are hypotheses through floor not yet seen, checked
    /// as the robot walks), or the seen box without a grid, grown to hold the robot's and the goal's
    /// discs.
    pub fn bounds(&self, robot: &Point2<f64>, config: &RunConfig) -> Option<Bounds> {
        let r = nalgebra::Vector2::repeat(config.model.body.radius);
        let (mut lo, mut hi) = self.seen.unwrap_or((*robot, *robot));
        if let Some(grid) = &self.grid {
            let g = grid.geometry();
            let extent =
                nalgebra::Vector2::new(g.width() as f64, g.height() as f64) * g.resolution();
            lo = lo.inf(&g.origin());
            hi = hi.sup(&(g.origin() + extent));
        }
        for p in [robot, &config.goal] {
            lo = lo.inf(&(p - r));
            hi = hi.sup(&(p + r));
        }
        Bounds::new(lo, hi).ok()
    }

    /// The validity checker for the current obstacles, for a robot grown by the configured clearance —
    /// or by less, down to none, when the robot already stands closer than that to something (after a
    /// push, or where the walk stopped short).
    pub fn validity(&self, robot: &Point2<f64>, config: &RunConfig) -> Result<Validity, String> {
        let mut last = Err("no planning bounds".to_string());
        for validity in self.validities(robot, config) {
            last = validity;
            if let Ok(v) = &last
                && nudge_motion::StateValidity::is_free(v, robot)
            {
                return last;
            }
        }
        last
    }

    /// Validity checkers for a robot grown by the configured clearance, then half of it, then none,
    /// each made when asked for; the obstacles (prisms and the grid's moving cells) are gathered once.
    pub fn validities<'a>(
        &'a self,
        robot: &'a Point2<f64>,
        config: &'a RunConfig,
    ) -> impl Iterator<Item = Result<Validity, String>> + 'a {
        let obstacles = self.obstacles(robot, config);
        CLEARANCE_FRACTIONS
            .into_iter()
            .map(move |f| self.validity_over(&obstacles, robot, config, config.clearance * f))
    }

    /// What the planner avoids: the prisms and, since motion reads the grid, what it saw moving or
    /// standing (a wall seen while walking) that no prism explains.
    fn obstacles(&self, robot: &Point2<f64>, config: &RunConfig) -> Vec<Prism> {
        let mut obstacles = self.prisms.clone();
        if let Some(grid) = &self.grid {
            obstacles.extend(super::grid::moving_obstacles(
                grid,
                &self.prisms,
                robot,
                config.model.body.radius,
            ));
            obstacles.extend(super::grid::stationary_obstacles(
                grid,
                &self.prisms,
                robot,
                config.model.body.radius,
                &self.last_motion,
            ));
        }
        obstacles
    }

    /// The validity checker over `obstacles` for a robot grown by `clearance` (m).
    fn validity_over(
        &self,
        obstacles: &[Prism],
        robot: &Point2<f64>,
        config: &RunConfig,
        clearance: f64,
    ) -> Result<Validity, String> {
        let bounds = self
            .bounds(robot, config)
            .ok_or_else(|| "no planning bounds".to_string())?;
        // Plan for a cylinder grown by the clearance; the bounds grow with it, since they were made for
        // the robot's own discs.
        let cylinder = nudge_motion::RobotCylinder {
            radius: config.model.body.radius + clearance,
            height: config.model.body.height,
        };
        let grow = nalgebra::Vector2::repeat(clearance);
        let bounds =
            Bounds::new(bounds.min() - grow, bounds.max() + grow).map_err(|e| e.to_string())?;
        Validity::new(cylinder, bounds, obstacles, config.validity).map_err(|e| e.to_string())
    }

    /// Replaces the obstacles with a new detection, remembering what is out of view (Tamura 3.2.3): a
    /// new obstacle overlapping an old one grows to cover it unless the new look saw floor where the old
    /// part stood (one object seen in parts) or the two are runs of structure meeting at a corner (a
    /// wall and a partition, whose hull is a triangle of floor wider than anything to push), and an
    /// old obstacle no new one absorbed this way is kept unless the new look saw floor inside it (it
    /// was moved away). An old obstacle that only touches what a new one grew over (the end of a wall
    /// beside its base, seen again) is judged on its own floor, not dropped for touching it.
    ///
    /// An obstacle a push test found static stays whole, whatever floor shows: it does not move, and
    /// floor seen between a table's legs must not shrink the table to the part of its top in view. A
    /// new obstacle overlapping it takes its id, so the verdict stays with the object; so does one
    /// overlapping an obstacle found movable, or one moved by a push (where it is now is what the
    /// look shows).
    pub fn remember(
        &mut self,
        detected: Vec<Prism>,
        floor_points: &ColourCloud,
        robot: &Point2<f64>,
        config: &RunConfig,
    ) {
        let outlines: Vec<Vec<Point2<f64>>> =
            detected.iter().map(|p| p.footprint.clone()).collect();
        // The robot cannot stand inside an object: what it stands on was moved (or never was).
        let radius = config.model.body.radius;
        self.prisms.retain(|p| !prism_covers_disc(p, robot, radius));
        let floor = FloorIndex::new(floor_points);
        let seen_floor = |old: &Prism, new: Option<&Prism>| {
            let (lo, hi) = footprint_box(old);
            floor
                .in_box(lo, hi)
                .filter(|q| old.contains_xy(q) && !new.is_some_and(|n| n.contains_xy(q)))
                .take(config.forget_after_floor_points)
                .count()
                >= config.forget_after_floor_points
        };
        let floor_between = |a: &Prism, b: &Prism| self.floor_between(a, b, &floor, config);
        // Cells near where something was ever seen moving: their returns may be a person who
        // stopped there and walked on (the grid clears a stationary cell only when crossed twice in a
        // row, which a look-around's panning views rarely do).
        let moved = self.grid.as_ref().and_then(|g| {
            super::grid::near_motion(g.geometry(), &self.last_motion, g.config().rest_radius)
        });
        let overlaps = |a: &Prism, b: &Prism| a.id == b.id || a.footprint_iou(b) > 0.0;
        let settled = |p: &Prism| self.objects.get(p.id).settled();
        let mut current: Vec<Prism> = Vec::with_capacity(detected.len() + self.prisms.len());
        let mut absorbed = Vec::new();
        let mut joins = Vec::new();
        let other_colours = |a: &Prism, b: &Prism| super::fragments::other_colours(a, b, config);
        let corner = |a: &Prism, b: &Prism| {
            super::fragments::structure_corner(a, b, config.max_candidate_extent)
        };
        for new in detected {
            let new = self.parted_from_what_it_rests_against(new, config);
            let mut merged = new.clone();
            let mut taken: Vec<ObjectId> = Vec::new();
            for old in self.prisms.iter().filter(|old| overlaps(old, &new)) {
                if taken
                    .iter()
                    .chain([&merged.id])
                    .any(|t| self.objects.apart(*t, old.id))
                {
                    // A push test saw them part: they are two, however one look shows them.
                    continue;
                }
                if corner(&merged, old) {
                    // Two runs of structure at a corner (a wall and a partition), even one found
                    // static: their hull would be a triangle of floor.
                    continue;
                }
                if other_colours(&merged, old) {
                    // Two things of two colours that touch, whatever floor shows between them.
                    continue;
                }
                if self.objects.get(old.id).predicted() && !settled(old) {
                    // A pushed object seen again: where it is now is what the look shows, under its
                    // own id (its verdict stays with it; the look numbers its detections afresh).
                    merged.id = old.id;
                } else if settled(old) {
                    // One object tested at two places (both found static): it keeps the first id.
                    let id = if settled(&merged) && merged.id != old.id {
                        joins.push((old.id, merged.id));
                        merged.id
                    } else {
                        old.id
                    };
                    merged = old.merged_with(&merged);
                    merged.id = id;
                } else if !seen_floor(old, Some(&new)) && !floor_between(&merged, old) {
                    merged = merged.merged_with(old);
                    let known = self.objects.get(old.id);
                    if known.movable() || known.ever_moved() {
                        merged.id = old.id;
                    }
                } else {
                    // Two obstacles side by side: the old one stays or goes on its own.
                    continue;
                }
                absorbed.push(old.id);
                taken.push(old.id);
            }
            current.push(merged);
        }
        for old in &self.prisms {
            // Floor seen inside an obstacle the look did not find again means it was moved away,
            // unless the grid still holds returns there (the legs of a chair seen from afar, the
            // floor under its seat in view).
            let gone = (seen_floor(old, None) && !self.grid_holds_returns(old, moved.as_deref()))
                || self.grid_sees_free(old);
            if !absorbed.contains(&old.id) && (settled(old) || !gone) {
                current.push(old.clone());
            }
        }
        for (part, whole) in joins {
            self.objects.learn(part).joined = Some(whole);
        }
        // A pushed object seen again is no longer a prediction.
        for id in &absorbed {
            self.objects.learn(*id).seen_again();
        }
        // Two detections merged into one settled obstacle: keep one prism per id.
        current.sort_by_key(|p| p.id);
        current.dedup_by(|b, a| {
            let same = a.id == b.id;
            if same {
                *a = a.merged_with(b);
            }
            same
        });
        self.prisms = current;
        self.merge_fragments(&floor, config);
        // Where each obstacle the look showed was seen from.
        for prism in &self.prisms {
            let shown = outlines.iter().any(|o| {
                nudge_perception::prism::convex_intersection_area(o, &prism.footprint) > 0.0
            });
            if shown {
                self.objects.learn(prism.id).seen_from_place(*robot);
            }
        }
    }

    /// A detection of a pushed object that came to rest against something that did not move (a cart
    /// pushed up to a wall's end, closer than perception tells apart), without the points of that
    /// thing: those within [`RESTING_MARGIN`] of an obstacle known from before that was not pushed,
    /// and every column of returns that rises above the pushed object's top (an object pushed over
    /// the floor keeps its height: what stands taller beside it is something else). Other detections
    /// are returned as they are.
    fn parted_from_what_it_rests_against(&self, new: Prism, config: &RunConfig) -> Prism {
        let overlapping = |old: &&Prism| old.id == new.id || old.footprint_iou(&new) > 0.0;
        let moved = |old: &Prism| {
            let known = self.objects.get(old.id);
            known.ever_moved() && !known.settled()
        };
        let Some(top) = self
            .prisms
            .iter()
            .filter(overlapping)
            .filter(|old| moved(old))
            .map(|old| old.z_max)
            .reduce(f64::max)
        else {
            return new;
        };
        let unmoved: Vec<&Prism> = self
            .prisms
            .iter()
            .filter(overlapping)
            .filter(|old| !moved(old) && !self.objects.get(old.id).movable())
            .collect();
        let taller = columns_above(&new.points, top + RESTING_COLUMN, |_| true);
        let keep = |p: &nalgebra::Point3<f32>| {
            let q = Point2::new(f64::from(p.x), f64::from(p.y));
            !taller.contains(&resting_column(p))
                && unmoved.iter().all(|o| o.distance_xy(&q) > RESTING_MARGIN)
        };
        new.with_points_where(keep, config.perception.prism.min_thickness)
            .unwrap_or(new)
    }

    /// Whether nobody has tested, moved or judged obstacle `id`: no push test's verdict, not known
    /// movable, never moved by the robot. Only such an obstacle can be a mistake of perception's (a
    /// smear, a piece of something else) to forget or join to another.
    pub(super) fn untouched(&self, id: ObjectId) -> bool {
        self.objects.get(id).untouched()
    }

    /// Splits obstacle `id` into `moved`, the part a push test moved (it keeps the id and what is
    /// known of the object: the test was of what the hand moved), and `rest`, what stayed. A rest
    /// no thicker than the touching gap (its area over its length) that touches another obstacle
    /// is a strip of that neighbour's face which the obstacle's hull had swallowed (a hull's edge
    /// runs up to a cell off the face it was made from, and the split's seam blurs as much): the
    /// neighbour's own outline already stands to within that gap of it, and the strip is dropped.
    /// Any other rest takes an id never used before and what was seen of the obstacle (see
    /// [`Objects::part`]). Returns the rest's id, `None` when it was a strip.
    pub fn split(&mut self, id: ObjectId, mut moved: Prism, mut rest: Prism) -> Option<ObjectId> {
        let gap = self.touching_gap();
        moved.id = id;
        self.prisms.retain(|p| p.id != id);
        let thin = super::fragments::area(&rest.footprint) <= gap * rest.extent();
        let Ok(strip) = nudge_motion::Obstacle::from_prism(&rest) else {
            self.prisms.push(moved);
            return None;
        };
        let touches = self.prisms.iter().any(|q| {
            nudge_motion::Obstacle::from_prism(q)
                .is_ok_and(|o| o.distance_to_obstacle(&strip) <= gap)
        });
        self.prisms.push(moved);
        if touches && thin {
            return None;
        }
        let rest_id = self.fresh_id();
        rest.id = rest_id;
        self.prisms.push(rest);
        self.objects.part(id, rest_id);
        Some(rest_id)
    }

    /// Moves obstacle `id` by a measured rigid `motion` (map frame; a confirmed push, which may have
    /// turned it as well as slid it): its old footprint is free now even where no background shows
    /// behind it. Marked pushed and moved.
    pub fn move_rigidly(&mut self, id: nudge_perception::ObjectId, motion: &Isometry3<f64>) {
        for p in self.prisms.iter_mut().filter(|p| p.id == id) {
            *p = p.transformed(motion);
        }
        self.objects.pushed(id);
    }

    /// Takes out of the other obstacles the points that were `moved`'s, as it stood before a push
    /// carried it away: where a look took part of its face together with what it stood against (a
    /// crate's side beside a doorway's jamb went into the jamb's obstacle), those points stay in the
    /// other obstacle's memory after the crate has gone, and its hull reaches into the doorway for
    /// the rest of the run (`crate-through-doorway` seed 25 with the push test below tipping: no path
    /// through a doorway left 0.75 m wide). The points shed are those within [`RESTING_MARGIN`] of
    /// `moved`'s footprint in columns ([`RESTING_COLUMN`]) that rise no higher than its top: a column
    /// that does is the other obstacle's own, which stands there too. An obstacle left with fewer
    /// than three points keeps them all; a footprint rebuilt is at least `min_thickness` thick.
    pub(super) fn shed_points_of(&mut self, moved: &Prism, min_thickness: f64) {
        let top = moved.z_max + RESTING_COLUMN;
        let within = |p: &nalgebra::Point3<f32>| {
            moved.distance_xy(&Point2::new(f64::from(p.x), f64::from(p.y))) <= RESTING_MARGIN
        };
        let (lo, hi) = footprint_box(moved);
        let near = |other: &Prism| {
            let (a, b) = footprint_box(other);
            a.x <= hi.x + RESTING_MARGIN
                && a.y <= hi.y + RESTING_MARGIN
                && b.x >= lo.x - RESTING_MARGIN
                && b.y >= lo.y - RESTING_MARGIN
        };
        for other in self.prisms.iter_mut().filter(|p| p.id != moved.id) {
            if !near(other) {
                continue;
            }
            let taller = columns_above(&other.points, top, within);
            let shed =
                |p: &nalgebra::Point3<f32>| within(p) && !taller.contains(&resting_column(p));
            if !other.points.iter_valid().any(|(_, p, _)| shed(&p)) {
                continue;
            }
            if let Some(kept) = other.with_points_where(|p| !shed(p), min_thickness) {
                *other = kept;
            }
        }
    }

    /// What the base's safety layer tells of a walk it stopped at `at`: something stands within its
    /// margin of the body's front half (the base faces the way it walks). The prism nearest the body
    /// on that side, within `reach` of its edge, is taken for it: returned with the point of the
    /// body's edge facing it, which the thing reaches at least (a hull is made of the points a look
    /// caught, and a face seen edge-on or not at all leaves it a few centimetres short). `None` when
    /// nothing is near on that side (someone who walked off, a thing never seen).
    pub fn touched(
        &self,
        at: &nalgebra::Isometry2<f64>,
        config: &RunConfig,
        reach: f64,
    ) -> Option<(usize, Point2<f64>)> {
        let body = &config.model.body;
        let here = Point2::from(at.translation.vector);
        let heading = at.rotation * nalgebra::Vector2::x();
        let blocks_body = |p: &Prism| p.z_max > body.step_over && p.z_min < body.height;
        let (i, q) = self
            .prisms
            .iter()
            .enumerate()
            .filter(|(_, p)| blocks_body(p) && !p.contains_xy(&here))
            .filter_map(|(i, p)| Some((i, p.nearest_on_outline(&here)?)))
            .filter(|(_, q)| {
                (q - here).dot(&heading) > 0.0 && (q - here).norm() <= body.radius + reach
            })
            .min_by(|a, b| (a.1 - here).norm().total_cmp(&(b.1 - here).norm()))?;
        let toward = (q - here).try_normalize(1e-9)?;
        Some((i, here + toward * body.radius))
    }

    /// Whether a push test decided `id` is `verdict`.
    fn decided(&self, id: ObjectId, verdict: nudge_perception::grid::Verdict) -> bool {
        self.objects.get(id).judged(verdict)
    }

    /// Whether `prism` may still move: neither decided static by a push test nor room structure.
    pub fn might_move(&self, prism: &Prism, config: &RunConfig) -> bool {
        use nudge_perception::grid::Verdict;
        !(self.decided(prism.id, Verdict::Static) || self.is_structure(prism, config))
    }

    /// The obstacles other than `target` that a push test found movable.
    pub fn known_movers(&self, target: ObjectId) -> Vec<ObjectId> {
        use nudge_perception::grid::Verdict;
        self.prisms
            .iter()
            .filter(|p| p.id != target && self.decided(p.id, Verdict::Movable))
            .map(|p| p.id)
            .collect()
    }

    /// Whether `prism` is room structure, not an object to push: it lies at the edge of everything
    /// seen and its top was out of the camera's view from every place a look showed it from (a
    /// wall is cut by the view's top). A low thing at the edge whose top was in view is a
    /// candidate, whatever stands beyond it: a box flush against a wall, or the farthest thing seen
    /// across a corridor. What it measurably is decides, the edge only says where walls can be.
    pub fn is_structure(&self, prism: &Prism, config: &RunConfig) -> bool {
        let Some((lo, hi)) = self.seen else {
            return false;
        };
        let m = config.structure_margin;
        let (plo, phi) = footprint_box(prism);
        let on_edge = Side::ALL.into_iter().any(|side| {
            let axis = side.axis;
            if side.outward {
                phi[axis] > hi[axis] - m
            } else {
                plo[axis] < lo[axis] + m
            }
        });
        on_edge && !self.top_seen(prism, config)
    }

    /// Whether the top of `prism` was in view from every place a look showed it from, with a margin
    /// for the elevation cells' size and the range noise: its top is a top, not where the views
    /// ended. The farthest place counts, where the view's top passes lowest: a wall seen from near
    /// and far reads as high as the near view shows, well above the far view's top. Not known to
    /// have been seen by a look: no.
    fn top_seen(&self, prism: &Prism, config: &RunConfig) -> bool {
        let places = &self.objects.get(prism.id).seen_from;
        places
            .iter()
            .map(|look| far_side(prism, look))
            .max_by(f64::total_cmp)
            .is_some_and(|d| prism.z_max + TOP_MARGIN < config.top_in_view(d))
    }

    /// How far behind `prism` its own shadow reaches on the floor (m), as seen from the look nearest
    /// it, and that look's place: the floor it hides from an eye at `eye_height` (see
    /// [`nudge_motion::shadow_length`]). No shadow, from the object's own place, before any look.
    pub fn own_shadow(&self, prism: &Prism, eye_height: f64) -> (f64, Point2<f64>) {
        self.looks
            .iter()
            .map(|look| (far_side(prism, look), *look))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map_or_else(
                || (0.0, prism.centroid().unwrap_or_else(Point2::origin)),
                |(d, look)| {
                    (
                        nudge_motion::shadow_length(d, prism.z_max, eye_height),
                        look,
                    )
                },
            )
    }

    /// The problem from `robot` to the goal.
    pub fn problem(robot: &Point2<f64>, config: &RunConfig) -> Result<Problem, String> {
        Problem::new(*robot, config.goal, config.goal_tolerance).map_err(|e| e.to_string())
    }
}

/// Points this close (m) to an unmoved obstacle's footprint are that obstacle's: a footprint is built
/// from the corners of 4 cm elevation cells, so a surface's points lie up to a cell inside it, and its
/// points seen again lie within the range noise (about a centimetre) of where they were.
const RESTING_MARGIN: f64 = 0.02;

/// Side (m) of the columns in which returns above a pushed object's top are looked for, and how far
/// above its top they must rise: perception's 4 cm elevation cell, a centimetre of range noise more.
pub(super) const RESTING_COLUMN: f64 = 0.05;

/// The [`RESTING_COLUMN`] a point stands in.
fn resting_column(p: &nalgebra::Point3<f32>) -> (i64, i64) {
    let k = |v: f32| (f64::from(v) / RESTING_COLUMN).floor() as i64;
    (k(p.x), k(p.y))
}

/// The columns ([`resting_column`]) holding a point of `points` that `near` accepts higher than
/// `top` (m).
fn columns_above(
    points: &ColourCloud,
    top: f64,
    near: impl Fn(&nalgebra::Point3<f32>) -> bool,
) -> std::collections::BTreeSet<(i64, i64)> {
    points
        .iter_valid()
        .filter(|(_, p, _)| f64::from(p.z) > top && near(p))
        .map(|(_, p, _)| resting_column(&p))
        .collect()
}

/// Elevation cells are 4 cm and the range noise about a centimetre: a surface cut by the view's top
/// ray reads up to this far below it, and one top seen twice reads up to this far apart (m).
pub(super) const TOP_MARGIN: f64 = 0.1;

/// Whether the robot's disc at `centre` overlaps `prism`'s footprint by more than a few centimetres.
fn prism_covers_disc(prism: &Prism, centre: &Point2<f64>, radius: f64) -> bool {
    let inner = radius * 0.5;
    prism.contains_xy(centre) || prism.footprint.iter().any(|v| (v - centre).norm() < inner)
}

/// One side of an axis-aligned box: the axis across it (0: x, 1: y) and whether it faces the
/// positive direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Side {
    axis: usize,
    outward: bool,
}

impl Side {
    /// -x, -y, +x, +y.
    const ALL: [Side; 4] = [
        Side {
            axis: 0,
            outward: false,
        },
        Side {
            axis: 1,
            outward: false,
        },
        Side {
            axis: 0,
            outward: true,
        },
        Side {
            axis: 1,
            outward: true,
        },
    ];
}

/// Distance (m) from `look` to the farthest vertex of `prism`'s footprint: how far off its far side
/// was from there.
pub(super) fn far_side(prism: &Prism, look: &Point2<f64>) -> f64 {
    prism
        .footprint
        .iter()
        .map(|v| (v - look).norm())
        .fold(0.0, f64::max)
}

/// Corners of the box around `prism`'s footprint.
pub(super) fn footprint_box(prism: &Prism) -> (Point2<f64>, Point2<f64>) {
    let first = prism
        .footprint
        .first()
        .copied()
        .unwrap_or_else(Point2::origin);
    prism
        .footprint
        .iter()
        .fold((first, first), |(lo, hi), p| (lo.inf(p), hi.sup(p)))
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use nudge_perception::CloudFrame;

    /// An axis-aligned box prism `[x0, x1] × [y0, y1]`, 0.72 m high.
    pub(in crate::runner) fn prism(id: u32, x0: f64, y0: f64, x1: f64, y1: f64) -> Prism {
        box_prism(id, (x0, y0, x1, y1), 0.72)
    }

    /// An axis-aligned box prism `[x0, x1] × [y0, y1]` from the floor to `z_max`, with no points.
    pub(in crate::runner) fn box_prism(
        id: u32,
        (x0, y0, x1, y1): (f64, f64, f64, f64),
        z_max: f64,
    ) -> Prism {
        Prism {
            id: ObjectId(id),
            footprint: vec![
                Point2::new(x0, y0),
                Point2::new(x1, y0),
                Point2::new(x1, y1),
                Point2::new(x0, y1),
            ],
            z_min: 0.0,
            z_max,
            points: ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0),
        }
    }

    /// A prism `[x0, x1] × [y0, y1]` up to `z` whose points cover its top at 2 cm spacing.
    pub(in crate::runner) fn solid(
        id: u32,
        (x0, y0, x1, y1): (f64, f64, f64, f64),
        z: f64,
    ) -> Prism {
        let mut p = box_prism(id, (x0, y0, x1, y1), z);
        let steps = |a: f64, b: f64| {
            (0..)
                .map(move |k| a + 0.02 * f64::from(k))
                .take_while(move |v| *v <= b + 1e-9)
        };
        for x in steps(x0, x1) {
            for y in steps(y0, y1) {
                p.points.push(
                    nalgebra::Point3::new(x as f32, y as f32, z as f32),
                    [90, 60, 30],
                );
            }
        }
        p
    }

    #[test]
    fn a_blocked_walk_is_put_down_to_the_nearest_obstacle_in_front_within_reach() {
        // Invariant: the obstacle taken for what stopped a walk is the nearest one in the body's front half within the reach of its edge, and the point returned is the body's edge facing it; one behind, one out of reach or one too low to stop the body is never taken.
        let config = config_to(Point2::new(5.0, 0.0));
        let r = config.model.body.radius;
        let facing = |yaw: f64| nalgebra::Isometry2::new(nalgebra::Vector2::zeros(), yaw);
        // A box whose face is 5 cm ahead of the body, one 2 cm behind it, and a mat right ahead.
        let ahead = prism(1, r + 0.05, -0.5, r + 0.85, 0.5);
        let behind = prism(2, -r - 0.8, -0.5, -r - 0.02, 0.5);
        let mat = box_prism(3, (r + 0.01, -0.2, r + 0.3, 0.2), 0.01);
        let world = WorldModel {
            prisms: vec![ahead, behind, mat],
            ..WorldModel::default()
        };
        let (i, point) = world
            .touched(&facing(0.0), &config, 0.13)
            .expect("the box ahead");
        assert_eq!(world.prisms[i].id, ObjectId(1));
        assert!((point - Point2::new(r, 0.0)).norm() < 1e-12, "{point}");
        // Turned round, the box 2 cm off the body's back is the one in front.
        let (i, _) = world
            .touched(&facing(std::f64::consts::PI), &config, 0.13)
            .expect("the other box");
        assert_eq!(world.prisms[i].id, ObjectId(2));
        // The face ahead beyond a reach of 4 cm.
        let near_only = world.touched(&facing(0.0), &config, 0.04);
        assert_eq!(near_only, None);
    }

    /// The run's configuration for the paper's robot and a goal at `goal` (0.2 m tolerance).
    pub(in crate::runner) fn config_to(goal: Point2<f64>) -> RunConfig {
        RunConfig::new(nudge_robot_model::RobotModel::default(), goal, 0.2, 1)
    }

    /// Floor points on a 2 cm grid over `[x0, x1] × [y0, y1]`.
    pub(in crate::runner) fn floor(x0: f64, y0: f64, x1: f64, y1: f64) -> ColourCloud {
        let mut cloud = ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0);
        let steps = |a: f64, b: f64| {
            (0..)
                .map(move |k| a + 0.02 * f64::from(k))
                .take_while(move |v| *v <= b)
        };
        for x in steps(x0, x1) {
            for y in steps(y0, y1) {
                cloud.push(
                    nalgebra::Point3::new(x as f32, y as f32, 0.0),
                    [150, 150, 140],
                );
            }
        }
        cloud
    }

    #[test]
    fn an_id_is_never_handed_out_twice_in_a_run() {
        // Invariant: an obstacle a new detection found afresh gets an id no obstacle of the run had before, even after the one with the highest id was forgotten (perception alone would hand that id out again); obstacles it matched keep theirs.
        let mut world = WorldModel::default();
        let mut first = vec![prism(0, 0.0, 0.0, 0.5, 0.5), prism(1, 1.0, 0.0, 1.5, 0.5)];
        world.number_fresh(&mut first);
        assert_eq!(first.iter().map(|p| p.id.0).collect::<Vec<_>>(), [0, 1]);
        world.prisms = first;
        world.prisms.retain(|p| p.id.0 == 0);
        // Perception numbers fresh obstacles on from the highest id it is shown: 1 again.
        let mut second = vec![prism(0, 0.0, 0.0, 0.5, 0.5), prism(1, 2.0, 0.0, 2.5, 0.5)];
        world.number_fresh(&mut second);
        assert_eq!(second.iter().map(|p| p.id.0).collect::<Vec<_>>(), [0, 2]);
    }

    #[test]
    fn a_static_table_seen_in_part_with_floor_between_its_legs_stays_whole_and_keeps_its_id() {
        // Invariant: an obstacle a push test found static is neither shrunk nor dropped by a later look that sees floor inside it, and a new detection overlapping it takes its id; an untested obstacle in the same situation is replaced.
        let config = config_to(Point2::new(5.4, 1.8));
        let robot = Point2::new(0.6, 1.8);
        let table = prism(2, 2.6, 1.2, 3.4, 2.4);
        // The new look sees only the near half of the top, and floor under the far half.
        let part = prism(22, 2.6, 1.2, 3.0, 2.4);
        let under = floor(3.05, 1.25, 3.35, 2.35);
        let mut world = WorldModel {
            prisms: vec![table.clone()],
            ..WorldModel::default()
        };
        world
            .objects
            .judge(ObjectId(2), nudge_perception::grid::Verdict::Static, 1);
        world.remember(vec![part.clone()], &under, &robot, &config);
        assert_eq!(world.prisms.len(), 1);
        assert_eq!(world.prisms[0].id, ObjectId(2));
        assert!(world.prisms[0].contains_xy(&Point2::new(3.3, 2.3)));

        let mut untested = WorldModel {
            prisms: vec![table],
            ..WorldModel::default()
        };
        untested.remember(vec![part], &under, &robot, &config);
        assert_eq!(untested.prisms.len(), 1);
        assert_eq!(untested.prisms[0].id, ObjectId(22));
        assert!(!untested.prisms[0].contains_xy(&Point2::new(3.3, 2.3)));
    }

    #[test]
    fn a_new_run_meeting_an_old_one_at_a_corner_is_not_merged_into_a_triangle_of_floor() {
        // Invariant: a new detection of the room's wall that overlaps an old detection of a
        // partition at their corner stays a separate obstacle (their hull would be a triangle of
        // floor between them); a new view of the same partition, overlapping it along its run,
        // still merges into one.
        let config = config_to(Point2::new(7.0, 2.5));
        let robot = Point2::new(3.0, 3.5);
        let partition = prism(3, 4.92, 3.0, 4.98, 5.0);
        let wall = prism(40, 2.7, 4.95, 4.97, 5.0);
        let no_floor = floor(1.0, 0.5, 1.2, 0.7);
        let mut world = WorldModel {
            prisms: vec![partition.clone()],
            ..WorldModel::default()
        };
        world.remember(vec![wall], &no_floor, &robot, &config);
        assert_eq!(world.prisms.len(), 2, "{:?}", world.prisms);
        let floor_between = Point2::new(4.2, 4.2);
        assert!(world.prisms.iter().all(|p| !p.contains_xy(&floor_between)));

        let mut again = WorldModel {
            prisms: vec![partition],
            ..WorldModel::default()
        };
        again.remember(
            vec![prism(41, 4.91, 2.9, 4.97, 4.2)],
            &no_floor,
            &robot,
            &config,
        );
        assert_eq!(again.prisms.len(), 1, "{:?}", again.prisms);
        assert!(again.prisms[0].contains_xy(&Point2::new(4.95, 2.95)));
        assert!(again.prisms[0].contains_xy(&Point2::new(4.95, 4.9)));
    }

    #[test]
    fn an_obstacle_touching_one_that_grew_is_kept_when_no_floor_shows_inside_it() {
        // Invariant: an old obstacle no new detection absorbed is kept unless floor shows inside it, even where it touches another old obstacle that a new detection grew over (the end of a wall beside the wall's base); floor inside it still makes it go.
        let config = config_to(Point2::new(6.2, 1.8));
        let robot = Point2::new(2.95, 1.4);
        let wall_end = prism(3, 3.47, 0.6, 3.53, 1.3);
        let wall_base = prism(2, 3.04, 0.0, 3.53, 0.68);
        let seen_again = prism(40, 3.0, 0.0, 3.5, 0.5);
        let no_floor = floor(1.0, 2.5, 1.2, 2.7);
        let mut world = WorldModel {
            prisms: vec![wall_base.clone(), wall_end.clone()],
            ..WorldModel::default()
        };
        world.remember(vec![seen_again.clone()], &no_floor, &robot, &config);
        assert_eq!(world.prisms.len(), 2, "{:?}", world.prisms);
        assert!(world.prisms.contains(&wall_end));
        assert!(
            world
                .prisms
                .iter()
                .any(|p| p.id == ObjectId(40) && p.contains_xy(&Point2::new(3.5, 0.65)))
        );
        // Floor seen all over where the wall's end was: it goes.
        let mut moved = WorldModel {
            prisms: vec![wall_base, wall_end],
            ..WorldModel::default()
        };
        moved.remember(
            vec![seen_again],
            &floor(3.47, 0.7, 3.53, 1.3),
            &robot,
            &config,
        );
        assert_eq!(moved.prisms.len(), 1, "{:?}", moved.prisms);
    }

    /// The south wall's run near the corner and the partition's face, as two views see them: thin
    /// strips overlapping at the corner (x = 3.5, y = 0).
    fn corner_strips() -> (Prism, Prism) {
        (
            prism(10, 2.8, -0.02, 3.53, 0.02),
            prism(16, 3.47, 0.0, 3.53, 0.64),
        )
    }

    #[test]
    fn two_wall_runs_meeting_at_a_corner_seen_with_floor_between_stay_apart() {
        // Invariant: a new obstacle does not grow over an old one it overlaps when the hull of the two covers floor this look saw (two wall runs at a corner, seen from inside it): both stay, and the floor between them stays free; with no floor seen between, they merge as parts of one object.
        let config = config_to(Point2::new(6.2, 1.8));
        let robot = Point2::new(2.9, 2.2);
        let (wall, face) = corner_strips();
        let between = Point2::new(3.3, 0.12);
        assert!(wall.merged_with(&face).contains_xy(&between));
        let mut world = WorldModel {
            prisms: vec![wall.clone()],
            ..WorldModel::default()
        };
        world.remember(
            vec![face.clone()],
            &floor(3.2, 0.05, 3.42, 0.2),
            &robot,
            &config,
        );
        assert_eq!(world.prisms.len(), 2, "{:?}", world.prisms);
        assert!(world.prisms.iter().all(|p| !p.contains_xy(&between)));

        let mut unseen = WorldModel {
            prisms: vec![wall],
            ..WorldModel::default()
        };
        unseen.remember(vec![face], &floor(1.0, 2.5, 1.2, 2.7), &robot, &config);
        assert_eq!(unseen.prisms.len(), 1, "{:?}", unseen.prisms);
        assert!(unseen.prisms[0].contains_xy(&between));
    }

    #[test]
    fn floor_the_grid_saw_free_keeps_two_obstacles_apart_when_this_look_cannot_see_it() {
        // Invariant: floor between two overlapping obstacles that this look cannot see (an object in front hides it) but that the grid saw free earlier keeps them apart as well: their hull would be a phantom over free floor.
        let config = config_to(Point2::new(6.2, 1.8));
        let robot = Point2::new(2.9, 2.2);
        let (wall, face) = corner_strips();
        let geometry =
            nudge_perception::grid::GridGeometry::new(Point2::new(0.0, -0.2), [4.0, 3.0], 0.05)
                .expect("a valid grid");
        let mut grid = ObstacleGrid::new(geometry, nudge_perception::grid::GridConfig::default());
        let sensor = Point2::new(3.3, 1.5);
        // Beams across the corner's triangle that return from the south wall, a few frames: the floor
        // they crossed was seen.
        for t in 1..=3 {
            let mut frame =
                nudge_perception::grid::RangeFrame::new(sensor).expect("a finite sensor position");
            for i in 0..200 {
                let end = Point2::new(3.05 + 0.002 * f64::from(i), -0.01);
                assert!(frame.push_hit(end));
            }
            grid.update(&frame, f64::from(t))
                .expect("a frame in clock order");
        }
        let between = Point2::new(3.3, 0.2);
        assert!(wall.merged_with(&face).contains_xy(&between));
        assert_eq!(
            grid.class_at(between),
            Some(nudge_perception::grid::CellClass::Free)
        );
        let mut world = WorldModel {
            prisms: vec![wall],
            grid: Some(grid),
            ..WorldModel::default()
        };
        world.remember(vec![face], &floor(1.0, 2.5, 1.2, 2.7), &robot, &config);
        assert_eq!(world.prisms.len(), 2, "{:?}", world.prisms);
        assert!(world.prisms.iter().all(|p| !p.contains_xy(&between)));
    }

    #[test]
    fn an_object_found_movable_keeps_its_id_through_later_looks() {
        // Invariant: a detection that overlaps an obstacle a push test found movable takes that obstacle's id (the look numbers its detections afresh), look after look, so the verdict stays with the object; an obstacle with no verdict takes the new detection's id as before.
        let config = config_to(Point2::new(6.2, 1.8));
        let robot = Point2::new(1.0, 1.8);
        let no_floor = floor(0.2, 0.2, 0.3, 0.3);
        let mut world = WorldModel {
            prisms: vec![
                prism(9, 2.75, 1.55, 3.25, 2.05),
                prism(10, 4.0, 0.5, 4.5, 1.0),
            ],
            ..WorldModel::default()
        };
        world
            .objects
            .judge(ObjectId(9), nudge_perception::grid::Verdict::Movable, 1);
        for look in 0..3 {
            let seen = vec![
                prism(20 + 2 * look, 2.8, 1.6, 3.3, 2.1),
                prism(21 + 2 * look, 4.0, 0.5, 4.4, 0.9),
            ];
            world.remember(seen, &no_floor, &robot, &config);
            let ids: Vec<u32> = world.prisms.iter().map(|p| p.id.0).collect();
            assert_eq!(ids, vec![9, 21 + 2 * look], "look {look}");
        }
    }

    #[test]
    fn a_pushed_object_seen_again_is_where_the_look_shows_it() {
        // Invariant: the footprint of an object moved by a push is a prediction: the next detection overlapping it replaces it (the object turned as it slid) instead of growing over it, keeps the object's id (its verdict), and after that sight the object is remembered as usual again.
        let config = config_to(Point2::new(6.2, 1.8));
        let robot = Point2::new(2.9, 2.4);
        let no_floor = floor(1.0, 2.5, 1.2, 2.7);
        let mut world = WorldModel {
            prisms: vec![prism(9, 2.75, 1.55, 3.25, 2.05)],
            ..WorldModel::default()
        };
        world.move_rigidly(ObjectId(9), &Isometry3::translation(0.0, -0.6, 0.0));
        assert!(world.prisms[0].contains_xy(&Point2::new(2.8, 1.0)));
        // The look shows it 0.1 m short of the prediction and further east.
        // The look numbers its detections afresh.
        let seen = prism(31, 2.85, 1.05, 3.35, 1.55);
        world.remember(vec![seen.clone()], &no_floor, &robot, &config);
        assert_eq!(
            world.prisms,
            vec![Prism {
                id: ObjectId(9),
                ..seen.clone()
            }]
        );
        assert!(!world.objects.get(ObjectId(9)).predicted());
        // Seen again in part: now it grows over what was seen before, as any object seen in parts.
        let part = prism(32, 2.85, 1.3, 3.35, 1.55);
        world.remember(vec![part], &no_floor, &robot, &config);
        assert_eq!(world.prisms.len(), 1);
        assert!(world.prisms[0].contains_xy(&Point2::new(3.0, 1.1)));
    }

    #[test]
    fn a_pushed_object_takes_its_points_out_of_the_jamb_it_stood_against() {
        // Invariant: before a push carries an object away, the points of its face that a look had taken into the obstacle it stood against (a jamb's end) leave that obstacle, whose footprint no longer reaches over the object's old place; the jamb's own points beside it, in columns rising above the object's top, stay, and an obstacle apart from it is left as it was.
        let mut jamb = solid(4, (4.4, 0.0, 4.6, 1.5), 2.0);
        let face = solid(0, (4.44, 1.5, 4.46, 1.66), 0.7);
        jamb = jamb.merged_with(&face);
        for (_, p, c) in face.points.iter_valid() {
            jamb.points.push(p, c);
        }
        let crate_ = solid(9, (4.44, 1.5, 5.24, 2.3), 0.7);
        let apart = solid(5, (1.0, 1.0, 1.4, 1.4), 0.7);
        let mut world = WorldModel {
            prisms: vec![jamb.clone(), crate_.clone(), apart.clone()],
            ..WorldModel::default()
        };
        assert!(jamb.contains_xy(&Point2::new(4.45, 1.62)));
        world.shed_points_of(&crate_, 0.02);
        let shed = world
            .prisms
            .iter()
            .find(|p| p.id == ObjectId(4))
            .expect("the jamb stays");
        assert!(
            !shed.contains_xy(&Point2::new(4.45, 1.58)),
            "{:?}",
            shed.footprint
        );
        assert!(
            shed.contains_xy(&Point2::new(4.5, 1.45)),
            "{:?}",
            shed.footprint
        );
        // The face's points north of the jamb's own 5 cm columns are gone; those in them stay.
        assert!(shed.points.iter_valid().all(|(_, p, _)| p.y < 1.55));
        assert!(shed.points.len() < jamb.points.len());
        assert_eq!(world.prisms[1], crate_);
        assert_eq!(world.prisms[2], apart);
    }

    #[test]
    fn a_pushed_object_come_to_rest_against_a_wall_end_is_parted_from_it() {
        // Invariant: a detection that joins an object the robot pushed to the wall end it came to rest against (closer than perception tells apart) keeps the object's id and only its points: those on the wall known from before and every column of returns rising above the object's top are left out, and the wall stays an obstacle of its own.
        let config = config_to(Point2::new(6.2, 1.8));
        let robot = Point2::new(1.5, 2.5);
        let far_floor = floor(0.5, 3.0, 0.6, 3.1);
        // The wall's west face, seen before the push; its end face (y = 1.2) was hidden by the cart.
        let wall = solid(4, (3.5, 0.0, 3.54, 1.2), 1.3);
        let cart = solid(9, (2.8, 1.6, 3.3, 2.1), 1.0);
        let mut world = WorldModel {
            prisms: vec![wall, cart],
            ..WorldModel::default()
        };
        world.move_rigidly(ObjectId(9), &Isometry3::translation(0.15, -0.65, 0.0));
        // The look's one detection: the cart where it came to rest, and the wall's end beside it.
        let end = solid(0, (3.5, 0.9, 3.7, 1.2), 1.3);
        let mut seen = solid(31, (2.95, 0.95, 3.45, 1.45), 1.0).merged_with(&end);
        for (_, p, c) in end.points.iter_valid() {
            seen.points.push(p, c);
        }
        world.remember(vec![seen], &far_floor, &robot, &config);
        let cart = world
            .prisms
            .iter()
            .find(|p| p.id == ObjectId(9))
            .expect("the cart keeps its id");
        assert!(cart.contains_xy(&Point2::new(3.2, 1.2)), "{cart:?}");
        assert!(!cart.contains_xy(&Point2::new(3.6, 1.1)), "{cart:?}");
        assert!(cart.z_max <= 1.0 + 1e-6);
        assert!(world.prisms.iter().any(|p| p.id == ObjectId(4)));
        // Seen again once it is no longer a prediction, the wall's end still stays out of it.
        let mut again = solid(32, (2.95, 0.95, 3.45, 1.45), 1.0).merged_with(&end);
        for (_, p, c) in end.points.iter_valid() {
            again.points.push(p, c);
        }
        world.remember(vec![again], &far_floor, &robot, &config);
        let cart = world
            .prisms
            .iter()
            .find(|p| p.id == ObjectId(9))
            .expect("the cart keeps its id");
        assert!(!cart.contains_xy(&Point2::new(3.6, 1.1)), "{cart:?}");
    }

    #[test]
    fn one_object_found_static_at_two_places_keeps_the_first_id_and_the_other_joins_it() {
        // Invariant: when a look shows two obstacles that push tests both found static to be one object, one obstacle remains under the first id, and the other id is recorded as joined to it (its verdict is about that obstacle).
        let config = config_to(Point2::new(5.4, 1.8));
        let robot = Point2::new(1.0, 2.5);
        let mut world = WorldModel {
            prisms: vec![
                solid(1, (2.6, 1.2, 3.0, 2.4), 1.1),
                solid(36, (3.15, 1.6, 3.4, 2.4), 1.1),
            ],
            ..WorldModel::default()
        };
        world
            .objects
            .judge(ObjectId(1), nudge_perception::grid::Verdict::Static, 1);
        world
            .objects
            .judge(ObjectId(36), nudge_perception::grid::Verdict::Static, 2);
        let whole = solid(50, (2.6, 1.2, 3.4, 2.4), 1.1);
        world.remember(vec![whole], &floor(0.5, 3.0, 0.6, 3.1), &robot, &config);
        assert_eq!(world.prisms.len(), 1, "{:?}", world.prisms);
        assert_eq!(world.prisms[0].id, ObjectId(1));
        assert!(world.prisms[0].contains_xy(&Point2::new(3.3, 2.0)));
        assert_eq!(world.objects.get(ObjectId(36)).joined, Some(ObjectId(1)));
    }

    /// A world seen out to the box (0, 0)–(6, 3), holding `prisms`, each shown by a look from (1, 1).
    fn seen_world(prisms: Vec<Prism>) -> WorldModel {
        let mut world = WorldModel {
            seen: Some((Point2::new(0.0, 0.0), Point2::new(6.0, 3.0))),
            looks: vec![Point2::new(1.0, 1.0)],
            prisms,
            ..WorldModel::default()
        };
        for p in &world.prisms {
            world
                .objects
                .learn(p.id)
                .seen_from_place(Point2::new(1.0, 1.0));
        }
        world
    }

    #[test]
    fn at_the_edge_of_all_seen_a_wall_is_structure_but_a_low_box_is_not_whatever_stands_beyond_it()
    {
        // Invariant: at the edge of everything seen, a wall (its top out of view) is structure, never a push candidate; a low cabinet flush against that wall and a low box whose top was in view with nothing seen beyond it (a box across a corridor, seen from its far end) are candidates; anything away from the edge is never structure.
        let config = config_to(Point2::new(5.0, 1.0));
        // The wall's top: the view's top ray 5 m away passes 1.4 − 5 · tan 2.7° ≈ 1.16 m up.
        let wall = box_prism(1, (0.0, -0.02, 6.0, 0.03), 1.15);
        let cabinet = box_prism(2, (2.0, 0.06, 2.9, 0.5), 0.8);
        let far_box = box_prism(3, (5.9, 1.0, 6.0, 2.0), 0.7);
        let middle = box_prism(4, (3.0, 1.2, 3.5, 1.8), 0.7);
        let world = seen_world(vec![
            wall.clone(),
            cabinet.clone(),
            far_box.clone(),
            middle.clone(),
        ]);
        assert!(world.is_structure(&wall, &config));
        assert!(!world.is_structure(&cabinet, &config));
        assert!(!world.is_structure(&far_box, &config));
        assert!(!world.is_structure(&middle, &config));
        // The same box, as tall as the view's top where it stands: it may be a wall.
        let tall = box_prism(3, (5.9, 1.0, 6.0, 2.0), 1.2);
        let world = seen_world(vec![wall, cabinet, tall.clone(), middle]);
        assert!(world.is_structure(&tall, &config));
    }
}
