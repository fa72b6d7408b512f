//! The tape's encoding reads back bit for bit, and bad bytes are errors, never panics.

use nalgebra::{Isometry2, Isometry3, Point2, Point3, Vector3};
use nudge_perception::{CloudFrame, ColourCloud};

use super::*;
use crate::robot::{
    ActionStatus, GuardedMove, HandOutcome, RobotError, Stamped, WalkOutcome, Wrench,
};

/// A NaN whose payload is not the canonical one.
fn odd_nan() -> f64 {
    f64::from_bits(0x7ff8_dead_beef_0001)
}

fn wrench(stamp: f64) -> Stamped<Wrench> {
    Stamped {
        stamp,
        value: Wrench {
            force: Vector3::new(1.5, -0.0, odd_nan()),
            torque: Vector3::new(f64::INFINITY, 1e-300, -2.25),
        },
    }
}

/// A 4 × 3 cloud: no-return slots, points, a NaN of another payload, a NaN point with colour.
fn cloud() -> ColourCloud {
    let n = 12;
    let mut x = vec![f32::NAN; n];
    let mut y = vec![f32::NAN; n];
    let mut z = vec![f32::NAN; n];
    let mut rgb = vec![[0u8; 3]; n];
    for i in [0, 3, 4, 9, 11] {
        x[i] = 1.0 + i as f32 * 0.37;
        y[i] = -0.5 * i as f32;
        z[i] = 0.001 * i as f32;
        rgb[i] = [i as u8, 200, 7];
    }
    x[5] = f32::from_bits(0x7fc0_1234);
    rgb[7] = [1, 2, 3];
    ColourCloud::organised(
        4,
        3,
        x,
        y,
        z,
        rgb,
        CloudFrame::Sensor,
        Isometry3::new(Vector3::new(1.0, 2.0, 1.4), Vector3::new(0.1, -0.7, 2.0)),
        12.5,
    )
    .expect("a 4 × 3 cloud")
}

/// One entry of every kind, errors of every kind among them.
fn every_entry() -> Vec<Entry> {
    let pose = Isometry2::new(nalgebra::Vector2::new(0.1, -3.0), 2.5);
    let refused = RobotError::Refused {
        capability: "base",
        reason: "out of reach".into(),
    };
    let motion = GuardedMove {
        from: Point3::new(0.3, -0.2, 0.9),
        to: Point3::new(0.6, -0.2, 0.9),
        speed: 0.02,
        force_limit: 20.0,
        acceleration: Some(0.01),
    };
    vec![
        Entry::Call(Request::Now, Reply::Time(odd_nan())),
        Entry::Call(Request::Advance(0.05), Reply::Done(Ok(()))),
        Entry::Call(
            Request::Advance(0.05),
            Reply::Done(Err(RobotError::Timeout {
                capability: "clock",
                seconds: 1.25,
            })),
        ),
        Entry::Call(
            Request::BasePose,
            Reply::Pose(Ok(Stamped {
                stamp: 3.0,
                value: pose,
            })),
        ),
        Entry::Call(
            Request::StartWalk(vec![Point2::new(1.0, 2.0), Point2::new(-0.0, f64::NAN)]),
            Reply::Done(Err(refused.clone())),
        ),
        Entry::Call(Request::StartTurn(-1.5), Reply::Done(Ok(()))),
        Entry::Call(Request::WalkStatus, Reply::Walk(Ok(ActionStatus::Running))),
        Entry::Call(
            Request::WalkStatus,
            Reply::Walk(Ok(ActionStatus::Done(WalkOutcome::Blocked { at: pose }))),
        ),
        Entry::Call(
            Request::WalkStatus,
            Reply::Walk(Ok(ActionStatus::Done(WalkOutcome::Stopped))),
        ),
        Entry::Call(Request::StopWalk, Reply::Done(Ok(()))),
        Entry::Call(
            Request::HeadAngles,
            Reply::Angles(Ok(Stamped {
                stamp: 4.0,
                value: (0.3, 0.7),
            })),
        ),
        Entry::Call(Request::StartPointHead(0.5, -0.25), Reply::Done(Ok(()))),
        Entry::Call(Request::HeadStatus, Reply::Head(Ok(ActionStatus::Done(())))),
        Entry::Call(Request::Capture, Reply::Cloud(Ok(cloud()))),
        Entry::Call(
            Request::Capture,
            Reply::Cloud(Ok(ColourCloud::empty(
                CloudFrame::Map,
                Isometry3::identity(),
                1.0,
            ))),
        ),
        Entry::Call(
            Request::Capture,
            Reply::Cloud(Err(RobotError::Unavailable {
                capability: "camera",
                reason: "no frame".into(),
            })),
        ),
        Entry::Call(Request::Tare, Reply::Done(Ok(()))),
        Entry::Call(Request::Wrench, Reply::Wrench(Ok(wrench(5.0)))),
        Entry::Call(
            Request::DrainWrenches,
            Reply::Wrenches(Ok(vec![wrench(5.001), wrench(5.002)])),
        ),
        Entry::Call(Request::DiscardWrenches, Reply::Done(Ok(()))),
        Entry::Call(
            Request::HandPosition,
            Reply::Hand(Ok(Stamped {
                stamp: 6.0,
                value: Point3::new(0.2, 0.3, 0.4),
            })),
        ),
        Entry::Call(Request::StartGuardedMove(motion), Reply::Done(Ok(()))),
        Entry::Call(Request::StartRetract, Reply::Done(Ok(()))),
        Entry::Call(
            Request::HandStatus,
            Reply::HandStatus(Ok(ActionStatus::Done(HandOutcome::ForceLimit {
                wrench: wrench(7.0),
                at: Point3::new(0.5, -0.2, 0.9),
            }))),
        ),
        Entry::Call(
            Request::HandStatus,
            Reply::HandStatus(Err(RobotError::Fault {
                capability: "gripper",
                reason: "an adapter's own capability name".into(),
            })),
        ),
        Entry::Call(Request::StopHand, Reply::Done(Ok(()))),
        Entry::Transition(Transition {
            from: "(start)".into(),
            edge: "Start".into(),
            to: "LookAround".into(),
        }),
    ]
}

/// A 4 × 3 camera, the test cloud's image size.
fn camera() -> CameraRays {
    CameraRays::new(&nudge_robot_model::CameraModel {
        width: 4,
        height: 3,
        ..Default::default()
    })
}

fn encode_all(entries: &[Entry]) -> Vec<u8> {
    let mut bytes = Vec::new();
    let camera = camera();
    for e in entries {
        encode_entry(e, &mut bytes, Some(&camera));
    }
    bytes
}

#[test]
fn every_entry_reads_back_bit_for_bit() {
    // Invariant: decoding the encoding of every kind of entry gives entries whose encoding is the same bytes (floats compared as bits, NaN payloads, -0.0 and no-return slots included), and a cloud reads back slot for slot.
    let entries = every_entry();
    let bytes = encode_all(&entries);
    let decoded = decode_batch(&bytes).expect("decodes");
    assert_eq!(decoded.len(), entries.len());
    assert_eq!(encode_all(&decoded), bytes);
    let Entry::Call(_, Reply::Time(t)) = &decoded[0] else {
        panic!("first entry is now(): {:?}", decoded[0]);
    };
    assert_eq!(t.to_bits(), odd_nan().to_bits());
    let Entry::Call(_, Reply::Cloud(Ok(c))) = &decoded[13] else {
        panic!("entry 13 is a cloud: {:?}", decoded[13]);
    };
    let original = cloud();
    assert_eq!((c.width(), c.height()), (4, 3));
    for (a, b) in [
        (c.xs(), original.xs()),
        (c.ys(), original.ys()),
        (c.zs(), original.zs()),
    ] {
        let bits = |v: &[f32]| v.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(a), bits(b));
    }
    assert_eq!(c.colours(), original.colours());
    assert_eq!(
        c.sensor_pose().rotation.coords,
        original.sensor_pose().rotation.coords
    );
    // Everything but the NaNs compares equal as values too.
    assert_eq!(decoded[1..4], entries[1..4]);
    assert_eq!(decoded[5..13], entries[5..13]);
    assert_eq!(decoded[24..], entries[24..]);
}

#[test]
fn cut_or_damaged_tape_bytes_are_errors_not_panics() {
    // Invariant: every strict prefix of an encoded batch that cuts an entry, and a batch with an unknown tag, fail to decode with an error giving the offset; none panics.
    let entries = every_entry();
    let mut ends = Vec::new();
    let mut bytes = Vec::new();
    let camera = camera();
    for e in &entries {
        encode_entry(e, &mut bytes, Some(&camera));
        ends.push(bytes.len());
    }
    for cut in 0..bytes.len() {
        let result = decode_batch(&bytes[..cut]);
        if ends.contains(&cut) || cut == 0 {
            assert!(result.is_ok(), "cut at an entry boundary {cut}");
        } else {
            assert!(result.is_err(), "cut inside an entry at {cut}");
        }
    }
    let err = decode_batch(&[0x7f]).expect_err("unknown tag");
    assert_eq!(err.at, 0);
    assert!(err.to_string().contains("unknown entry tag"), "{err}");
    // A count far beyond the bytes left is refused before anything is allocated for it.
    let err = decode_batch(&[14, 0, 0xff, 0xff, 0xff, 0xff, 0x0f]).expect_err("huge count");
    assert!(err.to_string().contains("does not fit"), "{err}");
}

#[test]
fn points_on_the_camera_rays_read_back_bit_for_bit_as_counts() {
    // Invariant: a cloud whose points are its pixels' rays times ranges on the camera's step grid, some off it, reads back bit for bit, and it costs under half the bytes of raw points (colours included).
    let model = nudge_robot_model::CameraModel::default();
    let rays = CameraRays::new(&model);
    let n = rays.len();
    let (mut x, mut y, mut z) = (vec![f32::NAN; n], vec![f32::NAN; n], vec![f32::NAN; n]);
    let mut rgb = vec![[0u8; 3]; n];
    for i in 0..n {
        if i % 7 == 0 {
            continue; // no return
        }
        let range = model.reported_range(1.0 + (i as f64 * 0.37).sin().abs() * 3.0);
        let count = (range / model.range_step()).round() as u16;
        let mut p = rays.point(i, count);
        if i % 11 == 0 {
            p[2] += 1.0e-3; // off its ray
        }
        [x[i], y[i], z[i]] = p;
        rgb[i] = [(i % 251) as u8, 40, 200];
    }
    let cloud = ColourCloud::organised(
        model.width,
        model.height,
        x,
        y,
        z,
        rgb,
        CloudFrame::Sensor,
        Isometry3::identity(),
        3.0,
    )
    .expect("an organised cloud");
    let entry = Entry::Call(Request::Capture, Reply::Cloud(Ok(cloud.clone())));
    let (mut counted, mut raw) = (Vec::new(), Vec::new());
    encode_entry(&entry, &mut counted, Some(&rays));
    encode_entry(&entry, &mut raw, None);
    assert!(
        counted.len() * 2 < raw.len(),
        "{} against {}",
        counted.len(),
        raw.len()
    );
    for bytes in [&counted, &raw] {
        let decoded = decode_batch(bytes).expect("decodes");
        let [Entry::Call(_, Reply::Cloud(Ok(c)))] = decoded.as_slice() else {
            panic!("one cloud: {decoded:?}");
        };
        let bits = |v: &[f32]| v.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(c.xs()), bits(cloud.xs()));
        assert_eq!(bits(c.ys()), bits(cloud.ys()));
        assert_eq!(bits(c.zs()), bits(cloud.zs()));
        assert_eq!(c.colours(), cloud.colours());
    }
}

#[test]
fn wrist_samples_on_a_power_of_two_grid_read_back_bit_for_bit_in_a_few_bytes() {
    // Invariant: a batch of 1 kHz samples stamped on whole microseconds, each axis a whole count of 1/64 N or 1/1024 N·m, reads back bit for bit in under 16 bytes a sample before compression, and one off the grid (a NaN, a −0) reads back too.
    let mut samples: Vec<Stamped<Wrench>> = (0..1000)
        .map(|i| {
            let t = f64::from(i);
            Stamped {
                stamp: (12_345_000 + 1000 * i) as f64 * 1.0e-6,
                value: Wrench {
                    force: Vector3::new(
                        ((t * 0.37).sin() * 900.0).round() / 64.0,
                        -(t * 3.0).round() / 64.0,
                        1.0,
                    ),
                    torque: Vector3::new((t * 0.01).round() / 1024.0, 0.0, -17.0 / 1024.0),
                },
            }
        })
        .collect();
    let entry = Entry::Call(Request::DrainWrenches, Reply::Wrenches(Ok(samples.clone())));
    let mut bytes = Vec::new();
    encode_entry(&entry, &mut bytes, None);
    assert!(bytes.len() < 16 * samples.len(), "{} bytes", bytes.len());
    samples[500].value.force.y = -0.0;
    samples[501].value.torque.x = odd_nan();
    samples[502].stamp = 0.1 + 0.2;
    for entry in [
        Entry::Call(Request::DrainWrenches, Reply::Wrenches(Ok(samples.clone()))),
        Entry::Call(Request::Wrench, Reply::Wrench(Ok(samples[501]))),
    ] {
        let mut bytes = Vec::new();
        encode_entry(&entry, &mut bytes, None);
        let decoded = decode_batch(&bytes).expect("decodes");
        let mut again = Vec::new();
        encode_entry(&decoded[0], &mut again, None);
        assert_eq!(again, bytes);
    }
    let mut bytes = Vec::new();
    encode_entry(
        &Entry::Call(Request::DrainWrenches, Reply::Wrenches(Ok(samples.clone()))),
        &mut bytes,
        None,
    );
    let decoded = decode_batch(&bytes).expect("decodes");
    let [Entry::Call(_, Reply::Wrenches(Ok(back)))] = decoded.as_slice() else {
        panic!("a batch of samples: {decoded:?}");
    };
    let bits = |s: &Stamped<Wrench>| {
        let w = &s.value;
        [
            s.stamp, w.force.x, w.force.y, w.force.z, w.torque.x, w.torque.y, w.torque.z,
        ]
        .map(f64::to_bits)
    };
    assert_eq!(
        back.iter().map(bits).collect::<Vec<_>>(),
        samples.iter().map(bits).collect::<Vec<_>>()
    );
}
