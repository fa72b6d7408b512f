//! The robot description (`[robot.model]` in a scenario) is the one place robot facts come from: the
//! simulated robot and the executive's configuration both follow it.

use nalgebra::Point3;
use nudge_executive::robot::{Arm, GuardedMove, Head, RangeCamera};
use nudge_executive::{CandidatePolicy, RobotModel};
use nudge_sim::adapter::SimRobot;
use nudge_sim::run::run_config;
use nudge_sim::scenario::Scenario;

/// An empty 6 × 3.6 m room with the robot at (1, 1.8) facing +x and `model` (TOML lines under
/// `[robot.model]`, its tables written `[robot.model.<part>]`).
fn room_with(model: &str) -> String {
    format!(
        "name = \"model\"\n[room]\nsize = [6.0, 3.6]\n[robot]\nstart = [1.0, 1.8, 0.0]\n\
         [goal]\nposition = [5.0, 1.8]\n{model}\n"
    )
}

fn scenario(model: &str) -> Scenario {
    Scenario::from_toml_str(&room_with(model), "model.toml").expect("a valid scenario")
}

#[test]
fn a_scenarios_robot_description_reaches_the_sim_and_the_executive() {
    // Invariant: a camera of another size, a lower head, a shorter arm and a wider body given in `[robot.model]` are what the simulated robot has and what the run's configuration plans with; nothing keeps the paper's values.
    let s = scenario(
        "[robot.model.camera]\nwidth = 88\nheight = 72\nmax_range = 4.0\n\
         [robot.model.head]\nheight = 1.2\n\
         [robot.model.arm]\nreach_x = [0.2, 0.7]\n\
         [robot.model.body]\nradius = 0.3\n",
    );
    let config = run_config(&s, 1, CandidatePolicy::Nearest);
    assert_eq!(config.model, s.robot.model());
    assert_eq!(config.model.head.height, 1.2);
    assert_eq!(config.cylinder().radius, 0.3);
    assert_eq!(config.push.reach_x, (0.2, 0.7));
    assert!(
        config.push.distances.iter().all(|d| *d <= 4.0 + 1e-9),
        "pushes planned no longer than the camera sees"
    );
    assert_eq!(config.look_coverage().eye_height, 1.2);

    let mut robot = SimRobot::new(&s, 1).expect("world");
    robot
        .start_point_head(0.0, 0.3)
        .expect("within the head's limits");
    while !matches!(
        robot.head_status().expect("status"),
        nudge_executive::robot::ActionStatus::Done(_)
    ) {
        nudge_executive::robot::Clock::advance(&mut robot, 0.05).expect("advance");
    }
    let cloud = robot.capture().expect("a frame");
    assert_eq!((cloud.width(), cloud.height()), (88, 72));
    assert!((cloud.sensor_pose().translation.z - 1.2).abs() < 1e-12);
    let eye = Point3::from(cloud.sensor_pose().translation.vector);
    let farthest = cloud
        .to_map()
        .iter_valid()
        .map(|(_, p, _)| (Point3::new(f64::from(p.x), f64::from(p.y), f64::from(p.z)) - eye).norm())
        .fold(0.0, f64::max);
    assert!(farthest > 3.0, "the far wall seen, {farthest} m");
    assert!(
        farthest <= 4.0 + 0.05,
        "a return {farthest} m away, past the 4 m range"
    );

    // The arm refuses a line past its 0.7 m reach, which the paper's 0.8 m arm would take.
    let past_reach = GuardedMove {
        from: Point3::new(0.5, 0.0, 0.8),
        to: Point3::new(0.75, 0.0, 0.8),
        speed: 0.02,
        force_limit: 20.0,
        acceleration: None,
    };
    assert!(robot.start_guarded_move(past_reach).is_err());
}

#[test]
fn a_bad_robot_description_is_placed_in_the_scenario() {
    // Invariant: a broken rule or an unknown key inside `[robot.model]` is an error naming the file, the line and column and the field's full path, never a panic.
    let at = |model: &str| {
        Scenario::from_toml_str(&room_with(model), "model.toml")
            .expect_err("invalid")
            .to_string()
    };
    assert_eq!(
        at("[robot.model.arm]\nreach_x = [0.8, 0.2]\n"),
        "model.toml:9:17: robot.model.arm.reach_x[1]: must be finite and above 0.8, got 0.2"
    );
    assert!(
        at("[robot.model.camera]\nwidht = 88\n").starts_with("model.toml:9:1: "),
        "{}",
        at("[robot.model.camera]\nwidht = 88\n")
    );
    assert_eq!(
        at("[robot.model.head]\ntilt_limits = [-0.5, 1.3, 2.0]\n"),
        "model.toml:9:15: robot.model.head.tilt_limits: needs exactly 2 entries, got 3"
    );
}

#[test]
fn the_shorthands_and_the_default_are_the_papers_robot() {
    // Invariant: a scenario without `[robot.model]` runs the paper's robot, and `radius`, `height` and `walk_speed` in `[robot]` set the model's body.
    let plain = scenario("");
    assert_eq!(plain.robot.model(), RobotModel::default());
    let text = room_with("").replace(
        "start = [1.0, 1.8, 0.0]\n",
        "start = [1.0, 1.8, 0.0]\nradius = 0.3\nwalk_speed = 0.2\n",
    );
    let s = Scenario::from_toml_str(&text, "short.toml").expect("valid");
    let model = s.robot.model();
    assert_eq!((model.body.radius, model.body.walk_speed), (0.3, 0.2));
    assert_eq!(model.body.height, RobotModel::default().body.height);
    let both = text.replace("[goal]", "[robot.model.body]\nradius = 0.4\n[goal]");
    let e = Scenario::from_toml_str(&both, "both.toml").expect_err("two radii");
    assert_eq!(
        e.to_string(),
        "both.toml:6:10: robot.radius: set here and as robot.model.body.radius (0.4): keep one"
    );
}
