//! People in the room (issue 18), end to end in the simulation and scored against its truth: a
//! person standing in the way of the only push, and four people wandering an 8 × 6 m room.

use nudge_executive::record::NullObserver;
use nudge_executive::{CandidatePolicy, RunReport, State};
use nudge_sim::adapter::SimRobot;
use nudge_sim::metrics::ghosts;
use nudge_sim::truth::Truth;
use nudge_tests::print_timeline;
use nudge_tests::truth::score;

/// Runs the shipped scenario `name` on `seed` and returns its report and the robot.
fn run(name: &str, seed: u64) -> (RunReport, SimRobot) {
    let scenario = nudge_tests::scenario(name).expect("scenario loads");
    let (report, robot): (RunReport, SimRobot) =
        nudge_tests::run(&scenario, seed, CandidatePolicy::Nearest, NullObserver)
            .expect("world builds");
    print_timeline(&report);
    (report, robot)
}

/// Asserts the run reached the goal and ended there, touched nobody, kept no ghost and judged every object right.
fn assert_safe_and_clean(name: &str, seed: u64) {
    let (report, robot) = run(name, seed);
    assert!(
        matches!(report.outcome, State::Goal),
        "{name} seed {seed}: {:?}",
        report.outcome
    );
    // The executive counts an arrival up to 5 cm past the tolerance: the walk's own error.
    let goal = nudge_tests::scenario(name).expect("scenario loads").goal;
    let at = nalgebra::Point2::from(robot.world().humanoid().base_pose().translation.vector);
    assert!(
        (at - goal.centre()).norm() <= goal.tolerance + 0.05,
        "{name} seed {seed}: ended at {at:?}, outside the goal region"
    );
    let effort = robot.world().effort();
    assert_eq!(
        (effort.people_contacts, effort.pushed_into_people),
        (0, 0),
        "{name} seed {seed}: contacts with people"
    );
    let truth = Truth::new(robot.world());
    let kept: Vec<String> = report
        .obstacles
        .iter()
        .filter(|p| ghosts::is_ghost(p, &truth))
        .map(|p| p.id.to_string())
        .collect();
    assert!(kept.is_empty(), "{name} seed {seed}: ghosts {kept:?}");
    for s in score(&report, &robot) {
        assert!(s.correct, "{name} seed {seed}: {s:?}");
    }
}

#[test]
fn a_push_waits_for_the_person_standing_in_its_way_and_touches_nobody() {
    // Invariant: with a person standing in the sweep of the only push until t = 100 s, the robot reaches the goal, its body, hand and pushed objects touch nobody (the simulation's contact count), no obstacle it keeps at the end stands where the truth has nothing, and every verdict is right (chair-1 movable).
    assert_safe_and_clean("person-beside-chair", 1);
}

#[test]
fn four_wanderers_are_waited_for_and_leave_no_ghost() {
    // Invariant: among four people wandering across its way, the robot reaches the goal without touching anyone, and keeps no obstacle where the truth has nothing at the end.
    assert_safe_and_clean("four-wanderers", 1);
}

#[test]
fn someone_who_stood_through_a_look_and_walked_off_unseen_is_looked_at_again_and_forgotten() {
    // Invariant: a wanderer who stood still through the robot's second look (kept as an obstacle like any other, never seen moving) and walked off while the robot walked on past them is looked at again from the goal and forgotten: the run keeps no obstacle where the truth has nothing (without the goal's glances seed 2 kept obj-32 at (5.19, 3.62), behind the robot), touches nobody and judges every object right.
    assert_safe_and_clean("four-wanderers", 2);
}

#[test]
fn someone_who_stood_beyond_the_floor_seen_from_the_goal_is_walked_towards_and_forgotten() {
    // Invariant: a wanderer who stood through a look 5.3 m from the goal (farther than the 4.8 m of floor the camera returns from there) and walked off is looked at again from a step towards them and forgotten, and the robot walks back into the goal region: the run keeps no ghost (without the closer look seed 11 kept obj-34 at (1.78, 3.69)), touches nobody and judges every object right.
    assert_safe_and_clean("four-wanderers", 11);
}

#[test]
fn someone_hidden_behind_a_passer_by_at_the_goals_glance_is_looked_at_again() {
    // Invariant: when a walker passes between the goal and a remembered person-sized obstacle just as the robot glances at it (seed 22: obj-23 at (2.81, 4.49), hidden by walker-3), the robot glances again once they have passed and forgets what is gone: no ghost, no contact, every verdict right.
    assert_safe_and_clean("four-wanderers", 22);
}

#[test]
fn a_person_pacing_past_the_barrier_is_never_push_tested_or_touched() {
    // Invariant: with a person pacing between the robot and the barrier for the whole run (they stop short of the robot and wait, as people do), the robot reaches the goal without push-testing them (every verdict right against the truth: a person would read static) and without touching them, and keeps no ghost.
    assert_safe_and_clean("person-pacing", 1);
}

#[test]
fn a_walk_the_pacer_blocks_is_waited_out_and_not_held_against_the_object() {
    // Invariant: when the pacer steps into the robot's way to a push pose and the base stops short, the robot waits for them and walks on (Miyazaki's stop and return) rather than counting the object's approach as blocked (on seed 10 two such blocks per chair once left no candidate and ended in no path): it reaches the goal, touches nobody, keeps no ghost and judges every object right.
    assert_safe_and_clean("person-pacing", 10);
}
