//! The MCAP recorder writes complete, deterministic, readable files.

use std::collections::BTreeMap;
use std::io::Cursor;

use nalgebra::{Isometry2, Isometry3, Point2, Point3, Unit, Vector2, Vector3};
use nudge_executive::record::{
    GridView, LogLevel, McapRecorder, Observer, RobotFrames, RunInfo, topics,
};
use nudge_executive::robot::Wrench;
use nudge_executive::{Edge, PushIntent, State};
use nudge_perception::{CloudFrame, ColourCloud, ObjectId, Prism};

fn info() -> RunInfo {
    RunInfo {
        scenario: "unit".into(),
        seed: 7,
        version: "0.1.0".into(),
        policy: "nearest".into(),
        scenario_file: Some(("unit.toml".into(), "name = \"unit\"\n".into())),
    }
}

fn observe(rec: &mut impl Observer) {
    let mut cloud = ColourCloud::empty(
        CloudFrame::Sensor,
        Isometry3::translation(0.0, 0.0, 1.4),
        0.5,
    );
    cloud.push(Point3::new(1.0, 0.0, -1.4), [150, 150, 140]);
    rec.cloud(&cloud);
    rec.transition(
        1.0,
        Some(&State::LookAround),
        Edge::LookAroundDone,
        &State::DetectObjects,
    );
    let square = vec![
        Point2::new(0.0, 0.0),
        Point2::new(1.0, 0.0),
        Point2::new(1.0, 1.0),
        Point2::new(0.0, 1.0),
    ];
    rec.prisms(
        2.0,
        &[Prism {
            id: ObjectId(3),
            footprint: square,
            z_min: 0.0,
            z_max: 0.7,
            points: cloud.clone(),
        }],
    );
    let classes = [0u8, 1, 2, 3, 4, 1];
    rec.grid(
        2.0,
        &GridView {
            origin: Point2::new(0.0, 0.0),
            resolution: 0.05,
            width: 3,
            height: 2,
            classes: &classes,
        },
    );
    rec.tree(3.0, &[[Point2::new(0.0, 0.0), Point2::new(0.5, 0.5)]]);
    rec.path(3.0, &[Point2::new(0.0, 0.0), Point2::new(2.0, 0.0)]);
    let intent = PushIntent {
        target: ObjectId(3),
        stand: Isometry2::new(Vector2::new(1.0, 1.0), 0.0),
        hand_height: 0.7,
        clear_height: 0.7,
        direction: Unit::new_normalize(Vector2::new(1.0, 0.0)),
        distance: 0.8,
        opens_way: true,
    };
    rec.push(4.0, &intent, Some(Vector2::new(-20.0, 0.0)));
    rec.frames(
        4.0,
        &RobotFrames {
            base: Isometry2::identity(),
            head: (0.1, 0.5),
            camera: Isometry3::translation(0.0, 0.0, 1.4),
            hand: Point3::new(0.4, 0.0, 0.7),
        },
    );
    rec.wrench(
        4.001,
        &Wrench {
            force: Vector3::new(-3.0, 0.0, 0.5),
            torque: Vector3::zeros(),
        },
    );
    rec.note(5.0, LogLevel::Info, "goal");
}

fn record() -> Vec<u8> {
    let mut rec = McapRecorder::new(Cursor::new(Vec::new()), &info()).expect("recorder");
    observe(&mut rec);
    rec.finish().expect("finish").into_inner()
}

#[test]
fn a_recording_reads_back_with_every_topic_stamped_in_robot_time() {
    // Invariant: each observation lands on its topic with its robot-clock stamp, readable by the mcap crate.
    let bytes = record();
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    let mut stamps = Vec::new();
    for message in mcap::MessageStream::new(&bytes).expect("stream") {
        let message = message.expect("message");
        *counts.entry(message.channel.topic.clone()).or_default() += 1;
        stamps.push(message.log_time);
    }
    for topic in [
        topics::CLOUD,
        topics::LOG,
        topics::PRISMS,
        topics::GRID,
        topics::TREE,
        topics::PATH,
        topics::PUSH,
        topics::WRENCH,
    ] {
        assert!(
            counts.get(topic).copied().unwrap_or(0) >= 1,
            "missing {topic}: {counts:?}"
        );
    }
    // One message of the four frames, all new.
    assert_eq!(counts.get(topics::TF), Some(&1));
    // The wrench's last 10 ms window is written when the recording is finished, after later
    // messages: the stamps, not the order, span the observations.
    assert_eq!(stamps.iter().min(), Some(&500_000_000));
    assert_eq!(stamps.iter().max(), Some(&5_000_000_000));
    let summary = mcap::Summary::read(&bytes)
        .expect("summary")
        .expect("has a summary");
    assert_eq!(summary.attachment_indexes.len(), 1);
    assert_eq!(summary.metadata_indexes.len(), 1);
}

#[test]
fn the_same_observations_give_the_same_bytes() {
    // Invariant: a recording depends only on what was observed, never on the wall clock.
    assert_eq!(record(), record());
}

#[test]
fn a_dropped_recorder_still_leaves_a_complete_file() {
    // Invariant: a run that ends without finish() (an error path) still leaves a file with a summary.
    let dir = std::env::temp_dir().join(format!("nudge-rec-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let path = dir.join("dropped.mcap");
    {
        let mut rec = McapRecorder::create(&path, &info()).expect("create");
        observe(&mut rec);
    }
    let bytes = std::fs::read(&path).expect("read");
    assert!(mcap::Summary::read(&bytes).expect("summary").is_some());
    assert_eq!(
        mcap::MessageStream::new(&bytes).expect("stream").count(),
        10
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A sink that takes `room` bytes and then fails every write: a disk that fills up.
#[derive(Debug)]
struct FillingDisk {
    inner: Cursor<Vec<u8>>,
    room: usize,
}

impl std::io::Write for FillingDisk {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if self.inner.get_ref().len() + buf.len() > self.room {
            return Err(std::io::Error::other("no space left on the device"));
        }
        std::io::Write::write(&mut self.inner, buf)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

impl std::io::Seek for FillingDisk {
    fn seek(&mut self, pos: std::io::SeekFrom) -> std::io::Result<u64> {
        self.inner.seek(pos)
    }
}

#[test]
fn a_disk_that_fills_up_ends_the_recording_with_its_error_not_the_run() {
    // Invariant: when the sink fails part way (the writer thread meets the I/O error), every observer call still returns normally and finish reports the writer's error; with room enough the same calls give the same bytes as an unbounded sink.
    let sink = FillingDisk {
        inner: Cursor::new(Vec::new()),
        room: 600,
    };
    let mut rec = McapRecorder::new(sink, &info()).expect("the header fits");
    for k in 0..2_000 {
        rec.wrench(
            f64::from(k) * 1e-3,
            &Wrench {
                force: Vector3::new(-3.0, 0.0, f64::from(k)),
                torque: Vector3::zeros(),
            },
        );
    }
    observe(&mut rec);
    let err = rec.finish().expect_err("the disk filled up");
    assert!(
        matches!(err, nudge_executive::record::RecordError::Mcap(_)),
        "the writer's I/O error: {err}"
    );
    let roomy = FillingDisk {
        inner: Cursor::new(Vec::new()),
        room: usize::MAX,
    };
    let mut rec = McapRecorder::new(roomy, &info()).expect("recorder");
    observe(&mut rec);
    assert_eq!(rec.finish().expect("finish").inner.into_inner(), record());
}

#[test]
fn the_viewing_stride_keeps_a_point_per_grid_cell_at_two_metres() {
    // Invariant: the clouds a recording shows keep every fifth pixel of the SR-4000 for 5 cm cells (0.25° pixels: 4.3 cm apart at 2 m, one stride more would be 5.2 cm), every pixel for cells finer than a pixel, and never a stride of 0.
    use nudge_executive::record::view_cloud_stride;
    let camera = nudge_robot_model::CameraModel::default();
    assert_eq!(view_cloud_stride(&camera, 0.05), 5);
    assert_eq!(view_cloud_stride(&camera, 0.001), 1);
    assert_eq!(view_cloud_stride(&camera, f64::NAN), 1);
}
