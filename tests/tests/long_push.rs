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
    let (report, moves) = run_watching(name, &[object]);
    let (moved, turned) = moves[0];
    (report, moved, turned)
}

/// Runs the scenario and returns its report and, for each named object, how far (m) it ended from
/// where it started (ground truth) and how far it turned (deg).
fn run_watching(name: &str, objects: &[&str]) -> (RunReport, Vec<(f64, f64)>) {
    let scenario: Scenario = nudge_tests::scenario(name).expect("scenario loads");
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
    let moves = objects
        .iter()
        .map(|object| {
            let index = scenario
                .objects
                .iter()
                .position(|o| o.name == *object)
                .expect("the scenario has the object");
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
            (moved, turned)
        })
        .collect();
    (report, moves)
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
    // Invariant: the crate filling the doorway is found movable by a short push test, and then at most two clearing pushes (the test's push finished and one long push, or the long push at once), each of several strokes rather than a push, a look and another push over and over, take it about 1.5 m into the next room, square to its push; the robot then walks through and around it to the goal.
    let (report, moved, turned) = run("crate-through-doorway", "crate");
    assert_eq!(report.outcome, State::Goal);
    assert!(clears(&report) <= 2, "{} clearing pushes", clears(&report));
    assert!(moved > 1.3, "the crate moved {moved:.2} m");
    assert!(turned.abs() < 5.0, "the crate turned {turned:.1}°");
}

#[test]
fn a_box_in_a_corridor_is_pushed_along_it_until_a_niche_lets_the_robot_pass() {
    // Invariant: the box filling the corridor is found movable by a short push test, and then one long clearing push of some ten strokes (planned at once, the test's short push opening no way; or after the test's push finished) takes it about 3 m along the corridor into the stretch beside the niche, where the robot passes it to the goal.
    let (report, moved, _) = run("corridor-niche", "box");
    assert_eq!(report.outcome, State::Goal);
    let n = clears(&report);
    assert!(
        (1..=2).contains(&n),
        "{n} clearing pushes: one long push, after the test's push at most"
    );
    assert!(moved > 2.5, "the box moved {moved:.2} m");
}

#[test]
fn two_boxes_side_by_side_in_a_doorway_are_both_pushed_through_before_the_robot_passes() {
    // Invariant: with two light boxes filling the only doorway, where either one alone leaves a gap narrower than the robot, both are found movable and both are pushed out of the doorway (each more than 0.35 m, its near face past the partition's far face, ground truth) before the robot walks through to the goal.
    let (report, moves) = run_watching("two-boxes-in-doorway", &["box-south", "box-north"]);
    let (moved_south, moved_north) = (moves[0].0, moves[1].0);
    assert_eq!(report.outcome, State::Goal);
    assert_eq!(report.knowledge.explanation.movable_objects().len(), 2);
    assert!(moved_south > 0.35, "box-south moved {moved_south:.2} m");
    assert!(moved_north > 0.35, "box-north moved {moved_north:.2} m");
}

#[test]
fn a_crate_that_can_only_go_as_far_as_a_bolted_wardrobe_leaves_no_path_explained() {
    // Invariant: a movable crate in the only doorway with a bolted wardrobe just behind it is found movable (and nothing is found movable that is not), the run ends with no path (never the goal, never an abort), the explanation names the crate as movable, says why it is pushed no farther, and names the goal region as unseen behind obstacles that close every way to it, and the crate never passes the wardrobe.
    let (report, moved, _) = run("crate-against-wardrobe", "crate");
    let State::NoPathToGoal(explanation) = &report.outcome else {
        panic!("expected no path, got {}", report.outcome.name());
    };
    assert_eq!(explanation.movable_objects().len(), 1, "{explanation}");
    assert!(!explanation.unseen.is_empty(), "{explanation}");
    // Why the crate is pushed no farther: set aside (its outline grown into the wardrobe's), no push
    // plan, or jammed.
    let crate_id = explanation.movable_objects()[0];
    assert!(
        explanation.set_aside.contains_key(&crate_id)
            || explanation.unpushable.contains_key(&crate_id)
            || explanation.jams.contains_key(&crate_id),
        "{explanation}"
    );
    // The crate's far face starts 0.5 m from the wardrobe.
    assert!(moved < 0.5, "the crate moved {moved:.2} m");
}
