//! Our ROS 2 messages' CDR against another implementation's: the `rosbags` package's serializer.

#[path = "../../../tests/python/python_env.rs"]
mod python_env;

use std::io::Write;
use std::process::{Command, Stdio};

use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use nudge_perception::{CloudFrame, ColourCloud};
use nudge_ros2::cdr;
use nudge_ros2::convert::{point_cloud, time_from_seconds, transform, wrench};
use nudge_ros2::msg::*;
use serde_json::Value;

const SCRIPT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../tests/python/ros2_cdr.py"
);

/// One message of each type, with strings of every length modulo 4 before aligned fields, empty and
/// full sequences, and a cloud with a no-return slot.
fn messages() -> Vec<(&'static str, Vec<u8>, Value)> {
    fn entry<T: RosMessage>(m: &T) -> (&'static str, Vec<u8>, Value) {
        let bytes = cdr::encode(m);
        let back: T = cdr::decode(&bytes).expect("our own bytes decode");
        assert_eq!(
            cdr::encode(&back),
            bytes,
            "{} round-trips through our decoder",
            T::TYPE_NAME
        );
        (T::TYPE_NAME, bytes, serde_json::to_value(m).expect("json"))
    }
    let header = |frame: &str, t: f64| Header {
        stamp: time_from_seconds(t).expect("a time"),
        frame_id: frame.into(),
    };
    let pose = Isometry3::from_parts(
        Translation3::new(1.25, -0.5, 1.4),
        UnitQuaternion::from_euler_angles(0.1, 0.35, -2.0),
    );
    let organised = ColourCloud::organised(
        3,
        2,
        vec![1.0, 1.5, f32::NAN, 2.0, -0.25, 3.5],
        vec![0.0, 0.25, f32::NAN, -1.0, 0.5, 0.75],
        vec![1.4, 1.2, f32::NAN, 0.0, 0.1, 0.2],
        vec![
            [255, 0, 0],
            [0, 255, 0],
            [0, 0, 0],
            [1, 2, 3],
            [250, 128, 7],
            [9, 9, 9],
        ],
        CloudFrame::Sensor,
        pose,
        12.5,
    )
    .expect("a 3 × 2 cloud");
    let wrist = nudge_executive::robot::Wrench {
        force: nalgebra::Vector3::new(1.5, -20.25, 0.125),
        torque: nalgebra::Vector3::new(0.01, 0.0, -0.5),
    };
    vec![
        entry(&header("", 0.0).stamp),
        entry(&Duration {
            sec: 3,
            nanosec: 500_000_000,
        }),
        entry(&header("", 1.0)),
        entry(&header("map", 192.6)),
        entry(&WrenchStamped {
            header: header("w", 34.5),
            wrench: wrench(&wrist),
        }),
        entry(&WrenchStamped {
            header: header("wrist", 34.501),
            wrench: wrench(&wrist),
        }),
        entry(&Twist {
            linear: Vector3 {
                x: 0.15,
                y: 0.0,
                z: 0.0,
            },
            angular: Vector3 {
                x: 0.0,
                y: 0.0,
                z: -0.5,
            },
        }),
        entry(&TwistStamped {
            header: header("hand", 3.0),
            twist: Twist::default(),
        }),
        entry(&TFMessage {
            transforms: vec![
                TransformStamped {
                    header: header("map", 7.0),
                    child_frame_id: "base_link".into(),
                    transform: transform(&pose),
                },
                TransformStamped {
                    header: header("base_link", 7.0),
                    child_frame_id: "hand".into(),
                    transform: Transform::default(),
                },
            ],
        }),
        entry(&TFMessage::default()),
        entry(&JointTrajectory {
            header: header("", 0.0),
            joint_names: vec!["head_pan".into(), "head_tilt".into()],
            points: vec![
                JointTrajectoryPoint {
                    positions: vec![0.5, 0.35],
                    velocities: vec![],
                    accelerations: vec![],
                    effort: vec![],
                    time_from_start: Duration {
                        sec: 0,
                        nanosec: 500_000_000,
                    },
                },
                JointTrajectoryPoint {
                    positions: vec![-0.5, 0.7],
                    velocities: vec![0.0, 0.0],
                    accelerations: vec![],
                    effort: vec![1.0],
                    time_from_start: Duration { sec: 2, nanosec: 0 },
                },
            ],
        }),
        entry(&point_cloud(
            &organised,
            time_from_seconds(12.5).expect("a time"),
            "camera",
        )),
        entry(&PointCloud2::default()),
        entry(&Clock {
            clock: time_from_seconds(61.25).expect("a time"),
        }),
        entry(&JointState {
            header: header("", 4.5),
            name: vec!["head_pan".into(), "head_tilt".into()],
            position: vec![0.25, -0.125],
            velocity: vec![0.0, 1.0],
            effort: vec![],
        }),
        entry(&JointState::default()),
    ]
}

#[test]
fn rosbags_reads_our_cdr_as_we_wrote_it_and_writes_the_same_bytes() {
    // Invariant: for every ROS 2 message type the adapter uses, rosbags decodes our CDR bytes to the same field values and, serializing them again, writes exactly our bytes.
    let messages = messages();
    let mut input = String::new();
    for (name, bytes, _) in &messages {
        let hex: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
        input.push_str(&serde_json::json!({"type": name, "cdr": hex}).to_string());
        input.push('\n');
    }
    let mut child = Command::new(python_env::python())
        .arg(SCRIPT)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run the rosbags check");
    child
        .stdin
        .take()
        .expect("stdin")
        .write_all(input.as_bytes())
        .expect("write the messages");
    let out = child.wait_with_output().expect("the check ends");
    assert!(
        out.status.success(),
        "ros2_cdr.py failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let answers: Vec<Value> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON line"))
        .collect();
    assert_eq!(answers.len(), messages.len(), "one answer per message");
    for ((name, _, ours), answer) in messages.iter().zip(&answers) {
        assert_eq!(answer["type"], *name);
        assert!(answer.get("error").is_none(), "{name}: {}", answer["error"]);
        assert_eq!(
            answer["same_bytes"], true,
            "{name}: rosbags writes {}",
            answer["rosbags_cdr"]
        );
        assert_eq!(&answer["value"], ours, "{name}: rosbags reads other values");
    }
}

#[test]
fn bytes_that_are_not_a_message_are_an_error() {
    // Invariant: short input, another encapsulation and a truncated payload are errors, never a panic.
    let bytes = cdr::encode(&WrenchStamped::default());
    assert_eq!(
        cdr::decode::<WrenchStamped>(&bytes[..3]),
        Err(cdr::CdrError::TooShort(3))
    );
    let mut xcdr2 = bytes.clone();
    xcdr2[1] = 0x07;
    assert!(matches!(
        cdr::decode::<WrenchStamped>(&xcdr2),
        Err(cdr::CdrError::Encapsulation(_))
    ));
    for cut in [4, 10, bytes.len() - 1] {
        assert!(
            cdr::decode::<WrenchStamped>(&bytes[..cut]).is_err(),
            "cut at {cut}"
        );
    }
    let cloud = cdr::encode(&PointCloud2 {
        data: vec![0; 64],
        ..PointCloud2::default()
    });
    // A sequence claiming four billion bytes.
    let mut huge = cloud.clone();
    let at = huge.len() - 64 - 1 - 4;
    huge[at..at + 4].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(cdr::decode::<PointCloud2>(&huge).is_err());
}
