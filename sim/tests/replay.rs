//! `nudge replay`: a recording of the paper's room replayed on the same build matches call for call;
//! with the push test's force limit changed it parts at the first push, at the recorded robot time;
//! bad files are errors naming the file, exit 1, never a panic.

use std::collections::BTreeMap;
use std::io::Cursor;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

use nudge_executive::record::TAPE_TOPIC;
use nudge_executive::record::tape::{Entry, Reply, Request, read_recording};
use nudge_sim::replay::{Setting, replay_file};

const NUDGE: &str = env!("CARGO_BIN_EXE_nudge");

fn scratch(name: &str) -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("replay-{name}"))
}

fn nudge(args: &[&str]) -> Output {
    Command::new(NUDGE)
        .args(args)
        .output()
        .expect("the nudge binary starts")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The shared recording: `nudge run --record` on the paper's room.
fn recording() -> &'static Path {
    static FILE: OnceLock<PathBuf> = OnceLock::new();
    FILE.get_or_init(|| {
        let path = scratch("room.mcap");
        let out = nudge(&["run", "--quiet", "--record", path.to_str().expect("utf-8")]);
        assert!(
            out.status.success(),
            "nudge run failed: {}",
            text(&out.stderr)
        );
        path
    })
}

#[test]
fn the_papers_room_replayed_on_the_same_build_matches_bit_for_bit() {
    // Invariant: replaying the recording of the paper's room consumes every tape entry with no divergence (every call's arguments equal bit for bit, every transition the same), ends in the recorded outcome with the recorded verdicts, and `nudge replay` says "match" and exits 0.
    let path = recording();
    let bytes = std::fs::read(path).expect("recording");
    let recorded = read_recording(&bytes).expect("the recording reads");
    let r = replay_file(path, &[]).expect("replays");
    assert!(r.divergence.is_none(), "{}", r.divergence.expect("some"));
    assert_eq!(r.calls + r.transitions, recorded.entries.len());
    let transitions = recorded
        .entries
        .iter()
        .filter(|e| matches!(e, Entry::Transition(_)))
        .count();
    assert_eq!(r.transitions, transitions);
    assert_eq!(r.transitions, r.report.timeline.len());
    let summary = recorded.summary.expect("a summary");
    assert_eq!(summary["outcome"], "Goal");
    assert_eq!(r.report.outcome.name(), "Goal");
    let verdicts: BTreeMap<String, String> = r
        .report
        .knowledge
        .explanation
        .verdicts
        .iter()
        .map(|(id, v)| (format!("verdict/{id}"), format!("{v:?}")))
        .collect();
    assert!(!verdicts.is_empty());
    for (k, v) in &verdicts {
        assert_eq!(summary.get(k), Some(v), "{k}");
    }
    let out = nudge(&["replay", path.to_str().expect("utf-8")]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}{}", text(&out.stderr));
    assert!(stdout.contains("match: "), "{stdout}");
    assert!(stdout.contains("same outcome"), "{stdout}");
}

#[test]
fn a_changed_force_limit_parts_at_the_first_push_at_its_recorded_robot_time() {
    // Invariant: with the push test's force limit changed, the replay reports its first divergence at the recording's first guarded move with the old limit (the first command that differs), at the robot time of the clock reading before it, in PushTest entered at or before that time in the recorded timeline; `nudge replay --set` exits 6 and prints both calls.
    let path = recording();
    let bytes = std::fs::read(path).expect("recording");
    let entries = read_recording(&bytes).expect("reads").entries;
    let index = entries
        .iter()
        .position(
            |e| matches!(e, Entry::Call(Request::StartGuardedMove(m), _) if m.force_limit == 20.0),
        )
        .expect("the paper's room has a push test at 20 N");
    let mut clock = 0.0;
    let mut entered_push_test = None;
    for e in &entries[..index] {
        match e {
            Entry::Call(Request::Now, Reply::Time(t)) => clock = *t,
            Entry::Transition(t) if t.to == "PushTest" => entered_push_test = Some(clock),
            _ => {}
        }
    }
    let entered = entered_push_test.expect("the recorded run entered PushTest before the push");
    let r = replay_file(path, &[Setting::ForceLimit(25.0)]).expect("replays");
    let d = r.divergence.expect("a divergence");
    assert_eq!(d.index, index, "{d}");
    assert_eq!(d.robot_time.to_bits(), clock.to_bits(), "{d}");
    assert!(d.robot_time >= entered, "{d}");
    assert_eq!(d.state.as_deref(), Some("PushTest"), "{d}");
    assert!(d.recorded.contains("force_limit 20,"), "{d}");
    assert!(d.new.contains("force_limit 25,"), "{d}");
    let out = nudge(&[
        "replay",
        path.to_str().expect("utf-8"),
        "--set",
        "force_limit=25",
    ]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(6), "{stdout}{}", text(&out.stderr));
    assert!(
        stdout.contains(&format!("divergence at tape entry {index}")),
        "{stdout}"
    );
    assert!(stdout.contains("recorded: start_guarded_move("), "{stdout}");
}

/// An MCAP file with one channel `topic` (`encoding`) holding `messages`, and a footer.
fn mcap_with(topic: &str, encoding: &str, messages: &[&[u8]]) -> Vec<u8> {
    let mut writer = mcap::Writer::new(Cursor::new(Vec::new())).expect("writer");
    let channel = writer
        .add_channel(0, topic, encoding, &BTreeMap::new())
        .expect("channel");
    for (i, data) in messages.iter().enumerate() {
        writer
            .write_to_known_channel(
                &mcap::records::MessageHeader {
                    channel_id: channel,
                    sequence: i as u32,
                    log_time: i as u64,
                    publish_time: i as u64,
                },
                data,
            )
            .expect("message");
    }
    writer.finish().expect("finish");
    writer.into_inner().into_inner()
}

#[test]
fn bad_files_are_errors_naming_the_file_and_what_is_wrong() {
    // Invariant: a missing file, random bytes, a truncated recording, a recording with a damaged byte in its data, an MCAP file without a tape, a tape in another encoding and a tape message that does not decode each make `nudge replay` exit 1 with one line naming the file and the fault, never a panic.
    let full = std::fs::read(recording()).expect("recording");
    let mut damaged = full.clone();
    let middle = damaged.len() / 2;
    for b in &mut damaged[middle..middle + 64] {
        *b ^= 0x5a;
    }
    let random: Vec<u8> = (0..4096u32)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
        .collect();
    let cases: Vec<(&str, Option<Vec<u8>>, &str)> = vec![
        ("missing.mcap", None, "cannot read"),
        ("random.mcap", Some(random), "not an MCAP file"),
        (
            "truncated.mcap",
            Some(full[..full.len() / 3].to_vec()),
            "truncated",
        ),
        // The reader checks a chunk's CRC once it has read the chunk through; a damaged tape message
        // in it may fail to decode first. Either way the error says what is wrong.
        ("damaged.mcap", Some(damaged), "corrupt|does not decode"),
        (
            "foreign.mcap",
            Some(mcap_with("/chatter", "json", &[b"{}"])),
            "no replay tape",
        ),
        (
            "future-tape.mcap",
            Some(mcap_with(TAPE_TOPIC, "nudge.tape/99", &[&[1]])),
            "nudge.tape/99",
        ),
        (
            "bad-tape.mcap",
            Some(mcap_with(
                TAPE_TOPIC,
                nudge_executive::record::tape::TAPE_ENCODING,
                &[&[1, 0, 0], &[0x7f]],
            )),
            "tape message 0 (robot time 0.000 s) does not decode",
        ),
    ];
    for (name, bytes, why) in cases {
        let path = scratch(name);
        match bytes {
            Some(b) => std::fs::write(&path, b).expect("write"),
            None => {
                let _ = std::fs::remove_file(&path);
            }
        }
        let out = nudge(&["replay", path.to_str().expect("utf-8")]);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{name}: {stderr}");
        assert!(!stderr.contains("panicked"), "{name}: {stderr}");
        assert!(
            stderr.contains(&path.display().to_string()),
            "{name}: the error names the file: {stderr}"
        );
        assert!(
            why.split('|').any(|w| stderr.contains(w)),
            "{name}: expected '{why}': {stderr}"
        );
        assert!(
            replay_file(&path, &[]).is_err(),
            "{name}: the library refuses it too"
        );
    }
}

/// The offsets and record lengths of `file`'s chunk records (opcode 0x06), walking its records from
/// the header on; stops at the footer or at anything that does not parse.
fn chunk_records(file: &[u8]) -> Vec<(usize, usize)> {
    let mut chunks = Vec::new();
    let mut at = mcap::MAGIC.len();
    while at + 9 <= file.len() {
        let opcode = file[at];
        let len = u64::from_le_bytes(file[at + 1..at + 9].try_into().expect("8 bytes")) as usize;
        match opcode {
            0x02 => break,
            0x06 => chunks.push((at, len)),
            _ => {}
        }
        at = at.saturating_add(9).saturating_add(len);
    }
    chunks
}

#[test]
fn twenty_one_kinds_of_damage_are_each_a_clean_error() {
    // Invariant: a recording emptied, cut short anywhere (in its header, its chunks, before its footer, in its closing magic), with a wrong magic, with a chunk's length or uncompressed size claiming exabytes, with chunk data zeroed, a chunk CRC that does not match or an unknown compression, makes `nudge replay` and `nudge inspect` exit 1 naming the file, never a panic or an abort — with the seven kinds of the test above, twenty-one in all.
    let full = std::fs::read(recording()).expect("recording");
    let chunks = chunk_records(&full);
    assert!(chunks.len() >= 2, "a recording of several chunks");
    let (first, first_len) = chunks[0];
    let (last, last_len) = chunks[chunks.len() - 1];
    // A chunk record: opcode, length, then start and end times, uncompressed size, CRC, compression.
    let size_at = first + 9 + 16;
    let crc_at = first + 9 + 24;
    let compression_at = first + 9 + 28 + 4;
    let with = |at: usize, bytes: &[u8]| {
        let mut f = full.clone();
        f[at..at + bytes.len()].copy_from_slice(bytes);
        f
    };
    let zeroed = |at: usize| with(at, &[0; 64]);
    let crc = u32::from_le_bytes(full[crc_at..crc_at + 4].try_into().expect("4 bytes"));
    assert_ne!(crc, 0, "the writer computes chunk CRCs");
    let n = full.len();
    let cases: Vec<(&str, Vec<u8>)> = vec![
        ("empty", Vec::new()),
        ("magic-only", full[..8].to_vec()),
        ("wrong-magic", with(1, b"X")),
        ("header-cut", full[..20].to_vec()),
        ("cut-at-a-tenth", full[..n / 10].to_vec()),
        ("cut-at-nine-tenths", full[..9 * n / 10].to_vec()),
        ("last-byte-cut", full[..n - 1].to_vec()),
        ("closing-magic-cut", full[..n - 8].to_vec()),
        (
            "chunk-size-huge",
            with(size_at, &(1u64 << 62).to_le_bytes()),
        ),
        (
            "chunk-length-huge",
            with(first + 1, &(1u64 << 62).to_le_bytes()),
        ),
        ("first-chunk-zeroed", zeroed(first + 9 + first_len / 2)),
        ("last-chunk-zeroed", zeroed(last + 9 + last_len / 2)),
        ("chunk-crc-wrong", with(crc_at, &(crc ^ 1).to_le_bytes())),
        ("compression-unknown", with(compression_at, b"zzzz")),
    ];
    for (name, bytes) in cases {
        let path = scratch(&format!("{name}.mcap"));
        std::fs::write(&path, bytes).expect("write");
        let shown = path.display().to_string();
        for command in ["replay", "inspect"] {
            let out = nudge(&[command, path.to_str().expect("utf-8")]);
            let stderr = text(&out.stderr);
            assert_eq!(out.status.code(), Some(1), "{command} {name}: {stderr}");
            assert!(!stderr.contains("panicked"), "{command} {name}: {stderr}");
            assert!(stderr.contains(&shown), "{command} {name}: {stderr}");
        }
        assert!(replay_file(&path, &[]).is_err(), "{name}: the library too");
    }
}

#[test]
#[ignore = "records and replays every shipped scenario (minutes); run with --ignored"]
fn every_shipped_scenario_replays_to_a_match() {
    // Invariant: for every scenario in scenarios/ at seed 1, `nudge run --record` then `nudge replay` on the same build exits 0 with "match".
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("scenarios/")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(!files.is_empty());
    let mut failed = Vec::new();
    for file in &files {
        let name = file.file_stem().and_then(|s| s.to_str()).unwrap_or("x");
        let path = scratch(&format!("all-{name}.mcap"));
        let out = nudge(&[
            "run",
            "--quiet",
            "--seed",
            "1",
            "--record",
            path.to_str().expect("utf-8"),
            file.to_str().expect("utf-8"),
        ]);
        assert!(
            out.status.code().is_some_and(|c| c != 1),
            "{name}: run failed to start: {}",
            text(&out.stderr)
        );
        let out = nudge(&["replay", path.to_str().expect("utf-8")]);
        if out.status.code() != Some(0) {
            failed.push(format!(
                "{name}: {}{}",
                text(&out.stdout),
                text(&out.stderr)
            ));
        }
        let _ = std::fs::remove_file(&path);
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}
