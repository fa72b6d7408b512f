//! The runner drives a robot through the machine and always ends cleanly: tested on the fake robot.

use std::sync::atomic::Ordering;

use nalgebra::{Isometry2, Point2, Vector2};
use nudge_executive::record::NullObserver;
use nudge_executive::record::Observer;
use nudge_executive::robot::{FakeRobot, ObjectResponse, RobotError};
use nudge_executive::{AbortReason, Edge, RunConfig, Runner, State};
use nudge_robot_model::RobotModel;

mod fake_world;

fn config() -> RunConfig {
    RunConfig::new(RobotModel::default(), Point2::new(5.4, 1.8), 0.2, 1)
}

fn robot() -> FakeRobot {
    FakeRobot::new(Isometry2::new(Vector2::new(0.6, 1.8), 0.0))
}

#[test]
fn a_cancel_retracts_the_arm_and_aborts() {
    // Invariant: a run cancelled from outside ends in Aborted(Cancelled) after retracting the arm.
    let mut runner = Runner::new(robot(), NullObserver, config());
    runner.cancel_flag().store(true, Ordering::Relaxed);
    let report = runner.run();
    assert!(
        matches!(report.outcome, State::Aborted(AbortReason::Cancelled, _)),
        "{:?}",
        report.outcome
    );
    assert!(runner.robot().calls().iter().any(|c| c == "start_retract"));
    assert_eq!(report.timeline.last().map(|t| t.to), Some("Aborted"));
}

#[test]
fn a_look_around_of_empty_clouds_ends_in_a_perception_abort() {
    // Invariant: perception failing on the robot's data ends the run in Aborted(Perception), never a panic.
    let mut runner = Runner::new(robot(), NullObserver, config());
    let report = runner.run();
    assert!(
        matches!(
            report.outcome,
            State::Aborted(AbortReason::Perception(_), _)
        ),
        "{:?}",
        report.outcome
    );
    let captures = runner
        .robot()
        .calls()
        .iter()
        .filter(|c| *c == "capture")
        .count();
    assert_eq!(captures, 15, "one capture per look-around view");
}

#[test]
fn the_robot_time_budget_ends_the_run() {
    // Invariant: once the robot-time budget is spent the run stops safely with TimeLimit.
    let mut config = config();
    config.executive.max_robot_time = 0.5;
    let mut runner = Runner::new(robot(), NullObserver, config);
    let report = runner.run();
    assert!(
        matches!(report.outcome, State::Aborted(AbortReason::TimeLimit(t), _) if t >= 0.5),
        "{:?}",
        report.outcome
    );
    assert!(report.robot_time < 1.0);
}

#[test]
fn an_adapter_error_ends_the_run_with_that_error() {
    // Invariant: an adapter failure ends in Aborted(Robot) carrying the adapter's message.
    let mut robot = robot();
    robot.fail_next(
        "camera",
        RobotError::Fault {
            capability: "camera",
            reason: "lens cap".into(),
        },
    );
    let mut runner = Runner::new(robot, NullObserver, config());
    let report = runner.run();
    match report.outcome {
        State::Aborted(AbortReason::Robot(message), _) => assert!(message.contains("lens cap")),
        other => panic!("expected Aborted(Robot), got {other:?}"),
    }
}

#[test]
fn the_same_seed_gives_the_same_run() {
    // Invariant: two runs of the same scripted world and seed, which get past perception, push-test a box, push it clear and reach the goal, produce identical reports (timeline, knowledge, obstacles, grid), make the same adapter calls and leave the world the same.
    let one = || {
        fake_world::run(fake_world::robot_in(fake_world::door_room(
            ObjectResponse::Sliding {
                force: fake_world::SLIDING,
            },
        )))
    };
    let (a, robot_a) = one();
    let (b, robot_b) = one();
    assert!(a.reached_goal(), "{}", fake_world::timeline(&a));
    assert!(
        !a.knowledge.explanation.tests.is_empty(),
        "a push test was made"
    );
    assert!(fake_world::edges(&a).contains(&Edge::Cleared));
    assert_eq!(a, b);
    assert_eq!(robot_a.calls(), robot_b.calls());
    assert_eq!(robot_a.scene(), robot_b.scene());
}

/// Every transition an observer is shown: (from, edge, to).
#[derive(Default)]
struct Transitions(Vec<(Option<&'static str>, Edge, &'static str)>);

impl Observer for Transitions {
    fn transition(&mut self, _stamp: f64, from: Option<&State>, edge: Edge, to: &State) {
        self.0.push((from.map(State::name), edge, to.name()));
    }
}

#[test]
fn the_start_leaves_no_state_and_every_later_step_leaves_the_one_before() {
    // Invariant: the run's first timeline entry and observed transition is the Start edge from no
    // state into LookAround; every later one leaves the state the one before entered, and the
    // observer sees exactly the timeline.
    let mut runner = Runner::new(robot(), Transitions::default(), config());
    let report = runner.run();
    let first = report.timeline.first().expect("a run has a start");
    assert_eq!(
        (first.from, first.edge, first.to),
        (None, Edge::Start, "LookAround")
    );
    for pair in report.timeline.windows(2) {
        assert_eq!(pair[1].from, Some(pair[0].to), "{:?}", pair[1]);
        assert_ne!(pair[1].edge, Edge::Start);
    }
    let (_, seen) = runner.into_parts();
    let timeline: Vec<_> = report
        .timeline
        .iter()
        .map(|t| (t.from, t.edge, t.to))
        .collect();
    assert_eq!(seen.0, timeline);
}
