//! Scenarios and drivers shared by the world tests.
#![allow(dead_code)]

use nudge_sim::scenario::Scenario;
use nudge_sim::world::World;

/// The paper's room (the brief's default geometry).
pub const KAKIUCHI_ROOM: &str = include_str!("kakiuchi_room.toml");

/// Parses a scenario written in a test.
pub fn scenario(toml_text: &str) -> Scenario {
    toml::from_str(toml_text).expect("test scenario parses")
}

/// A room with the robot at (1, 1.8) facing +x and one object described by `object` (TOML lines).
pub fn robot_and(object: &str) -> Scenario {
    scenario(&format!(
        r#"
name = "test"
[room]
size = [6.0, 3.6]
[robot]
start = [1.0, 1.8, 0.0]
[goal]
position = [5.0, 1.8]
[[object]]
{object}
"#
    ))
}

/// A world built from `s` with seed 1.
pub fn world(s: &Scenario) -> World {
    World::new(s, 1).expect("test world builds")
}
