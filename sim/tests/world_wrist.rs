//! The wrist sensor against known loads.
mod world_common;

use world_common::*;

#[test]
fn hanging_hand_reads_its_weight() {
    // The joint impulse → force convention (impulse × substeps / dt) gives the hanging hand's weight
    // on the wrist, (0, 0, −m g) within 1 %, for a fine (1 ms) and a coarse (10 ms) physics step alike.
    let s = robot_and(
        "name = \"far\"\nkind = \"box\"\nposition = [5.0, 3.0]\nsize = [0.2, 0.2, 0.2]\nmass = 1.0\ncolour = [1, 2, 3]",
    );
    let mut w = world(&s);
    w.advance(1.0).expect("settle");
    let hand = w.humanoid().parts().hand;
    for dt in [0.001, 0.01, 0.001] {
        // Exactly one physics step of length dt (the world is on a 10 ms boundary), with the hand awake.
        w.physics_mut().wake_up(hand, true);
        let steps = w.steps();
        w.advance(dt).expect("advance");
        assert_eq!(w.steps(), steps + 1, "one physics step of {dt} s");
        let f = w.wrist_truth().force;
        let weight = w.robot_model().arm.hand_mass * 9.81;
        assert!(
            (f.z + weight).abs() < 0.01 * weight,
            "dt {dt}: force {f:?}, weight {weight}"
        );
        assert!(
            f.x.abs() < 0.01 * weight && f.y.abs() < 0.01 * weight,
            "dt {dt}: force {f:?}"
        );
        w.advance(0.01 - dt).expect("back onto the 10 ms grid");
    }
}

#[test]
fn wrench_is_available_before_time_passes_and_stamped_with_the_clock() {
    // A reading is there at t = 0 without advancing time, and later readings carry the sensor's
    // 1 kHz stamps up to the current time; draining returns one sample per millisecond.
    use nudge_executive::robot::{Clock, WristSensor};
    use nudge_sim::adapter::SimRobot;
    let s = robot_and(
        "name = \"far\"\nkind = \"box\"\nposition = [5.0, 3.0]\nsize = [0.2, 0.2, 0.2]\nmass = 1.0\ncolour = [1, 2, 3]",
    );
    let mut robot = SimRobot::new(&s, 2).expect("world");
    let first = robot.wrench().expect("a reading at t = 0");
    assert_eq!(first.stamp, 0.0);
    assert_eq!(robot.now(), 0.0);
    robot.advance(0.25).expect("advance");
    let later = robot.wrench().expect("reading");
    assert!((later.stamp - 0.25).abs() < 1e-9, "stamp {}", later.stamp);
    assert_eq!(robot.drain_wrenches().expect("drain").len(), 250);
}

#[test]
fn bad_time_steps_are_errors() {
    // Negative, non-finite or absurdly long steps are refused and leave the clock where it was.
    let s = robot_and(
        "name = \"far\"\nkind = \"box\"\nposition = [5.0, 3.0]\nsize = [0.2, 0.2, 0.2]\nmass = 1.0\ncolour = [1, 2, 3]",
    );
    let mut w = world(&s);
    for dt in [-0.1, f64::NAN, f64::INFINITY, 1.0e12] {
        assert!(w.advance(dt).is_err(), "dt {dt}");
    }
    assert_eq!(w.time(), 0.0);
}
