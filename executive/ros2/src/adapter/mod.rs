//! [`Ros2Robot`]: the robot traits over ROS 2. Sensors arrive on standard topics (`/clock`, `/tf`,
//! `/joint_states`, a `WrenchStamped` stream, `PointCloud2` frames) and actions leave as the
//! commands a ROS 2 robot's controllers take: `/cmd_vel` for walking, a head trajectory, a
//! Cartesian hand velocity (MoveIt Servo's `TwistStamped`). The walk and hand profiles are the
//! shared [`controller`](nudge_executive::robot::controller)s, run here; the force guard runs here
//! too, on every wrist reading as it arrives.
//!
//! Time: with `use_sim_time` the clock is `/clock`, and [`Clock::advance`] asks a lock-stepped
//! simulator to run on (`step` topic) and waits for `/clock` to get there; otherwise it is the wall
//! clock and `advance` waits in real time. During a guarded hand move it advances one wrist period
//! at a time, so the guard sees each reading before the hand moves on.

mod base;
mod camera;
mod hand;
mod head;
mod inbox;

use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use nalgebra::{Isometry2, Point3};
use nudge_executive::robot::controller::{
    HandMotion, Rates, STEADY_PRESS_US, STEADY_STEP_US, Walk, steady_push,
};
use nudge_executive::robot::{Clock, RobotError};
use nudge_robot_model::RobotModel;

use crate::config::Ros2Config;
use crate::convert::time_from_seconds;
use crate::msg::{
    Clock as ClockMsg, Header, JointState, JointTrajectory, PointCloud2, TFMessage, Twist,
    TwistStamped, WrenchStamped,
};
use crate::node::{DdsError, RosNode, RosPublisher, RosSubscription};
use inbox::Inbox;

/// How long [`Ros2Robot::connect`] waits for the robot to be heard (wall time): DDS discovery takes
/// a few hundred milliseconds on one machine, a second or two across a network.
const CONNECT_TIMEOUT: Duration = Duration::from_secs(20);
/// Robot time past the end of a stretch (s) that the hand's profile catches up: far above the
/// clock's nanosecond rounding, far below a wrist period.
const LATE: f64 = 1.0e-6;
/// How often a lock-stepped step request is sent again while nothing comes back (wall time): the
/// clock travels best effort and one lost sample must not stall the run.
const RESEND: Duration = Duration::from_millis(250);

/// The publishers and subscriptions.
struct Endpoints {
    cmd_vel: RosPublisher<Twist>,
    head: RosPublisher<JointTrajectory>,
    hand: RosPublisher<TwistStamped>,
    trigger: RosPublisher<Header>,
    step: RosPublisher<ClockMsg>,
    clock: RosSubscription<ClockMsg>,
    tf: RosSubscription<TFMessage>,
    joints: RosSubscription<JointState>,
    wrench: RosSubscription<WrenchStamped>,
    cloud: RosSubscription<PointCloud2>,
}

/// A robot behind ROS 2 topics.
pub struct Ros2Robot {
    config: Ros2Config,
    model: RobotModel,
    node: RosNode,
    io: Endpoints,
    inbox: Inbox,
    /// The walk or turn under way, run here as `/cmd_vel` commands.
    walk: Walk,
    rates: Rates,
    /// Where the last `/cmd_vel` should have taken the base, to tell a blocked walk.
    expected: Option<(Isometry2<f64>, Isometry2<f64>)>,
    /// Whether the last `/cmd_vel` sent was not zero.
    walking: bool,
    /// The head's target, until it is reached.
    head_target: Option<(f64, f64)>,
    /// The hand's commanded motion, run here as Cartesian velocity commands.
    hand: HandMotion,
    /// Whether the last hand command sent was not zero.
    hand_moving: bool,
    /// Subtracted from raw wrist readings.
    tare: nudge_executive::robot::Wrench,
    /// When the hand's current unbroken press on a guarded line began (robot time, s).
    pressed_since: Option<f64>,
}

/// Robot time of wrist samples the wrist stream's history holds (s): two of the executive's default
/// 50 ms ticks, the longest stretch a lock-stepped simulator runs before it sends its samples at once.
const WRENCH_HISTORY: f64 = 0.1;

/// The wrist stream's QoS: the sensor profile, its history deep enough for [`WRENCH_HISTORY`] of
/// samples at the wrist's rate.
pub fn wrench_qos(sensor: crate::config::Qos, model: &RobotModel) -> crate::config::Qos {
    let tick_samples = (model.wrist.rate_hz * WRENCH_HISTORY).ceil() as u32;
    crate::config::Qos {
        depth: sensor.depth.max(tick_samples),
        ..sensor
    }
}

fn dds(e: DdsError) -> RobotError {
    RobotError::Unavailable {
        capability: "ros2",
        reason: e.to_string(),
    }
}

impl Ros2Robot {
    /// Joins the robot's ROS 2 graph as node `name` and waits until the robot is heard: its base
    /// transform, its head joints and, with `use_sim_time`, its clock.
    pub fn connect(config: Ros2Config, model: RobotModel, name: &str) -> Result<Self, RobotError> {
        let mut node = RosNode::new(name, config.domain_id).map_err(dds)?;
        let (t, sensor, command) = (&config.topics, config.qos.sensor, config.qos.command);
        let io = Endpoints {
            cmd_vel: node.publisher(&t.cmd_vel, command).map_err(dds)?,
            head: node.publisher(&t.head, command).map_err(dds)?,
            hand: node.publisher(&t.hand, command).map_err(dds)?,
            trigger: node.publisher(&t.camera_trigger, command).map_err(dds)?,
            step: node.publisher(&t.step, command).map_err(dds)?,
            clock: node.subscription(&t.clock, sensor).map_err(dds)?,
            tf: node.subscription(&t.tf, sensor).map_err(dds)?,
            joints: node.subscription(&t.joint_states, sensor).map_err(dds)?,
            wrench: node
                .subscription(&t.wrench, wrench_qos(sensor, &model))
                .map_err(dds)?,
            cloud: node.subscription(&t.cloud, sensor).map_err(dds)?,
        };
        let hand = HandMotion::new(&model.arm);
        let mut robot = Self {
            config,
            model,
            node,
            io,
            inbox: Inbox::default(),
            walk: Walk::Idle(None),
            rates: Rates::default(),
            expected: None,
            walking: false,
            head_target: None,
            hand,
            hand_moving: false,
            tare: Default::default(),
            pressed_since: None,
        };
        let deadline = Instant::now() + CONNECT_TIMEOUT;
        let mut last_ask = Instant::now() - RESEND;
        loop {
            robot.pump()?;
            let base = robot.config.frames.base.as_str().to_string();
            let heard = robot.inbox.tf.contains_key(&base)
                && robot.inbox.head.is_some()
                && (!robot.config.use_sim_time || robot.inbox.clock.is_some());
            if heard {
                return Ok(robot);
            }
            if Instant::now() > deadline {
                return Err(RobotError::Timeout {
                    capability: "ros2",
                    seconds: CONNECT_TIMEOUT.as_secs_f64(),
                });
            }
            if robot.config.use_sim_time && last_ask.elapsed() >= RESEND {
                // A lock-stepped simulator says where it is when asked to run to time zero.
                robot.ask_step(0.0)?;
                last_ask = Instant::now();
            }
            robot.node.wait(Duration::from_millis(20));
        }
    }

    /// The robot description the adapter was made with.
    pub fn model(&self) -> &RobotModel {
        &self.model
    }

    /// Takes every message waiting on every subscription into the inbox.
    fn pump(&mut self) -> Result<(), RobotError> {
        while let Some(m) = self.io.clock.take().map_err(dds)? {
            self.inbox.on_clock(&m);
        }
        while let Some(m) = self.io.tf.take().map_err(dds)? {
            self.inbox.on_tf(&m);
        }
        while let Some(m) = self.io.joints.take().map_err(dds)? {
            self.inbox.on_joints(&m, &self.config);
        }
        while let Some(m) = self.io.wrench.take().map_err(dds)? {
            self.inbox.on_wrench(&m);
            self.guard()?;
        }
        while let Some(m) = self.io.cloud.take().map_err(dds)? {
            self.inbox.on_cloud(m);
        }
        Ok(())
    }

    /// The first fault heard and not yet reported, as an error.
    fn check(&mut self) -> Result<(), RobotError> {
        self.inbox.fault.take().map_or(Ok(()), Err)
    }

    /// Asks a lock-stepped simulator to run until `t` (s).
    fn ask_step(&mut self, t: f64) -> Result<(), RobotError> {
        let clock = time_from_seconds(t).ok_or_else(|| RobotError::Refused {
            capability: "clock",
            reason: format!("time {t} s cannot be sent"),
        })?;
        self.io.step.publish(ClockMsg { clock }).map_err(dds)
    }

    /// The wall clock as ROS time (s since the epoch).
    fn wall_now() -> f64 {
        SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0.0, |d| d.as_secs_f64())
    }

    /// Waits until `done` holds of the inbox, pumping messages and, with sim time, asking the
    /// simulator for `until` again when nothing comes; a silence of the configured length is a
    /// timeout of `capability`.
    fn wait_for(
        &mut self,
        capability: &'static str,
        until: Option<f64>,
        mut done: impl FnMut(&Self) -> bool,
    ) -> Result<(), RobotError> {
        let quiet = Duration::from_secs_f64(self.config.timeouts.quiet);
        let mut heard = Instant::now();
        let mut asked = Instant::now();
        loop {
            let before = self.inbox.clock;
            self.pump()?;
            self.check()?;
            if done(self) {
                return Ok(());
            }
            if self.inbox.clock != before {
                heard = Instant::now();
            }
            if heard.elapsed() >= quiet {
                return Err(RobotError::Timeout {
                    capability,
                    seconds: quiet.as_secs_f64(),
                });
            }
            if let Some(t) = until
                && self.config.use_sim_time
                && asked.elapsed() >= RESEND
            {
                self.ask_step(t)?;
                asked = Instant::now();
            }
            self.node.wait(Duration::from_millis(5));
        }
    }

    /// The stamp of the newest base transform.
    fn base_stamp(&self) -> f64 {
        self.inbox
            .tf
            .get(self.config.frames.base.as_str())
            .map_or(f64::NEG_INFINITY, |e| e.stamp)
    }

    /// Runs one stretch of robot time of `dt` seconds: commands for it, then the wait.
    fn run_for(&mut self, dt: f64) -> Result<(), RobotError> {
        let end = self.now() + dt;
        self.command_base(dt)?;
        self.command_hand(dt)?;
        self.wait_until(end)?;
        // A robot that ran on past `end` (a free-running simulator between its clock messages, a
        // late wake-up on the wall clock) moved the hand at the commanded velocity all the while:
        // the hand's profile catches up, so what is commanded next starts where the hand is.
        let late = self.now() - end;
        if late > LATE {
            self.hand.step(late);
        }
        Ok(())
    }

    /// Waits until the robot's time reaches `end`: with sim time, asks a lock-stepped simulator to
    /// get there and waits for its clock, base transform and (with the hand moving) wrist sample.
    fn wait_until(&mut self, end: f64) -> Result<(), RobotError> {
        if self.config.use_sim_time {
            self.ask_step(end)?;
            let hand = self.hand_moving;
            self.wait_for("clock", Some(end), |r| {
                let t = end - 1e-9;
                r.inbox.clock.is_some_and(|c| c >= t)
                    && r.base_stamp() >= t
                    && (!hand || r.inbox.latest_wrench.is_some_and(|w| w.stamp >= t))
            })
        } else {
            self.wait_for("clock", None, |_| Self::wall_now() >= end)?;
            // On the wall clock nothing waits for the robot's streams: check they still come.
            let quiet = self.config.timeouts.quiet;
            let silent = |stamp: f64| end - stamp > quiet;
            if silent(self.base_stamp()) {
                return Err(RobotError::Timeout {
                    capability: "tf",
                    seconds: quiet,
                });
            }
            if self.hand.guard().is_some()
                && self.inbox.latest_wrench.is_none_or(|w| silent(w.stamp))
            {
                return Err(RobotError::Timeout {
                    capability: "wrist",
                    seconds: quiet,
                });
            }
            Ok(())
        }
    }

    /// Whether the guarded line under way is a steady push the guard may read at its coarser pace
    /// (the shared rule the simulation steps by).
    fn steady(&self) -> bool {
        let (Some((limit, speed)), Some(raw)) =
            (self.hand.guarded_line(), self.inbox.latest_wrench)
        else {
            return false;
        };
        let force = (raw.value.force - self.tare.force).norm();
        let held = self
            .pressed_since
            .is_some_and(|since| raw.stamp - since >= STEADY_PRESS_US as f64 * 1.0e-6 - 1.0e-9);
        let standing = matches!(self.walk, Walk::Idle(_));
        steady_push(
            force,
            limit,
            speed,
            self.model.wrist.stiffness,
            held,
            standing,
        )
    }

    /// A hand position from the transform tree: the hand frame in the base frame.
    fn hand_in_base(&self) -> Result<(Point3<f64>, f64), RobotError> {
        let (pose, stamp) = self.inbox.lookup(
            self.config.frames.base.as_str(),
            self.config.frames.hand.as_str(),
        )?;
        Ok((Point3::from(pose.translation.vector), stamp))
    }
}

impl Clock for Ros2Robot {
    fn now(&self) -> f64 {
        if self.config.use_sim_time {
            self.inbox.clock.unwrap_or(0.0)
        } else {
            Self::wall_now()
        }
    }

    fn advance(&mut self, dt: f64) -> Result<(), RobotError> {
        if !(dt.is_finite() && dt >= 0.0) {
            return Err(RobotError::Refused {
                capability: "clock",
                reason: format!("cannot advance by {dt} s"),
            });
        }
        self.check()?;
        let end = self.now() + dt;
        let period = 1.0 / self.model.wrist.rate_hz;
        loop {
            let left = end - self.now();
            if left <= 1e-9 {
                return Ok(());
            }
            // A guarded move goes one wrist period at a time, so the guard reads every sample before
            // the hand is commanded on; a steady push far below its limit at the guard's coarser pace.
            let chunk = if self.hand.guard().is_none() {
                left
            } else if self.steady() {
                left.min(STEADY_STEP_US as f64 * 1.0e-6)
            } else {
                left.min(period)
            };
            self.run_for(chunk)?;
        }
    }
}
