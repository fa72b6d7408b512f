//! Running a scenario: the executive's configuration a scenario implies, and a run in the simulation.

use nalgebra::Point2;
use nudge_executive::record::Observer;
use nudge_executive::record::tape::{Tape, Taped};
use nudge_executive::{CandidatePolicy, RunConfig, RunReport, Runner};

use crate::adapter::SimRobot;
use crate::scenario::Scenario;
use crate::world::WorldError;

/// How far the obstacle-type grid reaches past the room's inner walls (m): the walls' own cells.
const GRID_MARGIN: f64 = 0.5;

/// The run configuration a scenario implies: its robot, its goal, the seed, the policy and
/// a grid over its room.
pub fn run_config(scenario: &Scenario, seed: u64, policy: CandidatePolicy) -> RunConfig {
    let goal = Point2::new(scenario.goal.position[0], scenario.goal.position[1]);
    let mut config = RunConfig::new(scenario.robot.model(), goal, scenario.goal.tolerance, seed);
    config.executive.policy = policy;
    // The grid covers the room and a margin for its walls, as Tamura sizes it from the map.
    let margin = nalgebra::Vector2::repeat(GRID_MARGIN);
    let room = Point2::new(scenario.room.size[0], scenario.room.size[1]);
    config.grid.area = Some((Point2::origin() - margin, room + margin));
    config
}

/// A scenario's runner in the simulation, ready to run (its cancel flag can be taken first).
pub fn runner<O: Observer>(
    scenario: &Scenario,
    seed: u64,
    policy: CandidatePolicy,
    observer: O,
) -> Result<Runner<SimRobot, O>, WorldError> {
    let robot = SimRobot::new(scenario, seed)?;
    Ok(Runner::new(
        robot,
        observer,
        run_config(scenario, seed, policy),
    ))
}

/// A scenario's runner in the simulation with its robot wrapped in [`Taped`]: every adapter call
/// goes onto `tape` when there is one (`nudge run --record`), and is only forwarded otherwise.
pub fn taped_runner<O: Observer>(
    scenario: &Scenario,
    seed: u64,
    policy: CandidatePolicy,
    observer: O,
    tape: Option<Tape>,
) -> Result<Runner<Taped<SimRobot>, O>, WorldError> {
    let robot = SimRobot::new(scenario, seed)?;
    let robot = match tape {
        Some(tape) => Taped::new(robot, tape),
        None => Taped::untaped(robot),
    };
    Ok(Runner::new(
        robot,
        observer,
        run_config(scenario, seed, policy),
    ))
}

/// Runs `scenario` to its end; returns the report, the robot (for ground truth) and the observer.
pub fn run<O: Observer>(
    scenario: &Scenario,
    seed: u64,
    policy: CandidatePolicy,
    observer: O,
) -> Result<(RunReport, SimRobot, O), WorldError> {
    let mut runner = runner(scenario, seed, policy, observer)?;
    let report = runner.run();
    let (robot, observer) = runner.into_parts();
    Ok((report, robot, observer))
}
