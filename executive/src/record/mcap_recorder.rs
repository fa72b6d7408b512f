//! The MCAP recorder: every observation as a Foxglove message, stamped with robot time.
//!
//! Written with the `mcap` crate and the protobuf message types of the `foxglove` crate. Nothing in a
//! recording comes from the wall clock, so the same scenario and seed give the same file byte for
//! byte. Messages are encoded in the run's thread and compressed and written by a writer thread
//! (`writer_thread.rs`), in the same order. The writer finishes the file (summary, footer) when the
//! recorder is finished or dropped, so a failed or cancelled run still leaves a complete file; an
//! I/O error stops recording, is kept, and never stops the run.

use std::collections::{BTreeMap, BTreeSet};
use std::fs::File;
use std::io::{BufWriter, Seek, Write};
use std::path::{Path, PathBuf};

use foxglove::Encode;
use foxglove::messages::log::Level;
use foxglove::messages::{FrameTransforms, Log};
use mcap::records::{MessageHeader, Metadata};
use nalgebra::{Isometry3, Point2, Translation3, UnitQuaternion, Vector2};
use nudge_perception::{ColourCloud, ObjectId, Prism};
use nudge_robot_model::CameraModel;
use prost::Message as _;

use super::messages;
use super::observer::{GridView, LogLevel, Observer, RobotFrames};
use super::summary::{RUN_METADATA, RUN_SUMMARY_LOG, RunSummary, SUMMARY_METADATA};
use super::tape::{TAPE_ENCODING, TAPE_TOPIC, Tape, encode_entry};
use super::wrench_message::{WRIST_WRENCH_SCHEMA, WrenchWindows, WristWrench, wrist_wrench_schema};
use super::writer_thread::{Channel, Payload, WriterThread};
use crate::machine::Edge;
use crate::push_test::{PushEvidence, PushIntent, Verdict};
use crate::robot::Wrench;
use crate::state::State;

/// Topic names of a recording.
pub mod topics {
    /// Colour clouds (`foxglove.PointCloud`).
    pub const CLOUD: &str = "/camera/cloud";
    /// The obstacle-type grid (`foxglove.Grid`, uint8 field `class`).
    pub const GRID: &str = "/grid";
    /// Prisms (`foxglove.SceneUpdate`).
    pub const PRISMS: &str = "/perception/prisms";
    /// The planner's tree (`foxglove.SceneUpdate`).
    pub const TREE: &str = "/planner/tree";
    /// The planned path (`foxglove.SceneUpdate`).
    pub const PATH: &str = "/planner/path";
    /// Push direction and force arrows (`foxglove.SceneUpdate`).
    pub const PUSH: &str = "/push";
    /// Robot, head, camera and hand frames, those that moved since the last message (`foxglove.FrameTransforms`).
    pub const TF: &str = "/tf";
    /// Executive transitions, verdicts and notes (`foxglove.Log`).
    pub const LOG: &str = "/executive/log";
    /// Wrist wrench (protobuf `nudge.WristWrench`: force and torque, wrist frame, and the force's
    /// norm).
    pub const WRENCH: &str = "/wrist/wrench";
    /// The replay tape (`nudge.tape/2`, no schema): every adapter call and its result, in batches
    /// (see [`crate::record::tape`]).
    pub const TAPE: &str = super::TAPE_TOPIC;
}

/// Why recording failed.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    /// The file could not be created.
    #[error("cannot create recording {path}: {source}")]
    Create {
        /// The path.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The MCAP writer failed.
    #[error("recording failed: {0}")]
    Mcap(#[from] mcap::McapError),
    /// The writer thread could not be started, or stopped without a word.
    #[error("recording failed: {0}")]
    Writer(String),
    /// A message could not be encoded.
    #[error("cannot encode a {topic} message: {reason}")]
    Encode {
        /// The topic.
        topic: &'static str,
        /// The encoder's error.
        reason: String,
    },
}

/// What a recording says about its run (written as MCAP metadata and an attachment).
#[derive(Clone, Debug, PartialEq)]
pub struct RunInfo {
    /// Scenario name.
    pub scenario: String,
    /// Seed of the run.
    pub seed: u64,
    /// nudge version.
    pub version: String,
    /// Candidate policy.
    pub policy: String,
    /// The scenario file's name and text, attached to the recording.
    pub scenario_file: Option<(String, String)>,
}

/// An [`Observer`] that writes an MCAP file.
pub struct McapRecorder<W: Write + Seek + Send + 'static = BufWriter<File>> {
    writer: Option<WriterThread<W>>,
    /// Topics whose channel the writer has been given.
    announced: BTreeSet<&'static str>,
    sequence: u32,
    error: Option<RecordError>,
    tape: Option<Tape>,
    /// The wrist's samples waiting to be written as one viewing window.
    wrench_windows: WrenchWindows,
    /// The image stride of the clouds written for viewing ([`McapRecorder::set_cloud_stride`]).
    cloud_stride: usize,
    /// The frames last written to [`topics::TF`]: base, head, camera, hand.
    last_frames: [Option<Isometry3<f64>>; 4],
}

/// The fewest entries of tape a message holds before the recording's end: a message per tick
/// (3,900 in the paper's run) cost a record header and an index entry each, and split what the
/// compression could match; 512 make about fifty.
pub const TAPE_BATCH: usize = 512;

/// The range at which a recording's view of the clouds keeps a point per grid cell (m): the middle
/// half of a look-around's returns in the paper's room lie within 1.5–2.6 m of the camera.
const VIEW_RANGE: f64 = 2.0;

/// The image stride of the clouds a recording shows ([`topics::CLOUD`]) for `camera` and a grid of
/// `cell` m: the largest whose points still stand no farther apart than a cell at [`VIEW_RANGE`],
/// so the view shows every cell a look filled. For the SR-4000's 0.25° pixels and 5 cm cells that
/// is every fifth pixel of every fifth row, a twenty-fifth of the points: at full resolution the
/// clouds were two thirds of a recording. The replay tape keeps every point the executive consumed.
pub fn view_cloud_stride(camera: &CameraModel, cell: f64) -> usize {
    let pitch = camera.h_fov() / camera.width.max(1) as f64;
    let stride = (cell / (VIEW_RANGE * pitch)).floor();
    if stride.is_finite() && stride >= 1.0 {
        stride.min(64.0) as usize
    } else {
        1
    }
}

impl McapRecorder<BufWriter<File>> {
    /// Creates `path` and starts recording into it.
    pub fn create(path: &Path, info: &RunInfo) -> Result<Self, RecordError> {
        let file = File::create(path).map_err(|source| RecordError::Create {
            path: path.to_path_buf(),
            source,
        })?;
        Self::new(BufWriter::new(file), info)
    }
}

impl<W: Write + Seek + Send + 'static> McapRecorder<W> {
    /// Starts recording into `sink`, writing the run's metadata and the scenario attachment first.
    pub fn new(sink: W, info: &RunInfo) -> Result<Self, RecordError> {
        let mut writer = mcap::WriteOptions::new()
            .compression(Some(mcap::Compression::Zstd))
            // Level 1 halves the recorder's CPU cost against the default (3) for 0.5 % more bytes:
            // point clouds barely compress further.
            .compression_level(1)
            // One compressing thread, the writer's own: zstd's workers (one per core by default)
            // would compete with the run for the cores it is using.
            .compression_threads(0)
            .profile("")
            .create(sink)?;
        let mut metadata = BTreeMap::new();
        metadata.insert("scenario".to_string(), info.scenario.clone());
        metadata.insert("seed".to_string(), info.seed.to_string());
        metadata.insert("version".to_string(), info.version.clone());
        metadata.insert("policy".to_string(), info.policy.clone());
        writer.write_metadata(&Metadata {
            name: RUN_METADATA.into(),
            metadata,
        })?;
        if let Some((name, text)) = &info.scenario_file {
            writer.attach(&mcap::Attachment {
                log_time: 0,
                create_time: 0,
                name: name.clone(),
                media_type: "application/toml".into(),
                data: std::borrow::Cow::Borrowed(text.as_bytes()),
            })?;
        }
        Ok(Self {
            writer: Some(WriterThread::spawn(writer)?),
            announced: BTreeSet::new(),
            sequence: 0,
            error: None,
            tape: None,
            wrench_windows: WrenchWindows::default(),
            cloud_stride: 1,
            last_frames: [None; 4],
        })
    }

    /// Starts recording a replay tape: wrap the robot in a [`super::tape::Taped`] writing onto the
    /// tape returned. The recorder puts the executive's transitions on it and writes what waits on
    /// it to [`topics::TAPE`] in messages of at least [`TAPE_BATCH`] entries, before its summary, and
    /// when it is finished or dropped. The robot's `camera` lets the tape store a cloud's points as
    /// range counts along its pixel rays ([`Tape::for_camera`]).
    pub fn start_tape(&mut self, camera: &CameraModel) -> Tape {
        let tape = Tape::for_camera(camera);
        self.tape = Some(tape.clone());
        tape
    }

    /// Shows every `stride`-th pixel of every `stride`-th row of the clouds written for viewing
    /// from now on (1, the default: every pixel; [`view_cloud_stride`] gives one for viewing).
    pub fn set_cloud_stride(&mut self, stride: usize) {
        self.cloud_stride = stride.max(1);
    }

    /// Writes the tape's waiting entries as one message, stamped with the robot time they began at,
    /// once at least `min_entries` wait.
    fn drain_tape(&mut self, min_entries: usize) {
        let Some((stamp, entries, camera)) =
            self.tape.as_ref().and_then(|t| t.take_entries(min_entries))
        else {
            return;
        };
        // Encoded in the writer thread, beside the run.
        let encode = move || {
            let mut bytes = Vec::new();
            for entry in &entries {
                encode_entry(entry, &mut bytes, camera.as_deref());
            }
            bytes
        };
        let channel = || Channel {
            schema_name: String::new(),
            schema_encoding: String::new(),
            schema: Vec::new(),
            message_encoding: TAPE_ENCODING.into(),
        };
        self.write_raw(
            topics::TAPE,
            stamp,
            channel,
            Payload::Deferred(Box::new(encode)),
        );
    }

    /// Writes one viewing window of the wrist's samples.
    fn write_wrench(&mut self, stamp: f64, message: &WristWrench) {
        let channel = || Channel {
            schema_name: WRIST_WRENCH_SCHEMA.into(),
            schema_encoding: "protobuf".into(),
            schema: wrist_wrench_schema(),
            message_encoding: "protobuf".into(),
        };
        self.write_raw(topics::WRENCH, stamp, channel, message.encode_to_vec());
    }

    /// Writes what waits: the tape's entries and the open wrench window.
    fn flush(&mut self) {
        self.drain_tape(1);
        if let Some((stamp, message)) = self.wrench_windows.close() {
            self.write_wrench(stamp, &message);
        }
    }

    /// The first error met while encoding, if any (recording stopped there). An error of the
    /// writer thread (an I/O error) comes from [`McapRecorder::finish`].
    pub fn error(&self) -> Option<&RecordError> {
        self.error.as_ref()
    }

    /// Writes the run's summary: a last `foxglove.Log` line on [`topics::LOG`] (name
    /// [`RUN_SUMMARY_LOG`]) at `stamp`, and a metadata record named [`SUMMARY_METADATA`].
    /// Call it once, after the run and before [`McapRecorder::finish`].
    pub fn write_summary(&mut self, stamp: f64, summary: &RunSummary) {
        self.flush();
        self.log(stamp, Level::Info, RUN_SUMMARY_LOG, summary.line());
        let metadata = Metadata {
            name: SUMMARY_METADATA.into(),
            metadata: summary.entries(),
        };
        if let Some(writer) = self.writer.as_mut() {
            writer.metadata(metadata);
        }
    }

    /// Writes the summary section and footer and returns the sink (once the writer thread has
    /// written everything), or the first error met while recording.
    pub fn finish(mut self) -> Result<W, RecordError> {
        self.flush();
        let writer = self.writer.take();
        if let Some(e) = self.error.take() {
            // Dropping the writer finishes what it holds.
            drop(writer);
            return Err(e);
        }
        let mut writer = writer.ok_or(RecordError::Encode {
            topic: "",
            reason: "recorder already finished".into(),
        })?;
        writer.finish()
    }

    /// Writes a Foxglove message, registering its schema and channel on first use.
    fn write<M: Encode>(&mut self, topic: &'static str, stamp: f64, message: &M) {
        let mut data = Vec::with_capacity(message.encoded_len().unwrap_or(256));
        if let Err(e) = message.encode(&mut data) {
            self.fail(RecordError::Encode {
                topic,
                reason: e.to_string(),
            });
            return;
        }
        let channel = || {
            let (schema_name, schema_encoding, schema) = M::get_schema()
                .map(|s| (s.name, s.encoding, s.data.into_owned()))
                .unwrap_or_default();
            Channel {
                schema_name,
                schema_encoding,
                schema,
                message_encoding: M::get_message_encoding(),
            }
        };
        self.write_raw(topic, stamp, channel, data);
    }

    /// Hands a message to the writer, with its channel (made by `channel`) on the topic's first.
    fn write_raw(
        &mut self,
        topic: &'static str,
        stamp: f64,
        channel: impl FnOnce() -> Channel,
        data: impl Into<Payload>,
    ) {
        let Some(writer) = self.writer.as_mut() else {
            return;
        };
        let channel = self.announced.insert(topic).then(channel);
        let time = messages::nanos(stamp);
        let header = MessageHeader {
            // The writer thread puts in the channel's id.
            channel_id: 0,
            sequence: self.sequence,
            log_time: time,
            publish_time: time,
        };
        self.sequence = self.sequence.wrapping_add(1);
        writer.message(topic, channel, header, data.into());
    }

    /// Keeps the first error and stops recording, finishing what was written so far.
    fn fail(&mut self, error: RecordError) {
        if self.error.is_none() {
            self.error = Some(error);
        }
        // Dropping the writer finishes the file.
        self.writer = None;
    }

    fn log(&mut self, stamp: f64, level: Level, name: &str, text: String) {
        let message = Log {
            timestamp: Some(messages::timestamp(stamp)),
            level: level as i32,
            message: text,
            name: name.into(),
            file: String::new(),
            line: 0,
        };
        self.write(topics::LOG, stamp, &message);
    }
}

/// A recorder dropped without [`McapRecorder::finish`] (a failed or cancelled run) still writes
/// what waits on its tape; the writer then finishes the file as it drops.
impl<W: Write + Seek + Send + 'static> Drop for McapRecorder<W> {
    fn drop(&mut self) {
        self.flush();
    }
}

impl<W: Write + Seek + Send + 'static> Observer for McapRecorder<W> {
    fn transition(&mut self, stamp: f64, from: Option<&State>, edge: Edge, to: &State) {
        if let Some(tape) = &mut self.tape {
            tape.transition(stamp, from, edge, to);
        }
        self.drain_tape(TAPE_BATCH);
        let from = from.map_or("(start)", State::name);
        let text = format!("{from} -> {} ({edge:?})", to.name());
        self.log(stamp, Level::Info, "executive", text);
    }

    fn verdict(
        &mut self,
        stamp: f64,
        object: ObjectId,
        verdict: &Verdict,
        evidence: &PushEvidence,
    ) {
        let icp = evidence.icp.map_or_else(
            || "n/a".to_string(),
            |i| format!("{:.1} mm", i.displacement * 1e3),
        );
        let text = format!(
            "{object}: {verdict:?} (peak {:.1} N of {:.0} N limit, ICP {icp}, hand {:.1} mm after contact)",
            evidence.peak_force,
            evidence.force_limit,
            evidence.hand_travel * 1e3
        );
        self.log(stamp, Level::Info, "verdict", text);
    }

    fn cloud(&mut self, cloud: &ColourCloud) {
        self.drain_tape(TAPE_BATCH);
        let message = messages::point_cloud(cloud, self.cloud_stride);
        self.write(topics::CLOUD, cloud.stamp(), &message);
    }

    fn prisms(&mut self, stamp: f64, prisms: &[Prism]) {
        self.write(topics::PRISMS, stamp, &messages::prisms(stamp, prisms));
    }

    fn grid(&mut self, stamp: f64, grid: &GridView<'_>) {
        self.write(topics::GRID, stamp, &messages::grid(stamp, grid));
    }

    fn tree(&mut self, stamp: f64, edges: &[[Point2<f64>; 2]]) {
        let points: Vec<Point2<f64>> = edges.iter().flatten().copied().collect();
        let update = messages::lines(stamp, "tree", &points, true, [0.5, 0.5, 0.5, 0.6]);
        self.write(topics::TREE, stamp, &update);
    }

    fn path(&mut self, stamp: f64, waypoints: &[Point2<f64>]) {
        let update = messages::lines(stamp, "path", waypoints, false, [0.1, 0.8, 0.2, 1.0]);
        self.write(topics::PATH, stamp, &update);
    }

    fn push(&mut self, stamp: f64, intent: &PushIntent, force: Option<Vector2<f64>>) {
        self.write(topics::PUSH, stamp, &messages::push(stamp, intent, force));
    }

    fn frames(&mut self, stamp: f64, frames: &RobotFrames) {
        self.drain_tape(TAPE_BATCH);
        let b = frames.base;
        let base = Isometry3::from_parts(
            Translation3::new(b.translation.x, b.translation.y, 0.0),
            UnitQuaternion::from_euler_angles(0.0, 0.0, b.rotation.angle()),
        );
        let head = Isometry3::from_parts(
            Translation3::identity(),
            UnitQuaternion::from_euler_angles(0.0, frames.head.1, frames.head.0),
        );
        let hand = Isometry3::from_parts(
            Translation3::from(frames.hand.coords),
            UnitQuaternion::identity(),
        );
        // One message of the frames that moved since the last: a viewer holds a frame until it
        // is updated, and a still hand or head costs nothing.
        let mut moved = Vec::with_capacity(4);
        for (k, (parent, child, iso)) in [
            ("map", "base_link", base),
            ("base_link", "head", head),
            ("map", "camera", frames.camera),
            ("base_link", "hand", hand),
        ]
        .into_iter()
        .enumerate()
        {
            if self.last_frames[k] != Some(iso) {
                self.last_frames[k] = Some(iso);
                moved.push(messages::frame(stamp, parent, child, &iso));
            }
        }
        if !moved.is_empty() {
            let message = FrameTransforms { transforms: moved };
            self.write(topics::TF, stamp, &message);
        }
    }

    fn wrench(&mut self, stamp: f64, wrench: &Wrench) {
        if let Some((stamp, message)) = self.wrench_windows.push(stamp, wrench) {
            self.write_wrench(stamp, &message);
        }
    }

    fn note(&mut self, stamp: f64, level: LogLevel, text: &str) {
        let level = match level {
            LogLevel::Info => Level::Info,
            LogLevel::Warning => Level::Warning,
            LogLevel::Error => Level::Error,
        };
        self.log(stamp, level, "note", text.to_string());
    }
}
