//! End to end in the simulation: the executive against the paper's room and its variants, scored
//! against ground truth.

use nudge_executive::record::NullObserver;
use nudge_executive::{CandidatePolicy, Edge, RunReport, State, Verdict};
use nudge_sim::adapter::SimRobot;
use nudge_tests::truth::{Scored, score};

fn run(name: &str, policy: CandidatePolicy) -> (RunReport, Vec<Scored>) {
    let scenario = nudge_tests::scenario(name).expect("scenario loads");
    let (report, robot): (RunReport, SimRobot) =
        nudge_tests::run(&scenario, scenario.seed, policy, NullObserver).expect("world builds");
    let scored = score(&report, &robot);
    println!(
        "{name} ({policy:?}): {} after {:.1} s robot time",
        report.outcome.name(),
        report.robot_time
    );
    for t in &report.timeline {
        println!("  {:7.2} s  {} -> {} ({:?})", t.stamp, t.from, t.to, t.edge);
    }
    for s in &scored {
        println!(
            "  {} = {:?}: {:?} ({})",
            s.id,
            s.object,
            s.verdict,
            if s.correct { "right" } else { "WRONG" }
        );
    }
    (report, scored)
}

fn assert_all_correct(scored: &[Scored]) {
    for s in scored {
        assert!(
            s.correct,
            "{} ({:?}) classified {:?} against ground truth",
            s.id, s.object, s.verdict
        );
    }
}

fn assert_force_within_limit(report: &RunReport) {
    for t in &report.knowledge.explanation.tests {
        assert!(
            t.peak_force <= 1.1 * 20.0,
            "push test on {} peaked at {:.1} N",
            t.object,
            t.peak_force
        );
    }
}

fn named<'a>(scored: &'a [Scored], name: &str) -> Option<&'a Scored> {
    scored.iter().find(|s| s.object.as_deref() == Some(name))
}

#[test]
fn the_papers_room_reaches_the_goal_testing_the_table_first() {
    // Invariant: policy nearest tests the table first (as the paper did), finds it static, finds a chair movable, reaches the goal; every verdict matches truth.
    let (report, scored) = run("kakiuchi-room", CandidatePolicy::Nearest);
    assert_eq!(report.outcome, State::Goal);
    assert_all_correct(&scored);
    assert_force_within_limit(&report);
    let tests = &report.knowledge.explanation.tests;
    let first = tests.first().expect("at least one push test");
    assert_eq!(
        named(&scored, "table").map(|s| s.id),
        Some(first.object),
        "the table is tested first"
    );
    assert!(matches!(
        named(&scored, "table").map(|s| &s.verdict),
        Some(Verdict::Static { .. })
    ));
    assert!(
        scored.iter().any(
            |s| s.object.as_deref().is_some_and(|n| n.starts_with("chair"))
                && s.verdict == Verdict::Movable
        ),
        "a chair is found movable"
    );
    assert!(
        report.timeline.iter().any(|t| t.edge == Edge::Cleared),
        "the chair is pushed out of the way"
    );
}

#[test]
fn the_blocking_policy_needs_no_more_push_tests_than_nearest() {
    // Invariant: policy blocking reaches the goal in the paper's room with no more push tests than nearest, all verdicts right.
    let (nearest, _) = run("kakiuchi-room", CandidatePolicy::Nearest);
    let (blocking, scored) = run("kakiuchi-room", CandidatePolicy::Blocking);
    assert_eq!(blocking.outcome, State::Goal);
    assert_all_correct(&scored);
    assert_force_within_limit(&blocking);
    let (b, n) = (blocking.knowledge.push_tests, nearest.knowledge.push_tests);
    println!("push tests: blocking {b}, nearest {n}");
    assert!(b <= n, "blocking took {b} push tests, nearest {n}");
}

#[test]
fn an_all_static_room_ends_in_no_path_with_every_blocking_object_tested() {
    // Invariant: with nothing movable the run ends in NoPathToGoal, every blocking object tested and found static.
    let (report, scored) = run("all-static", CandidatePolicy::Nearest);
    assert!(
        matches!(report.outcome, State::NoPathToGoal(_)),
        "{:?}",
        report.outcome.name()
    );
    assert_all_correct(&scored);
    assert_force_within_limit(&report);
    for name in ["table", "chair-1", "chair-2"] {
        let s = named(&scored, name).unwrap_or_else(|| panic!("{name} was not tested"));
        assert!(
            matches!(s.verdict, Verdict::Static { .. }),
            "{name}: {:?}",
            s.verdict
        );
    }
}

#[test]
fn an_open_room_reaches_the_goal_without_a_push() {
    // Invariant: when a path exists the robot walks to the goal and pushes nothing.
    let (report, scored) = run("open-room", CandidatePolicy::Nearest);
    assert_eq!(report.outcome, State::Goal);
    assert!(scored.is_empty() && report.knowledge.push_tests == 0);
}

#[test]
fn the_same_scenario_and_seed_give_the_same_run() {
    // Invariant: two runs of the paper's room with one seed are identical, timeline, verdicts and obstacles.
    let a = run("kakiuchi-room", CandidatePolicy::Nearest).0;
    let b = run("kakiuchi-room", CandidatePolicy::Nearest).0;
    assert_eq!(a, b);
}
