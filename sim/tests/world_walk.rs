//! Walking against ground truth: the body never enters anything and says when it is blocked.
mod world_common;

use nalgebra::Point2;
use nudge_executive::robot::{ActionStatus, Base, Clock, WalkOutcome};
use nudge_sim::adapter::SimRobot;
use world_common::*;

/// Walks until the walk ends (or `limit` s), returning the outcome and the smallest x seen.
fn walk_to(robot: &mut SimRobot, goal: Point2<f64>, limit: f64) -> (WalkOutcome, f64) {
    robot.start_walk(&[goal]).expect("walk accepted");
    let mut min_x = f64::INFINITY;
    while robot.now() < limit {
        robot.advance(0.05).expect("advance");
        min_x = min_x.min(robot.base_pose().expect("pose").value.translation.x);
        if let ActionStatus::Done(outcome) = robot.walk_status().expect("status") {
            return (outcome, min_x);
        }
    }
    panic!("walk did not end by {limit} s");
}

#[test]
fn walking_into_a_wall_stops_short_and_reports_blocked() {
    // Walking at the wall x = 0 stops with the body (radius 0.35) 0–3 cm short of it, Blocked.
    let s = robot_and(
        "name = \"far\"\nkind = \"box\"\nposition = [5.0, 3.0]\nsize = [0.2, 0.2, 0.2]\nmass = 1.0\ncolour = [1, 2, 3]",
    );
    let mut robot = SimRobot::new(&s, 1).expect("world");
    let (outcome, min_x) = walk_to(&mut robot, Point2::new(-1.0, 1.8), 60.0);
    let WalkOutcome::Blocked { at } = outcome else {
        panic!("expected Blocked, got {outcome:?}")
    };
    let gap = at.translation.x - 0.35;
    assert!((0.0..0.03).contains(&gap), "stopped {gap} m from the wall");
    assert!(min_x - 0.35 >= 0.0, "body entered the wall: min x {min_x}");
    // It turned round to face the wall (yaw π) before walking.
    assert!((at.rotation.angle().abs() - std::f64::consts::PI).abs() < 0.06);
}

#[test]
fn walking_into_a_table_stops_short_without_touching_it() {
    // A table's legs and top stop the walking body before contact, a margin away from its edge; the
    // table is not pushed (it only settles on its legs, well under a millimetre).
    let s = robot_and(
        "name = \"table\"\nkind = \"table\"\nposition = [2.5, 1.8]\nsize = [0.8, 1.2, 0.72]\nmass = 25.0\nfriction = 0.6\ncolour = [140, 100, 60]",
    );
    let mut robot = SimRobot::new(&s, 1).expect("world");
    let (outcome, _) = walk_to(&mut robot, Point2::new(4.0, 1.8), 60.0);
    let WalkOutcome::Blocked { at } = outcome else {
        panic!("expected Blocked, got {outcome:?}")
    };
    let gap = (2.5 - 0.4) - (at.translation.x + 0.35);
    assert!((0.0..0.03).contains(&gap), "stopped {gap} m from the table");
    let table = robot.world().object_pose(0).expect("table");
    assert!(
        (table.translation.x - 2.5).abs() < 1e-3,
        "the table was pushed by the body: {table:?}"
    );
}

#[test]
fn free_walk_arrives_facing_its_direction() {
    // A walk through free space arrives at its last waypoint (within 1 mm), facing the last leg.
    let s = robot_and(
        "name = \"far\"\nkind = \"box\"\nposition = [5.0, 3.0]\nsize = [0.2, 0.2, 0.2]\nmass = 1.0\ncolour = [1, 2, 3]",
    );
    let mut robot = SimRobot::new(&s, 1).expect("world");
    robot
        .start_walk(&[Point2::new(2.0, 1.8), Point2::new(2.0, 1.0)])
        .expect("walk");
    while robot.walk_status().expect("status") == ActionStatus::Running {
        robot.advance(0.1).expect("advance");
        assert!(robot.now() < 60.0, "walk too slow");
    }
    assert_eq!(
        robot.walk_status().expect("status"),
        ActionStatus::Done(WalkOutcome::Arrived)
    );
    let pose = robot.base_pose().expect("pose").value;
    assert!(
        (pose.translation.vector - nalgebra::Vector2::new(2.0, 1.0)).norm() < 1e-3,
        "{pose:?}"
    );
    assert!(
        (pose.rotation.angle() + std::f64::consts::FRAC_PI_2).abs() < 0.06,
        "{pose:?}"
    );
    // 1.8 m of walking at 0.15 m/s plus a quarter turn at 0.5 rad/s: at least 15 s.
    assert!(robot.now() >= 15.0);
}

#[test]
fn walking_with_the_hand_out_into_a_wall_stops_on_overload() {
    // Walking with the hand held out at a wall ends Blocked once the hand presses on it, before the
    // body reaches it, with the wrist force capped near the 60 N overload (below 70 N).
    use nalgebra::Point3;
    use nudge_executive::robot::{Arm, GuardedMove, HandOutcome, WristSensor};
    let s = robot_and(
        "name = \"far\"\nkind = \"box\"\nposition = [5.0, 3.0]\nsize = [0.2, 0.2, 0.2]\nmass = 1.0\ncolour = [1, 2, 3]",
    );
    let mut robot = SimRobot::new(&s, 1).expect("world");
    robot.start_turn(std::f64::consts::PI).expect("turn");
    robot.advance(10.0).expect("turn");
    robot.tare().expect("tare");
    let hold = GuardedMove {
        from: Point3::new(0.5, 0.0, 1.0),
        to: Point3::new(0.6, 0.0, 1.0),
        speed: 0.05,
        force_limit: 20.0,
        acceleration: None,
    };
    robot.start_guarded_move(hold).expect("hand out");
    robot.advance(10.0).expect("hand out");
    assert_eq!(
        nudge_executive::robot::Arm::hand_status(&mut robot).expect("status"),
        ActionStatus::Done(HandOutcome::Reached)
    );
    robot.drain_wrenches().expect("drain");
    let (outcome, min_x) = walk_to(&mut robot, Point2::new(-1.0, 1.8), 60.0);
    let peak = robot
        .drain_wrenches()
        .expect("drain")
        .iter()
        .map(|w| w.value.force_norm())
        .fold(0.0, f64::max);
    assert!(
        matches!(outcome, WalkOutcome::Blocked { .. }),
        "{outcome:?}"
    );
    // The hand's front face is 0.62 m ahead of the body axis.
    assert!(min_x > 0.6, "the body walked on to x = {min_x}");
    assert!(peak < 70.0, "peak force {peak} N");
}

#[test]
fn walking_over_a_mat_leaves_it_in_place() {
    // A 1 cm mat on the floor is stepped over: the walk arrives and the mat does not move.
    let s = robot_and(
        "name = \"mat\"\nkind = \"mat\"\nposition = [2.0, 1.8]\nsize = [0.6, 0.4, 0.01]\nmass = 0.5\ncolour = [180, 40, 40]",
    );
    let mut robot = SimRobot::new(&s, 1).expect("world");
    let before = robot.world().object_pose(0).expect("mat");
    let (outcome, _) = walk_to(&mut robot, Point2::new(3.0, 1.8), 60.0);
    assert_eq!(outcome, WalkOutcome::Arrived);
    let after = robot.world().object_pose(0).expect("mat");
    assert!(
        (after.translation.vector - before.translation.vector).norm() < 1e-3,
        "mat moved from {before:?} to {after:?}"
    );
}
