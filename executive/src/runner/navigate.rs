//! Planning paths and walking them.

use nalgebra::{Point2, Vector2};
use nudge_motion::{Path, Problem, StateValidity, Validity, certainly_unreachable};

use super::world::WorldModel;
use super::{Interrupt, Runner};
use crate::event::Event;
use crate::push_test::PushIntent;
use crate::view::Viewpoint;

/// `a` wrapped into [-π, π).
pub(super) fn wrap(a: f64) -> f64 {
    (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
}
use crate::record::Observer;
use crate::robot::{ActionStatus, Robot, WalkOutcome};

/// Farthest the robot steps to get clear of an obstacle that seems to overlap it (m).
const ESCAPE_RADIUS: f64 = 0.25;

/// Where a push test's stroke must lie from the body for the arm to make it (m).
struct Reach {
    /// The farthest ahead of the body axis the stroke may end.
    ahead: f64,
    /// The arm's sideways reach, right then left.
    side: (f64, f64),
}

impl Reach {
    /// Whether a body stopped at `at`, short of the stand pose `stand` of a push along `d` whose
    /// hand meets the object at `contact`, can make the push test from there once turned to face
    /// `d`: it has not passed the stand pose, the stroke ends within the arm's reach ahead, and its
    /// line lies within the arm's reach to the side (each within
    /// [`super::stroke::LATERAL_SLACK`], what the arm absorbs of a missed pose).
    fn pushes_from(
        &self,
        at: &Point2<f64>,
        stand: &Point2<f64>,
        d: &Vector2<f64>,
        contact: &Point2<f64>,
    ) -> bool {
        // The contact to the body's left when it faces `d`.
        let side = d.perp(&(contact - at));
        (at - stand).dot(d) <= super::stroke::LATERAL_SLACK
            && (contact - at).dot(d) <= self.ahead
            && super::stroke::reaches_lateral(side, self.side)
    }
}

/// The free position nearest `here` within [`ESCAPE_RADIUS`], searched on rings 5 cm apart with 32
/// bearings each (deterministic), if any.
pub(super) fn nearest_free(
    here: &Point2<f64>,
    validity: &dyn StateValidity,
) -> Option<Point2<f64>> {
    const RINGS: usize = 5;
    const BEARINGS: usize = 32;
    (1..=RINGS).find_map(|ring| {
        let r = ESCAPE_RADIUS * ring as f64 / RINGS as f64;
        (0..BEARINGS)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / BEARINGS as f64;
                here + Vector2::new(a.cos(), a.sin()) * r
            })
            .find(|p| validity.is_free(p))
    })
}

/// The point `distance` from `here` (one of 32 bearings, deterministic) farthest from every obstacle
/// of `validity`: a step straight away from what the robot stands against.
fn step_away(here: &Point2<f64>, validity: &Validity, distance: f64) -> Point2<f64> {
    const BEARINGS: usize = 32;
    (0..BEARINGS)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / BEARINGS as f64;
            here + Vector2::new(a.cos(), a.sin()) * distance
        })
        .filter(|p| validity.walls().signed_inner_distance(p) >= validity.robot().radius)
        .map(|p| (room(validity, &p), p))
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map_or(*here, |(_, p)| p)
}

/// The point `distance` straight behind a robot at `here` facing `heading` (rad), if it lies inside the
/// walls and no nearer any obstacle of `validity` than `here` does. The base faces the way it walks,
/// so what stopped a walk touches the front half of the body; a step straight back moves away from
/// every point of that half, wherever the obstacles place the thing.
fn step_back(
    here: &Point2<f64>,
    heading: f64,
    validity: &Validity,
    distance: f64,
) -> Option<Point2<f64>> {
    let back = here - Vector2::new(heading.cos(), heading.sin()) * distance;
    let inside = validity.walls().signed_inner_distance(&back) >= validity.robot().radius;
    let farther = validity.is_free(&back) || room(validity, &back) >= room(validity, here);
    (inside && farther).then_some(back)
}

/// Distance (m) from `p` to the nearest obstacle of `validity` (infinite with none).
fn room(validity: &Validity, p: &Point2<f64>) -> f64 {
    validity
        .obstacles()
        .iter()
        .map(|o| o.distance_to_point(p))
        .fold(f64::INFINITY, f64::min)
}

/// `path` (planned from `start`) walked from `here` through `from`: the steps clear of what the robot
/// stood against, then the path.
fn joined(
    here: Point2<f64>,
    from: Point2<f64>,
    start: Point2<f64>,
    path: Path,
) -> Result<Path, String> {
    if start == here {
        return Ok(path);
    }
    let mut waypoints = vec![here];
    if from != here && from != start {
        waypoints.push(from);
    }
    waypoints.extend_from_slice(path.waypoints());
    Path::new(waypoints).map_err(|e| e.to_string())
}

/// How a watched walk ended.
enum Watched {
    /// The walk itself ended.
    Walked(WalkOutcome),
    /// The grid flagged the path (the walk is still going).
    Replan(String),
    /// The path ahead runs over floor the walking camera will not see before the robot is on it,
    /// this far ahead (m) (the walk is still going, or never started).
    Unseen(f64),
}

/// A robot within this distance (m) of where its last walk ended blocked still stands there.
const STUCK_DISTANCE: f64 = 0.02;

/// Extra distance beyond the goal tolerance within which an arrival counts (m): the walk's own error.
const ARRIVAL_SLACK: f64 = 0.05;

impl<R: Robot, O: Observer> Runner<R, O> {
    /// Where the robot stands (map frame).
    pub(super) fn position(&mut self) -> Result<Point2<f64>, Interrupt> {
        let pose = self.robot.base_pose()?.value;
        Ok(Point2::from(pose.translation.vector))
    }

    /// Plans a path from the robot to the goal among the latest obstacles.
    pub(crate) fn plan_path(&mut self) -> Event {
        let here = match self.position() {
            Ok(p) => p,
            Err(i) => return i.into(),
        };
        match self.plan_to(here, None) {
            Ok(path) => {
                let stamp = self.robot.now();
                self.observer.path(stamp, path.waypoints());
                self.watch_path(path.waypoints());
                let length = path.length();
                self.world.path = Some(path);
                Event::PathFound { length }
            }
            Err(reason) => {
                self.world.path = None;
                Event::NoPath { reason }
            }
        }
    }

    /// A shortcut path from `here` to the goal, or to `target` within 3 cm when given.
    fn plan_to(&mut self, here: Point2<f64>, target: Option<Point2<f64>>) -> Result<Path, String> {
        // A robot standing where its last walk ended blocked is within the base's safety margin of
        // something in front of it, which the obstacles may place a few centimetres off: a path that
        // leaves along it is blocked again at once. It first steps back, away from what stopped it.
        if let Some(at) = self.blocked_here(&here) {
            let validity = self.world.validity(&here, &self.config)?;
            let from = step_back(&here, at.rotation.angle(), &validity, self.config.clearance)
                .unwrap_or_else(|| step_away(&here, &validity, self.config.clearance));
            if let Ok(path) = self.plan_from(here, from, target) {
                return Ok(path);
            }
        }
        self.plan_from(here, here, target)
    }

    /// A shortcut path from `here` through `from` (where it starts planning) to the goal, or to
    /// `target` within 3 cm when given.
    fn plan_from(
        &mut self,
        here: Point2<f64>,
        from: Point2<f64>,
        target: Option<Point2<f64>>,
    ) -> Result<Path, String> {
        // Clearances from the largest down to the first at which the robot stands free and, when
        // walking to a target (a stand pose planned with less clearance), the target is free too: a
        // robot standing near something (after a push, where a walk stopped short) still plans its
        // way with the most clearance that has one, stepping clear first, rather than hugging every
        // obstacle on the way at the clearance it stands at. Below that first one nothing is tried:
        // a way that needs less clearance than the robot has is a way through a gap too tight.
        let mut levels = Vec::new();
        for validity in self.world.validities(&from, &self.config) {
            let validity = validity?;
            let stands = validity.is_free(&from) && target.is_none_or(|t| validity.is_free(&t));
            levels.push(validity);
            if stands {
                break;
            }
        }
        let Some((least, more)) = levels.split_last() else {
            return Err("no planning bounds".into());
        };
        for validity in more {
            if target.is_some_and(|t| !validity.is_free(&t)) {
                continue;
            }
            // The step clear is walked at the clearance the robot stands at.
            let start = nearest_free(&from, validity).filter(|s| least.motion_free(&from, s));
            if let Some(start) = start
                && let Ok(path) = self.solve(start, target, validity)
            {
                return joined(here, from, start, path);
            }
        }
        // Where an obstacle seems to overlap the robot (someone stepped up to it, or a hull is a few
        // centimetres generous), plan from the nearest free spot and step there first.
        let start = if least.is_free(&from) {
            from
        } else {
            nearest_free(&from, least).ok_or_else(|| {
                format!("the start is in collision and no free spot lies within {ESCAPE_RADIUS} m")
            })?
        };
        let path = self.solve(start, target, least)?;
        joined(here, from, start, path)
    }

    /// A shortcut path from `start` to the goal, or to `target` within 3 cm when given, among the
    /// obstacles of `validity`.
    fn solve(
        &mut self,
        start: Point2<f64>,
        target: Option<Point2<f64>>,
        validity: &Validity,
    ) -> Result<Path, String> {
        let problem = match target {
            Some(t) => Problem::new(start, t, 0.03).map_err(|e| e.to_string())?,
            None => WorldModel::problem(&start, &self.config)?,
        };
        // A flood fill proves most "no path" cases at once; the planner would spend its whole budget.
        if certainly_unreachable(validity, &problem.start(), problem.goal()) {
            return Err(
                "no free way joins the start to the goal region (flood fill over 5 cm cells)"
                    .into(),
            );
        }
        let (path, _, tree) = self.config.planner.solve_recorded(
            &problem,
            validity,
            self.config.budget,
            &mut self.rng,
        );
        let stamp = self.robot.now();
        self.observer.tree(stamp, &tree.edges);
        let path = path.map_err(|e| e.to_string())?;
        Ok(self.config.shortcut.shorten(&path, validity, &mut self.rng))
    }

    /// Walks from where the robot stands to `target`, or into the goal region when `None`, on a
    /// path planned among the latest obstacles, watching as every walk does (people in the way
    /// are waited for; a cell on the path the grid sees turn into an obstacle stops it); whether it
    /// got there. Leaves the run's own path to the goal as it was.
    pub(super) fn walk_to(&mut self, target: Option<Point2<f64>>) -> Result<bool, Interrupt> {
        let here = self.position()?;
        let Ok(path) = self.plan_to(here, target) else {
            return Ok(false);
        };
        let stamp = self.robot.now();
        self.observer.path(stamp, path.waypoints());
        self.watch_path(path.waypoints());
        let arrived = match self.walk_watching(path.waypoints(), false, true)? {
            Watched::Walked(outcome) => matches!(outcome, WalkOutcome::Arrived),
            Watched::Replan(_) | Watched::Unseen(_) => {
                self.robot.stop_walk()?;
                self.wait(|r| r.walk_status())?;
                false
            }
        };
        if let Some(path) = self.world.path.clone() {
            self.watch_path(path.waypoints());
        }
        Ok(arrived)
    }

    /// Walks the planned path to the goal; with `stop_at_unseen`, stops before floor under the path
    /// that the walking camera will not see in time.
    pub(crate) fn follow_path(&mut self, stop_at_unseen: bool) -> Event {
        let Some(path) = self.world.path.clone() else {
            return Event::PathInvalidated {
                reason: "no path to follow".into(),
            };
        };
        // A walk stopped on the way (before unseen floor) goes on from where the robot stands.
        let here = match self.position() {
            Ok(p) => p,
            Err(i) => return i.into(),
        };
        let rest = super::unseen::rest_of_path(path.waypoints(), here);
        match self.walk_watching(&rest, stop_at_unseen, true) {
            Ok(Watched::Replan(reason)) => Event::PathInvalidated { reason },
            Ok(Watched::Unseen(distance)) => Event::UnseenAhead { distance },
            Ok(Watched::Walked(WalkOutcome::Arrived)) => match self.position() {
                Ok(p)
                    if (p - self.config.goal).norm()
                        <= self.config.goal_tolerance + ARRIVAL_SLACK =>
                {
                    match self.recheck_at_goal() {
                        Ok(true) => Event::Arrived,
                        Ok(false) => Event::PathInvalidated {
                            reason: "walked off the goal to look closer and did not get back"
                                .into(),
                        },
                        Err(i) => i.into(),
                    }
                }
                Ok(p) => Event::PathInvalidated {
                    reason: format!(
                        "the walk ended at ({:.2}, {:.2}), outside the goal region",
                        p.x, p.y
                    ),
                },
                Err(i) => i.into(),
            },
            Ok(Watched::Walked(WalkOutcome::Blocked { .. })) => Event::WalkBlocked,
            Ok(Watched::Walked(WalkOutcome::Stopped)) => Event::PathInvalidated {
                reason: "the walk was stopped".into(),
            },
            Err(i) => i.into(),
        }
    }

    /// Walks `waypoints` like [`Self::walk`], taking a frame into the grid every watch period; stops
    /// watching (the walk goes on until the machine stops it) when the grid flags the path, or, with
    /// `stop_at_unseen`, when the path ahead runs over floor the walking camera will not see in time.
    fn walk_watching(
        &mut self,
        waypoints: &[Point2<f64>],
        stop_at_unseen: bool,
        heed_flags: bool,
    ) -> Result<Watched, Interrupt> {
        let rest = waypoints.get(1..).unwrap_or_default();
        if rest.is_empty() {
            return Ok(Watched::Walked(WalkOutcome::Arrived));
        }
        if stop_at_unseen && let Some(stop) = self.check_unseen_ahead(waypoints)? {
            return Ok(stop);
        }
        self.robot.start_walk(rest)?;
        // Someone who stopped the base is waited for while the walk is young: a walk stopped again
        // and again by people standing in its way (they yield to the robot as it yields to them)
        // ends blocked, and the machine looks and plans anew.
        let walk_started = self.robot.elapsed();
        let mut next_frame = self.robot.now() + self.config.grid.watch_period;
        loop {
            if let ActionStatus::Done(outcome) = self.robot.walk_status()? {
                // A walk the base stopped short, with someone moving just ahead, was blocked by
                // them, not by what it walks to: wait for them as the search space does, then walk
                // on (Miyazaki et al.: stop, let them pass, return to the path).
                if matches!(outcome, WalkOutcome::Blocked { .. })
                    && self.people_about()
                    && self.robot.elapsed() - walk_started < super::search_space::PERSON_WAIT
                    && self.blocked_by_someone(waypoints)?
                {
                    if let Some(end) = self.let_them_pass(waypoints)? {
                        return Ok(end);
                    }
                    next_frame = self.robot.now() + self.config.grid.watch_period;
                    continue;
                }
                self.note_blocked(&outcome);
                return Ok(Watched::Walked(outcome));
            }
            if self.robot.now() >= next_frame {
                next_frame += self.config.grid.watch_period;
                self.take_frame(true)?;
                self.publish_grid();
                // Miyazaki's search space: someone moving in the way ahead stops the walk until
                // they have passed (see `search_space.rs`).
                if self.people_about() {
                    let here = self.position()?;
                    let ahead = super::unseen::rest_of_path(waypoints, here);
                    if self.search_space_occupied(&ahead) {
                        if let Some(end) = self.let_them_pass(waypoints)? {
                            return Ok(end);
                        }
                        next_frame = self.robot.now() + self.config.grid.watch_period;
                    }
                }
                if heed_flags && let Some(reason) = self.replan_reason() {
                    return Ok(Watched::Replan(reason));
                }
                if stop_at_unseen && let Some(stop) = self.check_unseen_ahead(waypoints)? {
                    return Ok(stop);
                }
            }
            self.tick()?;
        }
    }

    /// Whether a fresh frame shows something moving in the search space ahead along `waypoints`
    /// from where the robot stands (see [`Self::search_space_occupied`]).
    fn blocked_by_someone(&mut self, waypoints: &[Point2<f64>]) -> Result<bool, Interrupt> {
        self.take_frame(true)?;
        let here = self.position()?;
        let ahead = super::unseen::rest_of_path(waypoints, here);
        Ok(self.search_space_occupied(&ahead))
    }

    /// Waits for the way ahead along `waypoints` to clear ([`Self::wait_for_clear_way`]) and walks on
    /// from where the robot stands: `None` once it walks again, else how the watched walk ends (planned
    /// anew after [`super::search_space::PERSON_WAIT`], or arrived with nothing left to walk).
    fn let_them_pass(&mut self, waypoints: &[Point2<f64>]) -> Result<Option<Watched>, Interrupt> {
        if !self.wait_for_clear_way(waypoints)? {
            return Ok(Some(Watched::Replan(format!(
                "someone moving stood in the way ahead for {:.0} s",
                super::search_space::PERSON_WAIT
            ))));
        }
        let here = self.position()?;
        let rest = super::unseen::rest_of_path(waypoints, here);
        if rest.len() < 2 {
            return Ok(Some(Watched::Walked(WalkOutcome::Arrived)));
        }
        self.robot.start_walk(&rest[1..])?;
        Ok(None)
    }

    /// Stops the walk along `waypoints` and waits, taking a frame into the grid every watch period,
    /// until the search space ahead is clear (true) or [`super::search_space::PERSON_WAIT`] has
    /// passed (false).
    fn wait_for_clear_way(&mut self, waypoints: &[Point2<f64>]) -> Result<bool, Interrupt> {
        self.robot.stop_walk()?;
        self.wait(|r| r.walk_status())?;
        let started = self.robot.now();
        let mut next_frame = started + self.config.grid.watch_period;
        loop {
            if self.robot.now() >= next_frame {
                next_frame += self.config.grid.watch_period;
                self.take_frame(true)?;
                let here = self.position()?;
                let ahead = super::unseen::rest_of_path(waypoints, here);
                if !self.search_space_occupied(&ahead) {
                    return Ok(true);
                }
                if self.robot.now() - started >= super::search_space::PERSON_WAIT {
                    return Ok(false);
                }
            }
            self.tick()?;
        }
    }

    /// Whether the walk must stop for unseen floor ahead: when there is some, the head first glances
    /// at it (one frame, the walk going on); what the glance shows of it is seen, and something
    /// standing on the path in it stops the walk as a flagged path does.
    fn check_unseen_ahead(
        &mut self,
        waypoints: &[Point2<f64>],
    ) -> Result<Option<Watched>, Interrupt> {
        let Some((_, at)) = self.unseen_ahead(waypoints)? else {
            return Ok(None);
        };
        if let Some(reason) = self.glance(waypoints, at)? {
            return Ok(Some(Watched::Replan(reason)));
        }
        Ok(self
            .unseen_ahead(waypoints)?
            .map(|(distance, _)| Watched::Unseen(distance)))
    }

    /// Points the head at `at` for one frame and back to the walking view: its floor counts as seen
    /// (the grid leaves steep frames out); returns why the walk must stop when obstacle points stand
    /// within the robot's radius of the path ahead.
    fn glance(
        &mut self,
        waypoints: &[Point2<f64>],
        at: Point2<f64>,
    ) -> Result<Option<String>, Interrupt> {
        let base = self.robot.base_pose()?.value;
        let here = Point2::from(base.translation.vector);
        let rel = at - here;
        let look = &self.config.perception.look_around;
        let widest = look
            .pans_deg
            .iter()
            .fold(0.0f64, |m, p| m.max(p.abs()))
            .to_radians();
        let steepest = look
            .tilts_deg
            .iter()
            .fold(0.0f64, |m, t| m.max(*t))
            .to_radians();
        let pan = wrap(rel.y.atan2(rel.x) - base.rotation.angle()).clamp(-widest, widest);
        let eye = self.config.model.head.height;
        let tilt = eye
            .atan2(rel.norm().max(0.1))
            .clamp(self.config.grid.watch_tilt, steepest);
        self.robot.start_point_head(pan, tilt)?;
        self.wait(|r| r.head_status())?;
        let cloud = self.take_frame(true)?;
        self.robot
            .start_point_head(0.0, self.config.grid.watch_tilt)?;
        self.wait(|r| r.head_status())?;
        let (Some(floor), Some(grid)) = (&self.world.floor, &self.world.grid) else {
            return Ok(None);
        };
        let (floor_points, others) = floor.split(&cloud.to_map());
        let geometry = *grid.geometry();
        self.world.memory.saw(&geometry, &floor_points);
        let here = self.position()?;
        let rest = super::unseen::rest_of_path(waypoints, here);
        let (low, high) = (
            self.config.validity.step_height,
            self.config.model.body.height,
        );
        let radius = self.config.model.body.radius;
        let on_path = others
            .iter_valid()
            .filter(|(_, p, _)| f64::from(p.z) > low && f64::from(p.z) < high)
            .filter(|(_, p, _)| {
                let q = Point2::new(f64::from(p.x), f64::from(p.y));
                (q - here).norm() > radius && super::unseen::distance_to_path(&rest, &q) < radius
            })
            .count();
        Ok((on_path >= self.config.forget_after_floor_points).then(|| {
            format!("a glance at the unseen floor ahead saw {on_path} obstacle points on the path")
        }))
    }

    /// How far ahead along `waypoints` (from where the robot stands) the first unseen floor lies that
    /// the walking camera will not see before the robot is on it, if any.
    ///
    /// The walking camera (head tilted [`GridSetup::watch_tilt`](super::config::GridSetup::watch_tilt)
    /// down) sees the floor from [`CameraModel::floor_near`](super::config::CameraModel::floor_near)
    /// of that tilt onwards; a frame a watch period later the robot is one period's walk further. Floor
    /// nearer than that which is still unseen will not be seen before the robot stands on it (it lies
    /// round a corner, past a door's jamb). Floor nearer than what a look-around shows is left out: no
    /// look from here would show it either. The band is the inner half of the body's width: what the
    /// outer half sweeps, the grid's watch of the path flags. Unseen floor counts once it adds up to
    /// the least area worth a look ([`Self::min_gain`]): a strip across the robot's width, not the
    /// odd cell in a leg's shadow.
    fn unseen_ahead(
        &mut self,
        waypoints: &[Point2<f64>],
    ) -> Result<Option<(f64, Point2<f64>)>, Interrupt> {
        let here = self.position()?;
        let Some(grid) = self.world.grid.as_ref() else {
            return Ok(None);
        };
        let steepest = self
            .config
            .perception
            .look_around
            .tilts_deg
            .iter()
            .fold(0.0f64, |m, t| m.max(t.to_radians()));
        let band = 0.5 * self.config.model.body.radius;
        // Cells within the band of a point `near` along the path may lie nearer than `near`.
        let near = self.config.floor_near(steepest) + band;
        let far = self.config.floor_near(self.config.grid.watch_tilt)
            + self.config.model.body.walk_speed * self.config.grid.watch_period;
        let rest = super::unseen::rest_of_path(waypoints, here);
        Ok(super::unseen::first_unseen_along(
            grid,
            &self.world.memory,
            &self.world.prisms,
            &rest,
            (near, far),
            band,
            self.min_gain(),
        )
        .map(|d| (d, super::unseen::point_along(&rest, d))))
    }

    /// Stands for [`GridSetup::settle_time`](super::config::GridSetup::settle_time), taking a frame
    /// into the grid every [`GridSetup::settle_period`](super::config::GridSetup::settle_period) with
    /// the head where the walk left it. The passive rules tell a thing that walks on from one left
    /// behind (movable by addition) or one that stands only from the same place in frames close in
    /// time; a look-around's panning views never give them that.
    pub(crate) fn watch_ahead(&mut self) -> Result<(), Interrupt> {
        let (period, until) = (
            self.config.grid.settle_period,
            self.robot.now() + self.config.grid.settle_time,
        );
        // A zero, negative or NaN period takes no frames (and must not loop for ever).
        if period.is_nan() || period <= 0.0 {
            return Ok(());
        }
        let mut next = self.robot.now() + period;
        while next <= until {
            while self.robot.now() < next {
                self.tick()?;
            }
            next += period;
            self.take_frame(true)?;
        }
        self.publish_grid();
        Ok(())
    }

    /// Starts a walk through `waypoints` (the first is where the robot stands) and waits for its end.
    fn walk(&mut self, waypoints: &[Point2<f64>]) -> Result<WalkOutcome, Interrupt> {
        let rest = waypoints.get(1..).unwrap_or_default();
        if rest.is_empty() {
            return Ok(WalkOutcome::Arrived);
        }
        self.robot.start_walk(rest)?;
        let outcome = self.wait(|r| r.walk_status())?;
        self.note_blocked(&outcome);
        Ok(outcome)
    }

    /// Walks `waypoints` as [`Self::walk`] does, but watching the way (frames into the grid, the
    /// search space ahead): with people about, a walk to a push pose or a viewpoint is no longer one
    /// the last look showed clear. A flagged path ends it stopped.
    fn walk_among_people(&mut self, waypoints: &[Point2<f64>]) -> Result<WalkOutcome, Interrupt> {
        // The grid watches the path to the goal, not this one: only the search space stops it.
        match self.walk_watching(waypoints, false, false)? {
            Watched::Walked(outcome) => Ok(outcome),
            Watched::Replan(_) | Watched::Unseen(_) => {
                self.robot.stop_walk()?;
                self.wait(|r| r.walk_status())?;
                Ok(WalkOutcome::Stopped)
            }
        }
    }

    /// The pose the last walk ended blocked at, while the robot at `here` still stands there.
    fn blocked_here(&self, here: &Point2<f64>) -> Option<nalgebra::Isometry2<f64>> {
        self.world
            .blocked_at
            .filter(|at| (Point2::from(at.translation.vector) - here).norm() < STUCK_DISTANCE)
    }

    /// Remembers where and facing which way a walk ended blocked (see [`Self::plan_to`]); any other
    /// end of a walk forgets it.
    fn note_blocked(&mut self, outcome: &WalkOutcome) {
        self.world.blocked_at = match outcome {
            WalkOutcome::Blocked { at } => Some(*at),
            _ => None,
        };
        // What stopped the walk reaches at least to the body's edge: its obstacle grows to there, so
        // that later paths keep the base's margin from it instead of meeting it again. Not where a
        // look ever saw something move: a person who stepped into the way and stood (as people do
        // when the robot comes at them) is not an obstacle's edge, and a scrap of them grown to the
        // body would become something to push.
        // The thing may lie beyond the body's edge by the planning clearance (a path may have led
        // the body up to the hull) and a grid cell (by which a hull whose face was seen edge-on
        // falls short of it): 13 cm for the paper's robot.
        let reach = self.config.clearance + self.config.grid.resolution;
        let touched = self
            .world
            .blocked_at
            .and_then(|at| self.world.touched(&at, &self.config, reach));
        if let Some((i, point)) = touched
            && !self.seen_moving_ever(&self.world.prisms[i])
        {
            self.world.prisms[i].grow_to(&point);
        }
    }

    /// Walks to the stand pose of `intent` and turns to face the push.
    pub(crate) fn walk_to_push_pose(&mut self, intent: &PushIntent) -> Event {
        let here = match self.position() {
            Ok(p) => p,
            Err(i) => return i.into(),
        };
        let stand = Point2::from(intent.stand.translation.vector);
        // Already there, within what the arm absorbs of a stand pose missed (a push planned from
        // where the last one left the robot): turn, do not step away and back. Farther off, the
        // stroke's line could leave the arm's reach: walk there.
        if (stand - here).norm() <= super::stroke::LATERAL_SLACK {
            return match self.turn_to(intent.direction.y.atan2(intent.direction.x)) {
                Ok(WalkOutcome::Arrived) => Event::Arrived,
                Ok(_) => Event::WalkBlocked,
                Err(i) => i.into(),
            };
        }
        let stuck = self.blocked_here(&here).is_some();
        let planned = self
            .world
            .push_plan
            .as_ref()
            .filter(|p| p.object == intent.target && (p.approach.start() - here).norm() < 0.05)
            .filter(|_| !stuck)
            .map(|p| p.approach.clone());
        let path = match planned.map_or_else(|| self.plan_to(here, Some(stand)), Ok) {
            Ok(path) => path,
            Err(_) => return Event::WalkBlocked,
        };
        let stamp = self.robot.now();
        self.observer.path(stamp, path.waypoints());
        let walked = if self.people_about() {
            self.walk_among_people(path.waypoints())
        } else {
            self.walk(path.waypoints())
        };
        // A walk the base stopped short of the stand pose has arrived where, facing the push, the
        // stroke still ends within the arm's reach ahead and its line within the arm's reach to the
        // side: the object's face stands nearer than its hull (the base keeps its margin from it),
        // and the push test meets the face where it is. The stroke follows the planned line
        // whatever the body's place (the hand goes to the planned contact in the body's frame), so
        // a stop beside the stand pose moves the hand sideways on the arm, not the contact.
        let d = intent.direction.into_inner();
        let reach = Reach {
            ahead: self.config.model.arm.reach_x[1] - self.config.push_motion.test_travel,
            side: self.config.push.reach_y,
        };
        let contact = self.planned_contact(intent);
        let arrived = |at: &nalgebra::Isometry2<f64>| {
            reach.pushes_from(&Point2::from(at.translation.vector), &stand, &d, &contact)
        };
        let there = match &walked {
            Ok(WalkOutcome::Arrived) => true,
            Ok(WalkOutcome::Blocked { at }) => arrived(at),
            _ => false,
        };
        let outcome = if there {
            self.turn_to(d.y.atan2(d.x))
        } else {
            walked
        };
        match outcome {
            Ok(WalkOutcome::Arrived) => Event::Arrived,
            Ok(_) => Event::WalkBlocked,
            Err(i) => i.into(),
        }
    }

    /// Walks to a viewpoint, watching the grid, and turns to face its heading.
    pub(crate) fn walk_to_view(&mut self, view: &Viewpoint) -> Event {
        let here = match self.position() {
            Ok(p) => p,
            Err(i) => return i.into(),
        };
        let path = match self.view_path(here, view) {
            Ok(path) => path,
            Err(_) => return Event::WalkBlocked,
        };
        let stamp = self.robot.now();
        self.observer.path(stamp, path.waypoints());
        self.watch_path(path.waypoints());
        let outcome = match self.walk_watching(path.waypoints(), false, true) {
            Ok(Watched::Walked(WalkOutcome::Arrived)) => self.turn_to(view.yaw),
            Ok(Watched::Replan(reason)) => return Event::PathInvalidated { reason },
            Ok(Watched::Unseen(_)) => Ok(WalkOutcome::Arrived),
            Ok(Watched::Walked(other)) => Ok(other),
            Err(i) => return i.into(),
        };
        match outcome {
            Ok(WalkOutcome::Arrived) => {
                self.world.pending_view = self.world.view_cells.take();
                Event::Arrived
            }
            Ok(_) => Event::WalkBlocked,
            Err(i) => i.into(),
        }
    }

    /// The walk to `view`: its path over seen floor when it starts where the robot stands and every
    /// leg is free among the obstacles (shortcut), else a planned one.
    fn view_path(&mut self, here: Point2<f64>, view: &Viewpoint) -> Result<Path, String> {
        let validity = self.world.validity(&here, &self.config)?;
        let starts_here = view.path.first().is_some_and(|p| (p - here).norm() < 0.05);
        if starts_here
            && let Ok(path) = Path::new(view.path.clone())
            && path
                .waypoints()
                .windows(2)
                .all(|w| validity.motion_free(&w[0], &w[1]))
        {
            return Ok(self
                .config
                .shortcut
                .shorten(&path, &validity, &mut self.rng));
        }
        self.plan_to(here, Some(view.position))
    }

    pub(super) fn turn_to(&mut self, yaw: f64) -> Result<WalkOutcome, Interrupt> {
        self.robot.start_turn(yaw)?;
        self.wait(|r| r.walk_status())
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use nudge_motion::{Bounds, RobotCylinder, Validity, ValidityConfig};
    use nudge_perception::{CloudFrame, ColourCloud, ObjectId, Prism};

    /// A world with a 1 m × 2 m box whose near face is `x0` ahead of the origin, for a robot of
    /// radius `radius`.
    pub(in crate::runner) fn validity_with_box(x0: f64, radius: f64) -> Validity {
        let square = Prism {
            id: ObjectId(1),
            footprint: vec![
                Point2::new(x0, -1.0),
                Point2::new(x0 + 1.0, -1.0),
                Point2::new(x0 + 1.0, 1.0),
                Point2::new(x0, 1.0),
            ],
            z_min: 0.0,
            z_max: 1.0,
            points: ColourCloud::empty(CloudFrame::Map, nalgebra::Isometry3::identity(), 0.0),
        };
        let robot = RobotCylinder {
            radius,
            height: 1.5,
        };
        let bounds =
            Bounds::new(Point2::new(-5.0, -5.0), Point2::new(5.0, 5.0)).expect("valid bounds");
        Validity::new(robot, bounds, &[square], ValidityConfig::default()).expect("valid world")
    }

    #[test]
    fn a_robot_overlapping_an_obstacle_steps_to_the_nearest_free_spot() {
        // Invariant: the escape point is free, within the escape radius, on the nearest ring that has one, and none is offered when the overlap is deeper than the radius.
        let here = Point2::origin();
        // The box's face is 0.3 m ahead: the 0.35 m disc overlaps it by 5 cm.
        let v = validity_with_box(0.3, 0.35);
        assert!(!v.is_free(&here));
        let p = nearest_free(&here, &v).expect("a free spot within reach");
        assert!(v.is_free(&p));
        let d = (p - here).norm();
        assert!(
            (d - 0.05).abs() < 1e-9,
            "stepped {d} m, the first ring is free"
        );
        // The face 0.1 m behind the robot's centre: 0.45 m of overlap, more than the radius.
        assert_eq!(nearest_free(&here, &validity_with_box(-0.1, 0.35)), None);
    }

    #[test]
    fn a_walk_stopped_short_of_its_stand_pose_has_arrived_where_the_arm_still_reaches_the_stroke() {
        // Invariant: a walk to a push pose stopped short of it has arrived when, facing the push, the stroke still ends within the arm's reach ahead and its line lies within the arm's reach to the side: 4 cm short and 5 cm beside the pose of a diagonal push (`long-hall` seed 25's table) has; a stop that leaves the contact past the forward reach, one that puts the line past the side reach, and one past the stand pose have not.
        let reach = Reach {
            ahead: 0.65,
            side: (-0.4, 0.4),
        };
        let d = Vector2::new(-0.7728, 0.6346).normalize();
        let stand = Point2::new(8.5009, 0.8967);
        let contact = stand + d * 0.48;
        let stopped = Point2::new(8.4982, 0.8350);
        assert!(reach.pushes_from(&stopped, &stand, &d, &contact));
        let far_short = stand - d * 0.25;
        assert!(!reach.pushes_from(&far_short, &stand, &d, &contact));
        let beside = stand + Vector2::new(-d.y, d.x) * 0.45;
        assert!(!reach.pushes_from(&beside, &stand, &d, &contact));
        let past = stand + d * 0.05;
        assert!(!reach.pushes_from(&past, &stand, &d, &contact));
    }

    #[test]
    fn a_blocked_robot_steps_straight_back_from_what_it_faced() {
        // Invariant: the step back lies the given distance behind the heading, farther from the obstacle ahead than the robot stands; none is offered where it would leave the walls.
        let radius = 0.35;
        // The box's near face 1.5 cm (the base's margin) ahead of the body.
        let v = validity_with_box(radius + 0.015, radius);
        let here = Point2::origin();
        let back = step_back(&here, 0.0, &v, 0.08).expect("room behind");
        assert!((back - Point2::new(-0.08, 0.0)).norm() < 1e-12, "{back}");
        let gap = |p: &Point2<f64>| v.obstacles()[0].distance_to_point(p);
        assert!(gap(&back) > gap(&here) + 0.079);
        // Facing the box at 45°: still straight back along the heading.
        let a = std::f64::consts::FRAC_PI_4;
        let back = step_back(&here, a, &v, 0.08).expect("room behind");
        assert!((back - here + Vector2::new(a.cos(), a.sin()) * 0.08).norm() < 1e-12);
        // A wall 0.4 m behind: the body would leave the room.
        let walls = Bounds::new(Point2::new(-0.4, -5.0), Point2::new(5.0, 5.0)).expect("bounds");
        let robot = RobotCylinder {
            radius,
            height: 1.5,
        };
        let hemmed = Validity::new(robot, walls, &[], ValidityConfig::default()).expect("world");
        assert_eq!(step_back(&here, 0.0, &hemmed, 0.08), None);
    }
}
