//! The `nudge` binary: runs the default scenario, and refuses bad input with a clear message.

use std::process::Command;

fn nudge(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_nudge"))
        .args(args)
        .output()
        .expect("the nudge binary runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn run_without_a_scenario_reaches_the_goal_in_the_papers_room() {
    // Invariant: `nudge run` with no scenario runs the embedded paper's room to the goal and exits 0.
    let (code, out, err) = nudge(&["run", "--quiet"]);
    assert_eq!(code, 0, "stdout:\n{out}\nstderr:\n{err}");
    assert!(
        out.contains("kakiuchi-room") && out.contains("reached the goal"),
        "{out}"
    );
    assert!(
        out.contains("real-time"),
        "the summary reports the real-time factor: {out}"
    );
}

#[test]
fn an_all_static_room_exits_with_the_no_path_code() {
    // Invariant: a run ending in NoPathToGoal exits 3 and says why.
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenarios/all-static.toml");
    let (code, out, _) = nudge(&["run", path, "--quiet"]);
    assert_eq!(code, 3, "{out}");
    assert!(out.contains("no path to the goal"), "{out}");
}

#[test]
fn a_missing_scenario_file_is_named_and_exits_1() {
    // Invariant: an unreadable scenario gives a message naming the path and exit code 1, never a panic.
    let (code, _, err) = nudge(&["run", "/no/such/scenario.toml"]);
    assert_eq!(code, 1);
    assert!(
        err.contains("/no/such/scenario.toml") && !err.contains("panicked"),
        "{err}"
    );
}

#[test]
fn a_bad_scenario_file_reports_line_column_and_field() {
    // Invariant: a scenario with a bad value is refused with file:line:column: field.
    let dir = std::env::temp_dir().join(format!("nudge-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("bad.toml");
    std::fs::write(
        &path,
        "name = \"bad\"\n[room]\nsize = [6.0, -3.0]\n[robot]\nstart = [1.0, 1.0, 0.0]\n[goal]\nposition = [5.0, 1.0]\n",
    )
    .expect("write");
    let (code, _, err) = nudge(&["run", path.to_str().expect("utf-8 path")]);
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(code, 1);
    assert!(
        err.contains("bad.toml:3:") && err.contains("room.size"),
        "{err}"
    );
}

#[test]
fn a_bad_flag_is_refused() {
    // Invariant: an unknown policy is refused with the possible values and a non-zero exit.
    let (code, _, err) = nudge(&["run", "--policy", "sideways"]);
    assert_ne!(code, 0);
    assert!(err.contains("nearest") && err.contains("blocking"), "{err}");
}
