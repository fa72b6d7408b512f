//! Actors: people and other robots that walk their waypoints as kinematic cylinders, optionally
//! pulling an object behind them which they leave (`drop_at`) and take back (`pick_at`).
//!
//! Timeline: at `start_time` the actor is at waypoint 0; it waits `pause[i]` at waypoint i, then walks
//! straight to the next at `speed`. With `repeat` it walks from the last waypoint back to the first and
//! goes round again. Arriving at waypoint `drop_at` leaves the carried object there at rest as a dynamic
//! body; arriving at `pick_at` takes it again.

use std::collections::HashMap;

use nalgebra::{Point2, Vector2};
use rapier3d::prelude::*;

use crate::scenario::{ActorSpec, ObjectKind, ObjectSpec, Texture};
use crate::surface::{Owner, Surface};
use crate::world::WorldError;
use crate::world::build::groups;

/// Gap between an actor and the object it pulls (m).
const CARRY_GAP: f64 = 0.05;
/// How close a yielding actor lets the robot's body or hand come before it stops (m, between their
/// outlines): Hall's intimate distance (0.45 m), the space people keep from strangers and from
/// machines they do not trust.
pub const PERSONAL_SPACE: f64 = 0.45;

/// A disc an actor keeps clear of: the robot's body or hand, seen from above.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KeepClear {
    /// Its centre (m, map).
    pub centre: Point2<f64>,
    /// Its radius (m).
    pub radius: f64,
}

/// Colour of actors as the range sensor sees them.
const ACTOR_COLOUR: [u8; 3] = [60, 90, 160];

/// Where an actor is at some time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ActorState {
    /// Position on the floor (m, map).
    pub position: Point2<f64>,
    /// Direction of travel of the current or last leg (rad).
    pub heading: f64,
    /// How many waypoint arrivals have happened (the start counts as the first).
    pub arrivals: usize,
}

/// The pure walking plan of an actor.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    waypoints: Vec<Point2<f64>>,
    pauses: Vec<f64>,
    speed: f64,
    start_time: f64,
    repeat: bool,
}

impl Plan {
    /// The plan of a scenario actor, or why it is invalid.
    pub fn new(spec: &ActorSpec) -> Result<Self, WorldError> {
        let bad = |reason: &str| {
            Err(WorldError::InvalidActor {
                name: spec.name.clone(),
                reason: reason.into(),
            })
        };
        if spec.waypoints.is_empty() {
            return bad("needs at least one waypoint");
        }
        if spec.waypoints.iter().flatten().any(|v| !v.is_finite()) {
            return bad("waypoints must be finite");
        }
        if !(spec.speed.is_finite() && spec.speed > 0.0) {
            return bad("speed must be positive");
        }
        if !spec.start_time.is_finite() {
            return bad("start_time must be finite");
        }
        if !(spec.pause.is_empty() || spec.pause.len() == spec.waypoints.len()) {
            return bad("pause needs one entry per waypoint, or none");
        }
        if spec.pause.iter().any(|p| !(p.is_finite() && *p >= 0.0)) {
            return bad("pauses must be >= 0");
        }
        if !(spec.radius.is_finite()
            && spec.radius > 0.0
            && spec.height.is_finite()
            && spec.height > 0.0)
        {
            return bad("radius and height must be positive");
        }
        let n = spec.waypoints.len();
        if spec.drop_at.is_some_and(|i| i >= n) || spec.pick_at.is_some_and(|i| i >= n) {
            return bad("drop_at / pick_at must be waypoint indices");
        }
        let waypoints: Vec<Point2<f64>> = spec
            .waypoints
            .iter()
            .map(|w| Point2::new(w[0], w[1]))
            .collect();
        let pauses = if spec.pause.is_empty() {
            vec![0.0; n]
        } else {
            spec.pause.clone()
        };
        let repeat = spec.repeat && n > 1;
        let plan = Self {
            waypoints,
            pauses,
            speed: spec.speed,
            start_time: spec.start_time,
            repeat,
        };
        if repeat && plan.cycle_time() <= 0.0 {
            return bad("a repeating actor needs a cycle longer than zero");
        }
        Ok(plan)
    }

    fn leg_time(&self, k: usize) -> f64 {
        let n = self.waypoints.len();
        (self.waypoints[(k + 1) % n] - self.waypoints[k]).norm() / self.speed
    }

    fn cycle_time(&self) -> f64 {
        (0..self.waypoints.len())
            .map(|k| self.pauses[k] + self.leg_time(k))
            .sum()
    }

    /// Where the actor is at time `t` (s).
    pub fn state_at(&self, t: f64) -> ActorState {
        let n = self.waypoints.len();
        let first_heading = if n > 1 {
            heading(self.waypoints[1] - self.waypoints[0])
        } else {
            0.0
        };
        let mut tau = t - self.start_time;
        if tau < 0.0 {
            return ActorState {
                position: self.waypoints[0],
                heading: first_heading,
                arrivals: 0,
            };
        }
        let mut arrivals_before = 0;
        if self.repeat {
            let cycles = (tau / self.cycle_time()).floor();
            tau -= cycles * self.cycle_time();
            arrivals_before = cycles as usize * n;
        }
        let mut leg_heading = first_heading;
        for k in 0..n {
            let last = k + 1 == n;
            let depart = self.pauses[k];
            if tau < depart || (last && !self.repeat) {
                return ActorState {
                    position: self.waypoints[k],
                    heading: leg_heading,
                    arrivals: arrivals_before + k + 1,
                };
            }
            tau -= depart;
            let (from, to) = (self.waypoints[k], self.waypoints[(k + 1) % n]);
            leg_heading = if to != from {
                heading(to - from)
            } else {
                leg_heading
            };
            let leg = self.leg_time(k);
            if tau < leg {
                let position = from + (to - from) * (tau / leg);
                return ActorState {
                    position,
                    heading: leg_heading,
                    arrivals: arrivals_before + k + 1,
                };
            }
            tau -= leg;
        }
        // Only reached by rounding at the very end of a cycle: back at the first waypoint.
        ActorState {
            position: self.waypoints[0],
            heading: leg_heading,
            arrivals: arrivals_before + n + 1,
        }
    }

    /// The waypoint index of the `arrival`-th arrival (1-based).
    pub fn waypoint_of_arrival(&self, arrival: usize) -> usize {
        (arrival.saturating_sub(1)) % self.waypoints.len()
    }
}

fn heading(v: Vector2<f64>) -> f64 {
    v.y.atan2(v.x)
}

/// An object an actor pulls.
#[derive(Clone, Debug, PartialEq)]
struct Carried {
    object: usize,
    body: RigidBodyHandle,
    /// Distance from the actor's axis to the object's centre (m).
    distance: f64,
    /// Height of the object's frame (its underside) while carried (m).
    z: f64,
    yaw: f64,
    held: bool,
}

/// One actor in the world.
#[derive(Clone, Debug, PartialEq)]
pub struct Actor {
    /// Its scenario description.
    pub spec: ActorSpec,
    /// Its kinematic body.
    pub body: RigidBodyHandle,
    plan: Plan,
    state: ActorState,
    moved: bool,
    carried: Option<Carried>,
    /// Time spent standing aside for the robot (s): the plan runs this much behind the clock.
    held: f64,
    /// The time of the last update (s).
    last: f64,
}

impl Actor {
    /// Builds actor `index` at its first waypoint; `objects` are the scenario's objects with their bodies.
    pub fn new(
        index: usize,
        spec: &ActorSpec,
        objects: &[(ObjectSpec, RigidBodyHandle)],
        physics: &mut PhysicsWorld,
        surfaces: &mut HashMap<ColliderHandle, Surface>,
    ) -> Result<Self, WorldError> {
        let plan = Plan::new(spec)?;
        let state = plan.state_at(f64::NEG_INFINITY);
        let body = physics.bodies.insert(
            RigidBodyBuilder::kinematic_position_based()
                .translation(Vector::new(
                    state.position.x as f32,
                    state.position.y as f32,
                    0.0,
                ))
                .build(),
        );
        let collider = ColliderBuilder::cylinder(spec.height as f32 / 2.0, spec.radius as f32)
            .position(Pose::from_parts(
                Vector::new(0.0, 0.0, spec.height as f32 / 2.0),
                Rotation::from_rotation_x(std::f32::consts::FRAC_PI_2),
            ))
            .collision_groups(InteractionGroups::new(
                groups::ACTOR,
                Group::ALL,
                InteractionTestMode::And,
            ))
            .build();
        let ch = physics
            .colliders
            .insert_with_parent(collider, body, &mut physics.bodies);
        surfaces.insert(
            ch,
            Surface::new(ACTOR_COLOUR, Texture::Plain, Owner::Actor(index)),
        );
        let carried = match &spec.carries {
            None => None,
            Some(name) => {
                let Some(object) = objects.iter().position(|(o, _)| &o.name == name) else {
                    return Err(WorldError::InvalidActor {
                        name: spec.name.clone(),
                        reason: format!("carries unknown object {name}"),
                    });
                };
                let (ospec, obody) = &objects[object];
                if ospec.fixed || ospec.elevation > 0.0 {
                    return Err(WorldError::InvalidActor {
                        name: spec.name.clone(),
                        reason: format!("cannot carry fixed object {name}"),
                    });
                }
                let reach = match ospec.kind {
                    ObjectKind::Cylinder => ospec.size.first().copied().unwrap_or(0.0) / 2.0,
                    _ => ospec.size.iter().take(2).fold(0.0_f64, |a, s| a.max(*s)) / 2.0,
                };
                if let Some(b) = physics.bodies.get_mut(*obody) {
                    b.set_body_type(RigidBodyType::KinematicPositionBased, true);
                }
                Some(Carried {
                    object,
                    body: *obody,
                    distance: spec.radius + CARRY_GAP + reach,
                    z: 0.0,
                    yaw: ospec.yaw.to_radians(),
                    held: true,
                })
            }
        };
        let mut actor = Self {
            spec: spec.clone(),
            body,
            plan,
            state,
            moved: false,
            carried,
            held: 0.0,
            last: 0.0,
        };
        actor.place_carried(physics, true);
        Ok(actor)
    }

    /// Where the actor is now.
    pub fn state(&self) -> &ActorState {
        &self.state
    }

    /// Whether it moved during the last update.
    pub fn is_moving(&self) -> bool {
        self.moved
    }

    /// The index of the object it pulls now, if it pulls one.
    pub fn carrying(&self) -> Option<usize> {
        self.carried.as_ref().filter(|c| c.held).map(|c| c.object)
    }

    /// Moves the actor to where its plan puts it at time `t`, leaving or taking its object on arrival.
    /// A yielding actor whose next step would bring it within [`PERSONAL_SPACE`] of a disc in `clear`,
    /// and closer to it than it stands, stays where it is and takes its plan up later.
    pub fn update(&mut self, t: f64, clear: &[KeepClear], physics: &mut PhysicsWorld) {
        let dt = (t - self.last).max(0.0);
        self.last = t;
        let mut next = self.plan.state_at(t - self.held);
        if self.spec.yields && self.would_crowd(&next.position, clear) {
            self.held += dt;
            next = self.state;
        }
        self.moved = next.position != self.state.position;
        for arrival in self.state.arrivals + 1..=next.arrivals {
            let wp = self.plan.waypoint_of_arrival(arrival);
            self.on_arrival(wp, physics);
        }
        self.state = next;
        if let Some(b) = physics.bodies.get_mut(self.body) {
            b.set_next_kinematic_translation(Vector::new(
                next.position.x as f32,
                next.position.y as f32,
                0.0,
            ));
        }
        self.place_carried(physics, false);
    }

    /// Whether stepping to `to` comes within personal space of a disc in `clear` while nearing it.
    fn would_crowd(&self, to: &Point2<f64>, clear: &[KeepClear]) -> bool {
        let from = self.state.position;
        clear.iter().any(|d| {
            let near = (to - d.centre).norm();
            near < (from - d.centre).norm() && near < self.spec.radius + d.radius + PERSONAL_SPACE
        })
    }

    fn on_arrival(&mut self, waypoint: usize, physics: &mut PhysicsWorld) {
        let Some(c) = self.carried.as_mut() else {
            return;
        };
        if c.held && self.spec.drop_at == Some(waypoint) {
            c.held = false;
            if let Some(b) = physics.bodies.get_mut(c.body) {
                b.set_body_type(RigidBodyType::Dynamic, true);
                b.set_linvel(Vector::ZERO, true);
                b.set_angvel(Vector::ZERO, true);
            }
        } else if !c.held && self.spec.pick_at == Some(waypoint) {
            c.held = true;
            if let Some(b) = physics.bodies.get_mut(c.body) {
                b.set_body_type(RigidBodyType::KinematicPositionBased, true);
            }
        }
    }

    /// Puts a held object behind the actor (at once when `teleport`, else as the next kinematic pose).
    fn place_carried(&mut self, physics: &mut PhysicsWorld, teleport: bool) {
        let Some(c) = self.carried.as_ref().filter(|c| c.held) else {
            return;
        };
        let back = Vector2::new(self.state.heading.cos(), self.state.heading.sin()) * c.distance;
        let p = self.state.position - back;
        let pose = Pose::from_parts(
            Vector::new(p.x as f32, p.y as f32, c.z as f32),
            Rotation::from_rotation_z(c.yaw as f32),
        );
        if let Some(b) = physics.bodies.get_mut(c.body) {
            if teleport {
                b.set_position(pose, true);
            } else {
                b.set_next_kinematic_position(pose);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(waypoints: Vec<[f64; 2]>, pause: Vec<f64>, repeat: bool) -> ActorSpec {
        ActorSpec {
            name: "a".into(),
            radius: 0.25,
            height: 1.7,
            waypoints,
            speed: 1.0,
            start_time: 2.0,
            pause,
            repeat,
            carries: None,
            drop_at: None,
            pick_at: None,
            yields: true,
        }
    }

    #[test]
    fn arrivals_count_each_waypoint_once() {
        // Arrivals rise by one at each waypoint reached; a one-way plan stops counting at its end.
        let plan = Plan::new(&spec(
            vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]],
            vec![],
            false,
        ))
        .expect("valid");
        let arrivals: Vec<usize> = [1.0, 2.0, 2.5, 3.5, 5.0, 50.0]
            .iter()
            .map(|t| plan.state_at(*t).arrivals)
            .collect();
        assert_eq!(arrivals, vec![0, 1, 1, 2, 3, 3]);
        assert_eq!(plan.state_at(50.0).position, Point2::new(1.0, 1.0));
    }

    #[test]
    fn repeating_plan_is_periodic() {
        // A repeating plan is at the same place one cycle later, and heads back to the first waypoint.
        let plan =
            Plan::new(&spec(vec![[0.0, 0.0], [2.0, 0.0]], vec![0.5, 0.5], true)).expect("valid");
        // Cycle: 0.5 + 2 + 0.5 + 2 = 5 s.
        for t in [2.3, 3.7, 5.9] {
            let (a, b) = (plan.state_at(t), plan.state_at(t + 5.0));
            assert!((a.position - b.position).norm() < 1e-9);
            assert_eq!(b.arrivals, a.arrivals + 2);
        }
        let back = plan.state_at(2.0 + 0.5 + 2.0 + 0.5 + 1.0);
        assert!((back.position - Point2::new(1.0, 0.0)).norm() < 1e-9);
        assert!((back.heading.abs() - std::f64::consts::PI).abs() < 1e-9);
    }

    #[test]
    fn a_yielding_actor_stops_short_of_the_robot_and_walks_on_when_it_has_gone() {
        // Invariant: a yielding actor walking at the robot stops while its next step would bring it within personal space of the robot's disc, never nearer than that, and takes its plan up where it left off once the disc is gone; an actor that does not yield walks through.
        let mut physics = PhysicsWorld::new();
        let mut surfaces = HashMap::new();
        let mut walker = spec(vec![[0.0, 0.0], [4.0, 0.0]], Vec::new(), false);
        walker.start_time = 0.0;
        let mut actor = Actor::new(0, &walker, &[], &mut physics, &mut surfaces).expect("an actor");
        let robot = KeepClear {
            centre: Point2::new(2.0, 0.0),
            radius: 0.35,
        };
        let limit = robot.radius + walker.radius + PERSONAL_SPACE;
        let mut t = 0.0;
        for _ in 0..400 {
            t += 0.01;
            actor.update(t, &[robot], &mut physics);
            let gap = (actor.state().position - robot.centre).norm();
            assert!(gap >= limit - 0.011, "came within {gap} of the robot");
        }
        let held = actor.state().position;
        assert!(
            held.x > 2.0 - limit - 0.02,
            "it walked up to the robot: {held}"
        );
        for _ in 0..100 {
            t += 0.01;
            actor.update(t, &[], &mut physics);
        }
        assert!(actor.state().position.x > held.x + 0.9, "it walked on");
        walker.yields = false;
        let mut rude = Actor::new(0, &walker, &[], &mut physics, &mut surfaces).expect("an actor");
        rude.update(3.0, &[robot], &mut physics);
        assert!(
            (rude.state().position.x - 3.0).abs() < 1e-9,
            "keeps its timetable"
        );
    }

    #[test]
    fn bad_actors_are_errors() {
        // No waypoints, a non-positive speed, or a drop index past the end are refused.
        assert!(Plan::new(&spec(vec![], vec![], false)).is_err());
        let mut s = spec(vec![[0.0, 0.0]], vec![], false);
        s.speed = 0.0;
        assert!(Plan::new(&s).is_err());
        let mut s = spec(vec![[0.0, 0.0], [1.0, 0.0]], vec![], false);
        s.drop_at = Some(2);
        assert!(Plan::new(&s).is_err());
    }
}
