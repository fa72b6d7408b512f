//! The HRP-2-like humanoid: a kinematic bounding cylinder that walks, a pan/tilt head carrying the
//! range sensor, and one arm whose kinematic wrist drags a small dynamic hand through a compliant
//! wrist joint (the F/T sensor reads that joint).

pub mod head;
pub mod walk;

use std::collections::HashMap;

use nalgebra::{Isometry2, Isometry3, Point2, Point3, Translation3, UnitQuaternion, Vector3};
use rapier3d::prelude::*;

use crate::scenario::{RobotSpec, Texture};
use crate::surface::{Owner, Surface};
use crate::world::build::groups;
use crate::world::convert::{iso_from_pose, pose_from_iso};
use head::Head;
use nudge_executive::robot::controller::{HandMotion as Arm, Rates, Walk};
use walk::WalkParams;

/// Colour of the robot's parts as the range sensor sees them.
const ROBOT_COLOUR: [u8; 3] = [230, 230, 235];

/// Why a command was refused.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[error("{0}")]
pub struct Refused(pub String);

/// Handles of the robot's rapier parts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Parts {
    /// The kinematic bounding cylinder's body.
    pub body: RigidBodyHandle,
    /// The bounding cylinder.
    pub body_collider: ColliderHandle,
    /// The kinematic wrist (no collider).
    pub wrist: RigidBodyHandle,
    /// The dynamic hand.
    pub hand: RigidBodyHandle,
    /// The hand's box.
    pub hand_collider: ColliderHandle,
    /// The compliant wrist joint (wrist → hand) the F/T sensor reads.
    pub joint: ImpulseJointHandle,
}

/// The humanoid's state and its rapier parts.
#[derive(Clone, Debug)]
pub struct Humanoid {
    parts: Parts,
    base: Isometry2<f64>,
    walk: Walk,
    rates: Rates,
    params: WalkParams,
    head: Head,
    arm: Arm,
    /// Half extents of the hand's box (m).
    hand_half: [f64; 3],
    /// The whole robot's mass (kg). The simulated body is kinematic, so physics never uses it; the
    /// effort metrics weigh the robot's own travel with it (`crate::metrics`).
    mass: f64,
}

impl Humanoid {
    /// Builds the robot `spec` describes (its [`RobotSpec::model`]) in `physics` at its start pose
    /// and registers their surfaces.
    pub fn new(
        spec: &RobotSpec,
        physics: &mut PhysicsWorld,
        surfaces: &mut HashMap<ColliderHandle, Surface>,
    ) -> Result<Self, Refused> {
        let model = spec.model();
        if !spec.start.iter().all(|v| v.is_finite()) {
            return Err(Refused(format!(
                "robot start {:?} must be finite",
                spec.start
            )));
        }
        model
            .validate()
            .map_err(|v| Refused(format!("robot description: {v}")))?;
        let body_model = &model.body;
        let step_over = body_model.step_over;
        let base = Isometry2::new(
            nalgebra::Vector2::new(spec.start[0], spec.start[1]),
            spec.start[2].to_radians(),
        );
        let arm = Arm::new(&model.arm);
        let hand_half = model.arm.hand_half;
        let surface = Surface::new(ROBOT_COLOUR, Texture::Plain, Owner::Robot);

        let body = physics.bodies.insert(
            RigidBodyBuilder::kinematic_position_based()
                .pose(pose_from_iso(&base3(&base)))
                .build(),
        );
        // The body starts above the floor like the walking shape cast, so it steps over mats instead
        // of shoving them.
        let half = ((body_model.height - step_over) / 2.0) as f32;
        let cylinder = ColliderBuilder::cylinder(half, body_model.radius as f32)
            .position(Pose::from_parts(
                Vector::new(0.0, 0.0, step_over as f32 + half),
                Rotation::from_rotation_x(std::f32::consts::FRAC_PI_2),
            ))
            .collision_groups(InteractionGroups::new(
                groups::ROBOT_BODY,
                groups::OBJECT | groups::ACTOR,
                InteractionTestMode::And,
            ))
            .build();
        let body_collider =
            physics
                .colliders
                .insert_with_parent(cylinder, body, &mut physics.bodies);

        let wrist_pose = pose_from_iso(&wrist_in_map(&base, &arm.command));
        let wrist = physics.bodies.insert(
            RigidBodyBuilder::kinematic_position_based()
                .pose(wrist_pose)
                .build(),
        );
        let hand = physics
            .bodies
            .insert(RigidBodyBuilder::dynamic().pose(wrist_pose).build());
        let [hx, hy, hz] = hand_half.map(|h| h as f32);
        let hand_box = ColliderBuilder::cuboid(hx, hy, hz)
            .mass(model.arm.hand_mass as f32)
            .friction(0.5)
            .collision_groups(InteractionGroups::new(
                groups::HAND,
                groups::FLOOR | groups::WALL | groups::OBJECT | groups::ACTOR,
                InteractionTestMode::And,
            ))
            .build();
        let hand_collider =
            physics
                .colliders
                .insert_with_parent(hand_box, hand, &mut physics.bodies);
        let mut joint = GenericJointBuilder::new(JointAxesMask::ANG_AXES).contacts_enabled(false);
        // The robot's wrist compliance (a rigid wrist driven kinematically into a fixed obstacle
        // would read an arbitrary solver force).
        let (stiffness, damping) = (model.wrist.stiffness as f32, model.wrist.damping as f32);
        for axis in [JointAxis::LinX, JointAxis::LinY, JointAxis::LinZ] {
            joint = joint
                .motor_model(axis, MotorModel::ForceBased)
                .motor_position(axis, 0.0, stiffness, damping);
        }
        let joint = physics
            .impulse_joints
            .insert(wrist, hand, joint.build(), true);

        surfaces.insert(body_collider, surface);
        surfaces.insert(hand_collider, surface);
        Ok(Self {
            parts: Parts {
                body,
                body_collider,
                wrist,
                hand,
                hand_collider,
                joint,
            },
            base,
            walk: Walk::Idle(None),
            rates: Rates::default(),
            params: WalkParams {
                limits: nudge_executive::robot::controller::WalkLimits::of(body_model),
                radius: body_model.radius,
                height: body_model.height,
                step_over,
                margin: body_model.safety_margin,
            },
            head: Head::new(&model.head),
            arm,
            hand_half,
            mass: body_model.mass,
        })
    }

    /// The whole robot's mass (kg).
    pub fn mass(&self) -> f64 {
        self.mass
    }

    /// The radius of the robot's body cylinder (m).
    pub fn radius(&self) -> f64 {
        self.params.radius
    }

    /// The radius of the disc the hand covers seen from above (m): its box's half-diagonal.
    pub fn hand_radius(&self) -> f64 {
        self.hand_half[0].hypot(self.hand_half[1])
    }

    /// Handles of the robot's rapier parts.
    pub fn parts(&self) -> &Parts {
        &self.parts
    }

    /// Base pose (`base_link` in map).
    pub fn base_pose(&self) -> Isometry2<f64> {
        self.base
    }

    /// The range sensor's pose in the map: x along the optical axis, y left, z up.
    pub fn sensor_pose(&self) -> Isometry3<f64> {
        self.head.sensor_pose(&self.base)
    }

    /// The walk state.
    pub fn walk(&self) -> &Walk {
        &self.walk
    }

    /// The head state.
    pub fn head(&self) -> &Head {
        &self.head
    }

    /// The arm's command state.
    pub fn arm(&self) -> &Arm {
        &self.arm
    }

    /// The arm's command state, to start and stop hand motions.
    pub fn arm_mut(&mut self) -> &mut Arm {
        &mut self.arm
    }

    /// Starts walking through `waypoints` (map frame); replaces any walk or turn under way.
    pub fn start_walk(&mut self, waypoints: &[Point2<f64>]) -> Result<(), Refused> {
        if waypoints
            .iter()
            .any(|p| !(p.x.is_finite() && p.y.is_finite()))
        {
            return Err(Refused("waypoints must be finite".into()));
        }
        self.walk = Walk::Path(waypoints.iter().copied().collect());
        Ok(())
    }

    /// Starts turning on the spot to `yaw` (rad, map).
    pub fn start_turn(&mut self, yaw: f64) -> Result<(), Refused> {
        if !yaw.is_finite() {
            return Err(Refused("yaw must be finite".into()));
        }
        self.walk = Walk::Turn(nudge_executive::robot::controller::wrap(yaw));
        Ok(())
    }

    /// Moves the base at a commanded velocity (`linear` in the base frame, m/s; `angular`, rad/s)
    /// until the next command, still never entering anything; zero stops it.
    pub fn command_velocity(
        &mut self,
        linear: nalgebra::Vector2<f64>,
        angular: f64,
    ) -> Result<(), Refused> {
        if !(linear.x.is_finite() && linear.y.is_finite() && angular.is_finite()) {
            return Err(Refused("velocities must be finite".into()));
        }
        if linear == nalgebra::Vector2::zeros() && angular == 0.0 {
            if matches!(self.walk, Walk::Velocity { .. }) {
                self.rates = Rates::default();
                self.walk = Walk::Idle(Some(nudge_executive::robot::WalkOutcome::Stopped));
            }
        } else {
            self.walk = Walk::Velocity { linear, angular };
        }
        Ok(())
    }

    /// Stops walking at once (a kinematic body can).
    pub fn stop_walk(&mut self) {
        if !matches!(self.walk, Walk::Idle(_)) {
            self.rates = Rates::default();
            self.walk = Walk::Idle(Some(nudge_executive::robot::WalkOutcome::Stopped));
        }
    }

    /// Ends a walk or turn at once because the hand is overloaded: the outcome is `Blocked` where
    /// the base stands (something the hand touched is in the way).
    pub fn protective_stop(&mut self) {
        if !matches!(self.walk, Walk::Idle(_)) {
            self.rates = Rates::default();
            self.walk = Walk::Idle(Some(nudge_executive::robot::WalkOutcome::Blocked {
                at: self.base,
            }));
        }
    }

    /// Starts moving the head, or refuses angles outside its limits.
    pub fn point_head(&mut self, pan: f64, tilt: f64) -> Result<(), Refused> {
        if !self.head.within_limits(pan, tilt) {
            return Err(Refused(format!(
                "head angles ({pan}, {tilt}) outside pan {:?} tilt {:?}",
                self.head.pan_limits(),
                self.head.tilt_limits()
            )));
        }
        self.head.point(pan, tilt);
        Ok(())
    }

    /// Whether a rapier body of the robot is being moved (walk, turn, hand); the head has no body.
    pub fn moves_bodies(&self) -> bool {
        !matches!(self.walk, Walk::Idle(_)) || self.arm.is_moving()
    }

    /// Whether anything of the robot is being moved (walk, head, hand).
    pub fn is_moving(&self) -> bool {
        !matches!(self.walk, Walk::Idle(_)) || self.head.is_moving() || self.arm.is_moving()
    }

    /// The hand's position in `base_link` (m).
    pub fn hand_position(&self, physics: &PhysicsWorld) -> Point3<f64> {
        let hand = physics
            .bodies
            .get(self.parts.hand)
            .map(|b| iso_from_pose(b.position()))
            .unwrap_or_else(|| wrist_in_map(&self.base, &self.arm.command));
        base3(&self.base).inverse_transform_point(&Point3::from(hand.translation.vector))
    }

    /// The hand's position in the map (m).
    pub fn hand_in_map(&self, physics: &PhysicsWorld) -> Point3<f64> {
        base3(&self.base) * self.hand_position(physics)
    }

    /// Moves walk, head and arm by `dt` seconds and sets the kinematic targets of body and wrist.
    pub fn pre_step(&mut self, dt: f64, physics: &mut PhysicsWorld) {
        let moving = self.moves_bodies();
        self.base = walk::step(
            &mut self.walk,
            &mut self.rates,
            self.base,
            &self.params,
            dt,
            physics,
        );
        self.head.step(dt);
        self.arm.step(dt);
        if !moving {
            return;
        }
        let body_pose = pose_from_iso(&base3(&self.base));
        let wrist_pose = pose_from_iso(&wrist_in_map(&self.base, &self.arm.command));
        if let Some(b) = physics.bodies.get_mut(self.parts.body) {
            b.set_next_kinematic_position(body_pose);
        }
        if let Some(w) = physics.bodies.get_mut(self.parts.wrist) {
            w.set_next_kinematic_position(wrist_pose);
        }
        physics.wake_up(self.parts.hand, true);
    }
}

/// The base pose as a 3-D isometry on the floor.
fn base3(base: &Isometry2<f64>) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(base.translation.x, base.translation.y, 0.0),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), base.rotation.angle()),
    )
}

/// The wrist pose in the map for a base pose and a wrist position in `base_link`.
fn wrist_in_map(base: &Isometry2<f64>, wrist: &Point3<f64>) -> Isometry3<f64> {
    base3(base) * Isometry3::translation(wrist.x, wrist.y, wrist.z)
}
