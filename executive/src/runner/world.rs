//! What the runner knows of the world between commands: the latest look, the obstacles, the plans.

use nalgebra::{Isometry3, Point2};
use nudge_motion::{Bounds, Path, Problem, PushPlan, Validity};
use nudge_perception::grid::ObstacleGrid;
use std::collections::BTreeSet;

use nudge_perception::{ColourCloud, FloorModel, ObjectId, Prism};

use super::config::RunConfig;
use super::unseen::SeenMemory;

/// The runner's world model.
#[derive(Clone, Debug, Default)]
pub(crate) struct WorldModel {
    /// Clouds of the latest look-around.
    pub views: Vec<ColourCloud>,
    /// Obstacles of the latest detection.
    pub prisms: Vec<Prism>,
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
    /// Obstacles a push test found static: they stay where they were measured (see [`Self::remember`]).
    pub settled: BTreeSet<ObjectId>,
    /// Obstacles a push test found movable: a detection that overlaps one takes its id, so the
    /// verdict stays with the object however often it is seen again (see [`Self::remember`]).
    pub movable: BTreeSet<ObjectId>,
    /// Obstacles moved by a confirmed push since they were last seen: their footprints are predictions
    /// (the object may have turned as it slid), which the next sight of them replaces.
    pub pushed: BTreeSet<ObjectId>,
    /// Per grid cell, the robot-clock stamp of the last look or walk frame that left it Moving (NaN:
    /// never). Frames of the robot's own pushes do not count: that motion is its own doing.
    pub last_motion: Vec<f64>,
    /// What the run has seen besides the grid's observations, and what it gave up asking about.
    pub memory: SeenMemory,
    /// Where each look-around was taken from (map frame).
    pub looks: Vec<Point2<f64>>,
    /// How long the last look-around took (robot time, s): what the view planner weighs a look at.
    pub look_time: f64,
    /// Where a walk was blocked before it got away (see the runner's `plan_to`).
    pub stuck_at: Option<Point2<f64>>,
    /// Per obstacle, the places the looks that showed it were taken from.
    pub seen_from: std::collections::BTreeMap<ObjectId, Vec<Point2<f64>>>,
    /// The cells the viewpoint chosen last is predicted to show.
    pub view_cells: Option<Vec<usize>>,
    /// The cells the viewpoint the robot arrived at is predicted to show: after its look, those still
    /// unseen count a failed look.
    pub pending_view: Option<Vec<usize>>,
}

/// Clearances tried when planning, as fractions of the configured one, largest first: where the robot
/// already stands closer than that to something (after a push, where a walk stopped short, in a tight
/// room), less.
const CLEARANCE_FRACTIONS: [f64; 3] = [1.0, 0.5, 0.0];

/// Points higher than this are ignored when growing the seen box (m): ceilings, not rooms.
const SEEN_MAX_HEIGHT: f32 = 2.5;

impl WorldModel {
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
        let r = nalgebra::Vector2::repeat(config.robot.radius);
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
                config.robot.radius,
            ));
            obstacles.extend(super::grid::stationary_obstacles(
                grid,
                &self.prisms,
                robot,
                config.robot.radius,
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
            radius: config.robot.radius + clearance,
            height: config.robot.height,
        };
        let grow = nalgebra::Vector2::repeat(clearance);
        let bounds =
            Bounds::new(bounds.min() - grow, bounds.max() + grow).map_err(|e| e.to_string())?;
        Validity::new(cylinder, bounds, obstacles, config.validity).map_err(|e| e.to_string())
    }

    /// Replaces the obstacles with a new detection, remembering what is out of view (Tamura 3.2.3): a
    /// new obstacle overlapping an old one grows to cover it unless the new look saw floor where the old
    /// part stood (one object seen in parts), and an old obstacle no new one absorbed this way is kept
    /// unless the new look saw floor inside it (it was moved away). An old obstacle that only touches
    /// what a new one grew over (the end of a wall beside its base, seen again) is judged on its own
    /// floor, not dropped for touching it.
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
        let radius = config.robot.radius;
        self.prisms.retain(|p| !prism_covers_disc(p, robot, radius));
        let seen_floor = |old: &Prism, new: Option<&Prism>| {
            // A box test first: most of the look's floor points lie far from any one obstacle.
            let (lo, hi) = footprint_box(old);
            floor_points
                .iter_valid()
                .map(|(_, p, _)| Point2::new(f64::from(p.x), f64::from(p.y)))
                .filter(|q| q.x >= lo.x && q.y >= lo.y && q.x <= hi.x && q.y <= hi.y)
                .filter(|q| old.contains_xy(q) && !new.is_some_and(|n| n.contains_xy(q)))
                .take(config.forget_after_floor_points)
                .count()
                >= config.forget_after_floor_points
        };
        let floor_between = |a: &Prism, b: &Prism| self.floor_between(a, b, floor_points, config);
        // Cells near where something was ever seen moving: their returns may be a person who
        // stopped there and walked on (the grid clears a stationary cell only when crossed twice in a
        // row, which a look-around's panning views rarely do).
        let moved = self.grid.as_ref().and_then(|g| {
            super::grid::near_motion(g.geometry(), &self.last_motion, g.config().rest_radius)
        });
        let overlaps = |a: &Prism, b: &Prism| a.id == b.id || a.footprint_iou(b) > 0.0;
        let settled = |p: &Prism| self.settled.contains(&p.id);
        let mut current: Vec<Prism> = Vec::with_capacity(detected.len() + self.prisms.len());
        let mut absorbed = Vec::new();
        for new in detected {
            let mut merged = new.clone();
            for old in self.prisms.iter().filter(|old| overlaps(old, &new)) {
                if self.pushed.contains(&old.id) && !settled(old) {
                    // A pushed object seen again: where it is now is what the look shows, under its
                    // own id (its verdict stays with it; the look numbers its detections afresh).
                    merged.id = old.id;
                } else if settled(old) {
                    merged = old.merged_with(&merged);
                } else if !seen_floor(old, Some(&new)) && !floor_between(&merged, old) {
                    merged = merged.merged_with(old);
                    if self.movable.contains(&old.id) {
                        merged.id = old.id;
                    }
                } else {
                    // Two obstacles side by side: the old one stays or goes on its own.
                    continue;
                }
                absorbed.push(old.id);
            }
            current.push(merged);
        }
        // A pushed object seen again is no longer a prediction.
        self.pushed.retain(|id| !absorbed.contains(id));
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
        self.merge_fragments(floor_points, config);
        // Where each obstacle the look showed was seen from.
        for prism in &self.prisms {
            let shown = outlines.iter().any(|o| {
                nudge_perception::prism::convex_intersection_area(o, &prism.footprint) > 0.0
            });
            let from = self.seen_from.entry(prism.id).or_default();
            if shown && !from.iter().any(|p| (p - robot).norm() < SAME_PLACE) {
                from.push(*robot);
            }
        }
    }

    /// How much of `prism`'s outline has been seen (0 to 1), and from where: the share of points
    /// every grid cell along its footprint's edges whose cell a cell and a half outwards was seen
    /// (its floor, or a return there), or lies inside another obstacle (it cannot be seen and does not
    /// matter); and the places the looks that showed it were taken from.
    pub fn outline_seen(&self, prism: &Prism) -> (f64, &[Point2<f64>]) {
        let from = self.seen_from.get(&prism.id).map_or(&[][..], Vec::as_slice);
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
    fn grid_holds_returns(&self, prism: &Prism, moved: Option<&[bool]>) -> bool {
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
        let half = geometry.resolution() / 2.0;
        let (lo, hi) = footprint_box(prism);
        let (Some(a), Some(b)) = (geometry.cell_of(lo), geometry.cell_of(hi)) else {
            return Vec::new();
        };
        let mut out = Vec::new();
        for y in a.y..=b.y {
            for x in a.x..=b.x {
                let cell = nudge_perception::grid::CellIndex { x, y };
                if super::grid::overlaps_cell(prism, geometry.centre(cell), half)
                    && let Some(i) = geometry.index(cell)
                {
                    out.push((i, grid.class(cell)));
                }
            }
        }
        out
    }

    /// Whether the grid holds every cell `prism`'s footprint overlaps Free: it saw floor all over
    /// where the obstacle was (a sliver left where an object stood before a push, too small to hold
    /// the look's floor points that forget larger ones).
    fn grid_sees_free(&self, prism: &Prism) -> bool {
        let classes = self.cells_under(prism);
        !classes.is_empty()
            && classes
                .iter()
                .all(|(_, c)| *c == Some(nudge_perception::grid::CellClass::Free))
    }

    /// Whether floor was seen where the hull of `a` and `b` covers neither (two wall runs meeting at a
    /// corner, seen from inside it; two chairs side by side): they are two things, and their hull would
    /// be a phantom over free floor.
    fn floor_between(
        &self,
        a: &Prism,
        b: &Prism,
        floor_points: &ColourCloud,
        config: &RunConfig,
    ) -> bool {
        let hull = a.merged_with(b);
        let outside_both = |q: &Point2<f64>| !a.contains_xy(q) && !b.contains_xy(q);
        let (lo, hi) = footprint_box(&hull);
        let in_gap = |q: &Point2<f64>| {
            q.x >= lo.x
                && q.y >= lo.y
                && q.x <= hi.x
                && q.y <= hi.y
                && hull.contains_xy(q)
                && outside_both(q)
        };
        let n = config.forget_after_floor_points;
        floor_points
            .iter_valid()
            .map(|(_, p, _)| Point2::new(f64::from(p.x), f64::from(p.y)))
            .filter(|q| in_gap(q))
            .take(n)
            .count()
            >= n
            || self
                .grid
                .as_ref()
                .is_some_and(|g| free_area_where(g, (lo, hi), in_gap) >= MERGE_BLOCKING_FREE_AREA)
    }

    /// Merges obstacles that are pieces of one thing: footprints within two grid cells of each other,
    /// height ranges that meet, and no floor seen between them (see [`Self::floor_between`]). A
    /// surface seen obliquely or from far (a wall, a table's top at 4 m) comes out of perception in
    /// pieces whose gaps are where its points thinned out; planning around the pieces is the same as
    /// around the whole, but a push of one piece "runs into" the next. Two obstacles that both carry a
    /// push test's verdict stay apart; a merge keeps the id of the one that has a verdict (else the
    /// older id).
    fn merge_fragments(&mut self, floor_points: &ColourCloud, config: &RunConfig) {
        // Two cells: a hull's edge runs a cell off the face it was made from, on either side.
        let gap = 2.0
            * self
                .grid
                .as_ref()
                .map_or(MERGE_GAP_FALLBACK, |g| g.geometry().resolution());
        let judged = |p: &Prism| self.settled.contains(&p.id) || self.movable.contains(&p.id);
        loop {
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
                        || !oa.heights_overlap(ob)
                        || !oa.aabb().inflated(SURFACE_GAP).overlaps(ob.aabb())
                    {
                        continue;
                    }
                    let apart = oa.distance_to_obstacle(ob);
                    let hull = a.merged_with(b);
                    // Their hull adds no more than a strip of the surface gap along it: pieces of one
                    // run, not two walls meeting at a corner (whose hull is a triangle of floor).
                    let added = area(&hull.footprint) - area(&a.footprint) - area(&b.footprint);
                    if added > SURFACE_GAP * extent(&hull) / 2.0 {
                        continue;
                    }
                    // Pieces of one object's surfaces (a table's edge seen from 4 m, floor showing
                    // under its top): points within the sensor's spacing, and together no larger
                    // than an object to push (a chair beside a wall stays a chair).
                    let one_surface = apart <= SURFACE_GAP
                        && extent(&hull) <= config.max_candidate_extent
                        && points_within(a, b, SURFACE_GAP);
                    let touching =
                        || apart <= gap && !self.floor_between(a, b, floor_points, config);
                    if !one_surface && !touching() {
                        continue;
                    }
                    pair = Some((i, j));
                    break 'search;
                }
            }
            let Some((i, j)) = pair else {
                return;
            };
            let b = self.prisms.remove(j);
            let a = &self.prisms[i];
            let id = match (judged(a), judged(&b)) {
                (true, _) => a.id,
                (false, true) => b.id,
                _ => a.id.min(b.id),
            };
            let mut merged = a.merged_with(&b);
            merged.id = id;
            for (_, p, c) in b.points.iter_valid() {
                merged.points.push(p, c);
            }
            self.prisms[i] = merged;
            self.pushed.remove(&b.id);
            // The merged obstacle was seen from wherever either piece was.
            let places = self.seen_from.remove(&b.id).unwrap_or_default();
            let from = self.seen_from.entry(id).or_default();
            for p in places {
                if !from.iter().any(|q| (q - p).norm() < SAME_PLACE) {
                    from.push(p);
                }
            }
        }
    }

    /// Moves `id`'s obstacle by a measured planar displacement (a confirmed push): its old footprint is
    /// free now even where no background shows behind it.
    pub fn displace(&mut self, id: nudge_perception::ObjectId, offset: nalgebra::Vector2<f64>) {
        let motion = Isometry3::translation(offset.x, offset.y, 0.0);
        for p in self.prisms.iter_mut().filter(|p| p.id == id) {
            *p = p.transformed(&motion);
        }
        self.pushed.insert(id);
    }

    /// Whether `prism` lies at the edge of everything seen: a wall, not an object to push.
    pub fn is_structure(&self, prism: &Prism, config: &RunConfig) -> bool {
        let Some((lo, hi)) = self.seen else {
            return false;
        };
        let m = config.structure_margin;
        prism
            .footprint
            .iter()
            .any(|p| p.x < lo.x + m || p.y < lo.y + m || p.x > hi.x - m || p.y > hi.y - m)
    }

    /// How far behind `prism` its own shadow reaches on the floor (m), as seen from the look nearest
    /// it: the floor it hides from an eye at `eye_height` (see [`nudge_motion::shadow_length`]).
    pub fn own_shadow(&self, prism: &Prism, eye_height: f64) -> f64 {
        let far_side = |look: &Point2<f64>| {
            prism
                .footprint
                .iter()
                .map(|v| (v - look).norm())
                .fold(0.0, f64::max)
        };
        self.looks
            .iter()
            .map(far_side)
            .min_by(f64::total_cmp)
            .map_or(0.0, |d| {
                nudge_motion::shadow_length(d, prism.z_max, eye_height)
            })
    }

    /// The problem from `robot` to the goal.
    pub fn problem(robot: &Point2<f64>, config: &RunConfig) -> Result<Problem, String> {
        Problem::new(*robot, config.goal, config.goal_tolerance).map_err(|e| e.to_string())
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
fn area(f: &[Point2<f64>]) -> f64 {
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

/// Largest distance between two footprint vertices (m).
fn extent(prism: &Prism) -> f64 {
    let f = &prism.footprint;
    f.iter()
        .flat_map(|a| f.iter().map(move |b| (a - b).norm()))
        .fold(0.0, f64::max)
}

/// Looks taken this close together (m) were taken from one place.
const SAME_PLACE: f64 = 0.05;

/// Gap (m) within which two pieces may be one thing when there is no grid to say its cell size.
const MERGE_GAP_FALLBACK: f64 = 0.05;

/// Free floor (m²) the grid saw between two obstacles that keeps them from merging: a few cells, more
/// than the slivers a hull adds along two overlapping views of one straight face.
const MERGE_BLOCKING_FREE_AREA: f64 = 0.02;

/// Whether the robot's disc at `centre` overlaps `prism`'s footprint by more than a few centimetres.
fn prism_covers_disc(prism: &Prism, centre: &Point2<f64>, radius: f64) -> bool {
    let inner = radius * 0.5;
    prism.contains_xy(centre) || prism.footprint.iter().any(|v| (v - centre).norm() < inner)
}

/// Corners of the box around `prism`'s footprint.
fn footprint_box(prism: &Prism) -> (Point2<f64>, Point2<f64>) {
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
    fn prism(id: u32, x0: f64, y0: f64, x1: f64, y1: f64) -> Prism {
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

    /// The run's configuration for the paper's robot and a goal at `goal` (0.2 m tolerance).
    fn config_to(goal: Point2<f64>) -> RunConfig {
        let robot_shape = nudge_motion::RobotCylinder {
            radius: 0.35,
            height: 1.54,
        };
        RunConfig::new(robot_shape, goal, 0.2, 1)
    }

    /// Floor points on a 2 cm grid over `[x0, x1] × [y0, y1]`.
    fn floor(x0: f64, y0: f64, x1: f64, y1: f64) -> ColourCloud {
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
        world.settled.insert(ObjectId(2));
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
        world.movable.insert(ObjectId(9));
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
        world.displace(ObjectId(9), nalgebra::Vector2::new(0.0, -0.6));
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
        assert!(world.pushed.is_empty());
        // Seen again in part: now it grows over what was seen before, as any object seen in parts.
        let part = prism(32, 2.85, 1.3, 3.35, 1.55);
        world.remember(vec![part], &no_floor, &robot, &config);
        assert_eq!(world.prisms.len(), 1);
        assert!(world.prisms[0].contains_xy(&Point2::new(3.0, 1.1)));
    }

    /// A prism `[x0, x1] × [y0, y1]` up to `z` whose points cover its top at 2 cm spacing.
    fn solid(id: u32, (x0, y0, x1, y1): (f64, f64, f64, f64), z: f64) -> Prism {
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
        world.settled.insert(ObjectId(3));
        world.movable.insert(ObjectId(4));
        world.merge_fragments(&floor(0.1, 0.1, 0.2, 0.2), &config);
        assert_eq!(world.prisms.len(), 2);
        let mut one = WorldModel {
            prisms: vec![solid(2, (2.0, 1.0, 2.5, 1.5), 0.8), b],
            ..WorldModel::default()
        };
        one.movable.insert(ObjectId(4));
        one.merge_fragments(&floor(0.1, 0.1, 0.2, 0.2), &config);
        assert_eq!(one.prisms.len(), 1);
        assert_eq!(one.prisms[0].id, ObjectId(4));
    }

    #[test]
    fn an_obstacle_seen_from_one_side_has_a_quarter_of_its_outline_seen() {
        // Invariant: the outline seen is the share of a footprint's edges whose floor just outside was seen, or that lie against another obstacle; a box whose west side alone was seen has a quarter of it, with a neighbour against its east side a half, with everything round it seen all of it; the places it was seen from are those of the looks that showed it.
        let config = config_to(Point2::new(5.0, 1.0));
        let geometry =
            nudge_perception::grid::GridGeometry::new(Point2::origin(), [4.0, 2.0], 0.05)
                .expect("a grid");
        let grid = ObstacleGrid::new(geometry, config.grid.rules);
        let mut world = WorldModel {
            memory: SeenMemory::new(geometry.len()),
            grid: Some(grid),
            ..WorldModel::default()
        };
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
}
