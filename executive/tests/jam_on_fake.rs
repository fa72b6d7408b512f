//! A clearing push that jams, on the fake robot: the box slides in its test, then holds a little
//! farther on as if it met something nobody saw.

mod fake_world;

use fake_world::{BOX_AT, SLIDING, STIFF, box_offset, door_room, edges, robot_in, run, timeline};
use nalgebra::Vector2;
use nudge_executive::robot::ObjectResponse;
use nudge_executive::{Edge, ExecutiveConfig, Finding, State};

/// How far the box slides, in all, before it holds (m): past its test's push, short of a way.
const FREE: f64 = 0.4;

#[test]
fn a_box_that_jams_while_cleared_stops_the_push_at_the_limit_and_is_given_up() {
    // Invariant: a box found movable by its test that holds 0.4 m on stops its clearing push at the force limit (edge Jammed, counted per object), is left by the executive where it truly held, is tried max_jams times and no more, and the run ends in NoPathToGoal rather than pushing forever.
    let (report, robot) = run(robot_in(door_room(ObjectResponse::SlidesThenJams {
        force: SLIDING,
        travel: FREE,
        stiffness: STIFF,
    })));
    let context = timeline(&report);
    let explanation = &report.knowledge.explanation;
    let first = explanation.tests.first().expect("a push test");
    assert_eq!(first.finding, Finding::Movable, "{first:?}\n{context}");
    let taken = edges(&report);
    let jammed = taken.iter().filter(|e| **e == Edge::Jammed).count();
    assert!(jammed >= 1, "no jam\n{context}");
    let jams = explanation.jams.get(&first.object).copied().unwrap_or(0);
    assert_eq!(jams as usize, jammed, "{:?}", explanation.jams);
    assert_eq!(
        jams,
        ExecutiveConfig::default().max_jams,
        "given up after max_jams"
    );
    let offset = box_offset(&robot);
    assert!(
        (offset.norm() - FREE).abs() < 1e-6,
        "the clearing pushed the box as far as it went: {} m",
        offset.norm()
    );
    let prism = report
        .obstacle(first.object)
        .expect("the box is still known");
    let centre = prism
        .footprint
        .iter()
        .fold(Vector2::zeros(), |acc, p| acc + p.coords)
        / prism.footprint.len() as f64;
    let truth = Vector2::new(BOX_AT.0, BOX_AT.1) + offset;
    assert!(
        (centre - truth).norm() < 0.1,
        "the executive's box at {centre}, in truth at {truth}"
    );
    assert!(
        matches!(report.outcome, State::NoPathToGoal(_)),
        "{:?}\n{context}",
        report.outcome
    );
}
