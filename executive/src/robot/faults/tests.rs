//! Each decorator changes what the executive reads through the traits, and only that.

use nalgebra::{Isometry2, Point2, Point3, Vector2, Vector3};
use nudge_perception::{CloudFrame, ColourCloud};

use super::*;
use crate::robot::{
    ActionStatus, Arm, Base, Clock, FakeRobot, GuardedMove, Head, RangeCamera, RobotError,
    WalkOutcome, WristSensor,
};

fn fake() -> FakeRobot {
    FakeRobot::new(Isometry2::new(Vector2::zeros(), 0.0))
}

/// A fake with one queued frame: a 3 × 2 organised cloud of finite points.
fn with_frame() -> FakeRobot {
    let mut robot = fake();
    let n = 6;
    let cloud = ColourCloud::organised(
        3,
        2,
        (0..n).map(|i| 1.0 + i as f32).collect(),
        vec![0.5; n],
        vec![0.2; n],
        vec![[10, 20, 30]; n],
        CloudFrame::Sensor,
        nalgebra::Isometry3::identity(),
        0.0,
    )
    .expect("a 3 × 2 cloud");
    robot.queue_cloud(cloud);
    robot
}

fn always() -> FaultWindow {
    FaultWindow::every(Trigger::Always)
}

fn push() -> GuardedMove {
    GuardedMove {
        from: Point3::new(0.3, -0.3, 0.8),
        to: Point3::new(0.6, -0.3, 0.8),
        speed: 0.1,
        force_limit: 20.0,
        acceleration: None,
    }
}

#[test]
fn camera_faults_change_the_frame_the_executive_reads() {
    // Invariant: a dropout fails the capture with Unavailable; an empty cloud keeps the stamp and pose with no point; a NaN cloud keeps the layout and spoils one coordinate of every n-th slot, leaving the others valid.
    let mut dropout = CameraDropout::new(with_frame(), always());
    assert!(matches!(
        dropout.capture(),
        Err(RobotError::Unavailable {
            capability: "camera",
            ..
        })
    ));
    let mut empty = EmptyCloud::new(with_frame(), always());
    let cloud = empty.capture().expect("a frame");
    assert_eq!(cloud.len(), 0);
    let mut nan = NanCloud::new(with_frame(), always(), 2);
    let cloud = nan.capture().expect("a frame");
    assert_eq!((cloud.width(), cloud.height()), (3, 2));
    assert_eq!(cloud.valid_count(), 3);
    assert!(cloud.xs()[0].is_nan() && cloud.ys()[2].is_nan() && cloud.zs()[4].is_nan());
    assert!(cloud.ys()[0].is_finite());
}

#[test]
fn a_scrambled_frame_comes_only_after_a_push() {
    // Invariant: a capture with no guarded move before it is the camera's own; the first after one is noise inside the frame's bounding box, with as many valid points, and the next is the camera's own again.
    let mut robot = with_frame();
    for _ in 0..2 {
        robot.queue_cloud(with_frame().capture().expect("a frame"));
    }
    let mut scrambled = ScrambledCloud::new(robot, always(), 7);
    let before = scrambled.capture().expect("a frame");
    scrambled.start_guarded_move(push()).expect("a push");
    let after = scrambled.capture().expect("a frame");
    let again = scrambled.capture().expect("a frame");
    assert_eq!(before, again);
    assert_ne!(before.xs(), after.xs());
    assert_eq!(after.valid_count(), before.valid_count());
    assert!(after.xs().iter().all(|x| (1.0..=6.0).contains(x)));
}

#[test]
fn wrench_faults_change_the_readings() {
    // Invariant: a spike replaces one fresh reading's force and no other; NaN wrench reads NaN; a stuck wrench repeats the reading before it stuck while the force changes.
    let mut spike = WrenchSpike::new(
        fake(),
        FaultWindow::once(Trigger::Always),
        Vector3::new(-500.0, 0.0, 0.0),
    );
    spike.tare().expect("tare");
    spike.advance(0.003).expect("advance");
    let forces: Vec<f64> = spike
        .drain_wrenches()
        .expect("samples")
        .iter()
        .map(|s| s.value.force_norm())
        .collect();
    assert_eq!(forces.len(), 3);
    assert_eq!(forces.iter().filter(|f| **f == 500.0).count(), 1);
    let mut nan = NanWrench::new(fake(), always());
    assert!(nan.wrench().expect("a reading").value.force.x.is_nan());
    let mut stuck = StuckWrench::new(fake(), FaultWindow::once(Trigger::FromChance(2)));
    let first = stuck.wrench().expect("a reading").value;
    stuck.tare().expect("tare");
    let later = stuck.wrench().expect("a reading").value;
    assert_eq!(first, later, "stuck at the reading before the tare");
    assert!(first.force_norm() > 1.0, "the untared bias");
}

#[test]
fn a_short_walk_says_arrived_where_it_stopped() {
    // Invariant: a walk cut short reports Arrived once it has run `after` seconds, and the base stands where it stopped, short of the waypoint.
    let mut robot = ShortWalk::new(fake(), always(), 1.0);
    robot.start_walk(&[Point2::new(2.0, 0.0)]).expect("walk");
    let outcome = loop {
        if let ActionStatus::Done(o) = robot.walk_status().expect("status") {
            break o;
        }
        robot.advance(0.05).expect("advance");
    };
    assert_eq!(outcome, WalkOutcome::Arrived);
    let x = robot.base_pose().expect("pose").value.translation.x;
    assert!((0.1..0.2).contains(&x), "stopped at {x} m");
}

#[test]
fn a_stalled_or_hung_action_runs_until_stopped() {
    // Invariant: a hand that has moved `after` seconds stalls out of its rest pose, stands still and reports Running until stop_hand, then Stopped; a hung head reports Running though it arrived, until a new head motion.
    let mut arm = ArmStall::new(fake(), FaultWindow::once(Trigger::Always), 0.5);
    arm.start_guarded_move(push()).expect("push");
    let rest = arm.hand_position().expect("hand").value;
    for _ in 0..20 {
        assert_eq!(arm.hand_status().expect("status"), ActionStatus::Running);
        arm.advance(0.05).expect("advance");
    }
    let at = arm.hand_position().expect("hand").value;
    assert_ne!(at, rest, "stalled out, not at rest");
    for _ in 0..100 {
        assert_eq!(arm.hand_status().expect("status"), ActionStatus::Running);
        arm.advance(0.05).expect("advance");
    }
    assert_eq!(arm.hand_position().expect("hand").value, at);
    arm.stop_hand().expect("stop");
    assert!(matches!(arm.hand_status(), Ok(ActionStatus::Done(_))));
    let mut head = ActionHang::new(fake(), FaultWindow::once(Trigger::Always));
    head.start_point_head(0.1, 0.0).expect("head");
    head.advance(1.0).expect("advance");
    assert_eq!(head.head_status().expect("status"), ActionStatus::Running);
    head.start_point_head(0.0, 0.0).expect("head");
    head.advance(1.0).expect("advance");
    assert_eq!(head.head_status().expect("status"), ActionStatus::Done(()));
}

#[test]
fn a_failing_call_fails_once_and_a_jumped_clock_stays_jumped() {
    // Invariant: a once-window call error fails the next call with the chosen kind and no later one; a clock jump moves now() and every stamp by its offset for good, while advance lets the same time pass.
    let kind = ErrorKind::Timeout { seconds: 2.0 };
    let mut robot = CallError::new(fake(), FaultWindow::once(Trigger::Always), kind);
    assert!(matches!(
        robot.base_pose(),
        Err(RobotError::Timeout {
            capability: "base",
            ..
        })
    ));
    assert!(robot.base_pose().is_ok());
    let mut clock = ClockJump::new(fake(), FaultWindow::once(Trigger::FromTime(1.0)), -3600.0);
    clock.advance(0.5).expect("advance");
    assert!((clock.now() - 0.5).abs() < 1e-9);
    clock.advance(0.5).expect("advance");
    assert!((clock.now() + 3599.0).abs() < 1e-9);
    assert!((clock.wrench().expect("a reading").stamp + 3599.0).abs() < 1e-9);
    clock.advance(1.0).expect("advance");
    assert!((clock.now() + 3598.0).abs() < 1e-9);
}
