//! Long pushes end to end in the simulation: an object that must go metres, not one short stroke,
//! before the way opens, pushed in strokes with the body walking after it and the object re-located
//! between strokes; each scenario run once with its seed and scored against ground truth.

use nudge_executive::record::NullObserver;
use nudge_executive::{CandidatePolicy, Edge, RunReport, State};
use nudge_sim::adapter::SimRobot;
use nudge_sim::scenario::Scenario;
use nudge_tests::truth::score;

/// Runs the scenario and returns its report, how far (m) the named object ended from where it
/// started (ground truth) and how far it turned (deg).
fn run(name: &str, object: &str) -> (RunReport, f64, f64) {
    let scenario: Scenario = nudge_tests::scenario(name).expect("scenario loads");
    let index = scenario
        .objects
        .iter()
        .position(|o| o.name == object)
        .expect("the scenario has the object");
    let (report, robot): (RunReport, SimRobot) = nudge_tests::run(
        &scenario,
        scenario.seed,
        CandidatePolicy::Nearest,
        NullObserver,
    )
    .expect("world builds");
    for s in score(&report, &robot) {
        assert!(
            s.correct,
            "{} ({:?}) classified {:?}",
            s.id, s.object, s.verdict
        );
    }
    nudge_tests::print_timeline(&report);
    let start = &scenario.objects[index];
    let end = robot.world().object_pose(index).expect("object pose");
    let moved = (end.translation.vector.xy()
        - nalgebra::Vector2::new(start.position[0], start.position[1]))
    .norm();
    let turned = end.rotation.euler_angles().2.to_degrees() - start.yaw;
    println!(
        "{name}: {} after {:.1} s; {object} moved {moved:.2} m, turned {turned:.1}°",
        report.outcome.name(),
        report.robot_time
    );
    (report, moved, turned)
}

fn clears(report: &RunReport) -> usize {
    report
        .timeline
        .iter()
        .filter(|t| matches!(t.edge, Edge::Cleared | Edge::OffLine | Edge::Jammed))
        .count()
}

#[test]
fn a_crate_in_the_only_doorway_is_pushed_through_it_in_one_long_push() {
    // Invariant: the crate filling the doorway is found movable by a short push test, its short push is finished, and then one long clearing push of several strokes (not a push, a look and another push, over and over) takes it about 1.5 m into the next room, square to its push; the robot then walks through and around it to the goal.
    let (report, moved, turned) = run("crate-through-doorway", "crate");
    assert_eq!(report.outcome, State::Goal);
    assert_eq!(clears(&report), 2, "the test's push, then one long push");
    assert!(moved > 1.3, "the crate moved {moved:.2} m");
    assert!(turned.abs() < 5.0, "the crate turned {turned:.1}°");
}

#[test]
fn a_box_in_a_corridor_is_pushed_along_it_until_a_niche_lets_the_robot_pass() {
    // Invariant: the box filling the corridor is found movable by a short push test, and after the test's short push one long clearing push of some ten strokes takes it about 3 m along the corridor into the stretch beside the niche, where the robot passes it to the goal.
    let (report, moved, _) = run("corridor-niche", "box");
    assert_eq!(report.outcome, State::Goal);
    assert_eq!(clears(&report), 2, "the test's push, then one long push");
    assert!(moved > 2.5, "the box moved {moved:.2} m");
}
