//! nudge-tests: end-to-end scenario tests across crates live in `tests/`; this library holds their
//! shared helpers.
#![warn(missing_docs)]

pub mod hallway;
pub mod truth;

use nalgebra::Isometry2;
use nudge_executive::record::Observer;
use nudge_executive::robot::{ActionStatus, Base, Clock, Head, RangeCamera};
use nudge_executive::{CandidatePolicy, RunReport};
use nudge_perception::{ColourCloud, PerceptionConfig};
use nudge_sim::adapter::SimRobot;
use nudge_sim::scenario::Scenario;

/// Prints a run's timeline, one transition a line with its robot-time stamp.
pub fn print_timeline(report: &RunReport) {
    for t in &report.timeline {
        println!(
            "  {:7.2} s  {} -> {} ({:?})",
            t.stamp,
            t.from.unwrap_or("(start)"),
            t.to,
            t.edge
        );
    }
}

/// Path of the repository's `scenarios/` folder, for tests that load scenario files.
pub fn scenarios_dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("scenarios")
}

/// Loads `scenarios/NAME.toml`.
pub fn scenario(name: &str) -> anyhow::Result<Scenario> {
    Ok(Scenario::from_path(
        &scenarios_dir().join(format!("{name}.toml")),
    )?)
}

/// Runs `scenario` in the simulation and returns the report and the robot (for ground truth).
pub fn run<O: Observer>(
    scenario: &Scenario,
    seed: u64,
    policy: CandidatePolicy,
    observer: O,
) -> anyhow::Result<(RunReport, SimRobot)> {
    let (report, robot, _) = nudge_sim::run::run(scenario, seed, policy, observer)?;
    Ok((report, robot))
}

/// The clouds of one look-around (the default perception config's views) from where `robot`
/// stands, and its base pose.
pub fn look_around(robot: &mut SimRobot) -> anyhow::Result<(Vec<ColourCloud>, Isometry2<f64>)> {
    let config = PerceptionConfig::default();
    let mut clouds = Vec::new();
    for view in config.look_around.views() {
        robot.start_point_head(view.pan_rad(), view.tilt_rad())?;
        while robot.head_status()? == ActionStatus::Running {
            robot.advance(0.05)?;
        }
        clouds.push(robot.capture()?);
    }
    Ok((clouds, robot.base_pose()?.value))
}
