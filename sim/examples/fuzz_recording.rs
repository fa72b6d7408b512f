//! A seeded, in-process mutation fuzzer for the recording reader (`read_recording`: our own MCAP
//! record reader, then the replay tape's decoder) that `nudge replay` and `nudge inspect` stand on.
//!
//! The corpus is three small recordings made here with the tape's own encoder: a tape of calls
//! (every kind of reply but the hand's status, errors among them, a small cloud) and transitions, the run's metadata, a
//! scenario attachment and a summary, written with chunks and zstd, with chunks uncompressed, and
//! without chunks. Every input is one of them mangled by a few mutations: bits flipped, spans deleted,
//! duplicated or overwritten with random bytes, a length-sized field set to a hostile value (zero,
//! one, the most a `u32` or `u64` holds, an exabyte), the file cut short. Each input must read as
//! `Ok` or fail with an error; a panic or an input slower than `--slow-ms` is written to `--out` and
//! counted, and the harness exits non-zero when any was found.
//!
//! ```text
//! cargo run --release -p nudge-sim --example fuzz_recording -- --inputs 1000000 --seed 1
//! ```

use std::collections::BTreeMap;
use std::io::Cursor;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use nalgebra::{Isometry2, Isometry3, Point2, Point3, Vector3};
use nudge_executive::record::tape::{
    Entry, Reply, Request, TAPE_ENCODING, TAPE_TOPIC, Transition, encode_entry, read_recording,
};
use nudge_executive::record::{RUN_METADATA, SUMMARY_METADATA};
use nudge_executive::robot::{ActionStatus, RobotError, Stamped, WalkOutcome, Wrench};
use nudge_perception::{CloudFrame, ColourCloud};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[path = "fuzz_common/mod.rs"]
mod fuzz_common;
use fuzz_common::Judged;

/// Command-line options.
#[derive(Parser, Debug)]
#[command(about = "Fuzz the recording reader with mutated MCAP recordings")]
struct Options {
    /// How many mutated inputs to try.
    #[arg(long, default_value_t = 100_000)]
    inputs: u64,
    /// Seed of the mutations: the same seed tries the same inputs.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Where inputs that panic or run slowly are written.
    #[arg(long, default_value = "target/fuzz-recording")]
    out: PathBuf,
    /// An input that takes longer than this (ms) to read counts as a hang.
    #[arg(long, default_value_t = 1000)]
    slow_ms: u64,
}

/// Values a length, count, offset or size field is set to: the edges of every width such a field
/// has in MCAP and on the tape.
const HOSTILE: [u64; 8] = [
    0,
    1,
    0xff,
    0xffff,
    u32::MAX as u64,
    1 << 60,
    i64::MAX as u64,
    u64::MAX,
];

fn main() -> ExitCode {
    let options = Options::parse();
    let corpus = match corpus() {
        Ok(corpus) => corpus,
        Err(e) => {
            eprintln!("fuzz_recording: could not write the corpus: {e}");
            return ExitCode::FAILURE;
        }
    };
    // Every corpus file must read: a mutation of a file the reader refuses proves little.
    for (i, file) in corpus.iter().enumerate() {
        if let Err(e) = read_recording(file) {
            eprintln!("fuzz_recording: corpus file {i} does not read: {e}");
            return ExitCode::FAILURE;
        }
    }
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    let tally = fuzz_common::drive(
        options.inputs,
        Duration::from_millis(options.slow_ms),
        |_| mutate(&corpus, &mut rng),
        |_, bytes| match fuzz_common::caught(|| read_recording(bytes).is_ok()) {
            Ok(true) => Judged::Accepted,
            Ok(false) => Judged::Refused,
            Err(why) => Judged::Finding(format!("panic: {why}")),
        },
        |i, bytes, why| {
            if let Err(e) = save(&options.out, i, bytes, why) {
                eprintln!("fuzz_recording: could not save input {i}: {e}");
            }
        },
    );
    tally.print(options.inputs, options.seed, "read", "refused");
    tally.exit_code()
}

/// The tape every corpus file holds: one call of each kind of reply but the hand's status (errors
/// among them, a cloud of a few points) and two transitions.
fn tape() -> Vec<Entry> {
    let error = RobotError::Unavailable {
        capability: "camera",
        reason: "driver down".into(),
    };
    let mut cloud = ColourCloud::empty(
        CloudFrame::Sensor,
        Isometry3::translation(0.0, 0.0, 1.2),
        2.0,
    );
    for k in 0..12u8 {
        let v = f32::from(k) * 0.1;
        cloud.push(Point3::new(1.0 + v, v - 0.5, -1.2 + v), [k, 2 * k, 3 * k]);
    }
    let wrench = |stamp: f64, fx: f64| Stamped {
        stamp,
        value: Wrench {
            force: Vector3::new(fx, 0.5, -2.0),
            torque: Vector3::new(0.0, 0.1, 0.0),
        },
    };
    let transition = |from: &str, edge: &str, to: &str| {
        Entry::Transition(Transition {
            from: from.into(),
            edge: edge.into(),
            to: to.into(),
        })
    };
    vec![
        transition("(start)", "Start", "LookAround"),
        Entry::Call(Request::Now, Reply::Time(0.0)),
        Entry::Call(Request::Advance(0.05), Reply::Done(Ok(()))),
        Entry::Call(
            Request::BasePose,
            Reply::Pose(Ok(Stamped {
                stamp: 0.05,
                value: Isometry2::new(nalgebra::Vector2::new(1.0, 2.0), 0.3),
            })),
        ),
        Entry::Call(
            Request::StartWalk(vec![Point2::new(1.0, 2.0), Point2::new(3.0, 2.5)]),
            Reply::Done(Ok(())),
        ),
        Entry::Call(
            Request::WalkStatus,
            Reply::Walk(Ok(ActionStatus::Done(WalkOutcome::Arrived))),
        ),
        Entry::Call(Request::StartPointHead(0.4, 0.2), Reply::Done(Ok(()))),
        Entry::Call(
            Request::HeadAngles,
            Reply::Angles(Ok(Stamped {
                stamp: 1.0,
                value: (0.4, 0.2),
            })),
        ),
        Entry::Call(Request::HeadStatus, Reply::Head(Ok(ActionStatus::Running))),
        Entry::Call(Request::Capture, Reply::Cloud(Ok(cloud))),
        Entry::Call(Request::Capture, Reply::Cloud(Err(error.clone()))),
        Entry::Call(Request::Tare, Reply::Done(Ok(()))),
        Entry::Call(Request::Wrench, Reply::Wrench(Ok(wrench(2.0, 4.0)))),
        Entry::Call(
            Request::DrainWrenches,
            Reply::Wrenches(Ok(vec![wrench(2.001, 5.0), wrench(2.002, 6.5)])),
        ),
        Entry::Call(
            Request::HandPosition,
            Reply::Hand(Ok(Stamped {
                stamp: 2.0,
                value: Point3::new(0.5, 0.0, 0.7),
            })),
        ),
        Entry::Call(Request::StopHand, Reply::Done(Err(error))),
        transition("LookAround", "LookAroundDone", "DetectObjects"),
    ]
}

/// How a corpus file is laid out.
#[derive(Clone, Copy)]
enum Layout {
    /// Chunks compressed with zstd, as the recorder writes.
    Zstd,
    /// Chunks, uncompressed: mutations reach the records inside them.
    Plain,
    /// No chunks: every record at the top level.
    Unchunked,
}

/// The three corpus files: [`tape`] in two messages, with the run's metadata, the scenario
/// attachment and the summary, in each [`Layout`].
fn corpus() -> mcap::McapResult<Vec<Vec<u8>>> {
    let entries = tape();
    let (first, second) = entries.split_at(entries.len() / 2);
    let batch = |part: &[Entry]| {
        let mut out = Vec::new();
        for entry in part {
            encode_entry(entry, &mut out, None);
        }
        out
    };
    let messages = [batch(first), batch(second)];
    [Layout::Zstd, Layout::Plain, Layout::Unchunked]
        .into_iter()
        .map(|layout| recording(layout, &messages))
        .collect()
}

/// One recording holding `messages` on the tape channel, laid out as `layout`.
fn recording(layout: Layout, messages: &[Vec<u8>]) -> mcap::McapResult<Vec<u8>> {
    let options = mcap::WriteOptions::new().profile("");
    let options = match layout {
        Layout::Zstd => options.compression(Some(mcap::Compression::Zstd)),
        Layout::Plain => options.compression(None),
        Layout::Unchunked => options.compression(None).use_chunks(false),
    };
    let mut writer = options.create(Cursor::new(Vec::new()))?;
    let run: BTreeMap<String, String> = [
        ("scenario", "fuzz"),
        ("seed", "1"),
        ("version", "0"),
        ("policy", "nearest"),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_owned(), v.to_owned()))
    .collect();
    writer.write_metadata(&mcap::records::Metadata {
        name: RUN_METADATA.into(),
        metadata: run,
    })?;
    writer.attach(&mcap::Attachment {
        log_time: 0,
        create_time: 0,
        name: "fuzz.toml".into(),
        media_type: "application/toml".into(),
        data: std::borrow::Cow::Borrowed(b"name = \"fuzz\"\n"),
    })?;
    let channel = writer.add_channel(0, TAPE_TOPIC, TAPE_ENCODING, &BTreeMap::new())?;
    for (i, data) in messages.iter().enumerate() {
        writer.write_to_known_channel(
            &mcap::records::MessageHeader {
                channel_id: channel,
                sequence: i as u32,
                log_time: i as u64 * 1_000_000_000,
                publish_time: i as u64 * 1_000_000_000,
            },
            data,
        )?;
    }
    writer.write_metadata(&mcap::records::Metadata {
        name: SUMMARY_METADATA.into(),
        metadata: [("outcome".to_owned(), "Goal".to_owned())].into(),
    })?;
    writer.finish()?;
    Ok(writer.into_inner().into_inner())
}

/// One corpus file with one to four mutations.
fn mutate(corpus: &[Vec<u8>], rng: &mut ChaCha8Rng) -> Vec<u8> {
    let mut bytes = corpus[rng.random_range(0..corpus.len())].clone();
    for _ in 0..rng.random_range(1..=4) {
        let len = bytes.len();
        let at = rng.random_range(0..=len);
        let span = rng.random_range(0..=16.min(len - at));
        match rng.random_range(0..8) {
            0 | 1 if len > 0 => {
                let i = rng.random_range(0..len);
                bytes[i] ^= 1 << rng.random_range(0..8);
            }
            2 => {
                bytes.drain(at..at + span);
            }
            3 => {
                let copy = bytes[at..at + span].to_vec();
                bytes.splice(at..at, copy);
            }
            4 => {
                let noise: Vec<u8> = (0..span).map(|_| rng.random()).collect();
                bytes.splice(at..at + span, noise);
            }
            5 | 6 => set_a_field(&mut bytes, rng),
            _ => bytes.truncate(at),
        }
    }
    bytes
}

/// Overwrites 1, 2, 4 or 8 bytes somewhere with a [`HOSTILE`] value, little-endian as MCAP's and
/// the tape's integers are.
fn set_a_field(bytes: &mut [u8], rng: &mut ChaCha8Rng) {
    let width = [1usize, 2, 4, 8][rng.random_range(0..4)];
    if bytes.len() < width {
        return;
    }
    let at = rng.random_range(0..=bytes.len() - width);
    let value = HOSTILE[rng.random_range(0..HOSTILE.len())].to_le_bytes();
    bytes[at..at + width].copy_from_slice(&value[..width]);
}

/// Writes a finding's input as it was to `out/input-N.mcap`, and why it is one to `input-N.txt`.
fn save(out: &Path, index: u64, bytes: &[u8], why: &str) -> std::io::Result<()> {
    std::fs::create_dir_all(out)?;
    std::fs::write(out.join(format!("input-{index}.mcap")), bytes)?;
    std::fs::write(out.join(format!("input-{index}.txt")), why)
}
