//! Moving to see, end to end in the simulation: rooms where one look-around from the start does not
//! show what matters, each run once with its scenario's seed and scored against ground truth.

use nudge_executive::record::NullObserver;
use nudge_executive::{CandidatePolicy, Edge, Question, RunReport, State, UnseenWhy};
use nudge_sim::adapter::SimRobot;
use nudge_tests::truth::{Scored, score};

fn run(name: &str) -> (RunReport, Vec<Scored>) {
    let scenario = nudge_tests::scenario(name).expect("scenario loads");
    let (report, robot): (RunReport, SimRobot) = nudge_tests::run(
        &scenario,
        scenario.seed,
        CandidatePolicy::Nearest,
        NullObserver,
    )
    .expect("world builds");
    let scored = score(&report, &robot);
    println!(
        "{name}: {} after {:.1} s robot time, {} push tests",
        report.outcome.name(),
        report.robot_time,
        report.knowledge.push_tests
    );
    nudge_tests::print_timeline(&report);
    for v in &report.knowledge.explanation.views {
        println!(
            "  view at ({:.2}, {:.2}) for {}",
            v.view.position.x,
            v.view.position.y,
            v.question.name()
        );
    }
    (report, scored)
}

/// Every verdict matches the truth and names a scenario object.
fn assert_all_right(scored: &[Scored]) {
    for s in scored {
        assert!(
            s.correct,
            "{} ({:?}) classified {:?} against ground truth",
            s.id, s.object, s.verdict
        );
    }
}

fn verdict_on<'a>(scored: &'a [Scored], name: &str) -> Option<&'a Scored> {
    scored.iter().find(|s| s.object.as_deref() == Some(name))
}

fn edges(report: &RunReport) -> Vec<Edge> {
    report.timeline.iter().map(|t| t.edge).collect()
}

#[test]
fn a_goal_two_rooms_away_is_reached_through_a_door_the_first_look_never_saw() {
    // Invariant: in the three-room flat the robot walks into rooms it has not seen, stops before floor it cannot see in time and looks from a viewpoint, finds the chair in the second door movable, and reaches the goal; every verdict right.
    let (report, scored) = run("three-room-flat");
    assert_eq!(report.outcome, State::Goal);
    assert_all_right(&scored);
    assert!(verdict_on(&scored, "chair").is_some_and(|s| s.verdict.is_movable()));
    assert!(edges(&report).contains(&Edge::AtViewpoint));
}

#[test]
fn a_barrier_beyond_the_cameras_range_is_found_by_walking_towards_the_goal() {
    // Invariant: in the 14 m hall the path is planned through floor never seen, the walk finds the paper's barrier 7.5 m out, and the robot tests the table static, finds a chair movable and reaches the goal; every verdict right.
    let (report, scored) = run("long-hall");
    assert_eq!(report.outcome, State::Goal);
    assert_all_right(&scored);
    assert!(verdict_on(&scored, "table").is_some_and(|s| !s.verdict.is_movable()));
    assert!(
        scored.iter().any(|s| s.verdict.is_movable()),
        "a chair is found movable"
    );
}

#[test]
fn a_movable_object_half_hidden_behind_a_sideboard_is_looked_at_then_pushed() {
    // Invariant: the box behind the sideboard, seen only in part from the start, is found movable and pushed out of the way, and the robot reaches the goal; every verdict right.
    let (report, scored) = run("hidden-behind-sideboard");
    assert_eq!(report.outcome, State::Goal);
    assert_all_right(&scored);
    assert!(verdict_on(&scored, "box").is_some_and(|s| s.verdict.is_movable()));
}

#[test]
fn a_bin_whose_stand_poses_were_never_seen_is_looked_for_before_it_is_ruled_out() {
    // Invariant: a push that needs floor not yet seen sends the robot to a viewpoint for that push (LookForPush, then a view for a push question) before the bin is ruled out; the bin is found movable and the goal reached; every verdict right.
    let (report, scored) = run("bin-seen-in-part");
    assert_eq!(report.outcome, State::Goal);
    assert_all_right(&scored);
    assert!(verdict_on(&scored, "bin").is_some_and(|s| s.verdict.is_movable()));
    assert!(edges(&report).contains(&Edge::LookForPush));
    assert!(
        report
            .knowledge
            .explanation
            .views
            .iter()
            .any(|v| matches!(v.question, Question::Push { .. }))
    );
}

#[test]
fn a_goal_room_whose_only_door_is_blocked_by_something_static_has_no_path_explained() {
    // Invariant: with the goal room's only door filled by a bolted cabinet, the run ends in NoPathToGoal after the cabinet tests static and the view planner finds no unseen floor that could open a way; the explanation names the goal region as unseen, behind obstacles that close every way to it.
    let (report, scored) = run("door-blocked-static");
    let State::NoPathToGoal(explanation) = &report.outcome else {
        panic!("expected NoPathToGoal, got {:?}", report.outcome.name());
    };
    assert_all_right(&scored);
    assert!(verdict_on(&scored, "cabinet").is_some_and(|s| !s.verdict.is_movable()));
    assert_eq!(
        report.timeline.last().map(|t| t.edge),
        Some(Edge::NothingLeftToSee)
    );
    let goal = nalgebra::Point2::new(7.0, 2.0);
    assert!(
        explanation
            .unseen
            .iter()
            .any(|r| r.why == UnseenWhy::BehindObstacles && (r.centre - goal).norm() < 0.5),
        "{:?}",
        explanation.unseen
    );
}

#[test]
fn a_goal_behind_a_partition_is_reached_by_walking_round_its_end() {
    // Invariant: with the goal out of sight behind a partition and nothing to push, the robot reaches it without a push test.
    let (report, scored) = run("goal-around-corner");
    assert_eq!(report.outcome, State::Goal);
    assert_eq!(report.knowledge.push_tests, 0);
    assert!(scored.is_empty());
}

#[test]
fn a_second_door_out_of_sight_is_found_when_the_first_is_blocked() {
    // Invariant: with the near door filled by a bolted cabinet and the far one hidden behind a shelf, the robot does not end in no path: it reaches the goal through the far door; any verdict is right.
    let (report, scored) = run("two-doors");
    assert_eq!(report.outcome, State::Goal);
    assert_all_right(&scored);
}
