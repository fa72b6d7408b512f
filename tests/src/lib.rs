//! nudge-tests: end-to-end scenario tests across crates live in `tests/`; this library holds their
//! shared helpers.
#![warn(missing_docs)]

/// Path of the repository's `scenarios/` folder, for tests that load scenario files.
pub fn scenarios_dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("scenarios")
}
