//! Scenario files (TOML): the public format of a run's room, robot, goal, objects and actors.
//!
//! Units as a person types them: metres, seconds, kilograms, degrees for angles, 0–255 colours.
//! Unknown fields are errors.

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
    #[serde(default, rename = "actor")]
    pub actors: Vec<ActorSpec>,
    /// What a correct run shows (used by tests and `nudge check`).
    #[serde(default)]
    pub expect: Option<Expect>,
}

fn default_seed() -> u64 {
    1
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

/// The robot: where it starts and its bounding cylinder.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotSpec {
    /// x, y (m), yaw (deg).
    pub start: [f64; 3],
    /// Radius of the bounding cylinder (m).
    #[serde(default = "default_robot_radius")]
    pub radius: f64,
    /// Height of the bounding cylinder (m).
    #[serde(default = "default_robot_height")]
    pub height: f64,
    /// Walking speed (m/s).
    #[serde(default = "default_walk_speed")]
    pub walk_speed: f64,
}

fn default_robot_radius() -> f64 {
    0.35
}
fn default_robot_height() -> f64 {
    1.54
}
fn default_walk_speed() -> f64 {
    0.15
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
