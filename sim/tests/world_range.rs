//! The range camera wired into the simulated robot.
mod world_common;

use nalgebra::Point3;
use nudge_executive::robot::{Clock, Head, RangeCamera};
use nudge_sim::adapter::SimRobot;
use world_common::*;

fn looking_at_table(seed: u64) -> SimRobot {
    let mut robot = SimRobot::new(&scenario(KAKIUCHI_ROOM), seed).expect("world");
    robot.start_point_head(0.0, 0.3).expect("head");
    robot.advance(1.0).expect("head moves");
    robot
}

#[test]
fn centre_ray_sees_the_table_top() {
    // From the start pose with the head 0.3 rad down, the centre of the image lies on the table top
    // (z = 0.72 m, x in 2.6..3.4), in the map frame through the cloud's sensor pose.
    let mut robot = looking_at_table(5);
    let cloud = robot.capture().expect("capture");
    assert_eq!((cloud.width(), cloud.height()), (176, 144));
    let i = 72 * 176 + 88;
    let p = cloud.point(i).expect("a return at the centre");
    let map = cloud.sensor_pose() * Point3::new(f64::from(p.x), f64::from(p.y), f64::from(p.z));
    assert!(
        (map.z - 0.72).abs() < 0.03 && (2.6..3.4).contains(&map.x),
        "centre at {map:?}"
    );
    assert!((cloud.stamp() - robot.now()).abs() < 1e-12);
}

#[test]
fn captures_repeat_with_the_seed() {
    // Two robots with the same scenario and seed capture identical frames; successive frames of one
    // robot differ (fresh noise per frame).
    let (mut a, mut b) = (looking_at_table(5), looking_at_table(5));
    let (a1, b1) = (a.capture().expect("a"), b.capture().expect("b"));
    assert_eq!(
        a1.zs().iter().map(|z| z.to_bits()).collect::<Vec<_>>(),
        b1.zs().iter().map(|z| z.to_bits()).collect::<Vec<_>>()
    );
    assert_eq!(a1.colours(), b1.colours());
    let a2 = a.capture().expect("a again");
    assert_ne!(
        a1.zs().iter().map(|z| z.to_bits()).collect::<Vec<_>>(),
        a2.zs().iter().map(|z| z.to_bits()).collect::<Vec<_>>()
    );
}
