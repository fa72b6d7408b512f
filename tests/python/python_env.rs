//! A pinned Python for the interop tests — the official `mcap` reader with its protobuf decoders for
//! the recording tests, `rosbags` for the ROS 2 CDR tests: a virtual environment under the target
//! directory, created on first use from `tests/python/requirements.txt` (pinned versions). Test
//! files of any crate take it in with `#[path = ".../tests/python/python_env.rs"] mod python_env;`.
//!
//! Needs `python3` (3.8 or newer, with its `venv` module and pip) and a package index: PyPI, or the
//! one pip's own settings name (`PIP_INDEX_URL`, `PIP_FIND_LINKS` for a folder of wheels). Anything
//! missing panics with what is missing and how to provide it: the test fails, it never skips.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

/// The pinned requirements, as committed.
const REQUIREMENTS: &str = include_str!("requirements.txt");

/// Where the environment lives: under `target/`, so it is never committed.
fn venv_dir() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("python-interop")
}

fn interpreter(venv: &Path) -> PathBuf {
    if cfg!(windows) {
        venv.join("Scripts").join("python.exe")
    } else {
        venv.join("bin").join("python")
    }
}

fn describe(out: &Output) -> String {
    format!(
        "exit {:?}\n{}{}",
        out.status.code(),
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

/// Runs `program args`, panicking with `what` and `fix` when it cannot start or fails.
fn run(program: &Path, args: &[&str], what: &str, fix: &str) {
    let out = Command::new(program)
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("{what}: cannot run {}: {e}. {fix}", program.display()));
    assert!(
        out.status.success(),
        "{what} failed. {fix}\n{}",
        describe(&out)
    );
}

/// Removes a half-made environment when its making fails (the panic unwinds through it).
struct Partial(PathBuf);

impl Drop for Partial {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Creates the environment in `dir` and installs the pinned requirements into it.
fn create(dir: &Path) {
    let python3 = Path::new("python3");
    run(
        python3,
        &["-m", "venv", dir.to_str().expect("utf-8 target path")],
        "creating a Python virtual environment for the interop tests (python3 -m venv)",
        "The interop tests need python3 with its venv module (Debian: apt install python3-venv).",
    );
    let requirements = dir.join("requirements.txt");
    std::fs::write(&requirements, REQUIREMENTS).expect("write requirements into the venv");
    run(
        &interpreter(dir),
        &[
            "-m",
            "pip",
            "install",
            "--quiet",
            "--disable-pip-version-check",
            "-r",
            requirements.to_str().expect("utf-8 target path"),
        ],
        "installing the pinned interop Python (tests/python/requirements.txt)",
        "pip needs PyPI, or an index or wheel folder named by PIP_INDEX_URL or PIP_FIND_LINKS.",
    );
}

/// The environment's Python, with the requirements importable: created on first use, kept between runs, and
/// created afresh when the requirements file changed.
pub fn python() -> PathBuf {
    static PYTHON: OnceLock<PathBuf> = OnceLock::new();
    PYTHON
        .get_or_init(|| {
            let dir = venv_dir();
            let installed = std::fs::read_to_string(dir.join("requirements.txt")).ok();
            let ready = dir.join("ready");
            if installed.as_deref() != Some(REQUIREMENTS) || !ready.exists() {
                // Built beside the final place and renamed into it, so a run killed half way or a
                // second test process never sees a half-made environment.
                let partial =
                    Partial(dir.with_extension(format!("partial-{}", std::process::id())));
                let _ = std::fs::remove_dir_all(&partial.0);
                create(&partial.0);
                std::fs::write(partial.0.join("ready"), b"").expect("mark the venv ready");
                let _ = std::fs::remove_dir_all(&dir);
                // When another process put its environment there first, this one is dropped.
                let _ = std::fs::rename(&partial.0, &dir);
            }
            interpreter(&dir)
        })
        .clone()
}
