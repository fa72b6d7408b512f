//! The `nudge` binary's recordings: one recording of the paper's room shared by several checks, read
//! back with the `mcap` crate, the official Python `mcap` package and `nudge inspect`; determinism; a
//! run interrupted by SIGINT; the `--map` picture.

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::OnceLock;

use nudge_executive::record::{RUN_METADATA, SUMMARY_METADATA, TAPE_TOPIC, WristWrench, topics};
use prost::Message as _;

#[path = "../../tests/python/python_env.rs"]
mod python_env;

const NUDGE: &str = env!("CARGO_BIN_EXE_nudge");

fn scratch(name: &str) -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("recording-{name}"))
}

fn nudge(args: &[&str]) -> Output {
    Command::new(NUDGE)
        .args(args)
        .output()
        .expect("the nudge binary starts")
}

/// The shared run: `nudge run --record --map` on the paper's room.
struct Recording {
    mcap: PathBuf,
    png: PathBuf,
    stdout: String,
}

fn recording() -> &'static Recording {
    static RUN: OnceLock<Recording> = OnceLock::new();
    RUN.get_or_init(|| {
        let (mcap, png) = (scratch("room.mcap"), scratch("room.png"));
        let out = nudge(&[
            "run",
            "--quiet",
            "--record",
            mcap.to_str().expect("utf-8 path"),
            "--map",
            png.to_str().expect("utf-8 path"),
        ]);
        let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
        assert!(
            out.status.success(),
            "nudge run failed: {stdout}\n{}",
            String::from_utf8_lossy(&out.stderr)
        );
        Recording { mcap, png, stdout }
    })
}

/// Everything the mcap crate reads from a file.
struct Read {
    counts: BTreeMap<String, u64>,
    schemas: BTreeMap<String, String>,
    /// Log times per topic, in file order.
    times: BTreeMap<String, Vec<u64>>,
    metadata: BTreeMap<String, BTreeMap<String, String>>,
    attachments: BTreeMap<String, Vec<u8>>,
    logs: Vec<Vec<u8>>,
    /// Message encoding per topic.
    encodings: BTreeMap<String, String>,
    /// The wrist wrench's largest force norm, decoded with the crate's own message type.
    wrench_peak: f64,
}

fn read(path: &Path) -> Read {
    let bytes = std::fs::read(path).expect("recording exists");
    let summary = mcap::read::Summary::read(&bytes)
        .expect("summary section parses")
        .expect("the file has a summary section");
    let mut r = Read {
        counts: BTreeMap::new(),
        schemas: BTreeMap::new(),
        times: BTreeMap::new(),
        metadata: BTreeMap::new(),
        attachments: BTreeMap::new(),
        logs: Vec::new(),
        encodings: BTreeMap::new(),
        wrench_peak: 0.0,
    };
    for message in mcap::MessageStream::new(&bytes).expect("starts with MCAP magic") {
        let message = message.expect("every message reads");
        let topic = message.channel.topic.clone();
        *r.counts.entry(topic.clone()).or_default() += 1;
        let schema = message.channel.schema.as_ref().map(|s| s.name.clone());
        r.schemas.insert(topic.clone(), schema.unwrap_or_default());
        r.times
            .entry(topic.clone())
            .or_default()
            .push(message.log_time);
        r.encodings
            .insert(topic.clone(), message.channel.message_encoding.clone());
        if topic == topics::WRENCH {
            let w = WristWrench::decode(message.data.as_ref()).expect("a nudge.WristWrench");
            r.wrench_peak = r.wrench_peak.max(w.force_norm).max(w.peak_force_norm);
        }
        if topic == topics::LOG {
            r.logs.push(message.data.into_owned());
        }
    }
    for index in &summary.metadata_indexes {
        let m = mcap::read::metadata(&bytes, index).expect("metadata reads");
        r.metadata.insert(m.name, m.metadata);
    }
    for index in &summary.attachment_indexes {
        let a = mcap::read::attachment(&bytes, index).expect("attachment reads");
        r.attachments.insert(a.name, a.data.into_owned());
    }
    let stats = summary.stats.expect("statistics record");
    assert_eq!(stats.message_count, r.counts.values().sum::<u64>());
    r
}

fn robot_time_ns(r: &Read) -> u64 {
    let s: f64 = r.metadata[SUMMARY_METADATA]["robot_time_s"]
        .parse()
        .expect("robot time is a number");
    (s * 1e9).round() as u64
}

#[test]
fn a_recording_of_the_papers_room_has_every_topic_with_plausible_counts() {
    // Invariant: every topic the recorder writes is present with its Foxglove schema and counts that fit the run's own summary.
    let r = read(&recording().mcap);
    let expected = [
        (topics::CLOUD, "foxglove.PointCloud"),
        (topics::GRID, "foxglove.Grid"),
        (topics::TREE, "foxglove.SceneUpdate"),
        (topics::PRISMS, "foxglove.SceneUpdate"),
        (topics::PATH, "foxglove.SceneUpdate"),
        (topics::PUSH, "foxglove.SceneUpdate"),
        (topics::TF, "foxglove.FrameTransforms"),
        (topics::LOG, "foxglove.Log"),
        (topics::WRENCH, "nudge.WristWrench"),
    ];
    for (topic, schema) in expected {
        assert!(
            r.counts.get(topic).is_some_and(|&n| n > 0),
            "{topic} missing: {:?}",
            r.counts
        );
        assert_eq!(r.schemas[topic], schema, "{topic}");
    }
    let summary = &r.metadata[SUMMARY_METADATA];
    assert_eq!(summary["outcome"], "Goal");
    let tests: u64 = summary["push_tests"].parse().expect("a count");
    assert!(
        tests >= 2,
        "the paper's room needs the table and a chair tested"
    );
    let robot_time = robot_time_ns(&r) as f64 * 1e-9;
    let n = |topic: &str| r.counts[topic];
    // Three look-arounds (one cloud at least each) and a cloud before and after every push test.
    assert!(
        n(topics::CLOUD) >= 3 + 2 * tests,
        "{} clouds",
        n(topics::CLOUD)
    );
    assert!(
        n(topics::PRISMS) >= 2,
        "detection before and after the clearing push"
    );
    assert!(n(topics::PATH) >= 1);
    // The grid changes at least once per look-around; every path found comes with its search tree.
    assert!(n(topics::GRID) >= 3, "{} grids", n(topics::GRID));
    assert!(n(topics::TREE) >= 1, "no search tree");
    // Each push is announced when planned and drawn again with its force when done.
    assert!(
        n(topics::PUSH) >= 2 * tests,
        "{} push updates",
        n(topics::PUSH)
    );
    // The frames that moved, at 10 Hz or more over the whole run: the robot walks, looks or
    // pushes nearly all of it.
    assert!(
        n(topics::TF) as f64 >= 10.0 * robot_time * 0.9,
        "{} tf",
        n(topics::TF)
    );
    // A 10 ms window of the wrist at least every tenth of a second of a push test (each lasts
    // seconds).
    assert!(
        n(topics::WRENCH) >= 10 * tests,
        "{} wrenches",
        n(topics::WRENCH)
    );
    assert!(
        n(topics::LOG) >= 10,
        "transitions, verdicts and the summary"
    );
}

#[test]
fn a_recording_is_stamped_with_robot_time_and_describes_its_run() {
    // Invariant: log times run from 0 to the run's robot time, never backwards on a topic; metadata and the scenario attachment describe the run; the first log line is the Start edge out of no state, the summary line is logged last.
    let r = read(&recording().mcap);
    let end = robot_time_ns(&r);
    assert!(
        end > 10_000_000_000,
        "a run of the room takes minutes of robot time"
    );
    for (topic, times) in &r.times {
        assert!(
            times.windows(2).all(|w| w[0] <= w[1]),
            "{topic} goes back in time"
        );
        assert!(
            times.iter().all(|&t| t <= end),
            "{topic} is stamped after the run's end"
        );
    }
    let last = r.times.values().filter_map(|t| t.last()).max();
    assert_eq!(last, Some(&end), "the summary is stamped at the run's end");
    let first = r.times.values().filter_map(|t| t.first()).min();
    assert!(
        first.is_some_and(|&t| t < 1_000_000_000),
        "the run starts at robot time 0"
    );
    let run = &r.metadata[RUN_METADATA];
    assert_eq!(run["scenario"], "kakiuchi-room");
    assert_eq!(run["seed"], "1");
    assert_eq!(run["policy"], "nearest");
    assert_eq!(
        r.attachments["kakiuchi-room.toml"],
        nudge_sim::scenario::DEFAULT_ROOM_TOML.as_bytes()
    );
    let first_log = r.logs.first().expect("log messages");
    let needle = b"(start) -> LookAround (Start)";
    assert!(
        first_log.windows(needle.len()).any(|w| w == needle),
        "the first log line is the Start edge, which leaves no state: {}",
        String::from_utf8_lossy(first_log)
    );
    let last_log = r.logs.last().expect("log messages");
    let needle = b"run ended: Goal";
    assert!(
        last_log.windows(needle.len()).any(|w| w == needle),
        "the last log line is the summary"
    );
}

#[test]
fn two_recordings_of_the_same_scenario_and_seed_are_identical() {
    // Invariant: the same scenario and seed give the same recording byte for byte (nothing from the wall clock).
    let again = scratch("room-again.mcap");
    let out = nudge(&["run", "--quiet", "--record", again.to_str().expect("utf-8")]);
    assert!(out.status.success());
    let (a, b) = (
        std::fs::read(&recording().mcap).expect("first recording"),
        std::fs::read(&again).expect("second recording"),
    );
    assert_eq!(a.len(), b.len(), "recordings differ in length");
    assert!(a == b, "recordings differ");
}

#[test]
fn nudge_inspect_reports_the_counts_the_mcap_crate_reads() {
    // Invariant: `nudge inspect` lists every topic with the message count the mcap crate counts, the robot-time span, the metadata, the attachment and the run's summary.
    let rec = recording();
    let r = read(&rec.mcap);
    let out = nudge(&["inspect", rec.mcap.to_str().expect("utf-8")]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    for (topic, count) in &r.counts {
        let line = text
            .lines()
            .find(|l| l.split_whitespace().next() == Some(topic.as_str()))
            .unwrap_or_else(|| panic!("{topic} not listed:\n{text}"));
        assert_eq!(
            line.split_whitespace().nth(1),
            Some(count.to_string().as_str()),
            "{line}"
        );
    }
    let end = robot_time_ns(&r) as f64 * 1e-9;
    assert!(text.contains(&format!("0.000 s .. {end:.3} s")), "{text}");
    for needle in [
        "complete",
        "kakiuchi-room.toml (application/toml",
        "run summary",
        "Goal",
        "seed         1",
    ] {
        assert!(text.contains(needle), "{needle:?} missing:\n{text}");
    }
}

#[test]
fn a_truncated_recording_is_reported_not_panicked_on() {
    // Invariant: `nudge inspect` on a recording cut in half prints what it could read and exits 1 naming the damage.
    let bytes = std::fs::read(&recording().mcap).expect("recording");
    let cut = scratch("cut.mcap");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).expect("write");
    let out = nudge(&["inspect", cut.to_str().expect("utf-8")]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("truncated or corrupt"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(String::from_utf8_lossy(&out.stdout).contains("BROKEN"));
}

#[test]
fn the_python_mcap_package_reads_the_recording() {
    // Invariant: the official Python reader sees the same topics, counts, time span, metadata and attachment as the mcap crate, and its protobuf decoders decode every protobuf message of every topic (the wrench's peak the same as the crate's own decoding).
    let rec = recording();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/python/read_mcap.py");
    let python = python_env::python();
    let out = Command::new(&python)
        .arg(&script)
        .arg(&rec.mcap)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {}: {e}", python.display()));
    assert!(
        out.status.success(),
        "the python reader failed (exit 3: mcap not importable in {}): {}",
        python.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    let py: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON from python");
    let r = read(&rec.mcap);
    for (topic, count) in &r.counts {
        assert_eq!(py["counts"][topic].as_u64(), Some(*count), "{topic}");
        assert_eq!(
            py["schemas"][topic].as_str(),
            Some(r.schemas[topic].as_str())
        );
    }
    assert_eq!(
        py["counts"].as_object().map(|o| o.len()),
        Some(r.counts.len())
    );
    // Every protobuf message of every topic decodes with the protobuf decoders (the tape is
    // nudge's own binary format, with no schema: `nudge replay` reads it).
    for (topic, encoding) in &r.encodings {
        let decoded = py["decoded"][topic].as_u64().unwrap_or(0);
        if encoding == "protobuf" {
            assert_eq!(decoded, r.counts[topic], "{topic} decoded");
        } else {
            assert_eq!(topic, TAPE_TOPIC, "{topic}: {encoding}");
        }
    }
    assert!(
        r.wrench_peak > 10.0,
        "the push tests press: {}",
        r.wrench_peak
    );
    assert_eq!(py["wrench_peak"].as_f64(), Some(r.wrench_peak));
    assert_eq!(py["end"].as_u64(), Some(robot_time_ns(&r)));
    assert_eq!(py["metadata"][RUN_METADATA]["scenario"], "kakiuchi-room");
    assert_eq!(py["metadata"][SUMMARY_METADATA]["outcome"], "Goal");
    assert_eq!(py["attachments"][0], "kakiuchi-room.toml");
}

#[test]
fn a_run_interrupted_by_sigint_leaves_a_complete_recording() {
    // Invariant: SIGINT mid-run aborts it (exit 4) and the recording is still complete and readable, with an Aborted summary.
    let path = scratch("interrupted.mcap");
    let mut child = Command::new(NUDGE)
        .args(["run", "--record", path.to_str().expect("utf-8")])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("nudge starts");
    let stdout = child.stdout.take().expect("piped stdout");
    let mut lines = BufReader::new(stdout).lines();
    // The first transition after the start (printed once the Ctrl-C handler is installed) comes at
    // the end of the first look-around.
    let mut seen = Vec::new();
    for line in lines.by_ref() {
        let line = line.expect("utf-8 output");
        let transition = line.contains(" -> ") && !line.contains("(start)");
        seen.push(line);
        if transition {
            break;
        }
    }
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(kill.success());
    seen.extend(lines.map_while(Result::ok));
    let status = child.wait().expect("nudge ends");
    let output = seen.join("\n");
    assert_eq!(status.code(), Some(4), "not aborted:\n{output}");
    assert!(output.contains("aborted: cancelled"), "{output}");
    let r = read(&path);
    assert_eq!(r.metadata[SUMMARY_METADATA]["outcome"], "Aborted");
    assert!(
        r.counts[topics::CLOUD] >= 1,
        "the first look-around is in the file"
    );
}

/// Rows at the top of the `--map` picture that hold the caption (its margin and text) and nothing
/// else.
const CAPTION_BAND: u32 = 50;

#[test]
fn the_map_shows_the_run_with_a_force_panel_per_push_test() {
    // Invariant: --map writes a PNG with the grid, the robot's track, a movable verdict's colour, the red force limit of the push-test panels, and text (the caption), whatever fonts the machine has.
    let rec = recording();
    assert!(
        rec.stdout.contains("push-test force panels"),
        "{}",
        rec.stdout
    );
    let image = image::open(&rec.png).expect("a PNG").to_rgb8();
    assert_eq!(image.width(), 1400);
    let has = |rgb: [u8; 3]| image.pixels().any(|p| p.0 == rgb);
    assert!(has([150, 20, 160]), "the track's purple");
    assert!(has([40, 90, 230]), "a movable verdict's blue");
    let unknown = image.pixels().filter(|p| p.0 == [215, 215, 215]).count();
    assert!(
        unknown > 10_000,
        "the grid's unknown cells are drawn ({unknown} px)"
    );
    assert!(has([255, 0, 0]), "the force limit's red");
    // The caption above the map is text, drawn with the font the binary carries: dark glyph pixels
    // in the band above the map, on any machine (without a font the band stays blank).
    let caption_ink = (0..image.width())
        .flat_map(|x| (0..CAPTION_BAND).map(move |y| (x, y)))
        .filter(|&(x, y)| image.get_pixel(x, y).0.iter().all(|&c| c < 90))
        .count();
    assert!(
        caption_ink > 300,
        "the caption's text is drawn ({caption_ink} dark px above the map)"
    );
    // The panels sit below the map: the bottom rows hold the force plots.
    let bottom = image.height() - 120;
    let red_low = (0..image.width())
        .any(|x| (bottom - 200..bottom).any(|y| image.get_pixel(x, y).0 == [255, 0, 0]));
    assert!(red_low, "a force panel's limit line below the map");
}
