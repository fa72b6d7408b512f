//! A seeded, in-process mutation fuzzer for the `nudge` command line.
//!
//! Every input is one of a set of valid command lines (each subcommand with each of its options)
//! mangled by a few mutations: tokens deleted, duplicated, swapped or replaced by hostile values
//! (numbers at and past every range, broken shard specs, empty and odd text), options of other
//! subcommands spliced in, characters of a token flipped. Each input goes through the same parser
//! the binary uses (`nudge_sim::cli::Cli`): it must parse, or be refused with an error that says
//! which argument was wrong (clap's message for a bad value names the option; ours add why). A
//! panic or an unplaced refusal is printed and counted, and the harness exits non-zero when any
//! was found. Commands are parsed, not run: running one is a scenario run, which the scenario
//! fuzzer and the tests cover.
//!
//! ```text
//! cargo run --release -p nudge-sim --example fuzz_cli -- --inputs 1000000 --seed 1
//! ```

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;
use clap::error::ErrorKind;
use nudge_sim::cli::Cli;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Command-line options.
#[derive(Parser, Debug)]
#[command(about = "Fuzz the nudge command line with mutated argument lists")]
struct Options {
    /// How many mutated inputs to try.
    #[arg(long, default_value_t = 100_000)]
    inputs: u64,
    /// Seed of the mutations: the same seed tries the same inputs.
    #[arg(long, default_value_t = 1)]
    seed: u64,
}

/// Valid command lines, one per subcommand and with every option of each.
const CORPUS: &[&[&str]] = &[
    &[],
    &["run"],
    &[
        "run",
        "scenarios/kakiuchi-room.toml",
        "--seed",
        "3",
        "--policy",
        "blocking",
        "--record",
        "run.mcap",
        "--map",
        "run.png",
        "--quiet",
    ],
    &[
        "check",
        "scenarios",
        "--seed",
        "2",
        "--seeds",
        "3",
        "--policy",
        "nearest",
        "--jobs",
        "2",
    ],
    &[
        "batch",
        "scenarios",
        "--seeds",
        "30",
        "--jobs",
        "2",
        "--out",
        "results.jsonl",
        "--shard",
        "1/4",
        "--policy",
        "nearest,blocking",
    ],
    &[
        "report", "a.jsonl", "b.jsonl", "--by", "scenario", "--csv", "runs.csv",
    ],
    &["inspect", "run.mcap"],
    &[
        "generate",
        "flat",
        "corridor",
        "wanderers",
        "--count",
        "5",
        "--seed",
        "7",
        "--out",
        "fam",
    ],
    &["--version"],
];

/// Every option of every subcommand, spliced into other places.
const OPTIONS: &[&str] = &[
    "--seed",
    "--seeds",
    "--policy",
    "--record",
    "--map",
    "--quiet",
    "--jobs",
    "--out",
    "--shard",
    "--by",
    "--csv",
    "--count",
    "--help",
    "--version",
    "-h",
    "-V",
    "--",
];

/// Hostile values: numbers at and past every range, broken shard specs, odd text.
const VALUES: &[&str] = &[
    "0",
    "1",
    "-1",
    "-0",
    "18446744073709551615",
    "18446744073709551616",
    "99999999999999999999999",
    "9223372036854775807",
    "10000",
    "10001",
    "1e9",
    "nan",
    "inf",
    "0x10",
    " 1",
    "1 ",
    "",
    "=",
    "0/0",
    "1/0",
    "4/4",
    "3/2",
    "-1/2",
    "1/-1",
    "/",
    "1/2/3",
    "0/18446744073709551616",
    "nearest,",
    ",",
    "nearest,,blocking",
    "NEAREST",
    "family",
    "scenario",
    "flat",
    "open-clutter",
    "no-such-family",
    "run",
    "batch",
    "-",
    "--policy=blocking",
    "--seed=",
    "--jobs=-3",
    "ünïcödé",
    "\u{0}",
    "\u{202e}",
    "a\nb",
    "/nonexistent/dir/file.toml",
    "C:\\x",
];

/// One input: a corpus line (after the program name) mutated a few times.
fn mutate(rng: &mut ChaCha8Rng) -> Vec<String> {
    let base = CORPUS[rng.random_range(0..CORPUS.len())];
    let mut args: Vec<String> = base.iter().map(|s| s.to_string()).collect();
    for _ in 0..rng.random_range(1..=4) {
        let n = args.len();
        match rng.random_range(0..7) {
            0 if n > 0 => {
                args.remove(rng.random_range(0..n));
            }
            1 if n > 0 => {
                let i = rng.random_range(0..n);
                args.insert(i, args[i].clone());
            }
            2 if n > 1 => {
                args.swap(rng.random_range(0..n), rng.random_range(0..n));
            }
            3 if n > 0 => {
                args[rng.random_range(0..n)] = VALUES[rng.random_range(0..VALUES.len())].into();
            }
            4 => {
                let at = rng.random_range(0..=n);
                args.insert(at, OPTIONS[rng.random_range(0..OPTIONS.len())].into());
                if rng.random_bool(0.7) {
                    args.insert(at + 1, VALUES[rng.random_range(0..VALUES.len())].into());
                }
            }
            5 if n > 0 => {
                let i = rng.random_range(0..n);
                args[i] = flip(&args[i], rng);
            }
            _ => {
                let at = rng.random_range(0..=n);
                args.insert(at, VALUES[rng.random_range(0..VALUES.len())].into());
            }
        }
    }
    args
}

/// `token` with one character replaced, dropped or doubled.
fn flip(token: &str, rng: &mut ChaCha8Rng) -> String {
    let mut chars: Vec<char> = token.chars().collect();
    if chars.is_empty() {
        return "x".into();
    }
    let i = rng.random_range(0..chars.len());
    match rng.random_range(0..3) {
        0 => chars[i] = ['0', '9', '-', '/', ',', '=', 'é', ' '][rng.random_range(0..8)],
        1 => {
            chars.remove(i);
        }
        _ => chars.insert(i, chars[i]),
    }
    chars.into_iter().collect()
}

/// Whether an input parsed (`Ok(true)`) or was refused well (`Ok(false)`); why it is a finding.
fn check(args: &[String]) -> Result<bool, String> {
    let argv = std::iter::once("nudge".to_string()).chain(args.iter().cloned());
    let parsed = catch_unwind(AssertUnwindSafe(|| Cli::try_parse_from(argv)))
        .map_err(|_| "the parser panicked".to_string())?;
    let Err(e) = parsed else {
        return Ok(true);
    };
    // A refused value must say which argument it was given to.
    if matches!(
        e.kind(),
        ErrorKind::InvalidValue | ErrorKind::ValueValidation
    ) {
        let text = e.render().to_string();
        if !(text.contains("--") || text.contains('<')) {
            return Err(format!(
                "a refused value's message names no argument: {text}"
            ));
        }
    }
    Ok(false)
}

fn main() -> ExitCode {
    let options = Options::parse();
    // The parser's own panics are caught and counted; the default hook would print each one.
    std::panic::set_hook(Box::new(|_| {}));
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    let started = Instant::now();
    let (mut parsed, mut refused, mut findings) = (0u64, 0u64, 0u64);
    for _ in 0..options.inputs {
        let args = mutate(&mut rng);
        match check(&args) {
            Ok(true) => parsed += 1,
            Ok(false) => refused += 1,
            Err(why) => {
                findings += 1;
                if findings <= 20 {
                    println!("finding: {args:?}: {why}");
                }
            }
        }
    }
    let seconds = started.elapsed().as_secs_f64();
    println!(
        "{} inputs (seed {}): {parsed} parsed, {refused} refused with a placed error, {findings} findings; {seconds:.1} s ({:.0} inputs/s)",
        options.inputs,
        options.seed,
        options.inputs as f64 / seconds.max(1e-9)
    );
    if findings == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}
