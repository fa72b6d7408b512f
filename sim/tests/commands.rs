//! The `nudge` binary's commands end to end: `check` against `[expect]` blocks, `batch` with shards
//! and `report`, and clear errors (never a panic) on bad paths, files and flags.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const NUDGE: &str = env!("CARGO_BIN_EXE_nudge");

fn nudge(args: &[&str]) -> Output {
    Command::new(NUDGE)
        .args(args)
        .output()
        .expect("the nudge binary starts")
}

fn scenarios() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios")
}

fn text(out: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A folder with two quick scenarios: the open room (expects the goal) and a copy of it that
/// wrongly expects no path and names an object that is never classified.
fn check_dir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("temp dir");
    let open = std::fs::read_to_string(scenarios().join("open-room.toml")).expect("open room");
    std::fs::write(dir.path().join("a-open.toml"), &open).expect("write");
    let (head, _) = open
        .split_once("[expect]")
        .expect("open room has an [expect] block");
    std::fs::write(
        dir.path().join("b-wrong.toml"),
        format!("{head}[expect]\noutcome = \"no_path\"\n"),
    )
    .expect("write");
    dir
}

#[test]
fn check_passes_what_meets_its_expect_block_and_fails_what_does_not() {
    // Invariant: `nudge check DIR` runs every scenario in name order, marks each pass or FAIL with what differed, and exits 5 on any failure.
    let dir = check_dir();
    let out = nudge(&["check", dir.path().to_str().expect("utf-8"), "--jobs", "2"]);
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(5), "{stdout}{stderr}");
    let a = stdout.find("a-open.toml").expect("a listed");
    let b = stdout.find("b-wrong.toml").expect("b listed");
    assert!(a < b, "name order");
    let line = |name: &str| {
        stdout
            .lines()
            .find(|l| l.contains(name))
            .unwrap_or_default()
            .to_string()
    };
    assert!(line("a-open.toml").contains("pass"), "{stdout}");
    assert!(
        line("b-wrong.toml").contains("FAIL")
            && line("b-wrong.toml").contains("outcome goal (expected no_path)"),
        "{stdout}"
    );
    assert!(stdout.contains("1 passed, 1 failed"), "{stdout}");
    let one = nudge(&[
        "check",
        dir.path().join("a-open.toml").to_str().expect("utf-8"),
    ]);
    assert!(one.status.success(), "{:?}", text(&one));
}

/// Result lines without their wall time, which is the one field allowed to differ.
fn without_wall_time(path: &Path) -> Vec<serde_json::Value> {
    std::fs::read_to_string(path)
        .expect("results")
        .lines()
        .map(|l| {
            let mut v: serde_json::Value = serde_json::from_str(l).expect("a JSON line");
            v.as_object_mut().expect("an object").remove("wall_time");
            v
        })
        .collect()
}

#[test]
fn batch_shards_merge_into_the_same_results_as_one_batch() {
    // Invariant: shards 0/2 and 1/2 together hold exactly the runs of the whole batch, with equal lines apart from wall time, and `report` on them prints the whole batch's table.
    let dir = tempfile::tempdir().expect("temp dir");
    let input = dir.path().join("in");
    std::fs::create_dir(&input).expect("mkdir");
    for name in ["open-room.toml", "all-static.toml"] {
        std::fs::copy(scenarios().join(name), input.join(name)).expect("copy");
    }
    let input = input.to_str().expect("utf-8");
    let all = dir.path().join("all.jsonl");
    let out = nudge(&[
        "batch",
        input,
        "--seeds",
        "2",
        "--jobs",
        "2",
        "--out",
        all.to_str().expect("utf-8"),
    ]);
    let (stdout, stderr) = text(&out);
    assert!(out.status.success(), "{stdout}{stderr}");
    let whole = without_wall_time(&all);
    assert_eq!(whole.len(), 4, "2 scenarios × 2 seeds");
    // Stable order: files by name, then seeds from the scenario's own.
    assert_eq!(whole[0]["scenario"], "all-static");
    assert_eq!(
        whole[1]["seed"].as_u64(),
        whole[0]["seed"].as_u64().map(|s| s + 1)
    );
    assert_eq!(whole[0]["outcome"], "no_path");
    assert_eq!(whole[0]["push_tests"], 3);
    assert_eq!(
        whole[0]["right"], 3,
        "the three static objects are classified right"
    );
    assert_eq!(whole[2]["scenario"], "open-room");
    assert_eq!(whole[2]["outcome"], "goal");
    let mut shards = Vec::new();
    for shard in ["0/2", "1/2"] {
        let path = dir.path().join(format!("shard-{}.jsonl", &shard[..1]));
        let out = nudge(&[
            "batch",
            input,
            "--seeds",
            "2",
            "--shard",
            shard,
            "--jobs",
            "1",
            "--out",
            path.to_str().expect("utf-8"),
        ]);
        assert!(out.status.success(), "{:?}", text(&out));
        shards.push(path);
    }
    let s0 = without_wall_time(&shards[0]);
    let s1 = without_wall_time(&shards[1]);
    assert_eq!(
        s0,
        vec![whole[0].clone(), whole[2].clone()],
        "shard 0 takes runs 0 and 2"
    );
    assert_eq!(s1, vec![whole[1].clone(), whole[3].clone()]);
    let table = |out: Output| -> String {
        let (stdout, _) = text(&out);
        stdout
            .lines()
            .filter(|l| !l.contains(" runs from ") && !l.contains("result lines"))
            .collect::<Vec<_>>()
            .join("\n")
    };
    let merged = nudge(&[
        "report",
        shards[0].to_str().expect("utf-8"),
        shards[1].to_str().expect("utf-8"),
        shards[1].to_str().expect("utf-8"),
    ]);
    let (_, merged_err) = text(&merged);
    assert!(
        merged_err.contains("2 duplicate runs ignored"),
        "{merged_err}"
    );
    let merged = table(merged);
    assert!(
        merged.contains("open-room") && merged.contains("all-static"),
        "{merged}"
    );
    assert_eq!(
        merged,
        table(nudge(&["report", all.to_str().expect("utf-8")]))
    );
    // The CSV holds a header and one row per run, with the metrics: the open room's run has an SPL
    // in (0, 1], the all-static room's none (no way exists even without movable objects).
    let csv_path = dir.path().join("runs.csv");
    let out = nudge(&[
        "report",
        all.to_str().expect("utf-8"),
        "--by",
        "scenario",
        "--csv",
        csv_path.to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{:?}", text(&out));
    let csv = std::fs::read_to_string(&csv_path).expect("csv written");
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(rows.len(), 5, "header and 4 runs: {csv}");
    let header: Vec<&str> = rows[0].split(',').collect();
    let spl = header.iter().position(|h| *h == "spl").expect("spl column");
    let field = |row: &str| row.split(',').nth(spl).unwrap_or("").to_string();
    assert_eq!(field(rows[1]), "", "all-static has no SPL: {}", rows[1]);
    let open_spl: f64 = field(rows[3]).parse().expect("open room's SPL");
    assert!(open_spl > 0.0 && open_spl <= 1.0, "{open_spl}");
}

#[test]
fn bad_paths_files_and_flags_give_a_clear_message_and_no_panic() {
    // Invariant: every bad input exits non-zero (1 for inputs, 2 for flags) with a message naming the problem, never a panic.
    let dir = tempfile::tempdir().expect("temp dir");
    let bad_toml = dir.path().join("bad.toml");
    std::fs::write(&bad_toml, "name = \"x\"\n[room]\nsize = [6.0, \n").expect("write");
    let not_mcap = dir.path().join("not.mcap");
    std::fs::write(&not_mcap, "hello").expect("write");
    let not_results = dir.path().join("r.jsonl");
    std::fs::write(&not_results, "{\"scenario\": 3}\n").expect("write");
    let empty_dir = dir.path().join("empty");
    std::fs::create_dir(&empty_dir).expect("mkdir");
    let s = |p: &Path| p.to_str().expect("utf-8").to_string();
    let missing = s(&dir.path().join("missing.toml"));
    let no_dir = s(&dir.path().join("no-such-dir").join("x"));
    let cases: Vec<(Vec<String>, i32, &str)> = vec![
        (vec!["run".into(), missing.clone()], 1, "missing.toml"),
        (vec!["run".into(), s(&bad_toml)], 1, "bad.toml:"),
        (
            vec!["run".into(), "--record".into(), no_dir.clone()],
            1,
            "cannot create recording",
        ),
        (
            vec!["run".into(), "--map".into(), no_dir.clone()],
            1,
            "cannot create",
        ),
        (
            vec!["run".into(), "--seed".into(), "abc".into()],
            2,
            "invalid value 'abc'",
        ),
        (
            vec!["run".into(), "--policy".into(), "random".into()],
            2,
            "invalid value 'random'",
        ),
        (
            vec!["run".into(), "--bogus".into()],
            2,
            "unexpected argument",
        ),
        (vec!["check".into(), missing.clone()], 1, "no such file"),
        (
            vec!["check".into(), s(&empty_dir)],
            1,
            "holds no scenario files",
        ),
        (vec!["check".into(), s(&bad_toml)], 5, ""),
        (
            vec!["batch".into(), s(&empty_dir), "--seeds".into(), "1".into()],
            1,
            "holds no scenario files",
        ),
        (
            vec![
                "batch".into(),
                s(&scenarios()),
                "--seeds".into(),
                "0".into(),
            ],
            2,
            "--seeds",
        ),
        (
            vec![
                "batch".into(),
                s(&scenarios()),
                "--seeds".into(),
                "1".into(),
                "--shard".into(),
                "2/2".into(),
            ],
            2,
            "must be below the count 2",
        ),
        (
            vec![
                "batch".into(),
                s(&scenarios()),
                "--seeds".into(),
                "1".into(),
                "--shard".into(),
                "1-2".into(),
            ],
            2,
            "is not I/N",
        ),
        (vec!["batch".into(), s(&scenarios())], 2, "--seeds"),
        (
            vec!["report".into(), s(&not_results)],
            1,
            "r.jsonl:1: not a nudge result line",
        ),
        (vec!["report".into(), missing.clone()], 1, "cannot read"),
        (vec!["inspect".into(), missing], 1, "cannot read"),
        (vec!["inspect".into(), s(&not_mcap)], 1, "not an MCAP file"),
        (vec!["inspect".into(), s(dir.path())], 1, "cannot read"),
    ];
    for (args, code, needle) in cases {
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = nudge(&refs);
        let (stdout, stderr) = text(&out);
        assert_eq!(out.status.code(), Some(code), "{args:?}: {stdout}{stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert!(
            stderr.contains(needle) || stdout.contains(needle),
            "{args:?}: {needle:?} not in {stdout}{stderr}"
        );
    }
}

#[test]
fn a_cancelled_batch_keeps_every_finished_run_as_a_whole_line() {
    // Invariant: SIGINT stops a batch with exit 4, and its result file holds only complete, readable lines, in run order.
    let dir = tempfile::tempdir().expect("temp dir");
    let out_path = dir.path().join("r.jsonl");
    let child = Command::new(NUDGE)
        .args([
            "batch",
            scenarios().join("open-room.toml").to_str().expect("utf-8"),
            "--seeds",
            "200",
            "--jobs",
            "1",
            "--out",
            out_path.to_str().expect("utf-8"),
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("nudge starts");
    // The first result line is written after the Ctrl-C handler is installed.
    let mut waited = 0;
    while std::fs::read_to_string(&out_path).map_or(true, |t| t.lines().count() == 0) {
        std::thread::sleep(std::time::Duration::from_millis(50));
        waited += 1;
        assert!(waited < 2400, "no result line within two minutes");
    }
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(kill.success());
    let out = child.wait_with_output().expect("nudge ends");
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(4), "{stdout}{stderr}");
    assert!(stderr.contains("batch cancelled"), "{stderr}");
    let lines = without_wall_time(&out_path);
    assert!(
        !lines.is_empty() && lines.len() < 200,
        "{} lines",
        lines.len()
    );
    assert!(
        lines.iter().all(|l| l["outcome"] == "goal"),
        "the run cut short by Ctrl-C is not reported as aborted"
    );
    for (k, line) in lines.iter().enumerate() {
        assert_eq!(
            line["seed"].as_u64(),
            lines[0]["seed"].as_u64().map(|s| s + k as u64)
        );
    }
}
