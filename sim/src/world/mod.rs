//! The simulated world: a rapier scene built from a scenario (Z up), with the humanoid, the actors
//! and the wrist sensor, advanced in physics steps whose length adapts to what is going on.
//!
//! Stepping: 1 ms steps while the hand touches something, or is on a guarded line within
//! [`NEAR_CONTACT`] of something it could touch (the guarded-move check runs every step, and every
//! contact is resolved at the wrist sensor's 1 kHz); 10 ms steps otherwise, aligned to a 10 ms grid.
//! A guarded line's first centimetres through free air are stepped like the unguarded move to its
//! start: nothing can touch the hand within a coarse step there, so no contact force is skipped.
//! When no body is commanded to move (the head has none) and every dynamic body sleeps, time passes
//! without a physics step. The wrist sensor samples at its own rate throughout, holding the last
//! step's wrench.

pub mod build;
pub mod convert;

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
/// Physics step otherwise (µs).
pub const COARSE_STEP_US: u64 = 10_000;
/// A hand on a guarded line steps finely once anything it can touch is this close (m, between the
/// shapes). A coarse step moves the hand at most 5 mm along a line (0.5 m/s, the fastest guarded
/// move) plus 1.5 mm with the walking base: 1 cm is more than a coarse step of warning.
pub const NEAR_CONTACT: f32 = 0.01;
/// How far a contact pair may move before rapier recomputes its contact points (m).
pub const CONTACT_RECYCLE_DISTANCE: f32 = 0.002;
/// Tared wrist force (N) at which a walk or turn stops at once: the hand, held out while walking,
/// presses on something that does not give (three times the paper's 20 N push limit).
pub const HAND_OVERLOAD: f64 = 60.0;

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
    time_us: u64,
    seed: u64,
    steps: u64,
    fine_steps: u64,
    room_size: [f64; 2],
    robot_height: f64,
}

impl World {
    /// Builds the scenario's world; `seed` fixes every random choice (sensor noise, textures).
    pub fn new(scenario: &Scenario, seed: u64) -> Result<Self, WorldError> {
        Self::with_wrist_config(scenario, seed, WristFtConfig::default())
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
            time_us: 0,
            seed,
            steps: 0,
            fine_steps: 0,
            room_size: room.size,
            robot_height: scenario.robot.height,
        };
        // Settle contacts and fill the query structures before anyone senses.
        world.physics.integration_parameters.dt = 0.0;
        world.physics.step();
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
        self.robot_height
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
            let grid = if self.needs_fine_steps() {
                FINE_STEP_US
            } else {
                COARSE_STEP_US
            };
            let h = (grid - self.time_us % grid).min(target - self.time_us);
            self.step(h);
        }
        Ok(())
    }

    /// Whether the hand touches something, or is on a guarded line close to something: then the
    /// force changes fast and the guard and the sensor need every millisecond.
    fn needs_fine_steps(&self) -> bool {
        let hand = self.humanoid.parts().hand_collider;
        let touching = self
            .physics
            .narrow_phase
            .contact_pairs_with(hand)
            .any(|p| p.has_any_active_contact());
        touching || (self.humanoid.arm().on_guarded_line() && self.hand_near_something(hand))
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
    fn step(&mut self, h_us: u64) {
        let h = h_us as f64 * 1.0e-6;
        let t1 = self.time_us + h_us;
        for actor in &mut self.actors {
            actor.update(t1 as f64 * 1.0e-6, &mut self.physics);
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
            self.physics.integration_parameters.num_solver_iterations = if h_us <= FINE_STEP_US {
                FINE_SUBSTEPS
            } else {
                COARSE_SUBSTEPS
            };
            self.physics
                .integration_parameters
                .num_internal_pgs_iterations = if h_us <= FINE_STEP_US {
                FINE_PGS_ITERATIONS
            } else {
                1
            };
            self.physics.step();
            self.steps += 1;
            if h_us <= FINE_STEP_US {
                self.fine_steps += 1;
            }
            let substeps = self.physics.integration_parameters.num_solver_iterations;
            if let Some(joint) = self.physics.impulse_joints.get(self.humanoid.parts().joint) {
                self.wrist_truth = wrench_on_wrist(joint, substeps, h);
            }
        }
        let truth = self.wrist_truth;
        let reading = self.wrist_ft.record(&truth, self.time_us, t1);
        self.time_us = t1;
        self.check_guard(reading);
    }

    /// Stops a guarded move the moment the tared force reaches its limit, and a walk when the hand
    /// is overloaded.
    fn check_guard(&mut self, reading: Stamped<Wrench>) {
        if reading.value.force_norm() >= HAND_OVERLOAD {
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
