//! The runner's push test on the fake robot, no rapier: a box in a doorway scripted static, sliding,
//! or sliding and then holding; the verdicts, the edges taken and the box's true pose afterwards.

mod fake_world;

use fake_world::{BOX_AT, SLIDING, STIFF, box_offset, door_room, edges, robot_in, run, timeline};
use nudge_executive::push_test::Ambiguity;
use nudge_executive::robot::Base;
use nudge_executive::robot::{FakeRobot, ObjectResponse};
use nudge_executive::{Edge, Finding, RunReport, State, TestRecord, Verdict};
use nudge_perception::ObjectId;

/// The box's id and its push tests. The box is what the first test pushed: the nearest candidate,
/// the only one in the way at the start (its outline is checked against the truth where it matters).
/// Other tests, of pieces of the partition taken for furniture, are left out.
fn tests_of_the_box(report: &RunReport) -> (ObjectId, Vec<TestRecord>) {
    let tests = &report.knowledge.explanation.tests;
    let id = tests.first().map(|t| t.object).unwrap_or_else(|| {
        panic!(
            "no push test; outcome {:?}\n{}",
            report.outcome,
            timeline(report)
        )
    });
    let of_box = tests.iter().filter(|t| t.object == id).cloned().collect();
    (id, of_box)
}

fn centre(report: &RunReport, id: ObjectId) -> nalgebra::Point2<f64> {
    let prism = report.obstacle(id).expect("the tested box is still known");
    let sum = prism
        .footprint
        .iter()
        .fold(nalgebra::Vector2::zeros(), |acc, p| acc + p.coords);
    nalgebra::Point2::from(sum / prism.footprint.len() as f64)
}

fn run_with(response: ObjectResponse) -> (RunReport, FakeRobot) {
    run(robot_in(door_room(response)))
}

#[test]
fn a_bolted_box_is_found_static_by_one_test_and_never_moves() {
    // Invariant: a box scripted static gets one push test that stops at the force limit with ICP under 10 mm: verdict Static (not after ambiguity), edge FoundStatic, no retest, the box truly unmoved, and with nothing else to push the run ends in NoPathToGoal.
    let (report, robot) = run_with(ObjectResponse::Static { stiffness: STIFF });
    let (id, tests) = tests_of_the_box(&report);
    let context = timeline(&report);
    assert_eq!(tests.len(), 1, "{tests:?}\n{context}");
    assert_eq!(tests[0].finding, Finding::Static, "{context}");
    assert!(tests[0].reached_limit);
    assert!(
        tests[0].icp_mm.is_some_and(|mm| mm < 10.0),
        "{:?}",
        tests[0]
    );
    assert_eq!(
        report.knowledge.explanation.verdicts.get(&id),
        Some(&Verdict::Static {
            after_ambiguity: false
        })
    );
    let taken = edges(&report);
    assert!(taken.contains(&Edge::FoundStatic), "{context}");
    assert!(!taken.contains(&Edge::Retest), "{context}");
    assert_eq!(box_offset(&robot).norm(), 0.0, "a static box never moves");
    let seen = centre(&report, id);
    assert!(
        (seen - nalgebra::Point2::new(BOX_AT.0, BOX_AT.1)).norm() < 0.1,
        "the tested obstacle is the box: {seen}"
    );
    assert!(
        matches!(report.outcome, State::NoPathToGoal(_)),
        "{:?}\n{context}",
        report.outcome
    );
}

#[test]
fn a_box_that_moves_then_holds_is_ambiguous_and_the_one_retest_decides() {
    // Invariant: a box that slides 5 cm and then holds reads "moved, then the limit" (ambiguous) on its first test; exactly one retest follows (edge Retest) and finds it held, so the verdict is Movable (edge SlidThenHeld: it slid with the hand, and what stopped it holds it), and the box truly moved 5 cm, no more.
    let (report, robot) = run_with(ObjectResponse::SlidesThenJams {
        force: SLIDING,
        travel: 0.05,
        stiffness: STIFF,
    });
    let (id, tests) = tests_of_the_box(&report);
    let context = timeline(&report);
    assert_eq!(tests.len(), 2, "{tests:?}\n{context}");
    assert_eq!((tests[0].attempt, tests[1].attempt), (1, 2));
    assert!(
        matches!(
            tests[0].finding,
            Finding::Ambiguous(Ambiguity::MovedThenLimit { .. })
        ),
        "{:?}",
        tests[0]
    );
    assert_eq!(tests[1].finding, Finding::Static, "{:?}", tests[1]);
    assert_eq!(
        report.knowledge.explanation.verdicts.get(&id),
        Some(&Verdict::Movable)
    );
    let taken = edges(&report);
    let retest = taken
        .iter()
        .position(|e| *e == Edge::Retest)
        .unwrap_or_else(|| panic!("no retest\n{context}"));
    assert_eq!(
        taken.get(retest + 1),
        Some(&Edge::SlidThenHeld),
        "{context}"
    );
    assert_eq!(taken.iter().filter(|e| **e == Edge::Retest).count(), 1);
    let moved = box_offset(&robot).norm();
    assert!((moved - 0.05).abs() < 1e-9, "the box moved {moved} m");
}

#[test]
fn a_sliding_box_is_found_movable_with_icp_agreeing_with_the_hand() {
    // Invariant: a box scripted to slide at 12 N (under the 20 N limit) is found movable by its first test: contact, no limit, the hand pushing on over 10 cm, and colour ICP on the camera's clouds reading the box's displacement within 1 cm of the hand's travel.
    let (report, _) = moving::run();
    let (id, tests) = tests_of_the_box(report);
    let first = &tests[0];
    assert_eq!(first.finding, Finding::Movable, "{first:?}");
    assert!(!first.reached_limit);
    assert!(first.hand_travel_mm > 100.0, "{first:?}");
    let icp = first.icp_mm.expect("ICP ran");
    assert!((icp - first.hand_travel_mm).abs() < 10.0, "{first:?}");
    assert_eq!(
        report.knowledge.explanation.verdicts.get(&id),
        Some(&Verdict::Movable)
    );
    assert!(edges(report).contains(&Edge::FoundMovable));
}

/// The sliding box's run, shared by the tests that read it.
pub(crate) mod moving {
    use std::sync::OnceLock;

    use super::*;

    /// The run with the box sliding at [`SLIDING`].
    pub fn run() -> &'static (RunReport, FakeRobot) {
        static RUN: OnceLock<(RunReport, FakeRobot)> = OnceLock::new();
        RUN.get_or_init(|| run_with(ObjectResponse::Sliding { force: SLIDING }))
    }
}

#[test]
fn a_movable_box_is_pushed_clear_and_the_robot_walks_through_the_door() {
    // Invariant: after the test finds the box movable, a clearing push (edge Cleared) takes it out of the door into the second room (in truth), the executive's outline of it ends within 10 cm of where it truly is, and the robot reaches the goal.
    let (report, robot) = moving::run();
    let context = timeline(report);
    assert!(report.reached_goal(), "{:?}\n{context}", report.outcome);
    let taken = edges(report);
    let found = taken.iter().position(|e| *e == Edge::FoundMovable);
    let cleared = taken.iter().position(|e| *e == Edge::Cleared);
    assert!(
        matches!((found, cleared), (Some(f), Some(c)) if f < c),
        "found movable, then cleared\n{context}"
    );
    let offset = box_offset(robot);
    assert!(
        offset.x > 0.6,
        "the box left the door for the second room: moved {offset}"
    );
    let (id, _) = tests_of_the_box(report);
    let truth = nalgebra::Point2::new(BOX_AT.0, BOX_AT.1) + offset;
    let seen = centre(report, id);
    assert!(
        (seen - truth).norm() < 0.1,
        "the executive's box at {seen}, in truth at {truth}"
    );
    let at = robot.clone().base_pose().expect("base pose").value;
    let goal = nalgebra::Vector2::new(fake_world::GOAL.0, fake_world::GOAL.1);
    assert!(
        (at.translation.vector - goal).norm() <= 0.2 + 1e-9,
        "the robot stands at the goal: {}",
        at.translation.vector
    );
}
