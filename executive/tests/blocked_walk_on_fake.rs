//! A walk the robot reports blocked, on the fake robot: the door is open, the walk stops anyway.

mod fake_world;

use fake_world::{GOAL, START, edges, robot_in, run_observed, timeline};
use nalgebra::{Isometry2, Point2, Vector2};
use nudge_executive::record::{Observer, RobotFrames};
use nudge_executive::robot::{Base, FakeScene, ObjectResponse};
use nudge_executive::{Edge, State};

/// How far the first walk gets before the robot reports it blocked (m).
const BLOCKED_AFTER: f64 = 0.5;

/// The two rooms with nothing in the door.
fn open_door() -> FakeScene {
    let mut scene = fake_world::door_room(ObjectResponse::RIGID);
    scene.boxes.retain(|b| b.name != fake_world::BOX);
    scene
}

/// Where the base stood when the machine took the `WalkBlocked` edge, and the first path planned after.
#[derive(Default)]
struct BlockedAt {
    base: Option<Isometry2<f64>>,
    at_block: Option<Isometry2<f64>>,
    path_after: Option<Vec<Point2<f64>>>,
}

impl Observer for BlockedAt {
    fn frames(&mut self, _stamp: f64, frames: &RobotFrames) {
        self.base = Some(frames.base);
    }
    fn path(&mut self, _stamp: f64, waypoints: &[Point2<f64>]) {
        if self.at_block.is_some() && self.path_after.is_none() {
            self.path_after = Some(waypoints.to_vec());
        }
    }
    fn transition(&mut self, _stamp: f64, _from: Option<&State>, edge: Edge, _to: &State) {
        if edge == Edge::WalkBlocked && self.at_block.is_none() {
            self.at_block = self.base;
        }
    }
}

#[test]
fn a_blocked_walk_stops_the_robot_which_looks_again_replans_and_goes_on() {
    // Invariant: a walk to the goal that the robot reports blocked 0.5 m on ends Navigate by WalkBlocked into a new look-around, with the robot standing where it was blocked and one replan counted; the next plan first steps straight back (the clearance, 8 cm, against the heading it was blocked at) and its walk reaches the goal, and no push is made: the door was open.
    let mut robot = robot_in(open_door());
    robot.block_next_walk_after(BLOCKED_AFTER);
    let (report, mut robot, seen) = run_observed(robot, BlockedAt::default());
    let context = timeline(&report);
    assert_eq!(report.outcome, State::Goal, "{context}");
    let taken = edges(&report);
    let blocked = taken
        .iter()
        .position(|e| *e == Edge::WalkBlocked)
        .unwrap_or_else(|| panic!("the walk was not blocked\n{context}"));
    assert_eq!(report.timeline[blocked].from, Some("Navigate"));
    assert_eq!(report.timeline[blocked].to, "LookAround");
    assert_eq!(
        taken.get(blocked + 1),
        Some(&Edge::LookAroundDone),
        "{context}"
    );
    assert!(
        taken[blocked..].contains(&Edge::PathFound),
        "a new plan after the block\n{context}"
    );
    assert_eq!(taken.last(), Some(&Edge::ReachedGoal));
    assert_eq!(report.knowledge.replans, 1, "{context}");
    assert!(report.knowledge.explanation.tests.is_empty());
    let stood = seen.at_block.expect("frames before the block");
    let walked = (stood.translation.vector - Vector2::new(START.0, START.1)).norm();
    assert!(
        (walked - BLOCKED_AFTER).abs() < 0.01,
        "blocked {walked} m from the start"
    );
    let path = seen.path_after.expect("a path planned after the block");
    let heading = stood.rotation * Vector2::x();
    let back = Point2::from(stood.translation.vector) - heading * 0.08;
    assert!(
        path.len() >= 3 && (path[1] - back).norm() < 0.02,
        "the path after the block does not start by stepping back to {back}: {path:?}"
    );
    let at = robot.base_pose().expect("pose").value.translation.vector;
    assert!(
        (at - Vector2::new(GOAL.0, GOAL.1)).norm() <= 0.2 + 1e-9,
        "{at}"
    );
}
