//! A run on the fake robot, no rapier: two rooms joined by one 1.2 m door with a box in it that leaves
//! 0.25 m either side, narrower than the robot (the `blocked-door` family's room), the box answering
//! pushes as the test scripts it. The camera shows the scripted world, so perception, the grid, the
//! planners and colour ICP all run on it; only the physics is a script.
#![allow(dead_code)]

use nalgebra::{Isometry2, Point2, Vector2, Vector3};
use nudge_executive::record::{NullObserver, Observer};
use nudge_executive::robot::{FakeRobot, FakeScene, ObjectResponse, SceneBox};
use nudge_executive::{Edge, RunConfig, RunReport, Runner};
use nudge_robot_model::RobotModel;

/// The box's name in the scene.
pub const BOX: &str = "box";
/// Where the box stands at the start: in the door.
pub const BOX_AT: (f64, f64) = (3.0, 1.8);
/// Where the robot starts, facing the door.
pub const START: (f64, f64) = (1.0, 1.8);
/// The goal, in the second room.
pub const GOAL: (f64, f64) = (5.0, 1.8);
/// A light box's friction force (N): μ m g of 3 kg at μ 0.4, well under the 20 N limit.
pub const SLIDING: f64 = 12.0;
/// A bolted box's (or a jammed one's) contact stiffness (N/m).
pub const STIFF: f64 = 20_000.0;

/// The two rooms (6 × 3.6 m, the partition at x = 3 with its door from y = 1.2 to 2.4) and the box.
pub fn door_room(response: ObjectResponse) -> FakeScene {
    let wall = [200, 195, 185];
    let partition = |name: &str, y: f64| {
        SceneBox::new(
            name,
            (3.0, y, 0.0),
            Vector3::new(0.1, 1.2, 2.0),
            wall,
            ObjectResponse::RIGID,
        )
    };
    FakeScene::new([150, 150, 140])
        .with_walls(Point2::new(0.0, 0.0), Point2::new(6.0, 3.6), 2.0, 0.1, wall)
        .with(partition("partition-south", 0.6))
        .with(partition("partition-north", 3.0))
        .with(SceneBox::new(
            BOX,
            (BOX_AT.0, BOX_AT.1, 0.0),
            Vector3::new(0.5, 0.7, 0.75),
            [40, 70, 170],
            response,
        ))
}

/// The fake robot at the start, in `scene`.
pub fn robot_in(scene: FakeScene) -> FakeRobot {
    let mut robot = FakeRobot::new(Isometry2::new(Vector2::new(START.0, START.1), 0.0));
    robot.set_scene(scene);
    robot
}

/// The run's configuration: the robot's cylinder, the goal, seed 1.
pub fn config() -> RunConfig {
    RunConfig::new(RobotModel::default(), Point2::new(GOAL.0, GOAL.1), 0.2, 1)
}

/// Runs `robot` to its end; the report and the robot, whose scene is the ground truth.
pub fn run(robot: FakeRobot) -> (RunReport, FakeRobot) {
    let (report, robot, _) = run_observed(robot, NullObserver);
    (report, robot)
}

/// Runs `robot` to its end, reporting to `observer`; the report, the robot and the observer.
pub fn run_observed<O: Observer>(robot: FakeRobot, observer: O) -> (RunReport, FakeRobot, O) {
    let mut runner = Runner::new(robot, observer, config());
    let report = runner.run();
    let (robot, observer) = runner.into_parts();
    (report, robot, observer)
}

/// The edges the run took, in order.
pub fn edges(report: &RunReport) -> Vec<Edge> {
    report.timeline.iter().map(|t| t.edge).collect()
}

/// The timeline as `from -edge-> to` lines, for failure messages.
pub fn timeline(report: &RunReport) -> String {
    report
        .timeline
        .iter()
        .map(|t| {
            format!(
                "{:7.1} s  {} -{:?}-> {}",
                t.stamp,
                t.from.unwrap_or("(start)"),
                t.edge,
                t.to
            )
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// How far the pushes moved the box, in truth (map frame, m).
pub fn box_offset(robot: &FakeRobot) -> Vector2<f64> {
    let b = robot
        .scene()
        .and_then(|s| s.get(BOX))
        .expect("the scene has the box");
    b.pose.translation.vector - Vector2::new(BOX_AT.0, BOX_AT.1)
}
