//! Every action the runner starts ends within a time derived from the action itself.
//!
//! The runner waits for an action by polling its status each tick. An adapter whose action never
//! reports done — a stalled arm, a lost completion message — would keep it polling until the whole
//! run's robot-time budget is spent (half an hour by default), the hand pressed where it stalled all
//! that while. The [`Watchdog`] wraps the robot inside the runner, as a decorator like the fault
//! ones ([`crate::robot::faults`]): it gives each action a deadline when it starts, and a status poll
//! past it stops the action and fails with [`RobotError::Timeout`], which the machine turns into a
//! safe stop (arm retracted) and `Aborted` with the reason.
//!
//! A deadline is [`FACTOR`] × the action's nominal duration + [`SLACK`]. The nominal duration comes
//! from the command and the robot description, with room for a robot slower than described: a
//! walk's path length at the walking speed plus a half turn per waypoint at [`TURN_RATE_SHARE`] of
//! the turning rate; a head motion's largest angle at [`HEAD_RATE_SHARE`] of the head's rate; a
//! guarded move's way to its line and the line itself at the move's own speed (the hand goes to the
//! line faster than that), plus the time its acceleration takes to reach that speed; a retract the
//! way back from the arm's farthest reach ([`retract_nominal`]). Deadlines count the robot time the
//! runner lets pass (`Clock::advance`), not the clock's reading, so a clock that steps neither fires
//! them nor hides a hang.

use nalgebra::{Isometry2, Point2, Point3};
use nudge_perception::ColourCloud;

use crate::robot::{
    ActionStatus, GuardedMove, HandOutcome, Robot, RobotError, Stamped, WalkOutcome, Wrench,
};

/// A deadline is this many times an action's nominal duration (plus [`SLACK`]): the nominal speeds
/// are floors already, so this only absorbs ramps, a replanned turn, a slow controller.
pub(crate) const FACTOR: f64 = 2.0;

/// Added to every deadline (s): an action of no length still needs its controller to answer.
pub(crate) const SLACK: f64 = 5.0;

/// Share of the described turning rate a base is assumed to reach at least: a turn may take twice
/// its time (the ramps, a controller slower than its description).
pub(crate) const TURN_RATE_SHARE: f64 = 0.5;

/// Share of the described pan/tilt rate a head is assumed to reach at least: a trajectory
/// controller's acceleration limits and settling can make a short motion four times as long.
pub(crate) const HEAD_RATE_SHARE: f64 = 0.25;

/// Share of the described free hand speed a retract is assumed to reach at least: the arm's
/// controller ramps and may be slower than described, as a base's turns are ([`TURN_RATE_SHARE`]).
pub(crate) const RETRACT_SPEED_SHARE: f64 = 0.5;

/// Nominal duration of a retract (s): the hand comes back from the farthest corner of the arm's
/// reach box to its rest position (1.02 m for the paper's robot) at [`RETRACT_SPEED_SHARE`] of the
/// free hand speed (0.1 m/s): 10.2 s, a 26 s deadline. The runner's safe stop waits for a retract by
/// the same deadline ([`retract_deadline`]).
pub(crate) fn retract_nominal(arm: &nudge_robot_model::ArmModel) -> f64 {
    let [rx, ry, rz] = arm.rest;
    let far = |[lo, hi]: [f64; 2], rest: f64| (lo - rest).abs().max((hi - rest).abs());
    let distance = nalgebra::Vector3::new(
        far(arm.reach_x, rx),
        far(arm.reach_y, ry),
        far(arm.reach_z, rz),
    )
    .norm();
    distance / (RETRACT_SPEED_SHARE * arm.free_speed).max(1e-3)
}

/// How long a retract may take before it has failed (s): [`FACTOR`] × [`retract_nominal`] +
/// [`SLACK`], in whole seconds, like every deadline.
pub(crate) fn retract_deadline(arm: &nudge_robot_model::ArmModel) -> f64 {
    (FACTOR * retract_nominal(arm) + SLACK).ceil()
}

/// When an action started and how long it may take (s of robot time let pass).
#[derive(Clone, Copy, Debug)]
struct Deadline {
    started: f64,
    bound: f64,
}

/// The runner's robot, with a deadline on every action; every call is forwarded.
///
/// Its methods are inherent ones named as the capability traits name them, so the runner's files
/// call them on it as they would on the robot, without importing a trait.
#[derive(Debug)]
pub(crate) struct Watchdog<R> {
    inner: R,
    walk_speed: f64,
    /// Slowest turning rate assumed of the base (rad/s).
    turn_floor: f64,
    /// Slowest pan/tilt rate assumed of the head (rad/s).
    head_floor: f64,
    /// Nominal duration of a retract (s), from the arm's description.
    retract: f64,
    elapsed: f64,
    walk: Option<Deadline>,
    head: Option<Deadline>,
    hand: Option<Deadline>,
    pose: Option<Point2<f64>>,
    angles: Option<(f64, f64)>,
    hand_at: Option<Point3<f64>>,
}

impl<R: Robot> Watchdog<R> {
    /// Wraps `inner`, a robot as `model` describes it.
    pub(crate) fn new(inner: R, model: &nudge_robot_model::RobotModel) -> Self {
        Self {
            inner,
            walk_speed: model.body.walk_speed.max(1e-3),
            turn_floor: (TURN_RATE_SHARE * model.body.turn_rate).max(1e-3),
            head_floor: (HEAD_RATE_SHARE * model.head.rate).max(1e-3),
            retract: retract_nominal(&model.arm),
            elapsed: 0.0,
            walk: None,
            head: None,
            hand: None,
            pose: None,
            angles: None,
            hand_at: None,
        }
    }

    /// The wrapped robot.
    pub(crate) fn inner(&self) -> &R {
        &self.inner
    }

    /// Unwraps it.
    pub(crate) fn into_inner(self) -> R {
        self.inner
    }

    /// Robot time let pass through `advance` so far (s).
    pub(crate) fn elapsed(&self) -> f64 {
        self.elapsed
    }

    fn deadline(&self, nominal: f64) -> Option<Deadline> {
        Some(Deadline {
            started: self.elapsed,
            // Whole seconds, so the reason a run ends with reads as a number a person chose.
            bound: (FACTOR * nominal.max(0.0) + SLACK).ceil(),
        })
    }

    /// The deadline `deadline` has passed: the timeout error of `capability`.
    fn overdue(&self, deadline: Option<Deadline>, capability: &'static str) -> Option<RobotError> {
        deadline
            .filter(|d| self.elapsed - d.started > d.bound)
            .map(|d| RobotError::Timeout {
                capability,
                seconds: d.bound,
            })
    }
}

/// [`Clock`](crate::robot::Clock): time passes through here, and the deadlines count it.
impl<R: Robot> Watchdog<R> {
    pub(crate) fn now(&self) -> f64 {
        self.inner.now()
    }

    pub(crate) fn advance(&mut self, dt: f64) -> Result<(), RobotError> {
        self.inner.advance(dt)?;
        self.elapsed += dt;
        Ok(())
    }
}

/// [`Base`](crate::robot::Base): walks and turns get a deadline.
impl<R: Robot> Watchdog<R> {
    pub(crate) fn base_pose(&mut self) -> Result<Stamped<Isometry2<f64>>, RobotError> {
        let pose = self.inner.base_pose()?;
        self.pose = Some(Point2::from(pose.value.translation.vector));
        Ok(pose)
    }

    pub(crate) fn start_walk(&mut self, waypoints: &[Point2<f64>]) -> Result<(), RobotError> {
        self.inner.start_walk(waypoints)?;
        let length: f64 = self
            .pose
            .iter()
            .chain(waypoints)
            .zip(waypoints)
            .map(|(a, b)| (b - a).norm())
            .sum();
        let turns = waypoints.len() as f64 * std::f64::consts::PI / self.turn_floor;
        self.walk = self.deadline(length / self.walk_speed + turns);
        Ok(())
    }

    pub(crate) fn start_turn(&mut self, yaw: f64) -> Result<(), RobotError> {
        self.inner.start_turn(yaw)?;
        self.walk = self.deadline(std::f64::consts::PI / self.turn_floor);
        Ok(())
    }

    pub(crate) fn walk_status(&mut self) -> Result<ActionStatus<WalkOutcome>, RobotError> {
        let status = self.inner.walk_status()?;
        if let ActionStatus::Done(_) = status {
            self.walk = None;
        } else if let Some(e) = self.overdue(self.walk, "base") {
            self.walk = None;
            self.inner.stop_walk()?;
            return Err(e);
        }
        Ok(status)
    }

    pub(crate) fn stop_walk(&mut self) -> Result<(), RobotError> {
        self.walk = None;
        self.inner.stop_walk()
    }
}

/// [`Head`](crate::robot::Head): head motions get a deadline.
impl<R: Robot> Watchdog<R> {
    pub(crate) fn head_angles(&mut self) -> Result<Stamped<(f64, f64)>, RobotError> {
        let angles = self.inner.head_angles()?;
        self.angles = Some(angles.value);
        Ok(angles)
    }

    pub(crate) fn start_point_head(&mut self, pan: f64, tilt: f64) -> Result<(), RobotError> {
        self.inner.start_point_head(pan, tilt)?;
        // Unknown angles: a half turn, more than any pan or tilt range.
        let angle = self.angles.map_or(std::f64::consts::PI, |(p, t)| {
            (pan - p).abs().max((tilt - t).abs())
        });
        self.head = self.deadline(angle / self.head_floor);
        Ok(())
    }

    pub(crate) fn head_status(&mut self) -> Result<ActionStatus<()>, RobotError> {
        let status = self.inner.head_status()?;
        if let ActionStatus::Done(_) = status {
            self.head = None;
        } else if let Some(e) = self.overdue(self.head, "head") {
            // A head has no stop; a new motion replaces this one.
            self.head = None;
            return Err(e);
        }
        Ok(status)
    }
}

/// [`RangeCamera`](crate::robot::RangeCamera): forwarded.
impl<R: Robot> Watchdog<R> {
    pub(crate) fn capture(&mut self) -> Result<ColourCloud, RobotError> {
        self.inner.capture()
    }
}

/// [`WristSensor`](crate::robot::WristSensor): forwarded.
impl<R: Robot> Watchdog<R> {
    pub(crate) fn tare(&mut self) -> Result<(), RobotError> {
        self.inner.tare()
    }

    // The runner reads the wrist through `drain_wrenches` today; kept so it can call every method
    // it could call on the robot.
    #[allow(dead_code)]
    pub(crate) fn wrench(&mut self) -> Result<Stamped<Wrench>, RobotError> {
        self.inner.wrench()
    }

    pub(crate) fn drain_wrenches(&mut self) -> Result<Vec<Stamped<Wrench>>, RobotError> {
        self.inner.drain_wrenches()
    }

    pub(crate) fn discard_wrenches(&mut self) -> Result<(), RobotError> {
        self.inner.discard_wrenches()
    }
}

/// [`Arm`](crate::robot::Arm): guarded moves and retracts get a deadline.
impl<R: Robot> Watchdog<R> {
    pub(crate) fn hand_position(&mut self) -> Result<Stamped<Point3<f64>>, RobotError> {
        let at = self.inner.hand_position()?;
        self.hand_at = Some(at.value);
        Ok(at)
    }

    pub(crate) fn start_guarded_move(&mut self, motion: GuardedMove) -> Result<(), RobotError> {
        let speed = motion.speed.max(1e-3);
        let to_line = self.hand_at.map_or(0.0, |h| (motion.from - h).norm());
        let line = (motion.to - motion.from).norm();
        let ramp = motion.acceleration.map_or(0.0, |a| speed / a.max(1e-6));
        let nominal = (to_line + line) / speed + ramp;
        self.inner.start_guarded_move(motion)?;
        self.hand = self.deadline(nominal);
        Ok(())
    }

    pub(crate) fn start_retract(&mut self) -> Result<(), RobotError> {
        self.inner.start_retract()?;
        self.hand = self.deadline(self.retract);
        Ok(())
    }

    pub(crate) fn hand_status(&mut self) -> Result<ActionStatus<HandOutcome>, RobotError> {
        let status = self.inner.hand_status()?;
        if let ActionStatus::Done(_) = status {
            self.hand = None;
        } else if let Some(e) = self.overdue(self.hand, "arm") {
            self.hand = None;
            self.inner.stop_hand()?;
            return Err(e);
        }
        Ok(status)
    }

    pub(crate) fn stop_hand(&mut self) -> Result<(), RobotError> {
        self.hand = None;
        self.inner.stop_hand()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robot::FakeRobot;
    use crate::robot::faults::{ArmStall, FaultWindow, Trigger};
    use nalgebra::Vector2;

    #[test]
    fn a_stalled_hand_times_out_at_its_derived_deadline_and_is_stopped() {
        // Invariant: a guarded move that never finishes fails its status poll with a Timeout once FACTOR × its nominal duration + SLACK of robot time has passed, not before; the hand is then stopped, so a retract can follow.
        let fake = FakeRobot::new(Isometry2::new(Vector2::zeros(), 0.0));
        let stalled = ArmStall::new(fake, FaultWindow::once(Trigger::Always), 0.0);
        let mut robot = Watchdog::new(stalled, &nudge_robot_model::RobotModel::default());
        robot.hand_position().expect("hand");
        let [x, y, z] = nudge_robot_model::RobotModel::default().arm.rest;
        let motion = GuardedMove {
            from: Point3::new(x + 0.1, y, z),
            to: Point3::new(x + 0.3, y, z),
            speed: 0.02,
            force_limit: 20.0,
            acceleration: None,
        };
        // 0.1 m to the line and 0.2 m along it at 2 cm/s: 15 s nominal, 35 s deadline.
        robot.start_guarded_move(motion).expect("start");
        let mut waited = 0.0_f64;
        let error = loop {
            match robot.hand_status() {
                Ok(ActionStatus::Running) => {}
                Ok(done) => panic!("a stalled hand finished: {done:?}"),
                Err(e) => break e,
            }
            robot.advance(0.05).expect("advance");
            waited += 0.05;
            assert!(waited < 100.0, "no timeout");
        };
        assert!(
            matches!(error, RobotError::Timeout { capability: "arm", seconds } if (seconds - 35.0).abs() < 1e-9),
            "{error:?}"
        );
        assert!((waited - 35.0).abs() < 0.1, "timed out after {waited} s");
        robot.start_retract().expect("retract");
        while robot.hand_status().expect("status") == ActionStatus::Running {
            robot.advance(0.05).expect("advance");
        }
    }

    #[test]
    fn a_retract_is_given_the_time_the_arm_needs_from_its_farthest_reach() {
        // Invariant: the retract's nominal duration is the way from the farthest corner of the reach box to rest at half the free hand speed (1.02 m at 0.1 m/s for the paper's robot: 10.2 s, a 26 s deadline), and grows with a longer arm or a slower hand.
        let arm = nudge_robot_model::RobotModel::default().arm;
        let nominal = retract_nominal(&arm);
        assert!((nominal - 10.16).abs() < 0.01, "{nominal}");
        assert_eq!(retract_deadline(&arm), 26.0);
        let longer = nudge_robot_model::ArmModel {
            reach_x: [0.2, 1.2],
            ..arm.clone()
        };
        assert!(retract_nominal(&longer) > nominal + 2.0);
        let slower = nudge_robot_model::ArmModel {
            free_speed: 0.1,
            ..arm
        };
        assert!((retract_nominal(&slower) - 2.0 * nominal).abs() < 1e-9);
    }
}
