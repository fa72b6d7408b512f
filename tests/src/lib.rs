//! nudge-tests: end-to-end scenario tests across crates live in `tests/`; this library holds their
//! shared helpers.
#![warn(missing_docs)]

pub mod hallway;
pub mod truth;

use nalgebra::Point2;
use nudge_executive::record::Observer;
use nudge_executive::{CandidatePolicy, RunConfig, RunReport, Runner};
use nudge_motion::RobotCylinder;
use nudge_sim::adapter::SimRobot;
use nudge_sim::scenario::Scenario;

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

/// The run configuration a scenario implies: its robot, goal and seed.
pub fn run_config(scenario: &Scenario, seed: u64, policy: CandidatePolicy) -> RunConfig {
    let robot = RobotCylinder {
        radius: scenario.robot.radius,
        height: scenario.robot.height,
    };
    let goal = Point2::new(scenario.goal.position[0], scenario.goal.position[1]);
    let mut config = RunConfig::new(robot, goal, scenario.goal.tolerance, seed);
    config.executive.policy = policy;
    config
}

/// Runs `scenario` in the simulation and returns the report and the robot (for ground truth).
pub fn run<O: Observer>(
    scenario: &Scenario,
    seed: u64,
    policy: CandidatePolicy,
    observer: O,
) -> anyhow::Result<(RunReport, SimRobot)> {
    let robot = SimRobot::new(scenario, seed)?;
    let mut runner = Runner::new(robot, observer, run_config(scenario, seed, policy));
    let report = runner.run();
    let (robot, _) = runner.into_parts();
    Ok((report, robot))
}
