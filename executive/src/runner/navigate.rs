//! Planning paths and walking them.

use nalgebra::{Point2, Vector2};
use nudge_motion::{Path, Problem, StateValidity, certainly_unreachable};

use super::world::WorldModel;
use super::{Interrupt, Runner};
use crate::event::Event;
use crate::push_test::PushIntent;
use crate::record::Observer;
use crate::robot::{ActionStatus, Robot, WalkOutcome};

/// Farthest the robot steps to get clear of an obstacle that seems to overlap it (m).
const ESCAPE_RADIUS: f64 = 0.25;

/// The free position nearest `here` within [`ESCAPE_RADIUS`], searched on rings 5 cm apart with 32
/// bearings each (deterministic), if any.
fn nearest_free(here: &Point2<f64>, validity: &dyn StateValidity) -> Option<Point2<f64>> {
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

/// How a watched walk ended.
enum Watched {
    /// The walk itself ended.
    Walked(WalkOutcome),
    /// The grid flagged the path (the walk is still going).
    Replan(String),
}

/// Extra distance beyond the goal tolerance within which an arrival counts (m): the walk's own error.
const ARRIVAL_SLACK: f64 = 0.05;

impl<R: Robot, O: Observer> Runner<R, O> {
    fn position(&mut self) -> Result<Point2<f64>, Interrupt> {
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
        let validity = self.world.validity(&here, &self.config)?;
        // Where an obstacle seems to overlap the robot (someone stepped up to it, or a hull is a few
        // centimetres generous), plan from the nearest free spot and step there first.
        let start = if validity.is_free(&here) {
            here
        } else {
            nearest_free(&here, &validity).ok_or_else(|| {
                format!("the start is in collision and no free spot lies within {ESCAPE_RADIUS} m")
            })?
        };
        let problem = match target {
            Some(t) => Problem::new(start, t, 0.03).map_err(|e| e.to_string())?,
            None => WorldModel::problem(&start, &self.config)?,
        };
        // A flood fill proves most "no path" cases at once; the planner would spend its whole budget.
        if certainly_unreachable(&validity, &problem.start(), problem.goal()) {
            return Err(
                "no free way joins the start to the goal region (flood fill over 5 cm cells)"
                    .into(),
            );
        }
        let (path, _, tree) = self.config.planner.solve_recorded(
            &problem,
            &validity,
            self.config.budget,
            &mut self.rng,
        );
        let stamp = self.robot.now();
        self.observer.tree(stamp, &tree.edges);
        let path = path.map_err(|e| e.to_string())?;
        let path = self
            .config
            .shortcut
            .shorten(&path, &validity, &mut self.rng);
        if start == here {
            return Ok(path);
        }
        let mut waypoints = vec![here];
        waypoints.extend_from_slice(path.waypoints());
        Path::new(waypoints).map_err(|e| e.to_string())
    }

    /// Walks the planned path to the goal.
    pub(crate) fn follow_path(&mut self) -> Event {
        let Some(path) = self.world.path.clone() else {
            return Event::PathInvalidated {
                reason: "no path to follow".into(),
            };
        };
        match self.walk_watching(path.waypoints()) {
            Ok(Watched::Replan(reason)) => Event::PathInvalidated { reason },
            Ok(Watched::Walked(WalkOutcome::Arrived)) => match self.position() {
                Ok(p)
                    if (p - self.config.goal).norm()
                        <= self.config.goal_tolerance + ARRIVAL_SLACK =>
                {
                    Event::Arrived
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
    /// watching (the walk goes on until the machine stops it) when the grid flags the path.
    fn walk_watching(&mut self, waypoints: &[Point2<f64>]) -> Result<Watched, Interrupt> {
        let rest = waypoints.get(1..).unwrap_or_default();
        if rest.is_empty() {
            return Ok(Watched::Walked(WalkOutcome::Arrived));
        }
        self.robot.start_walk(rest)?;
        let mut next_frame = self.robot.now() + self.config.grid.watch_period;
        loop {
            if let ActionStatus::Done(outcome) = self.robot.walk_status()? {
                return Ok(Watched::Walked(outcome));
            }
            if self.robot.now() >= next_frame {
                next_frame += self.config.grid.watch_period;
                let cloud = self.robot.capture()?;
                self.observer.cloud(&cloud);
                self.sense(&cloud, true);
                self.publish_grid();
                if let Some(reason) = self.replan_reason() {
                    return Ok(Watched::Replan(reason));
                }
            }
            self.tick()?;
        }
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
            let cloud = self.robot.capture()?;
            self.observer.cloud(&cloud);
            self.sense(&cloud, true);
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
        self.wait(|r| r.walk_status())
    }

    /// Walks to the stand pose of `intent` and turns to face the push.
    pub(crate) fn walk_to_push_pose(&mut self, intent: &PushIntent) -> Event {
        let here = match self.position() {
            Ok(p) => p,
            Err(i) => return i.into(),
        };
        let stand = Point2::from(intent.stand.translation.vector);
        let planned = self
            .world
            .push_plan
            .as_ref()
            .filter(|p| p.object == intent.target && (p.approach.start() - here).norm() < 0.05)
            .map(|p| p.approach.clone());
        let path = match planned.map_or_else(|| self.plan_to(here, Some(stand)), Ok) {
            Ok(path) => path,
            Err(_) => return Event::WalkBlocked,
        };
        let stamp = self.robot.now();
        self.observer.path(stamp, path.waypoints());
        let walked = self.walk(path.waypoints());
        let outcome = match walked {
            Ok(WalkOutcome::Arrived) => self.turn_to(intent.direction.y.atan2(intent.direction.x)),
            other => other,
        };
        match outcome {
            Ok(WalkOutcome::Arrived) => Event::Arrived,
            Ok(_) => Event::WalkBlocked,
            Err(i) => i.into(),
        }
    }

    fn turn_to(&mut self, yaw: f64) -> Result<WalkOutcome, Interrupt> {
        self.robot.start_turn(yaw)?;
        self.wait(|r| r.walk_status())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nudge_motion::{Bounds, RobotCylinder, Validity, ValidityConfig};
    use nudge_perception::{CloudFrame, ColourCloud, ObjectId, Prism};

    fn validity_with_box(x0: f64) -> Validity {
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
            radius: 0.35,
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
        let v = validity_with_box(0.3);
        assert!(!v.is_free(&here));
        let p = nearest_free(&here, &v).expect("a free spot within reach");
        assert!(v.is_free(&p));
        let d = (p - here).norm();
        assert!(
            (d - 0.05).abs() < 1e-9,
            "stepped {d} m, the first ring is free"
        );
        // The face 0.1 m behind the robot's centre: 0.45 m of overlap, more than the radius.
        assert_eq!(nearest_free(&here, &validity_with_box(-0.1)), None);
    }
}
