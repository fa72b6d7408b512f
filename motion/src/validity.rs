//! Is this configuration free? The robot's bounding cylinder against prisms and walls.
//!
//! The cylinder (radius, height) stands on the floor. A prism blocks it only when their height ranges
//! meet: a prism whose lowest point is at or above the robot's top (a pipe overhead, Miyazaki's
//! robot passing under a 73 cm pipe) does not block, nor does one whose top is below the step height
//! (a mat on the floor). The rest are exact 2D queries through parry2d: the disc against each
//! footprint for a point, the swept disc (a capsule: segment distance below the radius) for a motion,
//! with a uniform grid as broad phase. The bounds are walls: the whole disc must stay inside them.

use nalgebra::{Point2, Vector2};
use nudge_perception::{ObjectId, Prism};

use crate::broad_phase::Grid;
use crate::obstacle::{Aabb, Obstacle, ObstacleError};
use crate::space::Bounds;

/// The robot as the planner sees it: a vertical cylinder standing on the floor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RobotCylinder {
    /// Radius (m).
    pub radius: f64,
    /// Height (m).
    pub height: f64,
}

/// Rules that decide which prisms block the cylinder.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ValidityConfig {
    /// Prisms whose top is below this (m) are stepped over (a mat, a cable).
    pub step_height: f64,
}

impl Default for ValidityConfig {
    /// The paper's robot's ([`nudge_robot_model::RobotModel::default`]).
    fn default() -> Self {
        Self::for_body(&nudge_robot_model::BodyModel::default())
    }
}

impl ValidityConfig {
    /// What `body` steps over.
    pub fn for_body(body: &nudge_robot_model::BodyModel) -> Self {
        Self {
            step_height: body.step_over,
        }
    }
}

/// Why a validity checker could not be built.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum ValidityError {
    /// Radius or height not finite and positive.
    #[error("robot radius {radius} and height {height} must be finite and positive")]
    BadRobot {
        /// Radius given (m).
        radius: f64,
        /// Height given (m).
        height: f64,
    },
    /// The bounds are narrower than the robot's diameter: no position fits.
    #[error("the bounds leave no room for a robot of radius {radius} m")]
    BoundsTooSmall {
        /// Radius of the robot (m).
        radius: f64,
    },
    /// A prism could not be made an obstacle.
    #[error(transparent)]
    Obstacle(#[from] ObstacleError),
    /// An id named in an edit is not among the blocking obstacles.
    #[error("no blocking obstacle {0}")]
    UnknownObstacle(ObjectId),
}

/// What a planner needs from a validity checker (OMPL's `StateValidityChecker` + `MotionValidator`).
pub trait StateValidity {
    /// Whether the robot standing at `p` touches nothing.
    fn is_free(&self, p: &Point2<f64>) -> bool;
    /// Whether the robot sliding straight from `a` to `b` touches nothing on the way.
    fn motion_free(&self, a: &Point2<f64>, b: &Point2<f64>) -> bool;
    /// Where the robot's axis may be: the rectangle planners sample from.
    fn sampling_bounds(&self) -> &Bounds;
}

/// The validity checker for a cylinder among prisms inside walls.
#[derive(Clone, Debug)]
pub struct Validity {
    robot: RobotCylinder,
    config: ValidityConfig,
    walls: Bounds,
    centre_bounds: Bounds,
    obstacles: Vec<Obstacle>,
    passable: Vec<ObjectId>,
    grid: Grid,
}

impl Validity {
    /// A checker for `robot` inside `walls` among `prisms`.
    pub fn new(
        robot: RobotCylinder,
        walls: Bounds,
        prisms: &[Prism],
        config: ValidityConfig,
    ) -> Result<Self, ValidityError> {
        let obstacles = prisms
            .iter()
            .map(Obstacle::from_prism)
            .collect::<Result<Vec<_>, _>>()?;
        Self::from_obstacles(robot, walls, obstacles, config)
    }

    /// A checker from obstacles already built.
    pub fn from_obstacles(
        robot: RobotCylinder,
        walls: Bounds,
        obstacles: Vec<Obstacle>,
        config: ValidityConfig,
    ) -> Result<Self, ValidityError> {
        let ok = |v: f64| v.is_finite() && v > 0.0;
        if !ok(robot.radius) || !ok(robot.height) {
            return Err(ValidityError::BadRobot {
                radius: robot.radius,
                height: robot.height,
            });
        }
        let centre_bounds = walls
            .shrunk(robot.radius)
            .ok_or(ValidityError::BoundsTooSmall {
                radius: robot.radius,
            })?;
        let (blocking, passable): (Vec<Obstacle>, Vec<Obstacle>) = obstacles
            .into_iter()
            .partition(|o| blocks(&robot, &config, o.z_min(), o.z_max()));
        let boxes: Vec<Aabb> = blocking
            .iter()
            .map(|o| o.aabb().inflated(robot.radius))
            .collect();
        Ok(Self {
            robot,
            config,
            walls,
            centre_bounds,
            grid: Grid::new(&boxes),
            obstacles: blocking,
            passable: passable.iter().map(Obstacle::id).collect(),
        })
    }

    /// The same world without the obstacles in `ids` (unknown ids are ignored).
    pub fn without(&self, ids: &[ObjectId]) -> Self {
        let kept = self
            .obstacles
            .iter()
            .filter(|o| !ids.contains(&o.id()))
            .cloned()
            .collect();
        self.rebuilt(kept)
    }

    /// The same world with obstacle `id` translated by `offset` (m).
    pub fn with_moved(&self, id: ObjectId, offset: &Vector2<f64>) -> Result<Self, ValidityError> {
        let mut found = false;
        let moved = self
            .obstacles
            .iter()
            .map(|o| {
                if o.id() == id {
                    found = true;
                    o.translated(offset)
                } else {
                    Ok(o.clone())
                }
            })
            .collect::<Result<Vec<_>, _>>()?;
        if !found {
            return Err(ValidityError::UnknownObstacle(id));
        }
        Ok(self.rebuilt(moved))
    }

    fn rebuilt(&self, obstacles: Vec<Obstacle>) -> Self {
        let boxes: Vec<Aabb> = obstacles
            .iter()
            .map(|o| o.aabb().inflated(self.robot.radius))
            .collect();
        Self {
            grid: Grid::new(&boxes),
            obstacles,
            ..self.clone_without_obstacles()
        }
    }

    fn clone_without_obstacles(&self) -> Self {
        Self {
            robot: self.robot,
            config: self.config,
            walls: self.walls,
            centre_bounds: self.centre_bounds,
            obstacles: Vec::new(),
            passable: self.passable.clone(),
            grid: Grid::new(&[]),
        }
    }

    /// The robot checked.
    pub fn robot(&self) -> &RobotCylinder {
        &self.robot
    }

    /// The rules in force.
    pub fn config(&self) -> &ValidityConfig {
        &self.config
    }

    /// The walls: the rectangle the whole robot must stay in.
    pub fn walls(&self) -> &Bounds {
        &self.walls
    }

    /// The obstacles that block the robot (the others were passed under or stepped over).
    pub fn obstacles(&self) -> &[Obstacle] {
        &self.obstacles
    }

    /// The blocking obstacle `id`, if there is one.
    pub fn obstacle(&self, id: ObjectId) -> Option<&Obstacle> {
        self.obstacles.iter().find(|o| o.id() == id)
    }

    /// Prisms that do not block the robot: above its head or below the step height.
    pub fn passable(&self) -> &[ObjectId] {
        &self.passable
    }

    /// Distance from the cylinder's surface at `p` to the nearest blocking obstacle or wall (m);
    /// zero or negative when the robot touches or overlaps something.
    pub fn clearance(&self, p: &Point2<f64>) -> f64 {
        let wall = self.walls.signed_inner_distance(p);
        let nearest = self
            .obstacles
            .iter()
            .map(|o| o.distance_to_point(p))
            .fold(wall, f64::min);
        nearest - self.robot.radius
    }

    /// Whether the robot standing at `p` overlaps a blocking obstacle by more than `margin` (m): then
    /// every position within `margin` of `p` overlaps it too (the distance to a footprint changes no
    /// faster than the position). Walls are not counted.
    pub fn deeper_than(&self, p: &Point2<f64>, margin: f64) -> bool {
        let reach = self.robot.radius - margin;
        if reach.is_nan() || reach <= 0.0 {
            return false;
        }
        self.grid.any(&segment_box(p, p), |i| {
            self.obstacles[i].distance_to_point(p) < reach
        })
    }

    /// Like [`Validity::deeper_than`], saying which obstacle: one the robot standing at `p` overlaps by
    /// more than `margin`, or `None`.
    pub fn deeper_than_which(&self, p: &Point2<f64>, margin: f64) -> Option<ObjectId> {
        let reach = self.robot.radius - margin;
        if reach.is_nan() || reach <= 0.0 {
            return None;
        }
        let mut found = None;
        self.grid.any(&segment_box(p, p), |i| {
            let hit = self.obstacles[i].distance_to_point(p) < reach;
            if hit {
                found = Some(self.obstacles[i].id());
            }
            hit
        });
        found
    }

    /// Whether the robot standing at `p` overlaps obstacle `id` alone by more than `margin`; false
    /// when there is no such obstacle.
    pub fn obstacle_deeper_than(&self, id: ObjectId, p: &Point2<f64>, margin: f64) -> bool {
        let reach = self.robot.radius - margin;
        if reach.is_nan() || reach <= 0.0 {
            return false;
        }
        self.obstacle(id).is_some_and(|o| {
            o.aabb().inflated(reach).overlaps(&segment_box(p, p)) && o.distance_to_point(p) < reach
        })
    }

    /// The blocking obstacles the robot standing at `p` overlaps, in the order they were given.
    pub fn colliding(&self, p: &Point2<f64>) -> Vec<ObjectId> {
        self.hits_along(p, p)
    }

    /// The blocking obstacles the robot sliding from `a` to `b` overlaps, in the order given.
    pub fn hits_along(&self, a: &Point2<f64>, b: &Point2<f64>) -> Vec<ObjectId> {
        let mut hits = Vec::new();
        self.grid.for_each(&segment_box(a, b), |i| {
            let o = &self.obstacles[i];
            if o.capsule_hits(a, b, self.robot.radius) {
                hits.push(i);
            }
        });
        hits.sort_unstable();
        hits.into_iter().map(|i| self.obstacles[i].id()).collect()
    }

    fn point_hits_obstacle(&self, p: &Point2<f64>) -> bool {
        let r = self.robot.radius;
        self.grid.any(&segment_box(p, p), |i| {
            let o = &self.obstacles[i];
            o.aabb().inflated(r).overlaps(&segment_box(p, p)) && o.disc_hits(p, r)
        })
    }

    fn segment_hits_obstacle(&self, a: &Point2<f64>, b: &Point2<f64>) -> bool {
        let r = self.robot.radius;
        let query = segment_box(a, b);
        self.grid.any(&query, |i| {
            let o = &self.obstacles[i];
            o.aabb().inflated(r).overlaps(&query) && o.capsule_hits(a, b, r)
        })
    }
}

impl StateValidity for Validity {
    fn is_free(&self, p: &Point2<f64>) -> bool {
        self.centre_bounds.contains(p) && !self.point_hits_obstacle(p)
    }

    fn motion_free(&self, a: &Point2<f64>, b: &Point2<f64>) -> bool {
        // The centre bounds are convex: both ends inside means the whole segment is.
        self.centre_bounds.contains(a)
            && self.centre_bounds.contains(b)
            && !self.segment_hits_obstacle(a, b)
    }

    fn sampling_bounds(&self) -> &Bounds {
        &self.centre_bounds
    }
}

/// Whether a prism spanning `z_min..z_max` blocks `robot`: their height ranges meet, and it is not
/// low enough to step over.
pub fn blocks(robot: &RobotCylinder, config: &ValidityConfig, z_min: f64, z_max: f64) -> bool {
    z_min < robot.height && z_max >= config.step_height
}

fn segment_box(a: &Point2<f64>, b: &Point2<f64>) -> Aabb {
    Aabb {
        min: a.inf(b),
        max: a.sup(b),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(id: u32, x0: f64, y0: f64, x1: f64, y1: f64, z0: f64, z1: f64) -> Obstacle {
        let pts = [
            Point2::new(x0, y0),
            Point2::new(x1, y0),
            Point2::new(x1, y1),
            Point2::new(x0, y1),
        ];
        Obstacle::new(ObjectId(id), &pts, z0, z1).expect("rectangle")
    }

    fn world(obstacles: Vec<Obstacle>) -> Validity {
        let robot = RobotCylinder {
            radius: 0.3,
            height: 1.5,
        };
        let walls = Bounds::new(Point2::new(0.0, 0.0), Point2::new(10.0, 10.0)).expect("bounds");
        Validity::from_obstacles(robot, walls, obstacles, ValidityConfig::default())
            .expect("valid world")
    }

    #[test]
    fn pipes_overhead_and_mats_underfoot_do_not_block() {
        // Invariant: only prisms whose height range meets the cylinder's (above the step) block it.
        let v = world(vec![
            rect(1, 4.0, 4.0, 6.0, 6.0, 1.6, 1.8),  // pipe above the head
            rect(2, 1.0, 1.0, 2.0, 2.0, 0.0, 0.01), // mat
            rect(3, 7.0, 7.0, 8.0, 8.0, 1.2, 1.8),  // shelf at chest height
        ]);
        assert!(v.is_free(&Point2::new(5.0, 5.0)));
        assert!(v.is_free(&Point2::new(1.5, 1.5)));
        assert!(!v.is_free(&Point2::new(7.5, 7.5)));
        assert_eq!(v.passable(), &[ObjectId(1), ObjectId(2)]);
    }

    #[test]
    fn disc_and_capsule_checks_are_exact_at_the_radius() {
        // Invariant: free iff the distance to every footprint is at least the radius (to 1e-4 m).
        let v = world(vec![rect(1, 4.0, 0.0, 5.0, 6.0, 0.0, 1.0)]);
        assert!(v.is_free(&Point2::new(3.6999, 3.0)));
        assert!(!v.is_free(&Point2::new(3.7001, 3.0)));
        // A motion whose endpoints are free but whose sweep grazes the corner (5, 6).
        let a = Point2::new(3.0, 6.25);
        let b = Point2::new(7.0, 6.25);
        assert!(v.is_free(&a) && v.is_free(&b));
        assert!(!v.motion_free(&a, &b));
        assert!(v.motion_free(&Point2::new(3.0, 6.31), &Point2::new(7.0, 6.31)));
        assert_eq!(v.hits_along(&a, &b), vec![ObjectId(1)]);
        // Walls: the disc must stay inside.
        assert!(!v.is_free(&Point2::new(0.29, 5.0)));
        assert!((v.clearance(&Point2::new(3.0, 3.0)) - 0.7).abs() < 1e-5);
    }

    #[test]
    fn editing_the_world_moves_and_removes_obstacles() {
        // Invariant: without() frees the removed footprint; with_moved() blocks the new one.
        let v = world(vec![rect(1, 4.0, 4.0, 5.0, 5.0, 0.0, 1.0)]);
        let p = Point2::new(4.5, 4.5);
        assert!(!v.is_free(&p));
        assert!(v.without(&[ObjectId(1)]).is_free(&p));
        let moved = v
            .with_moved(ObjectId(1), &Vector2::new(2.0, 0.0))
            .expect("obstacle 1 exists");
        assert!(moved.is_free(&p));
        assert!(!moved.is_free(&Point2::new(6.5, 4.5)));
        assert!(v.with_moved(ObjectId(9), &Vector2::new(1.0, 0.0)).is_err());
    }
}
