//! `nudge sim-bridge`: the simulation as a ROS 2 robot. It takes the commands a robot's controllers
//! take (`/cmd_vel`, a head joint trajectory, a Cartesian hand velocity, a camera trigger) and
//! publishes what a robot publishes (`/clock`, `/tf`, `/joint_states`, the wrist's
//! `WrenchStamped` at its sample rate, `PointCloud2` frames), on the topics a [`Ros2Config`] names.
//!
//! It runs at one of two paces ([`Pace`]). Lock-stepped, time runs only when a client asks it to
//! run to a time (the config's `step` topic), so a run over DDS is the in-process run's physics
//! however slow or loaded the machine. Free-running, it runs on by itself at a real-time factor, as
//! a simulator does for any ROS 2 client (teleoperation, RViz, another executive), and step
//! requests are ignored. Each stretch it applies the latest commands, steps the world, then
//! publishes the wrist samples taken meanwhile, the transforms and joints, a frame if one was asked
//! for, and last the clock.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector2, Vector3};
use nudge_executive::robot::{RangeCamera, RobotError, WristSensor};
use nudge_ros2::config::Ros2Config;
use nudge_ros2::convert::{point_cloud, seconds, time_from_seconds, transform, wrench};
use nudge_ros2::msg::{
    Clock, Header, JointState, JointTrajectory, PointCloud2, TFMessage, Time, TransformStamped,
    Twist, TwistStamped, WrenchStamped,
};
use nudge_ros2::node::{DdsError, RosNode, RosPublisher, RosSubscription};

use crate::adapter::SimRobot;

/// Why the bridge stopped short.
#[derive(Debug, thiserror::Error)]
pub enum BridgeError {
    /// DDS could not be set up or used.
    #[error(transparent)]
    Dds(#[from] DdsError),
    /// The simulation failed.
    #[error("simulation: {0}")]
    Sim(#[from] RobotError),
}

/// A fault the bridge can put on the wire at a robot time, to test a client's handling of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BridgeFault {
    /// One wrist reading with a NaN force.
    NanWrench,
    /// One `/clock` a second behind the time reached.
    ClockBack,
    /// From then on the camera's transform keeps the stamp it had: every later frame's placement
    /// is stale.
    StaleCameraTransform,
    /// From then on nothing is published and no step is taken: a robot that went silent.
    Quiet,
}

impl std::str::FromStr for BridgeFault {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "nan-wrench" => Ok(Self::NanWrench),
            "clock-back" => Ok(Self::ClockBack),
            "stale-camera-tf" => Ok(Self::StaleCameraTransform),
            "quiet" => Ok(Self::Quiet),
            other => Err(format!(
                "`{other}` is not a bridge fault (nan-wrench, clock-back, stale-camera-tf, quiet)"
            )),
        }
    }
}

/// A fault and the robot time (s) it starts at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScheduledFault {
    /// What goes wrong.
    pub fault: BridgeFault,
    /// When (robot time, s).
    pub at: f64,
}

impl std::str::FromStr for ScheduledFault {
    type Err = String;

    /// `KIND@SECONDS`, e.g. `nan-wrench@38`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let (kind, at) = s
            .split_once('@')
            .ok_or_else(|| format!("`{s}` is not KIND@SECONDS"))?;
        let at: f64 = at
            .parse()
            .map_err(|_| format!("`{at}` in `{s}` is not a number of seconds"))?;
        if !(at.is_finite() && at >= 0.0) {
            return Err(format!(
                "`{s}`: the time must be a non-negative number of seconds"
            ));
        }
        Ok(Self {
            fault: kind.parse()?,
            at,
        })
    }
}

/// How the bridge lets time pass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Pace {
    /// Only when a client asks; the session ends once the client has been silent this long (wall).
    LockStep {
        /// Silence after which the session ends.
        idle: Duration,
    },
    /// By itself, at `factor` × real time (or as fast as the machine allows, when slower), until
    /// stopped or, with `until`, until that robot time.
    Free {
        /// Robot seconds per wall second.
        factor: f64,
        /// Robot time (s) at which the session ends.
        until: Option<f64>,
    },
}

/// Robot time a free-running bridge runs between two publications of its state (s): transforms,
/// joints and the clock at 100 Hz of robot time, every wrist sample all the same.
const FREE_PERIOD: f64 = 0.01;

/// How a bridge session ended.
#[derive(Clone, Debug, PartialEq)]
pub struct BridgeReport {
    /// Simulated time reached (s).
    pub robot_time: f64,
    /// Stretches of time run at a client's request.
    pub steps: u64,
    /// Frames rendered.
    pub frames: u64,
    /// Commands refused (out of limits, not finite), each said on stderr.
    pub refused: u64,
    /// How far the hand's command stood from its rest pose at the end (m): a client that ends a
    /// run safely leaves it at rest.
    pub hand_from_rest: f64,
}

struct Endpoints {
    clock: RosPublisher<Clock>,
    tf: RosPublisher<TFMessage>,
    joints: RosPublisher<JointState>,
    wrench: RosPublisher<WrenchStamped>,
    cloud: RosPublisher<PointCloud2>,
    cmd_vel: RosSubscription<Twist>,
    head: RosSubscription<JointTrajectory>,
    hand: RosSubscription<TwistStamped>,
    trigger: RosSubscription<Header>,
    step: RosSubscription<Clock>,
}

/// The simulated robot behind ROS 2 topics.
pub struct SimBridge {
    robot: SimRobot,
    config: Ros2Config,
    node: RosNode,
    io: Endpoints,
    frame_wanted: bool,
    report: BridgeReport,
    faults: Vec<ScheduledFault>,
    /// The camera transform's stamp once it froze.
    frozen_camera_stamp: Option<Time>,
    silent: bool,
}

impl SimBridge {
    /// Joins the ROS 2 graph as node `sim_bridge` with `robot` behind it.
    pub fn new(robot: SimRobot, config: Ros2Config) -> Result<Self, BridgeError> {
        let mut node = RosNode::new("nudge_sim_bridge", config.domain_id)?;
        let (t, sensor, command) = (&config.topics, config.qos.sensor, config.qos.command);
        let io = Endpoints {
            // The clock answers a step request: it goes reliably, like the commands.
            clock: node.publisher(&t.clock, command)?,
            tf: node.publisher(&t.tf, sensor)?,
            joints: node.publisher(&t.joint_states, sensor)?,
            // Up to a stretch's worth of samples go at once: the adapter's history for them.
            wrench: node.publisher(
                &t.wrench,
                nudge_ros2::adapter::wrench_qos(sensor, robot.world().robot_model()),
            )?,
            cloud: node.publisher(&t.cloud, sensor)?,
            cmd_vel: node.subscription(&t.cmd_vel, command)?,
            head: node.subscription(&t.head, command)?,
            hand: node.subscription(&t.hand, command)?,
            trigger: node.subscription(&t.camera_trigger, command)?,
            step: node.subscription(&t.step, command)?,
        };
        Ok(Self {
            robot,
            config,
            node,
            io,
            frame_wanted: false,
            report: BridgeReport {
                robot_time: 0.0,
                steps: 0,
                frames: 0,
                refused: 0,
                hand_from_rest: 0.0,
            },
            faults: Vec::new(),
            frozen_camera_stamp: None,
            silent: false,
        })
    }

    /// Puts `faults` on the wire at their times.
    pub fn with_faults(mut self, faults: Vec<ScheduledFault>) -> Self {
        self.faults = faults;
        self
    }

    /// Takes the faults due at the time reached, each once.
    fn due(&mut self) -> Vec<BridgeFault> {
        if self.faults.is_empty() {
            return Vec::new();
        }
        let now = self.robot.world().time();
        let (due, later): (Vec<_>, Vec<_>) = self.faults.iter().partition(|f| f.at <= now);
        self.faults = later;
        due.into_iter().map(|f| f.fault).collect()
    }

    /// The simulated robot, for its ground truth.
    pub fn robot(&self) -> &SimRobot {
        &self.robot
    }

    /// Serves until `stop` is set, or until `idle` passes (wall time) without a step request once
    /// a client has asked for one: a bridge ends when its client has gone.
    pub fn serve(
        &mut self,
        stop: &Arc<AtomicBool>,
        pace: Pace,
    ) -> Result<BridgeReport, BridgeError> {
        match pace {
            Pace::LockStep { idle } => self.lock_step(stop, idle)?,
            Pace::Free { factor, until } => self.free_run(stop, factor, until)?,
        }
        self.report.robot_time = self.robot.world().time();
        let humanoid = self.robot.world().humanoid();
        self.report.hand_from_rest = (humanoid.arm().command - humanoid.arm().rest()).norm();
        Ok(self.report.clone())
    }

    /// Runs on by itself at `factor` × real time, publishing every [`FREE_PERIOD`] of robot time.
    fn free_run(
        &mut self,
        stop: &Arc<AtomicBool>,
        factor: f64,
        until: Option<f64>,
    ) -> Result<(), BridgeError> {
        let started = Instant::now();
        let t0 = self.robot.world().time();
        while !stop.load(Ordering::Relaxed) {
            let now = self.robot.world().time();
            if until.is_some_and(|end| now >= end) {
                break;
            }
            // Step requests are a lock-stepped bridge's; here they are read and dropped.
            while self.io.step.take()?.is_some() {}
            self.take_commands();
            if self.silent {
                self.node.wait(Duration::from_millis(20));
                continue;
            }
            self.run_to(now + FREE_PERIOD)?;
            let due = Duration::from_secs_f64((self.robot.world().time() - t0) / factor);
            if let Some(ahead) = due.checked_sub(started.elapsed()) {
                self.node.wait(ahead);
            }
        }
        Ok(())
    }

    /// Runs only when asked, until the client has been silent for `idle`.
    fn lock_step(&mut self, stop: &Arc<AtomicBool>, idle: Duration) -> Result<(), BridgeError> {
        let mut last_request: Option<Instant> = None;
        while !stop.load(Ordering::Relaxed) {
            self.take_commands();
            let mut target = None;
            while let Some(m) = self.io.step.take()? {
                let t = seconds(&m.clock);
                target = Some(target.map_or(t, |old: f64| old.max(t)));
            }
            match target {
                Some(t) => {
                    last_request = Some(Instant::now());
                    if !self.silent {
                        self.take_commands();
                        self.run_to(t)?;
                    }
                }
                None => {
                    if last_request.is_some_and(|at| at.elapsed() >= idle) {
                        break;
                    }
                    self.node.wait(Duration::from_millis(20));
                }
            }
        }
        Ok(())
    }

    fn refused(&mut self, what: &str, why: impl std::fmt::Display) {
        self.report.refused += 1;
        eprintln!("sim-bridge: refused {what}: {why}");
    }

    /// Applies every command waiting; the latest of each kind wins.
    fn take_commands(&mut self) {
        while let Ok(Some(t)) = self.io.cmd_vel.take() {
            let linear = Vector2::new(t.linear.x, t.linear.y);
            if let Err(e) = self
                .robot
                .world_mut()
                .humanoid_mut()
                .command_velocity(linear, t.angular.z)
            {
                self.refused("a base velocity", e);
            }
        }
        while let Ok(Some(t)) = self.io.hand.take() {
            let v = Vector3::new(t.twist.linear.x, t.twist.linear.y, t.twist.linear.z);
            if v.iter().all(|c| c.is_finite()) {
                self.robot
                    .world_mut()
                    .humanoid_mut()
                    .arm_mut()
                    .set_velocity(v);
            } else {
                self.refused("a hand velocity", format!("{v:?} is not finite"));
            }
        }
        while let Ok(Some(trajectory)) = self.io.head.take() {
            self.point_head(&trajectory);
        }
        while let Ok(Some(_)) = self.io.trigger.take() {
            self.frame_wanted = true;
        }
    }

    /// Points the head at the trajectory's last point (the simulated head moves at its own rate).
    fn point_head(&mut self, trajectory: &JointTrajectory) {
        let names = &self.config.head_joints;
        let Some(last) = trajectory.points.last() else {
            return;
        };
        let at = |name: &str| {
            trajectory
                .joint_names
                .iter()
                .position(|n| n == name)
                .and_then(|i| last.positions.get(i).copied())
        };
        match (at(&names.pan), at(&names.tilt)) {
            (Some(pan), Some(tilt)) => {
                if let Err(e) = self.robot.world_mut().humanoid_mut().point_head(pan, tilt) {
                    self.refused("a head trajectory", e);
                }
            }
            _ => self.refused(
                "a head trajectory",
                format!("it names neither {} nor {}", names.pan, names.tilt),
            ),
        }
    }

    /// Runs the world to `t` (nothing to run when it is there already) and publishes the state.
    fn run_to(&mut self, t: f64) -> Result<(), BridgeError> {
        let now = self.robot.world().time();
        if t > now {
            nudge_executive::robot::Clock::advance(&mut self.robot, t - now)?;
            self.report.steps += 1;
        }
        self.publish_state()
    }

    fn stamp(&self) -> Time {
        time_from_seconds(self.robot.world().time()).unwrap_or_default()
    }

    fn publish_state(&mut self) -> Result<(), BridgeError> {
        let stamp = self.stamp();
        let frames = self.config.frames.clone();
        let due = self.due();
        if due.contains(&BridgeFault::Quiet) {
            self.silent = true;
            return Ok(());
        }
        if due.contains(&BridgeFault::StaleCameraTransform) {
            self.frozen_camera_stamp = Some(stamp);
        }
        if due.contains(&BridgeFault::NanWrench) {
            let mut w = nudge_executive::robot::Wrench::default();
            w.force.x = f64::NAN;
            self.io.wrench.publish(WrenchStamped {
                header: Header {
                    stamp,
                    frame_id: frames.hand.as_str().into(),
                },
                wrench: wrench(&w),
            })?;
        }
        if due.contains(&BridgeFault::ClockBack) {
            let back = time_from_seconds((self.robot.world().time() - 1.0).max(0.0));
            self.io.clock.publish(Clock {
                clock: back.unwrap_or_default(),
            })?;
        }
        for sample in self.robot.drain_wrenches()? {
            self.io.wrench.publish(WrenchStamped {
                header: Header {
                    stamp: time_from_seconds(sample.stamp).unwrap_or_default(),
                    frame_id: frames.hand.as_str().into(),
                },
                wrench: wrench(&sample.value),
            })?;
        }
        let world = self.robot.world();
        let humanoid = world.humanoid();
        let base = humanoid.base_pose();
        let base3 = Isometry3::from_parts(
            Translation3::new(base.translation.x, base.translation.y, 0.0),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), base.rotation.angle()),
        );
        let camera = base3.inverse() * humanoid.sensor_pose();
        let hand = Isometry3::from_parts(
            Translation3::from(humanoid.hand_position(world.physics()).coords),
            UnitQuaternion::identity(),
        );
        let camera_stamp = self.frozen_camera_stamp.unwrap_or(stamp);
        let edge =
            |parent: &str, child: &str, pose: &Isometry3<f64>, stamp: Time| TransformStamped {
                header: Header {
                    stamp,
                    frame_id: parent.into(),
                },
                child_frame_id: child.into(),
                transform: transform(pose),
            };
        let head = humanoid.head();
        let (pan, tilt, moving) = (head.pan, head.tilt, head.is_moving());
        self.io.tf.publish(TFMessage {
            transforms: vec![
                edge(frames.map.as_str(), frames.base.as_str(), &base3, stamp),
                edge(
                    frames.base.as_str(),
                    frames.camera.as_str(),
                    &camera,
                    camera_stamp,
                ),
                edge(frames.base.as_str(), frames.hand.as_str(), &hand, stamp),
            ],
        })?;
        self.io.joints.publish(JointState {
            header: Header {
                stamp,
                frame_id: String::new(),
            },
            name: vec![
                self.config.head_joints.pan.clone(),
                self.config.head_joints.tilt.clone(),
            ],
            position: vec![pan, tilt],
            velocity: if moving { vec![] } else { vec![0.0, 0.0] },
            effort: vec![],
        })?;
        if std::mem::take(&mut self.frame_wanted) {
            let cloud = self.robot.capture()?;
            self.report.frames += 1;
            self.io
                .cloud
                .publish(point_cloud(&cloud, stamp, frames.camera.as_str()))?;
        }
        self.io.clock.publish(Clock { clock: stamp })?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fault_specs_parse_or_say_what_is_wrong() {
        // Invariant: KIND@SECONDS parses for the four kinds; a missing @, an unknown kind, a bad or negative time is refused with the reason.
        assert_eq!(
            "nan-wrench@38.5".parse(),
            Ok(ScheduledFault {
                fault: BridgeFault::NanWrench,
                at: 38.5
            })
        );
        for kind in ["clock-back", "stale-camera-tf", "quiet"] {
            assert!(
                format!("{kind}@0").parse::<ScheduledFault>().is_ok(),
                "{kind}"
            );
        }
        for (bad, why) in [
            ("nan-wrench", "is not KIND@SECONDS"),
            ("sparks@3", "is not a bridge fault"),
            ("quiet@soon", "is not a number"),
            ("quiet@-1", "non-negative"),
        ] {
            let err = bad.parse::<ScheduledFault>().expect_err(bad);
            assert!(err.contains(why), "{bad}: {err}");
        }
    }
}
