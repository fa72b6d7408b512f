//! The fake robot keeps the adapter contract: guarded moves, scripted objects and walks, failures.

use super::*;

fn run_until_hand_done(robot: &mut FakeRobot) -> HandOutcome {
    for _ in 0..100_000 {
        if let Ok(ActionStatus::Done(outcome)) = robot.hand_status() {
            return outcome;
        }
        robot.advance(0.01).expect("advance");
    }
    panic!("hand never finished");
}

fn push(limit: f64) -> GuardedMove {
    GuardedMove {
        from: Point3::new(0.3, 0.0, 0.7),
        to: Point3::new(0.7, 0.0, 0.7),
        speed: 0.1,
        force_limit: limit,
        acceleration: None,
    }
}

#[test]
fn a_static_object_stops_the_guarded_move_at_the_limit() {
    // Invariant: against a stiff object the tared force norm stops the hand at the limit, within 10 %.
    let mut robot = FakeRobot::new(Isometry2::identity());
    robot.tare().expect("tare");
    robot.set_object(Some(ScriptedObject {
        contact_at: 0.1,
        response: ObjectResponse::Static {
            stiffness: 20_000.0,
        },
    }));
    robot.start_guarded_move(push(20.0)).expect("start");
    match run_until_hand_done(&mut robot) {
        HandOutcome::ForceLimit { wrench, at } => {
            let f = wrench.value.force_norm();
            assert!((20.0..=22.0).contains(&f), "stopped at {f} N");
            assert!((at.x - 0.4).abs() < 0.005, "hand stopped at {at}");
        }
        other => panic!("expected ForceLimit, got {other:?}"),
    }
}

#[test]
fn a_sliding_object_lets_the_hand_reach_the_end_below_the_limit() {
    // Invariant: a sliding object under the limit never stops the move; the trace shows its friction force.
    let mut robot = FakeRobot::new(Isometry2::identity());
    robot.tare().expect("tare");
    robot.set_object(Some(ScriptedObject {
        contact_at: 0.1,
        response: ObjectResponse::Sliding { force: 12.0 },
    }));
    robot.start_guarded_move(push(20.0)).expect("start");
    assert_eq!(run_until_hand_done(&mut robot), HandOutcome::Reached);
    let peak = robot
        .drain_wrenches()
        .expect("drain")
        .iter()
        .map(|s| s.value.force_norm())
        .fold(0.0, f64::max);
    assert!((peak - 12.0).abs() < 1e-9, "peak {peak}");
}

#[test]
fn a_scripted_block_stops_the_walk_at_that_distance() {
    // Invariant: a walk blocked after d metres reports Blocked at d along the path.
    let mut robot = FakeRobot::new(Isometry2::identity());
    robot.block_next_walk_after(0.5);
    robot.start_walk(&[Point2::new(2.0, 0.0)]).expect("walk");
    let outcome = loop {
        if let ActionStatus::Done(o) = robot.walk_status().expect("status") {
            break o;
        }
        robot.advance(0.1).expect("advance");
    };
    match outcome {
        WalkOutcome::Blocked { at } => assert!((at.translation.x - 0.5).abs() < 0.01),
        other => panic!("expected Blocked, got {other:?}"),
    }
}

#[test]
fn an_injected_failure_fails_exactly_the_next_call() {
    // Invariant: fail_next makes one call of that capability fail, then the robot works again.
    let mut robot = FakeRobot::new(Isometry2::identity());
    let err = RobotError::Timeout {
        capability: "camera",
        seconds: 1.0,
    };
    robot.fail_next("camera", err.clone());
    assert_eq!(robot.capture(), Err(err));
    assert!(robot.capture().is_ok());
}

/// A robot at the origin facing +x, a box of 0.4 m side and 0.8 m height centred 1 m ahead (its near
/// face at x = 0.8) answering as `response`.
fn facing_a_box(response: ObjectResponse) -> FakeRobot {
    let mut robot = FakeRobot::new(Isometry2::identity());
    robot.set_scene(FakeScene::new([150, 150, 140]).with(SceneBox::new(
        "box",
        (1.0, 0.0, 0.0),
        Vector3::new(0.4, 0.4, 0.8),
        [40, 70, 170],
        response,
    )));
    robot.tare().expect("tare");
    robot
}

fn box_x(robot: &FakeRobot) -> f64 {
    robot
        .scene()
        .and_then(|s| s.get("box"))
        .expect("box")
        .pose
        .translation
        .x
}

fn line(to_x: f64) -> GuardedMove {
    GuardedMove {
        from: Point3::new(0.5, 0.0, 0.5),
        to: Point3::new(to_x, 0.0, 0.5),
        speed: 0.1,
        force_limit: 20.0,
        acceleration: None,
    }
}

#[test]
fn a_scene_box_is_met_at_its_face_and_slides_with_the_hand() {
    // Invariant: a guarded move towards a sliding scene box touches it where its face stands (0.8 m), loads the hand with its friction force, and moves it exactly as far as the hand went past the face.
    let mut robot = facing_a_box(ObjectResponse::Sliding { force: 12.0 });
    robot.start_guarded_move(line(0.95)).expect("start");
    assert_eq!(run_until_hand_done(&mut robot), HandOutcome::Reached);
    let trace = robot.drain_wrenches().expect("drain");
    let peak = trace
        .iter()
        .map(|s| s.value.force_norm())
        .fold(0.0, f64::max);
    assert!((peak - 12.0).abs() < 1e-9, "peak {peak}");
    assert!(
        (box_x(&robot) - 1.15).abs() < 1e-6,
        "box at {}",
        box_x(&robot)
    );
    assert!((robot.scene().expect("scene").boxes[0].moved - 0.15).abs() < 1e-6);
}

#[test]
fn a_box_that_jams_slides_its_travel_then_stops_the_hand_at_the_limit() {
    // Invariant: a box scripted to jam after 5 cm moves 5 cm with the hand, then holds: the guarded move stops at the force limit and the box moves no farther, on this push or the next.
    let mut robot = facing_a_box(ObjectResponse::SlidesThenJams {
        force: 12.0,
        travel: 0.05,
        stiffness: 20_000.0,
    });
    robot.start_guarded_move(line(0.95)).expect("start");
    assert!(matches!(
        run_until_hand_done(&mut robot),
        HandOutcome::ForceLimit { .. }
    ));
    assert!(
        (box_x(&robot) - 1.05).abs() < 1e-6,
        "box at {}",
        box_x(&robot)
    );
    robot.start_retract().expect("retract");
    run_until_hand_done(&mut robot);
    robot.tare().expect("tare");
    robot.start_guarded_move(line(0.95)).expect("again");
    assert!(matches!(
        run_until_hand_done(&mut robot),
        HandOutcome::ForceLimit { .. }
    ));
    assert!(
        (box_x(&robot) - 1.05).abs() < 1e-6,
        "box at {}",
        box_x(&robot)
    );
}

#[test]
fn the_camera_shows_a_scene_box_where_it_stands_now() {
    // Invariant: with no cloud queued, a capture renders the scene from the head: the nearest return straight ahead at hand height lies on the box's near face, and after the box slid 10 cm, on the face where it is now.
    fn nearest_ahead(robot: &mut FakeRobot) -> f64 {
        let cloud = robot.capture().expect("capture").to_map();
        cloud
            .iter_valid()
            .filter(|(_, p, _)| p.y.abs() < 0.05 && (p.z - 0.5).abs() < 0.05)
            .map(|(_, p, _)| f64::from(p.x))
            .fold(f64::INFINITY, f64::min)
    }
    let mut robot = facing_a_box(ObjectResponse::Sliding { force: 12.0 });
    robot.start_point_head(0.0, 0.8).expect("tilt");
    while robot.head_status().expect("head") == ActionStatus::Running {
        robot.advance(0.01).expect("advance");
    }
    let before = nearest_ahead(&mut robot);
    assert!((before - 0.8).abs() < 0.01, "face seen at {before}");
    robot.start_guarded_move(line(0.9)).expect("push");
    run_until_hand_done(&mut robot);
    let after = nearest_ahead(&mut robot);
    assert!((after - 0.9).abs() < 0.01, "face seen at {after}");
}
