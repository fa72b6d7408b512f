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

/// A 4 kg chair with μ = 0.4 at x 1.55..2.05 ahead of [`robot_and`]'s robot, its seat's edge
/// towards it (TOML lines for [`robot_and`]).
pub const TEST_CHAIR: &str = "name = \"chair\"\nkind = \"chair\"\nyaw = 180.0\nposition = [1.8, 1.8]\nsize = [0.5, 0.5, 0.85]\nmass = 4.0\nfriction = 0.4\ncolour = [40, 120, 200]";

/// μ m g of [`TEST_CHAIR`] (N).
pub const TEST_CHAIR_MU_M_G: f64 = 0.4 * 4.0 * 9.81;

/// Asserts that every 250 samples (a quarter second) of `forces` (time, force) between half a
/// second after `contact` and 0.1 s before `stop` average within 1 N of `mu_m_g`, over at least
/// 20 such windows: the chair slides at friction, no stale contact holds the force above it.
pub fn assert_slides_at(forces: &[(f64, f64)], contact: f64, stop: f64, mu_m_g: f64) {
    let sliding: Vec<f64> = forces
        .iter()
        .filter(|(t, _)| *t > contact + 0.5 && *t < stop - 0.1)
        .map(|(_, f)| *f)
        .collect();
    let windows: Vec<f64> = sliding
        .chunks(250)
        .map(|w| w.iter().sum::<f64>() / w.len() as f64)
        .collect();
    assert!(windows.len() >= 20, "only {} windows", windows.len());
    for (k, mean) in windows.iter().enumerate() {
        assert!(
            (mean - mu_m_g).abs() < 1.0,
            "window {k}: {mean:.2} N vs μmg {mu_m_g:.2} N"
        );
    }
}

/// The hand held where it stopped for half a second: the greatest force read then, or `peak` if
/// greater (a guard that stopped must not let the force keep climbing).
pub fn peak_while_holding(robot: &mut nudge_sim::adapter::SimRobot, peak: f64) -> f64 {
    use nudge_executive::robot::{Clock, WristSensor};
    robot.advance(0.5).expect("hold");
    robot
        .drain_wrenches()
        .expect("drain")
        .iter()
        .map(|w| w.value.force_norm())
        .fold(peak, f64::max)
}

/// A world built from `s` with seed 1.
pub fn world(s: &Scenario) -> World {
    World::new(s, 1).expect("test world builds")
}

/// A prism over the floor rectangle `[x0, x1] × [y0, y1]`.
pub fn rectangle(id: u32, x0: f64, x1: f64, y0: f64, y1: f64) -> nudge_perception::Prism {
    nudge_perception::Prism {
        id: nudge_perception::ObjectId(id),
        footprint: vec![
            nalgebra::Point2::new(x0, y0),
            nalgebra::Point2::new(x1, y0),
            nalgebra::Point2::new(x1, y1),
            nalgebra::Point2::new(x0, y1),
        ],
        z_min: 0.0,
        z_max: 1.0,
        points: nudge_perception::ColourCloud::empty(
            nudge_perception::CloudFrame::Map,
            nalgebra::Isometry3::identity(),
            0.0,
        ),
    }
}
