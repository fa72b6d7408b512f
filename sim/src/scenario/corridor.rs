//! The push-test corridor: one box across a corridor too narrow to pass it, so that the executive
//! must push-test it to get by (the push-test sweep of `sim/examples/push_test_sweep.rs`, and the
//! tests that pin its margin).

use super::{Scenario, ScenarioError};

/// A 7 m × 1.4 m corridor with the robot at one end, the goal at the other and a box 0.6 m deep,
/// 0.9 m wide and 0.7 m tall between them, of `mass` (kg) on a floor of `friction` (μ): 0.25 m either
/// side, less than the robot's 0.7 m width, so it must be pushed. The box slides at μmg and, pushed
/// just below its top, tips at m g d / 2h: under 10 N for the lightest.
pub fn push_test_corridor(mass: f64, friction: f64) -> Result<Scenario, ScenarioError> {
    let text = format!(
        r#"name = "push-test-corridor"
[room]
size = [7.0, 1.4]
wall_height = 2.0
[robot]
start = [1.0, 0.7, 0.0]
radius = 0.35
height = 1.54
walk_speed = 0.15
[goal]
position = [6.2, 0.7]
tolerance = 0.2
[[object]]
name = "box"
kind = "box"
position = [3.0, 0.7]
size = [0.6, 0.9, 0.7]
mass = {mass}
friction = {friction}
colour = [170, 120, 60]
"#
    );
    Scenario::from_toml_str(&text, "push-test-corridor.toml")
}
