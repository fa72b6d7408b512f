//! A seeded, in-process mutation fuzzer for the scenario loader and the world built from what it loads.
//!
//! Every input is a shipped scenario (or the embedded default room) mangled by a few mutations: bytes
//! flipped, spans deleted, duplicated or swapped, hostile tokens spliced in, numbers replaced, lines
//! shuffled, the text cut short. Each input must load as `Ok`, or fail with an error that names the
//! origin and a line and column inside the text; whatever loads must build a world or refuse with an
//! error. A panic, a misplaced error or an input slower than `--slow-ms` is written to `--out` and
//! counted, and the harness exits non-zero when any was found.
//!
//! ```text
//! cargo run --release -p nudge-sim --example fuzz_scenarios -- --inputs 1000000 --seed 1
//! ```

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use nudge_sim::scenario::{DEFAULT_ROOM_TOML, Scenario, ScenarioError};
use nudge_sim::world::World;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[path = "fuzz_common/mod.rs"]
mod fuzz_common;
use fuzz_common::Judged;

/// Command-line options.
#[derive(Parser, Debug)]
#[command(about = "Fuzz the scenario loader and world builder with mutated scenario files")]
struct Options {
    /// How many mutated inputs to try.
    #[arg(long, default_value_t = 100_000)]
    inputs: u64,
    /// Seed of the mutations: the same seed tries the same inputs.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Folder of scenario files to mutate (the embedded default room is always included).
    #[arg(long, default_value = "scenarios")]
    corpus: PathBuf,
    /// Where inputs that panic, misplace their error or run slowly are written.
    #[arg(long, default_value = "target/fuzz-scenarios")]
    out: PathBuf,
    /// An input that takes longer than this (ms) to load and build counts as a hang.
    #[arg(long, default_value_t = 1000)]
    slow_ms: u64,
}

/// Hostile pieces of TOML: numbers at and past every limit, broken syntax, odd text.
const TOKENS: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "-0.0",
    "0",
    "-1",
    "1e308",
    "-1e308",
    "1e-320",
    "1e999",
    "99999999999999999999",
    "9223372036854775807",
    "-9223372036854775808",
    "0x7f",
    "true",
    "\"\"",
    "\"é\u{0}\"",
    "[]",
    "[[]]",
    "{}",
    "[1, 2",
    "]",
    "[[object]]",
    "[[actor]]",
    "[room]",
    "[robot]",
    "[goal]",
    "[expect]",
    "=",
    "==",
    "\n",
    "\r\n",
    "#",
    "'",
    "\"\"\"",
    "1979-05-27T07:32:00Z",
    "[1e9, 1e9]",
    "[-5.0, -5.0]",
    "[0.0, 0.0, 0.0]",
    "size = [0.0, 0.0, 0.0]",
    "mass = 0.0",
    "mass = -1.0",
    "friction = 9.0",
    "yaw = 1e300",
    "kind = \"sofa\"",
    "kind = \"chair\"",
    "speed = 0.0",
    "path = []",
    "path = [[0.0, 0.0]]",
    "elevation = 5.0",
    "fixed = true",
    "name = \"\"",
    "\u{feff}",
    "\t",
];

fn main() -> ExitCode {
    let options = Options::parse();
    let corpus = match read_corpus(&options.corpus) {
        Ok(corpus) => corpus,
        Err(e) => {
            eprintln!("fuzz_scenarios: {}: {e}", options.corpus.display());
            return ExitCode::FAILURE;
        }
    };
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    let tally = fuzz_common::drive(
        options.inputs,
        Duration::from_millis(options.slow_ms),
        |_| mutate(&corpus, &mut rng),
        |i, text| try_input(text, i),
        |i, text, why| {
            if let Err(e) = save(&options.out, i, text, why) {
                eprintln!("fuzz_scenarios: could not save input {i}: {e}");
            }
        },
    );
    tally.print(
        options.inputs,
        options.seed,
        "loaded and built",
        "refused in place",
    );
    tally.exit_code()
}

/// The shipped scenario files, sorted by name so a seed means the same inputs everywhere, and the
/// embedded default room.
fn read_corpus(dir: &Path) -> std::io::Result<Vec<String>> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    paths.sort();
    let mut corpus = vec![DEFAULT_ROOM_TOML.to_owned()];
    for path in paths {
        corpus.push(std::fs::read_to_string(path)?);
    }
    Ok(corpus)
}

/// Loads `text` and builds its world (seeded with the input's `index`); panics are caught.
fn try_input(text: &str, index: u64) -> Judged {
    let run = fuzz_common::caught(|| match Scenario::from_toml_str(text, "fuzz.toml") {
        Ok(scenario) => {
            // A refusal is fine; the build must only not panic.
            let _ = World::new(&scenario, index);
            Ok(true)
        }
        Err(error) => check_place(text, &error).map(|()| false),
    });
    match run {
        Ok(Ok(true)) => Judged::Accepted,
        Ok(Ok(false)) => Judged::Refused,
        Ok(Err(why)) => Judged::Finding(format!("misplaced error: {why}")),
        Err(why) => Judged::Finding(format!("panic: {why}")),
    }
}

/// Whether a loader error names the origin and a line and column inside `text`.
fn check_place(text: &str, error: &ScenarioError) -> Result<(), String> {
    let invalid = error
        .invalid()
        .ok_or_else(|| format!("not a located error: {error}"))?;
    invalid.place_within(text)?;
    if invalid.origin != "fuzz.toml" {
        return Err(format!("the error names another origin: {invalid}"));
    }
    Ok(())
}

/// One corpus entry with one to four mutations, as text (invalid UTF-8 replaced, as a reader that
/// got past decoding would see it).
fn mutate(corpus: &[String], rng: &mut ChaCha8Rng) -> String {
    let mut bytes = corpus[rng.random_range(0..corpus.len())]
        .clone()
        .into_bytes();
    for _ in 0..rng.random_range(1..=4) {
        let len = bytes.len();
        let at = rng.random_range(0..=len);
        let span = rng.random_range(0..=16.min(len - at));
        match rng.random_range(0..8) {
            0 if len > 0 => {
                let i = rng.random_range(0..len);
                bytes[i] ^= 1 << rng.random_range(0..8);
            }
            1 => {
                bytes.drain(at..at + span);
            }
            2 => {
                let copy = bytes[at..at + span].to_vec();
                bytes.splice(at..at, copy);
            }
            3 | 4 => {
                let token = TOKENS[rng.random_range(0..TOKENS.len())].as_bytes();
                bytes.splice(at..at + span, token.iter().copied());
            }
            5 => replace_a_number(&mut bytes, rng),
            6 => shuffle_lines(&mut bytes, rng),
            _ => bytes.truncate(at),
        }
    }
    String::from_utf8_lossy(&bytes).into_owned()
}

/// Replaces the digits of one number in the text with a hostile token.
fn replace_a_number(bytes: &mut Vec<u8>, rng: &mut ChaCha8Rng) {
    let digits: Vec<usize> = (0..bytes.len())
        .filter(|&i| bytes[i].is_ascii_digit())
        .collect();
    let Some(&start) = digits.get(rng.random_range(0..digits.len().max(1))) else {
        return;
    };
    let end = (start..bytes.len())
        .find(|&i| !(bytes[i].is_ascii_digit() || bytes[i] == b'.' || bytes[i] == b'e'))
        .unwrap_or(bytes.len());
    let token = TOKENS[rng.random_range(0..TOKENS.len())].as_bytes();
    bytes.splice(start..end, token.iter().copied());
}

/// Swaps two lines, or drops one.
fn shuffle_lines(bytes: &mut Vec<u8>, rng: &mut ChaCha8Rng) {
    let mut lines: Vec<Vec<u8>> = bytes.split(|&b| b == b'\n').map(<[u8]>::to_vec).collect();
    if lines.len() < 2 {
        return;
    }
    let (a, b) = (
        rng.random_range(0..lines.len()),
        rng.random_range(0..lines.len()),
    );
    if rng.random_bool(0.5) {
        lines.swap(a, b);
    } else {
        lines.remove(a);
    }
    *bytes = lines.join(&b'\n');
}

/// Writes a finding's input as it was to `out/input-N.toml`, and why it is one to `input-N.txt`.
fn save(out: &Path, index: u64, text: &str, why: &str) -> std::io::Result<()> {
    std::fs::create_dir_all(out)?;
    std::fs::write(out.join(format!("input-{index}.toml")), text)?;
    std::fs::write(out.join(format!("input-{index}.txt")), why)
}
