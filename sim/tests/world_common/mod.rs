//! Scenarios and drivers shared by the world tests.
#![allow(dead_code)]

use nudge_sim::scenario::Scenario;
use nudge_sim::world::World;

/// The paper's room (the brief's default geometry).
pub const KAKIUCHI_ROOM: &str = r#"
name = "kakiuchi-room"
seed = 7
[room]
size = [6.0, 3.6]
[robot]
start = [0.6, 1.8, 0.0]
[goal]
position = [5.4, 1.8]
[[object]]
name = "table"
kind = "table"
position = [3.0, 1.8]
yaw = 90.0
size = [1.2, 0.8, 0.72]
mass = 25.0
friction = 0.6
colour = [140, 100, 60]
texture = "stripes"
[[object]]
name = "chair-1"
kind = "chair"
position = [3.8, 0.85]
size = [0.5, 0.5, 0.85]
mass = 4.0
friction = 0.4
colour = [40, 120, 200]
texture = "checker"
[[object]]
name = "chair-2"
kind = "chair"
position = [3.8, 2.75]
size = [0.5, 0.5, 0.85]
mass = 4.0
friction = 0.4
colour = [40, 160, 90]
texture = "noise"
[[object]]
name = "mat"
kind = "mat"
position = [1.6, 2.9]
size = [0.6, 0.4, 0.01]
mass = 0.5
colour = [180, 40, 40]
"#;

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
