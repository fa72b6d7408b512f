//! `SimRobot`: the simulated world behind the executive's adapter traits. Time is simulated time
//! only; actions start here and progress while [`Clock::advance`] steps the physics.

use nalgebra::{Isometry2, Point2, Point3};
use nudge_executive::robot::{
    ActionStatus, Arm, Base, Clock, GuardedMove, HandOutcome, Head, RangeCamera, RobotError,
    Stamped, WalkOutcome, Wrench, WristSensor,
};
use nudge_perception::ColourCloud;

use crate::scenario::Scenario;
use crate::sensors::colour_range::{ColourRangeConfig, ColourRangeSensor};
use crate::world::{World, WorldError};
use nudge_executive::robot::controller::Walk;

/// The simulated robot: owns the world it lives in.
pub struct SimRobot {
    world: World,
    range: ColourRangeSensor,
    frames: u64,
}

impl SimRobot {
    /// A robot in a new world built from `scenario` with `seed`.
    pub fn new(scenario: &Scenario, seed: u64) -> Result<Self, WorldError> {
        Ok(Self::from_world(World::new(scenario, seed)?))
    }

    /// A robot in an existing world, with a range sensor of its robot's camera.
    pub fn from_world(world: World) -> Self {
        let camera = ColourRangeConfig::for_camera(&world.robot_model().camera);
        Self::with_range_sensor(world, ColourRangeSensor::new(camera))
    }

    /// A robot in an existing world with a chosen range sensor.
    pub fn with_range_sensor(world: World, range: ColourRangeSensor) -> Self {
        Self {
            world,
            range,
            frames: 0,
        }
    }

    /// The world, for ground truth and recording.
    pub fn world(&self) -> &World {
        &self.world
    }

    /// The world, mutably (tests, scripted disturbances).
    pub fn world_mut(&mut self) -> &mut World {
        &mut self.world
    }

    /// The range sensor model.
    pub fn range_sensor(&self) -> &ColourRangeSensor {
        &self.range
    }

    /// How many range frames were captured.
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// Who owns the surface each pixel of a capture from the head's current pose returns
    /// ([`ColourRangeSensor::owners`]): ground truth for scoring a segmentation. Taken before or
    /// after [`RangeCamera::capture`] with the world unchanged, it matches that capture pixel for
    /// pixel.
    pub fn owners(&self) -> Vec<Option<crate::surface::Owner>> {
        let pose = self.world.humanoid().sensor_pose();
        self.world
            .in_sensor_scene(|scene| self.range.owners(scene, &pose))
    }

    fn stamp<T>(&self, value: T) -> Stamped<T> {
        Stamped {
            stamp: self.world.time(),
            value,
        }
    }
}

fn refused(capability: &'static str) -> impl Fn(crate::humanoid::Refused) -> RobotError {
    move |e| RobotError::Refused {
        capability,
        reason: e.0,
    }
}

impl Clock for SimRobot {
    fn now(&self) -> f64 {
        self.world.time()
    }

    fn advance(&mut self, dt: f64) -> Result<(), RobotError> {
        self.world.advance(dt).map_err(|e| RobotError::Refused {
            capability: "clock",
            reason: e.to_string(),
        })
    }
}

impl Base for SimRobot {
    fn base_pose(&mut self) -> Result<Stamped<Isometry2<f64>>, RobotError> {
        Ok(self.stamp(self.world.humanoid().base_pose()))
    }

    fn start_walk(&mut self, waypoints: &[Point2<f64>]) -> Result<(), RobotError> {
        self.world
            .humanoid_mut()
            .start_walk(waypoints)
            .map_err(refused("base"))
    }

    fn start_turn(&mut self, yaw: f64) -> Result<(), RobotError> {
        self.world
            .humanoid_mut()
            .start_turn(yaw)
            .map_err(refused("base"))
    }

    fn walk_status(&mut self) -> Result<ActionStatus<WalkOutcome>, RobotError> {
        Ok(match self.world.humanoid().walk() {
            Walk::Idle(outcome) => {
                ActionStatus::Done(outcome.clone().unwrap_or(WalkOutcome::Arrived))
            }
            _ => ActionStatus::Running,
        })
    }

    fn stop_walk(&mut self) -> Result<(), RobotError> {
        self.world.humanoid_mut().stop_walk();
        Ok(())
    }
}

impl Head for SimRobot {
    fn head_angles(&mut self) -> Result<Stamped<(f64, f64)>, RobotError> {
        let h = self.world.humanoid().head();
        Ok(self.stamp((h.pan, h.tilt)))
    }

    fn start_point_head(&mut self, pan: f64, tilt: f64) -> Result<(), RobotError> {
        self.world
            .humanoid_mut()
            .point_head(pan, tilt)
            .map_err(refused("head"))
    }

    fn head_status(&mut self) -> Result<ActionStatus<()>, RobotError> {
        Ok(if self.world.humanoid().head().is_moving() {
            ActionStatus::Running
        } else {
            ActionStatus::Done(())
        })
    }
}

impl WristSensor for SimRobot {
    fn tare(&mut self) -> Result<(), RobotError> {
        self.world.tare_wrist();
        Ok(())
    }

    fn wrench(&mut self) -> Result<Stamped<Wrench>, RobotError> {
        Ok(self.world.wrist_reading())
    }

    fn drain_wrenches(&mut self) -> Result<Vec<Stamped<Wrench>>, RobotError> {
        Ok(self.world.wrist_sensor().drain())
    }

    fn discard_wrenches(&mut self) -> Result<(), RobotError> {
        self.world.wrist_sensor().discard();
        Ok(())
    }
}

impl Arm for SimRobot {
    fn hand_position(&mut self) -> Result<Stamped<Point3<f64>>, RobotError> {
        let p = self.world.humanoid().hand_position(self.world.physics());
        Ok(self.stamp(p))
    }

    fn start_guarded_move(&mut self, motion: GuardedMove) -> Result<(), RobotError> {
        self.world
            .humanoid_mut()
            .arm_mut()
            .start_guarded(motion)
            .map_err(|reason| RobotError::Refused {
                capability: "arm",
                reason,
            })
    }

    fn start_retract(&mut self) -> Result<(), RobotError> {
        self.world.humanoid_mut().arm_mut().start_retract();
        Ok(())
    }

    fn hand_status(&mut self) -> Result<ActionStatus<HandOutcome>, RobotError> {
        Ok(self.world.humanoid().arm().status())
    }

    fn stop_hand(&mut self) -> Result<(), RobotError> {
        self.world.humanoid_mut().arm_mut().stop();
        Ok(())
    }
}

impl RangeCamera for SimRobot {
    /// One frame from the head's current pose. The robot's bounding body is invisible to it; the
    /// hand occludes but its own returns are self-filtered (lost pixels). Noise is fixed by the
    /// world's seed and the frame number, so a run is the same every time.
    fn capture(&mut self) -> Result<ColourCloud, RobotError> {
        let world = &self.world;
        let pose = world.humanoid().sensor_pose();
        let (stamp, seed) = (world.time(), frame_seed(world.seed(), self.frames));
        let cloud = self
            .world
            .in_sensor_scene(|scene| self.range.capture(scene, &pose, stamp, seed));
        self.frames += 1;
        Ok(cloud)
    }
}

/// The noise seed of frame `frame` of a run with `seed` (SplitMix64 of the pair).
fn frame_seed(seed: u64, frame: u64) -> u64 {
    let mut z = seed ^ frame.wrapping_add(1).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}
