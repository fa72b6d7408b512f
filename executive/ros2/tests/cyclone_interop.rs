//! Interop with a DDS nudge did not write: a peer on Eclipse Cyclone DDS (the `cyclonedds` Python
//! package, pinned in `tests/python/requirements.txt`) plays a robot on the ROS 2 topic names and
//! types. It receives the adapter's `/cmd_vel` and publishes the `WrenchStamped` (and the `/tf` and
//! `/joint_states`) the adapter reads. Both run inside a private network namespace with only
//! loopback (`unshare -rn`), so discovery never leaves the machine. Missing tools fail the test.

#[path = "../../../tests/python/python_env.rs"]
mod python_env;

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};

use nudge_executive::robot::{Base, Clock, Head, WristSensor};
use nudge_robot_model::RobotModel;
use nudge_ros2::adapter::Ros2Robot;
use nudge_ros2::config::Ros2Config;

const PEER: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../tests/python/cyclone_peer.py"
);

#[test]
fn a_cyclone_dds_peer_takes_our_cmd_vel_and_we_read_its_wrench() {
    // Invariant: across RustDDS and Cyclone DDS on ROS 2 names and types, the adapter reads the peer's wrench, transform and joints exactly, and the peer receives the adapter's turn as a /cmd_vel with a positive yaw rate and no linear part.
    let python = python_env::python();
    let me = std::env::current_exe().expect("the test binary");
    let out = Command::new("unshare")
        .args([
            "-rn",
            "sh",
            "-c",
            "ip link set lo up && exec \"$0\" exchange_inside_a_private_network --exact --ignored --nocapture",
        ])
        .arg(me)
        .env("NUDGE_PEER_PYTHON", python)
        .output()
        .unwrap_or_else(|e| panic!("cannot run unshare (util-linux): {e}"));
    let all = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "the exchange failed:\n{all}");
    assert!(
        all.contains("1 passed"),
        "the inner test did not run:\n{all}"
    );
}

#[test]
#[ignore = "run by the test above inside a private network namespace"]
fn exchange_inside_a_private_network() {
    let python = std::env::var("NUDGE_PEER_PYTHON").expect("NUDGE_PEER_PYTHON");
    let mut peer = Command::new(python)
        .args([PEER, "8"])
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("start the Cyclone DDS peer");
    let mut robot = Ros2Robot::connect(Ros2Config::default(), RobotModel::default(), "interop")
        .expect("the adapter hears the Cyclone peer's /tf and /joint_states");

    let pose = robot.base_pose().expect("a base pose").value;
    assert_eq!(pose.translation.vector.as_slice(), &[1.5, -0.25]);
    assert_eq!(robot.head_angles().expect("head").value, (0.25, 0.5));
    let start = robot.now();
    while robot.now() - start < 0.5 {
        robot.advance(0.05).expect("time passes");
    }
    let w = robot.wrench().expect("a wrench from the peer").value;
    assert_eq!(w.force.as_slice(), &[1.5, -2.25, 3.125]);
    assert_eq!(w.torque.as_slice(), &[0.5, 0.0, -0.75]);

    robot.start_turn(1.0).expect("a turn");
    for _ in 0..20 {
        robot.advance(0.05).expect("time passes");
    }
    robot.stop_walk().expect("stop");
    drop(robot);

    let stdout = peer.stdout.take().expect("peer stdout");
    let twists: Vec<serde_json::Value> = BufReader::new(stdout)
        .lines()
        .map(|l| serde_json::from_str(&l.expect("a line")).expect("json"))
        .collect();
    assert!(peer.wait().expect("peer ends").success());
    let turning = twists
        .iter()
        .filter(|t| t["angular"][2].as_f64().is_some_and(|z| z > 0.0))
        .count();
    assert!(
        turning >= 10,
        "{turning} turning twists of {}: {twists:?}",
        twists.len()
    );
    assert!(
        twists.iter().all(|t| t["linear"][0].as_f64() == Some(0.0)),
        "a turn on the spot has no linear part: {twists:?}"
    );
    assert!(
        twists
            .last()
            .is_some_and(|t| t["angular"][2].as_f64() == Some(0.0)),
        "the stop is a zero twist: {twists:?}"
    );
}
