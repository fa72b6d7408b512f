//! Same scenario and seed → the same run, bit for bit.
mod world_common;

use nalgebra::{Isometry3, Point2, Point3};
use nudge_executive::robot::{
    Arm, Base, Clock, GuardedMove, RangeCamera, Stamped, Wrench, WristSensor,
};
use nudge_sim::adapter::SimRobot;
use world_common::*;

/// Walks towards chair-1's back in the paper's room, pushes it, and records everything (wrist
/// samples, object poses every 0.1 s, and the bits of one range frame at the end).
fn run(seed: u64) -> (Vec<Stamped<Wrench>>, Vec<Isometry3<f64>>) {
    let mut robot = SimRobot::new(&scenario(KAKIUCHI_ROOM), seed).expect("world");
    robot
        .start_walk(&[
            Point2::new(1.5, 0.6),
            Point2::new(3.1, 0.6),
            Point2::new(3.1, 0.8),
        ])
        .expect("walk");
    robot.advance(25.0).expect("walk");
    robot.start_turn(0.0).expect("turn");
    robot.advance(5.0).expect("turn");
    robot.tare().expect("tare");
    robot.drain_wrenches().expect("drain");
    let push = GuardedMove {
        from: Point3::new(0.4, 0.0, 0.43),
        to: Point3::new(0.75, 0.0, 0.43),
        speed: 0.05,
        force_limit: 40.0,
        acceleration: None,
    };
    robot.start_guarded_move(push).expect("push");
    let mut poses = Vec::new();
    for _ in 0..100 {
        robot.advance(0.1).expect("advance");
        poses.extend((0..4).filter_map(|i| robot.world().object_pose(i)));
    }
    let cloud = robot.capture().expect("range frame");
    // The frame's coordinates ride along as poses' translations, bit for bit.
    poses.extend(
        cloud
            .xs()
            .iter()
            .zip(cloud.ys())
            .zip(cloud.zs())
            .map(|((x, y), z)| {
                Isometry3::translation(
                    f64::from(x.to_bits()),
                    f64::from(y.to_bits()),
                    f64::from(z.to_bits()),
                )
            }),
    );
    (robot.drain_wrenches().expect("drain"), poses)
}

#[test]
fn same_seed_same_run() {
    // Two runs with the same scenario and seed give identical wrist traces and object poses.
    let (w1, p1) = run(11);
    let (w2, p2) = run(11);
    assert!(w1.len() > 9000, "{} samples", w1.len());
    assert_eq!(w1, w2);
    assert_eq!(p1, p2);
    // The push did touch something, so the comparison covers contact dynamics.
    assert!(w1.iter().any(|w| w.value.force_norm() > 5.0));
}

#[test]
fn another_seed_changes_the_noise() {
    // A different seed changes the sensor noise (the scene itself is the same).
    let (w1, _) = run(11);
    let (w2, _) = run(12);
    assert_ne!(w1, w2);
}

#[test]
fn thread_count_does_not_change_the_run() {
    // The physics (rapier's parallel solver) and the sensors give the same run on 1 and on 3 threads.
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool")
            .install(|| run(11))
    };
    let (w1, p1) = on(1);
    let (w3, p3) = on(3);
    assert_eq!(w1, w3);
    assert_eq!(p1, p3);
}
