//! Broken and mangled scenario text: loading answers Ok or a well-placed error, and never panics.

use nudge_sim::scenario::{DEFAULT_ROOM_TOML, Scenario, ScenarioError};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

/// Loads `text` and checks that any error points at a real place in it.
fn load_and_check_place(text: &str) -> Result<(), String> {
    match Scenario::from_toml_str(text, "fuzz.toml") {
        Ok(scenario) => scenario
            .validate()
            .map_err(|v| format!("loaded but invalid: {v}")),
        Err(ScenarioError::Io { .. }) => Err("an io error from a string".into()),
        Err(ScenarioError::Invalid(invalid)) => {
            invalid.place_within(text)?;
            if !invalid.to_string().starts_with("fuzz.toml:") {
                return Err(format!("message does not start with the origin: {invalid}"));
            }
            Ok(())
        }
    }
}

#[test]
fn every_prefix_of_every_shipped_file_loads_or_fails_in_place() {
    // Invariant: a file cut off anywhere (a half-written save) gives Ok or a located error, never a panic.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios");
    let mut cuts = 0;
    for entry in std::fs::read_dir(dir).expect("scenarios/ exists") {
        let text = std::fs::read_to_string(entry.expect("an entry").path()).expect("a UTF-8 file");
        for end in (0..=text.len()).filter(|&i| text.is_char_boundary(i)) {
            load_and_check_place(&text[..end]).unwrap_or_else(|e| panic!("cut at byte {end}: {e}"));
            cuts += 1;
        }
    }
    assert!(cuts > 5000, "only {cuts} cuts tried");
}

/// Pieces of TOML and numbers that tend to break things.
const TOKENS: &[&str] = &[
    "",
    "-",
    "-1",
    "0",
    "0.0",
    "nan",
    "-inf",
    "1e400",
    "\"",
    "'",
    "[",
    "]",
    "[[",
    "]]",
    "{",
    "}",
    ",",
    "=",
    ".",
    "\n",
    "#",
    "ü",
    "[[object]]\n",
    "[[actor]]\n",
    "[expect]\n",
    "true",
    "\"chair-1\"",
    "size",
    "mass = ",
    "99999999999999999999",
    "1979-05-27T07:32:00Z",
];

fn config() -> Config {
    Config {
        cases: 512,
        rng_seed: RngSeed::Fixed(20_101),
        failure_persistence: None,
        ..Config::default()
    }
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn splicing_tokens_into_the_room_never_panics(
        edits in prop::collection::vec((any::<prop::sample::Index>(), 0usize..12, prop::sample::select(TOKENS)), 1..4)
    ) {
        // Invariant: replacing any spans of a good file with hostile tokens gives Ok or a located error.
        let mut text = DEFAULT_ROOM_TOML.to_owned();
        for (at, len, token) in edits {
            let start = floor_boundary(&text, at.index(text.len() + 1));
            let end = floor_boundary(&text, (start + len).min(text.len()));
            text.replace_range(start..end, token);
        }
        prop_assert!(load_and_check_place(&text).is_ok(), "{}\n---\n{text}", load_and_check_place(&text).err().unwrap_or_default());
    }

    #[test]
    fn shuffling_and_dropping_lines_never_panics(
        order in Just((0..DEFAULT_ROOM_TOML.lines().count()).collect::<Vec<_>>()).prop_shuffle(),
        keep in 1usize..120,
    ) {
        // Invariant: lines in any order, any subset of them, give Ok or a located error.
        let lines: Vec<&str> = DEFAULT_ROOM_TOML.lines().collect();
        let text: String = order.iter().take(keep).map(|&i| format!("{}\n", lines[i])).collect();
        prop_assert!(load_and_check_place(&text).is_ok(), "{}", load_and_check_place(&text).err().unwrap_or_default());
    }
}

fn floor_boundary(text: &str, mut i: usize) -> usize {
    while !text.is_char_boundary(i) {
        i -= 1;
    }
    i
}

#[test]
fn deeply_nested_arrays_are_an_error_not_a_stack_overflow() {
    // Invariant: hostile nesting depth is refused by the parser's limit before any recursive walk.
    let text = format!(
        "name = \"deep\"\nx = {}{}\n",
        "[".repeat(100_000),
        "]".repeat(100_000)
    );
    let error = Scenario::from_toml_str(&text, "deep.toml").expect_err("nesting too deep");
    assert!(error.to_string().starts_with("deep.toml:2:"), "{error}");
}
