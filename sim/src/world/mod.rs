//! The simulated world: a rapier scene built from a scenario (Z up), with the humanoid, the actors
//! and the wrist sensor, advanced in physics steps whose length adapts to what is going on.
//!
//! Stepping: 1 ms steps while the hand touches something, or is on a guarded line within
//! [`NEAR_CONTACT`] of something it could touch (the guarded-move check runs every step, and every
//! contact is resolved at the wrist sensor's 1 kHz); 10 ms steps otherwise, aligned to a 10 ms grid.
//! A steady push far below its guard's limit is the exception (see `World::steady_push`): once the
//! hand has pressed with at least the robot's contact threshold for [`STEADY_PRESS_US`] and the
//! force lies further below the limit than a 10 ms step can raise it (the guard's pace,
//! [`nudge_executive::robot::controller::steady_push`]), the
//! guard cannot be skipped, and a long clearing push is stepped in 10 ms steps made of ten fine
//! steps' solver substeps (same contact and wrist dynamics; collision detection, the guard and the
//! sensor's fresh value every 10 ms) until the force comes near its limit again.
//! A guarded line's first centimetres through free air are stepped like the unguarded move to its
//! start: nothing can touch the hand within a coarse step there, so no contact force is skipped.
//! When no body is commanded to move (the head has none) and every dynamic body sleeps, time passes
//! without a physics step. The wrist sensor samples at its own rate throughout, holding the last
//! step's wrench.

pub mod build;
pub mod convert;
pub mod effort;
mod pose_log;

use std::collections::HashMap;

use nalgebra::Isometry3;
use nudge_executive::robot::{Stamped, Wrench};
use rapier3d::parry::query;
use rapier3d::prelude::*;

use crate::actors::Actor;
use crate::humanoid::Humanoid;
use crate::scenario::{ObjectSpec, Scenario};
use crate::sensors::wrist_ft::{WristFt, WristFtConfig, WristFtError, wrench_on_wrist};
use crate::surface::Surface;
use convert::iso_from_pose;
use effort::Effort;
use nudge_executive::robot::controller::Walk;
use nudge_executive::robot::controller::{STEADY_PRESS_US, STEADY_STEP_US, steady_push};
use nudge_robot_model::RobotModel;

/// Physics step while the hand moves or touches (µs): the wrist sensor's 1 kHz.
pub const FINE_STEP_US: u64 = 1_000;
/// Solver substeps of a fine step: 1 ms is already short for the hand's 20 kN/m wrist (ω h ≈ 0.2).
/// A chair sliding at 5 cm/s reads 15.1 N against μ m g = 15.7 N, as with two substeps, which cost
/// a third more.
pub const FINE_SUBSTEPS: usize = 1;
/// Gauss–Seidel iterations in a fine step's substep. With one, the hand's impact on a 4 kg chair
/// rings higher: push tests of movable chairs peaked at 20.2 N and read static in 9 of 140 batch runs.
pub const FINE_PGS_ITERATIONS: usize = 2;
/// Solver substeps of a coarse step (rapier's default).
pub const COARSE_SUBSTEPS: usize = 4;
/// Physics step otherwise (µs): the pace at which a guard may read a steady push, so a steady push
/// is stepped coarsely.
pub const COARSE_STEP_US: u64 = STEADY_STEP_US;
/// A hand on a guarded line steps finely once anything it can touch is this close (m, between the
/// shapes). A coarse step moves the hand at most 5 mm along a line (0.5 m/s, the fastest guarded
/// move) plus 1.5 mm with the walking base: 1 cm is more than a coarse step of warning.
pub const NEAR_CONTACT: f32 = 0.01;
/// How far a contact pair may move before rapier recomputes its contact points (m).
pub const CONTACT_RECYCLE_DISTANCE: f32 = 0.002;
/// Tared wrist force at which a walk or turn stops at once, as a multiple of the push test's limit:
/// the hand, held out while walking, presses on something that does not give (60 N for the paper's
/// 20 N).
pub const HAND_OVERLOAD_FACTOR: f64 = 3.0;

/// How the next physics step is taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stepping {
    /// [`FINE_STEP_US`] long, one solver substep.
    Fine,
    /// Up to [`COARSE_STEP_US`] long, in fine steps' solver substeps: a steady push (see
    /// `World::steady_push`).
    Pressing,
    /// Up to [`COARSE_STEP_US`] long, [`COARSE_SUBSTEPS`] substeps.
    Coarse,
}

/// Why a world could not be built or advanced.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum WorldError {
    /// The room's numbers are unusable.
    #[error("invalid room: {0}")]
    InvalidRoom(String),
    /// An object's numbers are unusable.
    #[error("invalid object {name}: {reason}")]
    InvalidObject {
        /// The object's name.
        name: String,
        /// What is wrong.
        reason: String,
    },
    /// An actor's numbers are unusable.
    #[error("invalid actor {name}: {reason}")]
    InvalidActor {
        /// The actor's name.
        name: String,
        /// What is wrong.
        reason: String,
    },
    /// The robot's numbers are unusable.
    #[error("invalid robot: {0}")]
    InvalidRobot(String),
    /// The wrist sensor's parameters are unusable.
    #[error(transparent)]
    WristSensor(#[from] WristFtError),
    /// A time step was negative, not finite, or longer than a million seconds.
    #[error("invalid time step {0}")]
    InvalidStep(f64),
}

/// The simulated world.
pub struct World {
    physics: PhysicsWorld,
    surfaces: HashMap<ColliderHandle, Surface>,
    objects: Vec<(ObjectSpec, RigidBodyHandle)>,
    actors: Vec<Actor>,
    humanoid: Humanoid,
    wrist_ft: WristFt,
    /// The true wrench on the wrist during the last physics step.
    wrist_truth: Wrench,
    /// When the hand's current unbroken press began (µs): it touches something and the tared force
    /// is at least the robot's contact threshold.
    pressed_since_us: Option<u64>,
    time_us: u64,
    seed: u64,
    steps: u64,
    fine_steps: u64,
    room_size: [f64; 2],
    /// What the robot is.
    robot_model: RobotModel,
    effort: Effort,
    hand_touching: bool,
    touching_person: bool,
    /// Whether an object the hand pushes touched a person at the last step.
    pushed_touching_person: bool,
    /// Where each object stood over the run.
    pose_log: pose_log::PoseLog,
}

impl World {
    /// Builds the scenario's world; `seed` fixes every random choice (sensor noise, textures).
    pub fn new(scenario: &Scenario, seed: u64) -> Result<Self, WorldError> {
        let wrist = WristFtConfig::for_wrist(&scenario.robot.model().wrist);
        Self::with_wrist_config(scenario, seed, wrist)
    }

    /// Like [`World::new`] with a chosen wrist sensor.
    pub fn with_wrist_config(
        scenario: &Scenario,
        seed: u64,
        wrist: WristFtConfig,
    ) -> Result<Self, WorldError> {
        let room = &scenario.room;
        if !(room.size.iter().all(|s| s.is_finite() && *s > 0.0)
            && room.wall_height.is_finite()
            && room.wall_height > 0.0)
        {
            return Err(WorldError::InvalidRoom(format!(
                "size {:?}, wall height {}",
                room.size, room.wall_height
            )));
        }
        let mut physics = PhysicsWorld::new();
        physics.gravity = Vector::new(0.0, 0.0, -9.81);
        physics.integration_parameters.dt = (COARSE_STEP_US as f64 * 1.0e-6) as f32;
        // One Coulomb cone per contact point: the simplified model under-reads a sliding chair's
        // friction (μ m g is what the push test measures).
        physics.integration_parameters.friction_model = FrictionModel::Coulomb;
        // Contact points are recomputed once a pair has moved 2 mm. Rapier's default, 5 cm, keeps a
        // chair's resting contacts for the first seconds of a 2 cm/s push, and they read up to
        // 1.6 N above μ m g (the force a push test compares with its limit).
        physics
            .integration_parameters
            .normalized_contact_recycle_distance = CONTACT_RECYCLE_DISTANCE;
        let mut surfaces = HashMap::new();
        build::build_room(room, &mut physics.colliders, &mut surfaces);
        let mut objects = Vec::with_capacity(scenario.objects.len());
        for (i, spec) in scenario.objects.iter().enumerate() {
            let body = build::build_object(
                i,
                spec,
                &mut physics.bodies,
                &mut physics.colliders,
                &mut surfaces,
            )?;
            objects.push((spec.clone(), body));
        }
        let humanoid = Humanoid::new(&scenario.robot, &mut physics, &mut surfaces)
            .map_err(|e| WorldError::InvalidRobot(e.0))?;
        let mut actors = Vec::with_capacity(scenario.actors.len());
        for (i, spec) in scenario.actors.iter().enumerate() {
            actors.push(Actor::new(i, spec, &objects, &mut physics, &mut surfaces)?);
        }
        let wrist_ft = WristFt::new(wrist, seed)?;
        let mut world = Self {
            physics,
            surfaces,
            objects,
            actors,
            humanoid,
            wrist_ft,
            wrist_truth: Wrench::default(),
            pressed_since_us: None,
            time_us: 0,
            seed,
            steps: 0,
            fine_steps: 0,
            room_size: room.size,
            robot_model: scenario.robot.model(),
            effort: Effort::default(),
            hand_touching: false,
            touching_person: false,
            pushed_touching_person: false,
            pose_log: pose_log::PoseLog::default(),
        };
        // Settle contacts and fill the query structures before anyone senses.
        world.physics.integration_parameters.dt = 0.0;
        world.physics.step();
        world.pose_log =
            pose_log::PoseLog::new((0..world.objects.len()).filter_map(|i| world.object_pose(i)));
        Ok(world)
    }

    /// Simulated time (s).
    pub fn time(&self) -> f64 {
        self.time_us as f64 * 1.0e-6
    }

    /// The seed the world was built with.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// What the robot has spent and disturbed so far (ground truth).
    pub fn effort(&self) -> &Effort {
        &self.effort
    }

    /// Number of physics steps taken so far.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Number of physics steps of [`FINE_STEP_US`] or less taken so far.
    pub fn fine_steps(&self) -> u64 {
        self.fine_steps
    }

    /// The room's extent along x and y (m); its corner is at the origin.
    pub fn room_size(&self) -> [f64; 2] {
        self.room_size
    }

    /// Height of the robot's bounding cylinder (m).
    pub fn humanoid_height(&self) -> f64 {
        self.robot_model.body.height
    }

    /// What the robot is: the scenario's robot description.
    pub fn robot_model(&self) -> &RobotModel {
        &self.robot_model
    }

    /// The rapier bodies.
    pub fn bodies(&self) -> &RigidBodySet {
        &self.physics.bodies
    }

    /// The rapier colliders.
    pub fn colliders(&self) -> &ColliderSet {
        &self.physics.colliders
    }

    /// The whole rapier world (broad phase and narrow phase for scene queries).
    pub fn physics(&self) -> &PhysicsWorld {
        &self.physics
    }

    /// The whole rapier world, mutably: for tests and scripted disturbances. Moving bodies behind the
    /// world's back is the caller's responsibility.
    pub fn physics_mut(&mut self) -> &mut PhysicsWorld {
        &mut self.physics
    }

    /// Calls `f` with the scene the head's camera sees: every collider with its surface, the
    /// robot's bounding body left out (the sensor rides on it), textures seeded by the world.
    pub fn in_sensor_scene<T>(
        &self,
        f: impl FnOnce(&crate::sensors::colour_range::SensorScene<'_>) -> T,
    ) -> T {
        let surfaces = self.surfaces();
        let lookup = move |h| surfaces.get(&h).copied();
        let scene = crate::sensors::colour_range::SensorScene {
            bodies: self.bodies(),
            colliders: self.colliders(),
            broad_phase: &self.physics().broad_phase,
            surface: &lookup,
            texture_seed: self.seed(),
            exclude: Some(self.humanoid().parts().body),
        };
        f(&scene)
    }

    /// Appearance and owner of every collider.
    pub fn surfaces(&self) -> &HashMap<ColliderHandle, Surface> {
        &self.surfaces
    }

    /// Appearance and owner of a collider.
    pub fn surface(&self, handle: ColliderHandle) -> Option<Surface> {
        self.surfaces.get(&handle).copied()
    }

    /// The scenario objects with their bodies, in scenario order.
    pub fn objects(&self) -> &[(ObjectSpec, RigidBodyHandle)] {
        &self.objects
    }

    /// The actors, in scenario order.
    pub fn actors(&self) -> &[Actor] {
        &self.actors
    }

    /// The robot.
    pub fn humanoid(&self) -> &Humanoid {
        &self.humanoid
    }

    /// The robot, to command it.
    pub fn humanoid_mut(&mut self) -> &mut Humanoid {
        &mut self.humanoid
    }

    /// The wrist sensor.
    pub fn wrist_sensor(&mut self) -> &mut WristFt {
        &mut self.wrist_ft
    }

    /// The true wrench on the wrist during the last physics step (no bias, no noise).
    pub fn wrist_truth(&self) -> Wrench {
        self.wrist_truth
    }

    /// The wrist sensor's latest tared reading; before its first sample, one fresh reading now.
    pub fn wrist_reading(&mut self) -> Stamped<Wrench> {
        match self.wrist_ft.latest() {
            Some(w) => w,
            None => {
                let truth = self.wrist_truth;
                self.wrist_ft.record(&truth, self.time_us, self.time_us)
            }
        }
    }

    /// Zeroes the wrist sensor on its recent readings.
    pub fn tare_wrist(&mut self) {
        let truth = self.wrist_truth;
        self.wrist_ft.tare(&truth);
    }

    /// The pose of object `i` (its frame: footprint centre on its underside), or `None` if no such object.
    pub fn object_pose(&self, i: usize) -> Option<Isometry3<f64>> {
        let (_, body) = self.objects.get(i)?;
        self.physics
            .bodies
            .get(*body)
            .map(|b| iso_from_pose(b.position()))
    }

    /// Where object `i` stood at `time` (s of simulated time), to within the pose log's step and
    /// turn (`pose_log::LOG_STEP`, `pose_log::LOG_TURN`); its pose at the start for times before then.
    pub fn object_pose_at(&self, i: usize, time: f64) -> Option<Isometry3<f64>> {
        let time_us = if time.is_finite() {
            (time.max(0.0) * 1.0e6) as u64
        } else {
            u64::MAX
        };
        self.pose_log.at(i, time_us)
    }

    /// The speed of object `i`'s centre of mass (m/s).
    pub fn object_speed(&self, i: usize) -> Option<f64> {
        let (_, body) = self.objects.get(i)?;
        let b = self.physics.bodies.get(*body)?;
        Some(f64::from(b.linvel().length()))
    }

    /// Lets `dt` seconds of simulated time pass, in physics steps that suit what is going on.
    pub fn advance(&mut self, dt: f64) -> Result<(), WorldError> {
        // A million seconds per call is far beyond any run and keeps the µs clock from overflowing.
        if !(dt.is_finite() && (0.0..=1.0e6).contains(&dt)) {
            return Err(WorldError::InvalidStep(dt));
        }
        let target = self.time_us + (dt * 1.0e6).round() as u64;
        while self.time_us < target {
            let stepping = self.stepping();
            let grid = match stepping {
                Stepping::Fine => FINE_STEP_US,
                Stepping::Coarse | Stepping::Pressing => COARSE_STEP_US,
            };
            let h = (grid - self.time_us % grid).min(target - self.time_us);
            self.step(h, stepping);
        }
        Ok(())
    }

    /// How to step next: finely while the hand touches something, or is on a guarded line close to
    /// something (then the force changes fast and the guard and the sensor need every millisecond),
    /// a steady push far below its limit excepted; coarsely otherwise. Also keeps track of how long
    /// the hand has pressed.
    fn stepping(&mut self) -> Stepping {
        let hand = self.humanoid.parts().hand_collider;
        let touching = self
            .physics
            .narrow_phase
            .contact_pairs_with(hand)
            .any(|p| p.has_any_active_contact());
        let pressing = touching
            && self
                .wrist_ft
                .latest()
                // The executive's contact threshold: a hand resting against something at the
                // noise's level is not yet pushing it.
                .is_some_and(|r| {
                    r.value.force_norm() >= self.robot_model().force.contact_threshold
                });
        self.pressed_since_us = pressing.then(|| self.pressed_since_us.unwrap_or(self.time_us));
        self.hand_touching = touching;
        if touching {
            if self.steady_push() {
                Stepping::Pressing
            } else {
                Stepping::Fine
            }
        } else if self.humanoid.arm().on_guarded_line() && self.hand_near_something(hand) {
            Stepping::Fine
        } else {
            Stepping::Coarse
        }
    }

    /// Whether the hand, touching something, pushes steadily along a guarded line with the force
    /// so far below the limit that a coarse step cannot carry it past: the guard's pace
    /// ([`steady_push`]) with the press lasting [`STEADY_PRESS_US`] and the robot's wrist stiffness.
    fn steady_push(&self) -> bool {
        let Some((limit, speed)) = self.humanoid.arm().guarded_line() else {
            return false;
        };
        let held = self
            .pressed_since_us
            .is_some_and(|since| self.time_us - since >= STEADY_PRESS_US);
        let standing = matches!(self.humanoid.walk(), Walk::Idle(_));
        let Some(reading) = self.wrist_ft.latest() else {
            return false;
        };
        steady_push(
            reading.value.force_norm(),
            limit,
            speed,
            self.robot_model().wrist.stiffness,
            held,
            standing,
        )
    }

    /// Whether anything the hand can touch lies within [`NEAR_CONTACT`] of it: the broad phase's
    /// boxes find the candidates, the exact distance between shapes decides. A missing hand, or a
    /// shape pair parry cannot measure, counts as near.
    fn hand_near_something(&self, hand: ColliderHandle) -> bool {
        let Some(collider) = self.physics.colliders.get(hand) else {
            return true;
        };
        let reach = collider.compute_aabb().loosened(NEAR_CONTACT);
        let filter = QueryFilter::new()
            .groups(collider.collision_groups())
            .exclude_collider(hand);
        self.physics
            .intersect_aabb_conservative(reach, filter)
            .any(|(_, other)| {
                query::distance(
                    collider.position(),
                    collider.shape(),
                    other.position(),
                    other.shape(),
                )
                .map_or(true, |d| d.distance < NEAR_CONTACT)
            })
    }

    /// One physics step of `h_us` microseconds.
    fn step(&mut self, h_us: u64, stepping: Stepping) {
        let h = h_us as f64 * 1.0e-6;
        let t1 = self.time_us + h_us;
        let before = self.robot_pose();
        let clear = [
            crate::actors::KeepClear {
                centre: before.base,
                radius: self.humanoid.radius(),
            },
            crate::actors::KeepClear {
                centre: before.hand,
                radius: self.humanoid.hand_radius(),
            },
        ];
        for actor in &mut self.actors {
            actor.update(t1 as f64 * 1.0e-6, &clear, &mut self.physics);
        }
        self.humanoid.pre_step(h, &mut self.physics);
        let commanded = self.humanoid.moves_bodies() || self.actors.iter().any(|a| a.is_moving());
        let awake = self
            .physics
            .islands
            .active_bodies()
            .any(|b| self.physics.bodies.get(b).is_some_and(|b| b.is_dynamic()));
        if commanded || awake {
            self.physics.integration_parameters.dt = h as f32;
            let (substeps, pgs_iterations) = match stepping {
                // A fine step's solver substep, repeated: the contact's stiffness and the wrist's
                // reading stay those of fine steps (a coarse step's longer substeps let a jammed chair
                // sink further into what jams it, and the first fine steps then read a spike).
                Stepping::Pressing => (
                    h_us.div_ceil(FINE_STEP_US) as usize * FINE_SUBSTEPS,
                    FINE_PGS_ITERATIONS,
                ),
                _ if h_us <= FINE_STEP_US => (FINE_SUBSTEPS, FINE_PGS_ITERATIONS),
                _ => (COARSE_SUBSTEPS, 1),
            };
            let params = &mut self.physics.integration_parameters;
            params.num_solver_iterations = substeps;
            params.num_internal_pgs_iterations = pgs_iterations;
            self.physics.step();
            self.steps += 1;
            if h_us <= FINE_STEP_US {
                self.fine_steps += 1;
            }
            if let Some(joint) = self.physics.impulse_joints.get(self.humanoid.parts().joint) {
                self.wrist_truth = wrench_on_wrist(joint, substeps, h);
            }
            self.log_moving_objects(t1);
        }
        self.measure_effort(h, before);
        let truth = self.wrist_truth;
        let reading = self.wrist_ft.record(&truth, self.time_us, t1);
        self.time_us = t1;
        self.check_guard(reading);
    }

    /// Notes the pose of every object the physics moved this step.
    fn log_moving_objects(&mut self, time_us: u64) {
        for body in self.physics.islands.active_bodies() {
            if let Some(i) = self.objects.iter().position(|(_, b)| *b == body)
                && let Some(b) = self.physics.bodies.get(body)
            {
                self.pose_log.note(i, time_us, iso_from_pose(b.position()));
            }
        }
    }

    /// Where the base and the hand are on the floor plan.
    fn robot_pose(&self) -> effort::Pose {
        let base = self.humanoid.base_pose().translation.vector;
        let hand = self.humanoid.hand_in_map(&self.physics);
        effort::Pose {
            base: nalgebra::Point2::from(base),
            hand: nalgebra::Point2::new(hand.x, hand.y),
        }
    }

    /// Adds the step just taken to the run's effort: the base's and hand's travel, the wrist's true
    /// force turned into the map while the hand touches something, and new contacts with people.
    fn measure_effort(&mut self, h: f64, before: effort::Pose) {
        let after = self.robot_pose();
        // A person shoving the hand is not the robot's effort: steps where the hand touches one
        // count towards contacts, not towards the hand's work.
        let pushing = self.hand_touching
            && (self.actors.is_empty()
                || !self.touches_a_person(self.humanoid.parts().hand_collider));
        let force = pushing.then(|| {
            let wrist = self
                .physics
                .bodies
                .get(self.humanoid.parts().wrist)
                .map(|b| iso_from_pose(b.position()).rotation)
                .unwrap_or_default();
            let f = wrist * self.wrist_truth.force;
            nalgebra::Vector2::new(f.x, f.y)
        });
        self.effort.add_step(h, before, after, force);
        if !self.actors.is_empty() {
            let touching = self.robot_touches_a_person();
            self.effort.person_contact(self.touching_person, touching);
            self.touching_person = touching;
            let pushed = self.hand_touching && self.pushed_object_touches_a_person();
            self.effort
                .pushed_into_person(self.pushed_touching_person, pushed);
            self.pushed_touching_person = pushed;
        }
    }

    /// Whether the robot's body or hand is in contact with any actor.
    fn robot_touches_a_person(&self) -> bool {
        let parts = self.humanoid.parts();
        self.touches_a_person(parts.body_collider) || self.touches_a_person(parts.hand_collider)
    }

    /// Whether an object the hand touches (pushes) is in contact with any actor.
    fn pushed_object_touches_a_person(&self) -> bool {
        let hand = self.humanoid.parts().hand_collider;
        self.physics
            .narrow_phase
            .contact_pairs_with(hand)
            .filter(|pair| pair.has_any_active_contact())
            .map(|pair| {
                if pair.collider1 == hand {
                    pair.collider2
                } else {
                    pair.collider1
                }
            })
            .filter(|other| {
                matches!(
                    self.surfaces.get(other).map(|s| s.owner),
                    Some(crate::surface::Owner::Object(_))
                )
            })
            .any(|object| self.touches_a_person(object))
    }

    /// Whether collider `own` is in contact with any actor.
    fn touches_a_person(&self, own: ColliderHandle) -> bool {
        self.physics
            .narrow_phase
            .contact_pairs_with(own)
            .any(|pair| {
                let other = if pair.collider1 == own {
                    pair.collider2
                } else {
                    pair.collider1
                };
                pair.has_any_active_contact()
                    && matches!(
                        self.surfaces.get(&other).map(|s| s.owner),
                        Some(crate::surface::Owner::Actor(_))
                    )
            })
    }

    /// Stops a guarded move the moment the tared force reaches its limit, and a walk when the hand
    /// is overloaded.
    fn check_guard(&mut self, reading: Stamped<Wrench>) {
        let overload = HAND_OVERLOAD_FACTOR * self.robot_model().force.test_limit;
        if reading.value.force_norm() >= overload {
            self.humanoid.protective_stop();
        }
        let Some(limit) = self.humanoid.arm().guard() else {
            return;
        };
        if reading.value.force_norm() < limit {
            return;
        }
        let at = self.humanoid.hand_position(&self.physics);
        let arm = self.humanoid.arm_mut();
        arm.force_limit_reached(reading, at);
    }
}
