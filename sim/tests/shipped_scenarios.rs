//! CI runs the scenarios: every shipped scenario meets its `[expect]` block on a few seeds, checked
//! through the `nudge check` command a user would type.

use std::path::Path;
use std::process::Command;

/// Seeds per scenario: the scenario's own and the next two. The batch in BENCHMARKS.md covers 30.
const SEEDS: usize = 3;

#[test]
fn every_shipped_scenario_meets_its_expect_block_on_three_seeds() {
    // Invariant: `nudge check scenarios --seeds 3` passes every run, and every shipped scenario has
    // an `[expect]` block (outcome and verdicts scored against the simulation's ground truth).
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios");
    let files = std::fs::read_dir(&dir)
        .expect("scenarios folder")
        .filter_map(Result::ok)
        .filter(|e| e.path().extension().is_some_and(|x| x == "toml"))
        .count();
    assert!(files >= 18, "the shipped scenarios are found ({files})");
    let out = Command::new(env!("CARGO_BIN_EXE_nudge"))
        .args(["check", dir.to_str().expect("utf-8"), "--seeds", "3"])
        .output()
        .expect("the nudge binary starts");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let runs = files * SEEDS;
    assert!(
        stdout.contains(&format!("{runs} passed, 0 failed, 0 without [expect]")),
        "{stdout}{stderr}"
    );
    assert!(out.status.success(), "{stdout}{stderr}");
}
