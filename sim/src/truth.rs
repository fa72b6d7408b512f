//! Ground truth for scoring a run: where objects really are, which really move, and what a map
//! point really is now.
//!
//! Movability rule: an object is [`Movability::Movable`] when it is a dynamic body (not bolted, not
//! lifted) and the force to slide it, μ·m·g, is below 80 % of the push test's force limit (the
//! robot's, [`nudge_robot_model::ForceModel::test_limit`]: the paper's 20 N) — the margin keeps
//! borderline objects out of the score.
//! Everything else is [`Movability::Static`]: it would not move under a guarded push.

use nalgebra::{Isometry3, Point2, Point3};

use crate::scenario::ObjectKind;
use crate::world::World;

/// Fraction of the push limit a movable object's sliding force must stay below.
pub const MOVABLE_MARGIN: f64 = 0.8;
/// Objects faster than this are moving (m/s).
pub const MOVING_SPEED: f64 = 0.05;
/// Objects whose top is at most this high are flat on the floor and not obstacles (m).
pub const FLAT: f64 = 0.02;

/// Whether an object moves when pushed with the guarded push.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Movability {
    /// It slides under a push below the force limit.
    Movable,
    /// It does not: bolted, lifted, or too heavy.
    Static,
}

/// The true class of a map point now.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrueClass {
    /// Nothing there (the robot's own body does not count).
    Free,
    /// Walls, outside the room, static objects.
    Stationary,
    /// A movable object at rest.
    Movable,
    /// An actor, or an object moving faster than [`MOVING_SPEED`].
    Moving,
}

/// Ground-truth queries on a world.
pub struct Truth<'a> {
    world: &'a World,
}

impl<'a> Truth<'a> {
    /// Ground truth of `world` at its current time.
    pub fn new(world: &'a World) -> Self {
        Self { world }
    }

    /// The push test's force limit of the world's robot (N), which movability is judged against.
    pub fn push_limit(&self) -> f64 {
        self.world.robot_model().force.test_limit
    }

    /// The true pose of object `i` (footprint centre on its underside), or `None` if there is none.
    pub fn object_pose(&self, i: usize) -> Option<Isometry3<f64>> {
        self.world.object_pose(i)
    }

    /// The true movability of object `i`, by the rule in the module docs.
    pub fn movability(&self, i: usize) -> Option<Movability> {
        let (spec, _) = self.world.objects().get(i)?;
        let dynamic = !crate::world::build::is_fixed(spec);
        let slide = spec.sliding_force();
        Some(if dynamic && slide < MOVABLE_MARGIN * self.push_limit() {
            Movability::Movable
        } else {
            Movability::Static
        })
    }

    /// Whether some actor of the scenario carries object `i` at some time (it is moved by a person,
    /// whatever the robot's push could do).
    pub fn carried_by_an_actor(&self, i: usize) -> bool {
        let Some((spec, _)) = self.world.objects().get(i) else {
            return false;
        };
        self.world
            .actors()
            .iter()
            .any(|a| a.spec.carries.as_deref() == Some(spec.name.as_str()))
    }

    /// The true obstacle type of the map point `p` now, in Tamura et al.'s terms (the classes of the
    /// obstacle-type grid): like [`Truth::true_class_at`], except that a resting object is
    /// [`TrueClass::Movable`] when anything in this world can move it — an actor carries it at some
    /// time (the suitcase a person leaves and takes again), or the robot's guarded push slides it. The
    /// push-test scoring keeps [`Truth::movability`] (robot-pushable only): an 8 kg suitcase a person
    /// pulls is movable to Tamura and static to a 20 N push.
    pub fn obstacle_type_at(&self, p: Point2<f64>) -> TrueClass {
        match self.true_class_at(p) {
            TrueClass::Stationary => {
                let moved_by_an_actor = self
                    .object_at(p)
                    .is_some_and(|i| self.carried_by_an_actor(i));
                if moved_by_an_actor {
                    TrueClass::Movable
                } else {
                    TrueClass::Stationary
                }
            }
            c => c,
        }
    }

    /// The true class of the map point `p` now.
    pub fn true_class_at(&self, p: Point2<f64>) -> TrueClass {
        let room = &self.world_room();
        if !(p.x > 0.0 && p.y > 0.0 && p.x < room[0] && p.y < room[1]) {
            return TrueClass::Stationary;
        }
        for a in self.world.actors() {
            if (a.state().position - p).norm() <= a.spec.radius {
                return TrueClass::Moving;
            }
        }
        let Some(i) = self.object_at(p) else {
            return TrueClass::Free;
        };
        let moving = self.world.object_speed(i).is_some_and(|s| s > MOVING_SPEED)
            || self.world.actors().iter().any(|a| a.carrying() == Some(i));
        match (moving, self.movability(i)) {
            (true, _) => TrueClass::Moving,
            (false, Some(Movability::Movable)) => TrueClass::Movable,
            _ => TrueClass::Stationary,
        }
    }

    /// The first object (in scenario order) whose footprint holds the map point `p` now, leaving out
    /// objects flat on the floor and objects lifted above the robot (they are no obstacles).
    pub fn object_at(&self, p: Point2<f64>) -> Option<usize> {
        let robot_height = self.world.humanoid_height();
        self.world
            .objects()
            .iter()
            .enumerate()
            .position(|(i, (spec, _))| {
                let top = spec.elevation
                    + if spec.kind == ObjectKind::Cylinder {
                        spec.size[1]
                    } else {
                        spec.size[2]
                    };
                top > FLAT && spec.elevation < robot_height && self.footprint_holds(i, p)
            })
    }

    /// Whether anything real stands at the map point `p` now: the room's walls (everything outside
    /// the room), a person, or an object of any height (a mat too, a pipe overhead too). An obstacle
    /// the executive keeps where nothing of these is, is a ghost.
    pub fn anything_at(&self, p: Point2<f64>) -> bool {
        let room = self.world_room();
        !(p.x > 0.0 && p.y > 0.0 && p.x < room[0] && p.y < room[1])
            || self
                .world
                .actors()
                .iter()
                .any(|a| (a.state().position - p).norm() <= a.spec.radius)
            || (0..self.world.objects().len()).any(|i| self.footprint_holds(i, p))
    }

    /// Whether object `i`'s footprint (where it stands now) holds the map point `p`.
    fn footprint_holds(&self, i: usize, p: Point2<f64>) -> bool {
        let (Some((spec, _)), Some(pose)) =
            (self.world.objects().get(i), self.world.object_pose(i))
        else {
            return false;
        };
        let local = pose.inverse_transform_point(&Point3::new(p.x, p.y, pose.translation.z));
        match spec.kind {
            ObjectKind::Cylinder => local.x.hypot(local.y) <= spec.size[0] / 2.0,
            _ => local.x.abs() <= spec.size[0] / 2.0 && local.y.abs() <= spec.size[1] / 2.0,
        }
    }

    fn world_room(&self) -> [f64; 2] {
        self.world.room_size()
    }
}
