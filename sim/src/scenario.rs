//! Scenario files (TOML): the public format of a run's room, robot, goal, objects and actors.
//!
//! Units as a person types them: metres, seconds, kilograms, degrees for angles (counter-clockwise from
//! +x), 0–255 RGB colours. The map frame has its origin at a corner of the room, x along `room.size[0]`,
//! y along `room.size[1]`, z up. Unknown fields are errors; so is any value outside the rules below.
//!
//! # Example (the paper's room, abridged: one chair)
//!
//! ```toml
//! name = "kakiuchi-room"
//! description = "The paper's room: a table and two chairs bar the way; one chair moves."
//! seed = 1                           # default 1; the CLI may override it
//! # family = "open-clutter"          # set by `nudge generate`; results are summed per family
//!
//! [room]
//! size = [6.0, 3.6]                  # x, y (m), at most 100 m a side; walls all around
//! wall_height = 2.0                  # m, default 2.0
//! floor_colour = [150, 150, 140]     # default [150, 150, 140]
//! wall_colour = [225, 222, 210]      # default [225, 222, 210]
//!
//! [robot]
//! start = [0.6, 1.8, 0.0]            # x, y (m), yaw (deg)
//! radius = 0.35                      # bounding cylinder (m), default 0.35
//! height = 1.54                      # default 1.54 m
//! walk_speed = 0.15                  # m/s, default 0.15
//!
//! [goal]
//! position = [5.4, 1.8]              # x, y (m)
//! tolerance = 0.2                    # m, default 0.2
//!
//! [[object]]
//! name = "chair-1"                   # unique among objects
//! kind = "chair"                     # box | cylinder | table | chair | mat
//! position = [3.8, 0.85]             # footprint centre x, y (m)
//! yaw = 0.0                          # deg, default 0
//! size = [0.5, 0.5, 0.85]            # x, y, z (m); a cylinder takes [diameter, height]
//! elevation = 0.0                    # underside above the floor (m), default 0
//! mass = 4.0                         # kg
//! friction = 0.4                     # against the floor, in [0, 2], default 0.6
//! fixed = false                      # bolted to the floor, default false
//! colour = [40, 70, 170]             # RGB
//! texture = "noise"                  # plain | stripes | checker | noise, default plain
//!
//! [[actor]]
//! name = "person"                    # unique among actors
//! radius = 0.25                      # default 0.25 m
//! height = 1.7                       # default 1.7 m
//! waypoints = [[1.0, 3.2], [5.0, 3.2]]   # x, y (m), at least one; starts at the first
//! speed = 0.6                        # m/s
//! start_time = 0.0                   # s, default 0
//! pause = [0.0, 3.0]                 # s at each waypoint: empty (default) or one per waypoint
//! repeat = false                     # walk the list again when done, default false
//! # carries = "suitcase"             # an object it pulls along from the start
//! # drop_at = 1                      # waypoint index where it leaves the object
//! # pick_at = 2                      # waypoint index where it takes it back (after drop_at)
//!
//! [expect]                           # optional: what a correct run shows
//! outcome = "goal"                   # goal | no_path
//! movable = ["chair-1"]              # object names, default []
//! static = []                        # object names, default []
//! ```
//!
//! # Rules
//!
//! Loading ([`Scenario::from_toml_str`], [`Scenario::from_path`]) refuses, with the file, line, column and
//! field path of the offending value (`kakiuchi-room.toml:31:8: object[1].mass: must be positive, got -3`):
//!
//! - TOML syntax errors, unknown fields, missing required fields, values of the wrong type;
//! - NaN or infinite numbers anywhere;
//! - sizes, masses, radii, heights, the wall height, the goal tolerance and speeds that are zero or
//!   negative; a negative elevation, start time or pause; friction outside [0, 2];
//! - a `size` with the wrong number of entries (3 for box, table, chair, mat; 2 for cylinder);
//! - a room over 100 m a side, or more than 500 objects;
//! - object footprints (rotated by their yaw), the robot's start disc, the goal point, or an actor's disc at
//!   any waypoint outside the room (touching a wall is allowed);
//! - the robot's disc at the start overlapping an object, or the goal point inside one. Mats do not count
//!   (the robot walks over them), nor do objects whose `elevation` is at or above the robot's height (it
//!   walks under them);
//! - duplicate object names or duplicate actor names;
//! - an actor with no waypoints, a `pause` list neither empty nor one per waypoint, `carries` naming an
//!   unknown or fixed object or one another actor already carries, `drop_at`/`pick_at` without `carries`
//!   or past the last waypoint, `pick_at` without `drop_at` or not after it (unless the walk repeats);
//! - `[expect]` naming unknown objects, or one object both movable and static.

mod corridor;
mod error;
mod geometry;
mod load;
mod locate;
mod validate;

pub use corridor::push_test_corridor;
pub use error::{FieldPath, InvalidScenario, PathSegment, ScenarioError, ScenarioFault};
pub use geometry::{BOUNDARY_TOLERANCE, DISC_POLYGON_CORNERS, Footprint, GRAVITY, Shape};
pub use load::{DEFAULT_ROOM_ORIGIN, DEFAULT_ROOM_TOML};
pub use validate::{FRICTION_RANGE, MAX_OBJECTS, MAX_ROOM_SIDE, Violation};

use nudge_robot_model::RobotModel;
use serde::{Deserialize, Serialize};

/// A whole scenario file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Short name, e.g. "kakiuchi-room".
    pub name: String,
    /// One line on what the scenario shows.
    #[serde(default)]
    pub description: String,
    /// The family a generated scenario belongs to (`nudge generate`); results are summed per family.
    /// None for a hand-made scenario, whose family is its own name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub family: Option<String>,
    /// Default seed of a run; the CLI may override it.
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// The room, with walls built around it.
    pub room: Room,
    /// The robot's start and body.
    pub robot: RobotSpec,
    /// Where the robot must go.
    pub goal: Goal,
    /// Obstacles, movable or not.
    #[serde(default, rename = "object")]
    pub objects: Vec<ObjectSpec>,
    /// Things that move by themselves.
    #[serde(default, rename = "actor", skip_serializing_if = "Vec::is_empty")]
    pub actors: Vec<ActorSpec>,
    /// What a correct run shows (used by tests and `nudge check`).
    #[serde(default)]
    pub expect: Option<Expect>,
}

fn default_seed() -> u64 {
    1
}

impl Scenario {
    /// An empty `size` room with the robot at `start` (x, y, yaw in degrees) and the goal at `goal`,
    /// everything else the format's defaults: what a generator starts from.
    pub fn bare(name: &str, size: [f64; 2], start: [f64; 3], goal: [f64; 2]) -> Self {
        Self {
            name: name.to_string(),
            description: String::new(),
            family: None,
            seed: default_seed(),
            room: Room {
                size,
                wall_height: default_wall_height(),
                floor_colour: default_floor_colour(),
                wall_colour: default_wall_colour(),
            },
            robot: RobotSpec::at(start),
            goal: Goal {
                position: goal,
                tolerance: default_goal_tolerance(),
            },
            objects: Vec::new(),
            actors: Vec::new(),
            expect: None,
        }
    }
}

/// The room: a floor `size[0] × size[1]` with its corner at the origin, walls around it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Room {
    /// Extent along x and y (m).
    pub size: [f64; 2],
    /// Height of the walls (m).
    #[serde(default = "default_wall_height")]
    pub wall_height: f64,
    /// Floor colour, RGB 0–255.
    #[serde(default = "default_floor_colour")]
    pub floor_colour: [u8; 3],
    /// Wall colour, RGB 0–255.
    #[serde(default = "default_wall_colour")]
    pub wall_colour: [u8; 3],
}

fn default_wall_height() -> f64 {
    2.0
}
fn default_floor_colour() -> [u8; 3] {
    [150, 150, 140]
}
fn default_wall_colour() -> [u8; 3] {
    [225, 222, 210]
}

/// The robot: where it starts, and what it is.
///
/// What it is comes from `[robot.model]`, a robot description (`nudge_robot_model::RobotModel`: body,
/// head, camera, arm, wrist, force limits), every field of which defaults to the paper's HRP-2;
/// `radius`, `height` and `walk_speed` are shorthands for its `body` fields.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotSpec {
    /// x, y (m), yaw (deg).
    pub start: [f64; 3],
    /// Radius of the bounding cylinder (m): `model.body.radius`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Height of the bounding cylinder (m): `model.body.height`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    /// Walking speed (m/s): `model.body.walk_speed`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub walk_speed: Option<f64>,
    /// The robot description, short of the shorthands above.
    #[serde(default, skip_serializing_if = "is_default_model")]
    pub model: RobotModel,
}

fn is_default_model(model: &RobotModel) -> bool {
    *model == RobotModel::default()
}

impl RobotSpec {
    /// A robot of the paper's kind starting at `start` (x, y in m, yaw in deg).
    pub fn at(start: [f64; 3]) -> Self {
        Self {
            start,
            radius: None,
            height: None,
            walk_speed: None,
            model: RobotModel::default(),
        }
    }

    /// The robot description with the shorthands applied: what every part of a run reads.
    pub fn model(&self) -> RobotModel {
        let mut model = self.model.clone();
        model.body.radius = self.radius();
        model.body.height = self.height();
        model.body.walk_speed = self.walk_speed();
        model
    }

    /// Radius of the bounding cylinder (m).
    pub fn radius(&self) -> f64 {
        self.radius.unwrap_or(self.model.body.radius)
    }

    /// Height of the bounding cylinder (m).
    pub fn height(&self) -> f64 {
        self.height.unwrap_or(self.model.body.height)
    }

    /// Walking speed (m/s).
    pub fn walk_speed(&self) -> f64 {
        self.walk_speed.unwrap_or(self.model.body.walk_speed)
    }
}

/// The goal region: a disc on the floor.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Goal {
    /// Centre x, y (m).
    pub position: [f64; 2],
    /// Radius within which the goal counts as reached (m).
    #[serde(default = "default_goal_tolerance")]
    pub tolerance: f64,
}

fn default_goal_tolerance() -> f64 {
    0.2
}

/// The shape family of an object.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ObjectKind {
    /// A solid box.
    Box,
    /// An upright cylinder.
    Cylinder,
    /// A top on four legs.
    Table,
    /// A seat, a back and four legs.
    Chair,
    /// A thin flat object lying on the floor.
    Mat,
}

/// Colour variation over an object's surface, which colour ICP needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Texture {
    /// One colour.
    #[default]
    Plain,
    /// Stripes of the colour and a darker shade.
    Stripes,
    /// A checkerboard of the colour and a darker shade.
    Checker,
    /// Per-patch colour noise, fixed by the scenario seed.
    Noise,
}

/// One object in the room.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectSpec {
    /// Unique name, used by `[expect]` and in reports.
    pub name: String,
    /// Shape family.
    pub kind: ObjectKind,
    /// x, y of the footprint centre (m).
    pub position: [f64; 2],
    /// Heading (deg).
    #[serde(default)]
    pub yaw: f64,
    /// Box, table, chair, mat: x, y, z (m); cylinder: diameter, height (m).
    pub size: Vec<f64>,
    /// Height of the underside above the floor (m): a shelf, a pipe.
    #[serde(default)]
    pub elevation: f64,
    /// Mass (kg).
    pub mass: f64,
    /// Coulomb friction coefficient against the floor, in [0, 2].
    #[serde(default = "default_friction")]
    pub friction: f64,
    /// True: bolted to the floor.
    #[serde(default)]
    pub fixed: bool,
    /// Main colour, RGB 0–255; parts of tables and chairs may shade it.
    pub colour: [u8; 3],
    /// Colour variation.
    #[serde(default)]
    pub texture: Texture,
}

fn default_friction() -> f64 {
    0.6
}

/// Something that moves by itself along waypoints: a person, another robot.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ActorSpec {
    /// Unique name.
    pub name: String,
    /// Radius of its bounding cylinder (m).
    #[serde(default = "default_actor_radius")]
    pub radius: f64,
    /// Height of its bounding cylinder (m).
    #[serde(default = "default_actor_height")]
    pub height: f64,
    /// Points it walks through, x, y (m); it starts at the first.
    pub waypoints: Vec<[f64; 2]>,
    /// Walking speed (m/s).
    pub speed: f64,
    /// When it starts walking (s).
    #[serde(default)]
    pub start_time: f64,
    /// Seconds to wait at each waypoint (one entry per waypoint, or empty for none).
    #[serde(default)]
    pub pause: Vec<f64>,
    /// Walk the waypoints again from the first when done.
    #[serde(default)]
    pub repeat: bool,
    /// Name of an object it pulls along from the start.
    #[serde(default)]
    pub carries: Option<String>,
    /// Waypoint index where it leaves the carried object.
    #[serde(default)]
    pub drop_at: Option<usize>,
    /// Waypoint index where it takes the object back.
    #[serde(default)]
    pub pick_at: Option<usize>,
    /// Whether it stops rather than walk into the robot (as people do): it waits while its next step
    /// would bring it closer to the robot's body or hand than its personal space, and walks on when
    /// the way is clear. Default true; false for a walker that keeps to its timetable whatever stands
    /// in its way (a test of contact counting).
    #[serde(default = "default_yields")]
    pub yields: bool,
}

fn default_yields() -> bool {
    true
}

fn default_actor_radius() -> f64 {
    0.25
}
fn default_actor_height() -> f64 {
    1.7
}

/// How a run ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ExpectedOutcome {
    /// The robot reaches the goal.
    Goal,
    /// The executive proves there is no path.
    NoPath,
}

/// What a correct run shows.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Expect {
    /// The outcome must match.
    pub outcome: ExpectedOutcome,
    /// Objects that must be classified movable.
    #[serde(default)]
    pub movable: Vec<String>,
    /// Objects that must be classified static.
    #[serde(default, rename = "static")]
    pub static_: Vec<String>,
}
