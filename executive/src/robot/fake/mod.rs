//! A scripted in-memory robot for unit tests: no physics, no sensors, just the adapter contract.
//!
//! It walks straight lines at a fixed speed (through anything; a walk can be scripted to stop
//! blocked), turns at a fixed rate, moves the head at a fixed rate, and answers guarded moves from a
//! scripted object: a static one (a stiff spring), a sliding one (constant friction force) or one
//! that slides and then jams. The object is either put in front of the hand for every move
//! ([`FakeRobot::set_object`]) or met where it stands in a scripted world of boxes
//! ([`FakeRobot::set_scene`]), which the camera then shows, moved by the pushes, as organised colour
//! clouds. Clouds can also be queued. Failures can be injected per capability. Time passes only
//! through [`Clock::advance`], in 1 ms substeps (the wrist rate).

mod object;
mod render;
mod scene;

use object::Contact;
pub use object::{ObjectResponse, ScriptedObject};
pub use render::FakeCamera;
pub use scene::{FakeScene, SceneBox};

use std::collections::{BTreeMap, VecDeque};

use nalgebra::{
    Isometry2, Isometry3, Point2, Point3, Translation3, UnitQuaternion, Vector2, Vector3,
};
use nudge_perception::{CloudFrame, ColourCloud};
use nudge_robot_model::RobotModel;

use super::{
    ActionStatus, Arm, Base, Clock, GuardedMove, HandOutcome, Head, RangeCamera, RobotError,
    Stamped, WalkOutcome, Wrench, WristSensor,
};

/// Substep of the fake's simulation and period of its wrist sensor (s).
const SUBSTEP: f64 = 0.001;

#[derive(Clone, Debug)]
enum BaseMotion {
    Walk(VecDeque<Point2<f64>>),
    Turn(f64),
}

#[derive(Clone, Debug)]
enum HandMotion {
    Guarded {
        motion: GuardedMove,
        travelled: f64,
        /// Hand speed along the line now (m/s): it ramps up at the move's acceleration, if any.
        speed: f64,
        approach_done: bool,
    },
    Retract,
}

/// The largest contact force one guarded move met, beside the limit it was given: the ground truth
/// a fault test checks the force against, whatever the wrist readings said.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForcePeak {
    /// The move's force limit (N).
    pub force_limit: f64,
    /// The largest contact force on the hand during the move (N), bias and tare left out.
    pub peak: f64,
}

/// The scripted fake robot.
#[derive(Clone, Debug)]
pub struct FakeRobot {
    now: f64,
    pose: Isometry2<f64>,
    walk_speed: f64,
    turn_rate: f64,
    /// Height of the head's pan/tilt centre, where the camera sits (m).
    eye_height: f64,
    base_motion: Option<BaseMotion>,
    base_done: Option<WalkOutcome>,
    walked: f64,
    block_after: Option<f64>,
    head: (f64, f64),
    head_target: Option<(f64, f64)>,
    head_rate: f64,
    clouds: VecDeque<ColourCloud>,
    hand_pos: Point3<f64>,
    hand_rest: Point3<f64>,
    hand_motion: Option<HandMotion>,
    hand_done: Option<HandOutcome>,
    object: Option<ScriptedObject>,
    scene: Option<FakeScene>,
    contact: Option<Contact>,
    force: Vector3<f64>,
    bias: Vector3<f64>,
    tare: Vector3<f64>,
    samples: Vec<Stamped<Wrench>>,
    peaks: Vec<ForcePeak>,
    failures: BTreeMap<&'static str, RobotError>,
    calls: Vec<String>,
}

impl FakeRobot {
    /// The paper's robot ([`RobotModel::default`]) standing at `pose`.
    pub fn new(pose: Isometry2<f64>) -> Self {
        Self::with_model(pose, &RobotModel::default())
    }

    /// A fake `model` standing at `pose`: its gait, head, hand rest and camera height are the model's
    /// (a scene's camera image is the scene's, [`FakeScene::camera`]).
    pub fn with_model(pose: Isometry2<f64>, model: &RobotModel) -> Self {
        let [x, y, z] = model.arm.rest;
        let hand_rest = Point3::new(x, y, z);
        Self {
            now: 0.0,
            pose,
            walk_speed: model.body.walk_speed,
            turn_rate: model.body.turn_rate,
            eye_height: model.head.height,
            base_motion: None,
            base_done: None,
            walked: 0.0,
            block_after: None,
            head: (0.0, 0.0),
            head_target: None,
            head_rate: model.head.rate,
            clouds: VecDeque::new(),
            hand_pos: hand_rest,
            hand_rest,
            hand_motion: None,
            hand_done: None,
            object: None,
            scene: None,
            contact: None,
            force: Vector3::zeros(),
            bias: Vector3::new(0.8, -0.4, 1.1),
            tare: Vector3::zeros(),
            samples: Vec::new(),
            peaks: Vec::new(),
            failures: BTreeMap::new(),
            calls: Vec::new(),
        }
    }

    /// Queues a cloud for the next [`RangeCamera::capture`].
    pub fn queue_cloud(&mut self, cloud: ColourCloud) {
        self.clouds.push_back(cloud);
    }

    /// Puts a scripted object in front of the hand for the next guarded moves (`None` removes it).
    /// It takes precedence over the scene's boxes.
    pub fn set_object(&mut self, object: Option<ScriptedObject>) {
        self.object = object;
    }

    /// Puts the robot in a scripted world: the camera shows it (when no cloud is queued) and guarded
    /// moves meet its boxes where they stand.
    pub fn set_scene(&mut self, scene: FakeScene) {
        self.scene = Some(scene);
    }

    /// The scripted world as it is now (boxes where the pushes left them): the ground truth.
    pub fn scene(&self) -> Option<&FakeScene> {
        self.scene.as_ref()
    }

    /// Makes the next walk stop, blocked, after `distance` metres.
    pub fn block_next_walk_after(&mut self, distance: f64) {
        self.block_after = Some(distance);
    }

    /// Makes the next call to `capability` ("base", "head", "camera", "wrist", "arm", "clock") fail.
    pub fn fail_next(&mut self, capability: &'static str, error: RobotError) {
        self.failures.insert(capability, error);
    }

    /// Every guarded move started so far, in order: its force limit and the largest contact force it
    /// met.
    pub fn force_peaks(&self) -> &[ForcePeak] {
        &self.peaks
    }

    /// True when the hand stands still at its rest pose beside the body (retracted).
    pub fn hand_at_rest(&self) -> bool {
        self.hand_motion.is_none() && self.hand_pos == self.hand_rest
    }

    /// Every adapter call made so far, in order, e.g. `"start_walk 2"`.
    pub fn calls(&self) -> &[String] {
        &self.calls
    }

    fn call(&mut self, capability: &'static str, what: String) -> Result<(), RobotError> {
        self.calls.push(what);
        self.failures.remove(capability).map_or(Ok(()), Err)
    }

    /// What `motion` will meet: the scripted object in front of the hand, else the first scene box
    /// on its line (cast from the base as it stands now).
    fn contact_for(&self, motion: &GuardedMove) -> Option<Contact> {
        let dir = motion.direction()?;
        let map_dir = self.pose.rotation * Vector2::new(dir.x, dir.y);
        if let Some(object) = self.object {
            return Some(Contact {
                at: object.contact_at,
                response: object.response,
                give: object.response.give(0.0),
                target: None,
                direction: map_dir,
                pushed: 0.0,
            });
        }
        let scene = self.scene.as_ref()?;
        let from = self.pose * Point2::new(motion.from.x, motion.from.y);
        let horizontal = map_dir.try_normalize(1e-9)?;
        let (i, t) = scene.first_hit(&from, &horizontal, motion.from.z)?;
        // Along the line, not its horizontal part: the same for the level pushes the runner makes.
        let at = t / map_dir.norm().max(1e-9);
        let target = &scene.boxes[i];
        Some(Contact {
            at,
            response: target.response,
            give: target.response.give(target.moved),
            target: Some(i),
            direction: horizontal,
            pushed: 0.0,
        })
    }

    fn sensor_pose(&self) -> Isometry3<f64> {
        let yaw = self.pose.rotation.angle() + self.head.0;
        let t = self.pose.translation.vector;
        Isometry3::from_parts(
            Translation3::new(t.x, t.y, self.eye_height),
            UnitQuaternion::from_euler_angles(0.0, self.head.1, yaw),
        )
    }

    fn substep(&mut self) {
        self.now += SUBSTEP;
        self.step_head();
        self.step_base();
        self.step_hand();
        let wrench = Wrench {
            force: self.force + self.bias - self.tare,
            torque: Vector3::zeros(),
        };
        self.samples.push(Stamped {
            stamp: self.now,
            value: wrench,
        });
    }

    fn step_head(&mut self) {
        let Some((pan, tilt)) = self.head_target else {
            return;
        };
        let max = self.head_rate * SUBSTEP;
        self.head.0 += (pan - self.head.0).clamp(-max, max);
        self.head.1 += (tilt - self.head.1).clamp(-max, max);
        if (self.head.0 - pan).abs() < 1e-9 && (self.head.1 - tilt).abs() < 1e-9 {
            self.head_target = None;
        }
    }

    fn step_base(&mut self) {
        let Some(motion) = self.base_motion.as_mut() else {
            return;
        };
        match motion {
            BaseMotion::Turn(yaw) => {
                let yaw = *yaw;
                if turn_towards(&mut self.pose, yaw, self.turn_rate * SUBSTEP) {
                    self.finish_walk(WalkOutcome::Arrived);
                }
            }
            BaseMotion::Walk(waypoints) => {
                let Some(&next) = waypoints.front() else {
                    self.finish_walk(WalkOutcome::Arrived);
                    return;
                };
                let here = Point2::from(self.pose.translation.vector);
                let to_next: Vector2<f64> = next - here;
                let yaw = to_next.y.atan2(to_next.x);
                if to_next.norm() > 1e-9
                    && !turn_towards(&mut self.pose, yaw, self.turn_rate * SUBSTEP)
                {
                    return;
                }
                let stepped = (self.walk_speed * SUBSTEP).min(to_next.norm());
                if self.block_after.is_some_and(|d| self.walked + stepped > d) {
                    self.block_after = None;
                    let at = self.pose;
                    self.finish_walk(WalkOutcome::Blocked { at });
                    return;
                }
                self.walked += stepped;
                if to_next.norm() > 1e-12 {
                    self.pose.translation.vector += to_next.normalize() * stepped;
                }
                if (next - Point2::from(self.pose.translation.vector)).norm() < 1e-9 {
                    waypoints.pop_front();
                }
            }
        }
    }

    fn finish_walk(&mut self, outcome: WalkOutcome) {
        self.base_motion = None;
        self.base_done = Some(outcome);
    }

    fn step_hand(&mut self) {
        self.force = Vector3::zeros();
        let Some(motion) = self.hand_motion.as_mut() else {
            return;
        };
        match motion {
            HandMotion::Retract => {
                if move_towards(&mut self.hand_pos, self.hand_rest, 0.3 * SUBSTEP) {
                    self.hand_motion = None;
                    self.hand_done = Some(HandOutcome::Reached);
                }
            }
            HandMotion::Guarded {
                motion,
                travelled,
                speed,
                approach_done,
            } => {
                if !*approach_done {
                    *approach_done = move_towards(&mut self.hand_pos, motion.from, 0.3 * SUBSTEP);
                    return;
                }
                let Some(dir) = motion.direction() else {
                    self.hand_motion = None;
                    self.hand_done = Some(HandOutcome::Reached);
                    return;
                };
                let length = (motion.to - motion.from).norm();
                *speed = motion
                    .acceleration
                    .map_or(motion.speed, |a| (*speed + a * SUBSTEP).min(motion.speed));
                let next = (*travelled + *speed * SUBSTEP).min(length);
                let (force, holds) = self.contact.map_or((0.0, false), |c| {
                    let depth = next - c.at;
                    (c.response.force(depth, c.give), depth > c.give)
                });
                let limit = motion.force_limit;
                let stopped = holds && force >= limit;
                let travel = if stopped { *travelled } else { next };
                *travelled = travel;
                if let Some(c) = self.contact.as_mut() {
                    let pushed = (travel - c.at).clamp(0.0, c.give);
                    if let (Some(i), Some(scene)) = (c.target, self.scene.as_mut())
                        && pushed > c.pushed
                    {
                        scene.boxes[i].shift(&(c.direction * (pushed - c.pushed)));
                    }
                    c.pushed = pushed;
                }
                self.hand_pos = motion.from + dir * travel;
                self.force = -dir * force;
                if let Some(p) = self.peaks.last_mut() {
                    p.peak = p.peak.max(force);
                }
                let tared = (self.force + self.bias - self.tare).norm();
                // A hand the guard held back reports the limit even where the tared norm rounds a
                // hair under it (a line with a vertical part): else it would stand still, running,
                // for ever.
                if stopped || tared >= limit {
                    let wrench = Stamped {
                        stamp: self.now,
                        value: Wrench {
                            force: self.force + self.bias - self.tare,
                            torque: Vector3::zeros(),
                        },
                    };
                    let at = self.hand_pos;
                    self.hand_motion = None;
                    self.hand_done = Some(HandOutcome::ForceLimit { wrench, at });
                } else if travel >= length {
                    self.hand_motion = None;
                    self.hand_done = Some(HandOutcome::Reached);
                }
            }
        }
    }
}

/// Turns `pose` towards `yaw` by at most `max` rad; true once facing it.
fn turn_towards(pose: &mut Isometry2<f64>, yaw: f64, max: f64) -> bool {
    let current = pose.rotation.angle();
    let error = (yaw - current + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
        - std::f64::consts::PI;
    let turn = error.clamp(-max, max);
    pose.rotation = nalgebra::UnitComplex::new(current + turn);
    (error - turn).abs() < 1e-9
}

/// Moves `p` towards `target` by at most `max` m; true once there.
fn move_towards(p: &mut Point3<f64>, target: Point3<f64>, max: f64) -> bool {
    let d = target - *p;
    if d.norm() <= max {
        *p = target;
        true
    } else {
        *p += d.normalize() * max;
        false
    }
}

impl Clock for FakeRobot {
    fn now(&self) -> f64 {
        self.now
    }

    fn advance(&mut self, dt: f64) -> Result<(), RobotError> {
        self.call("clock", format!("advance {dt}"))?;
        let steps = (dt / SUBSTEP).round().max(1.0) as u64;
        for _ in 0..steps {
            self.substep();
        }
        Ok(())
    }
}

impl Base for FakeRobot {
    fn base_pose(&mut self) -> Result<Stamped<Isometry2<f64>>, RobotError> {
        self.call("base", "base_pose".into())?;
        Ok(Stamped {
            stamp: self.now,
            value: self.pose,
        })
    }

    fn start_walk(&mut self, waypoints: &[Point2<f64>]) -> Result<(), RobotError> {
        self.call("base", format!("start_walk {}", waypoints.len()))?;
        self.walked = 0.0;
        self.base_done = None;
        self.base_motion = Some(BaseMotion::Walk(waypoints.iter().copied().collect()));
        Ok(())
    }

    fn start_turn(&mut self, yaw: f64) -> Result<(), RobotError> {
        self.call("base", format!("start_turn {yaw:.3}"))?;
        self.base_done = None;
        self.base_motion = Some(BaseMotion::Turn(yaw));
        Ok(())
    }

    fn walk_status(&mut self) -> Result<ActionStatus<WalkOutcome>, RobotError> {
        self.call("base", "walk_status".into())?;
        Ok(match (&self.base_motion, &self.base_done) {
            (Some(_), _) => ActionStatus::Running,
            (None, Some(outcome)) => ActionStatus::Done(outcome.clone()),
            (None, None) => ActionStatus::Done(WalkOutcome::Arrived),
        })
    }

    fn stop_walk(&mut self) -> Result<(), RobotError> {
        self.call("base", "stop_walk".into())?;
        if self.base_motion.take().is_some() {
            self.base_done = Some(WalkOutcome::Stopped);
        }
        Ok(())
    }
}

impl Head for FakeRobot {
    fn head_angles(&mut self) -> Result<Stamped<(f64, f64)>, RobotError> {
        self.call("head", "head_angles".into())?;
        Ok(Stamped {
            stamp: self.now,
            value: self.head,
        })
    }

    fn start_point_head(&mut self, pan: f64, tilt: f64) -> Result<(), RobotError> {
        self.call("head", format!("start_point_head {pan:.3} {tilt:.3}"))?;
        self.head_target = Some((pan, tilt));
        Ok(())
    }

    fn head_status(&mut self) -> Result<ActionStatus<()>, RobotError> {
        self.call("head", "head_status".into())?;
        Ok(if self.head_target.is_some() {
            ActionStatus::Running
        } else {
            ActionStatus::Done(())
        })
    }
}

impl RangeCamera for FakeRobot {
    fn capture(&mut self) -> Result<ColourCloud, RobotError> {
        self.call("camera", "capture".into())?;
        let pose = self.sensor_pose();
        Ok(match (self.clouds.pop_front(), &self.scene) {
            (Some(cloud), _) => cloud,
            (None, Some(scene)) => render::render(scene, &pose, self.now),
            (None, None) => ColourCloud::empty(CloudFrame::Sensor, pose, self.now),
        })
    }
}

impl WristSensor for FakeRobot {
    fn tare(&mut self) -> Result<(), RobotError> {
        self.call("wrist", "tare".into())?;
        self.tare = self.force + self.bias;
        Ok(())
    }

    fn wrench(&mut self) -> Result<Stamped<Wrench>, RobotError> {
        self.call("wrist", "wrench".into())?;
        Ok(Stamped {
            stamp: self.now,
            value: Wrench {
                force: self.force + self.bias - self.tare,
                torque: Vector3::zeros(),
            },
        })
    }

    fn drain_wrenches(&mut self) -> Result<Vec<Stamped<Wrench>>, RobotError> {
        self.call("wrist", "drain_wrenches".into())?;
        Ok(std::mem::take(&mut self.samples))
    }

    fn discard_wrenches(&mut self) -> Result<(), RobotError> {
        self.call("wrist", "discard_wrenches".into())?;
        self.samples.clear();
        Ok(())
    }
}

impl Arm for FakeRobot {
    fn hand_position(&mut self) -> Result<Stamped<Point3<f64>>, RobotError> {
        self.call("arm", "hand_position".into())?;
        Ok(Stamped {
            stamp: self.now,
            value: self.hand_pos,
        })
    }

    fn start_guarded_move(&mut self, motion: GuardedMove) -> Result<(), RobotError> {
        self.call("arm", "start_guarded_move".into())?;
        if !(motion.speed > 0.0
            && motion.force_limit > 0.0
            && motion.acceleration.is_none_or(|a| a > 0.0))
        {
            return Err(RobotError::Refused {
                capability: "arm",
                reason: format!(
                    "speed {}, force limit {} and acceleration {:?} must be positive",
                    motion.speed, motion.force_limit, motion.acceleration
                ),
            });
        }
        self.hand_done = None;
        self.contact = self.contact_for(&motion);
        self.peaks.push(ForcePeak {
            force_limit: motion.force_limit,
            peak: 0.0,
        });
        self.hand_motion = Some(HandMotion::Guarded {
            motion,
            travelled: 0.0,
            speed: 0.0,
            approach_done: false,
        });
        Ok(())
    }

    fn start_retract(&mut self) -> Result<(), RobotError> {
        self.call("arm", "start_retract".into())?;
        self.hand_done = None;
        self.hand_motion = Some(HandMotion::Retract);
        Ok(())
    }

    fn hand_status(&mut self) -> Result<ActionStatus<HandOutcome>, RobotError> {
        self.call("arm", "hand_status".into())?;
        Ok(match (&self.hand_motion, &self.hand_done) {
            (Some(_), _) => ActionStatus::Running,
            (None, Some(outcome)) => ActionStatus::Done(outcome.clone()),
            (None, None) => ActionStatus::Done(HandOutcome::Reached),
        })
    }

    fn stop_hand(&mut self) -> Result<(), RobotError> {
        self.call("arm", "stop_hand".into())?;
        if self.hand_motion.take().is_some() {
            self.hand_done = Some(HandOutcome::Stopped);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;
