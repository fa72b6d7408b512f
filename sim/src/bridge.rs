//! `nudge sim-bridge`: the simulation as a ROS 2 robot. It takes the commands a robot's controllers
//! take (`/cmd_vel`, a head joint trajectory, a Cartesian hand velocity, a camera trigger) and
//! publishes what a robot publishes (`/clock`, `/tf`, `/joint_states`, the wrist's
//! `WrenchStamped` at its sample rate, `PointCloud2` frames), on the topics a [`Ros2Config`] names.
//!
//! It is lock-stepped: time runs only when a client asks it to run to a time (the config's `step`
//! topic), so a run over DDS is the in-process run's physics however slow or loaded the machine.
//! Each stretch it applies the latest commands, steps the world, then publishes the wrist samples
//! taken meanwhile, the transforms and joints, a frame if one was asked for, and last the clock.

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
            // Up to a stretch's worth of samples go at once: keep them all for a best-effort reader.
            wrench: node.publisher(&t.wrench, sensor)?,
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
            },
        })
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
        idle: Duration,
    ) -> Result<BridgeReport, BridgeError> {
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
                    self.take_commands();
                    self.run_to(t)?;
                }
                None => {
                    if last_request.is_some_and(|at| at.elapsed() >= idle) {
                        break;
                    }
                    self.node.wait(Duration::from_millis(20));
                }
            }
        }
        self.report.robot_time = self.robot.world().time();
        Ok(self.report.clone())
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
        let edge = |parent: &str, child: &str, pose: &Isometry3<f64>| TransformStamped {
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
                edge(frames.map.as_str(), frames.base.as_str(), &base3),
                edge(frames.base.as_str(), frames.camera.as_str(), &camera),
                edge(frames.base.as_str(), frames.hand.as_str(), &hand),
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
