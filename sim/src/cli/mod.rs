//! Command-line interface: `nudge run`, `check`, `batch`, `report`, `inspect`, `replay` and
//! `generate`. It lives
//! in the library so that harnesses (the argument fuzzer in `examples/fuzz_cli.rs`) parse and
//! dispatch exactly what the `nudge` binary does.

mod batch;
mod check;
mod generate;
mod inspect;
mod map;
mod pool;
mod replay;
mod report;
mod results;
mod run;
mod schedule;
mod segmentation;
mod sim_bridge;
mod source;
mod timeline;

use std::path::PathBuf;
use std::process::ExitCode;
use std::str::FromStr;

use clap::{Parser, Subcommand, ValueEnum};
use nudge_executive::CandidatePolicy;

/// Exit code: bad input (files, scenarios, recordings) or a run that could not be set up.
pub const EXIT_INPUT: u8 = 1;
/// Exit code: the run ended in NoPathToGoal.
pub const EXIT_NO_PATH: u8 = 3;
/// Exit code: the run was aborted (robot failure, limit, Ctrl-C), or a batch was cancelled.
pub const EXIT_ABORTED: u8 = 4;
/// Exit code: `nudge check` found a scenario that did not meet its `[expect]` block.
pub const EXIT_FAILED: u8 = 5;
/// Exit code: `nudge replay` found the new run parting from the recorded one.
pub const EXIT_DIVERGED: u8 = 6;

/// nudge: a humanoid reaches a goal among unknown obstacles, pushing them to learn which move.
#[derive(Parser, Debug)]
#[command(name = "nudge", version)]
pub struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run one scenario (the paper's room when none is given) and print its timeline and summary.
    Run(RunArgs),
    /// Run scenarios and compare each with its `[expect]` block (and the force limits: no push more
    /// than 10 % over its limit); exit 5 when any differs.
    Check(CheckArgs),
    /// Run every scenario of a folder with many seeds in parallel; one JSON line per run.
    Batch(BatchArgs),
    /// Merge result files of `nudge batch` (e.g. its shards) and print the summary table.
    Report(ReportArgs),
    /// Show what an MCAP recording holds: topics, counts, time span, metadata, the run's summary.
    Inspect(InspectArgs),
    /// Run the current executive on a recording's inputs (its /nudge/tape) and report whether every
    /// call and transition matches. Exit 0: match; 6: the run parted from the recording (the first
    /// divergence is printed); 1: the file is missing, not MCAP, truncated, corrupt or has no tape.
    Replay(ReplayArgs),
    /// Write generated scenarios of one or more families, each with an [expect] block right by
    /// construction (checked against the true world).
    Generate(GenerateArgs),
    /// Score perception's segmentation against the simulation's truth: one look-around from each
    /// scenario's start, each object's purity and completeness, averaged per family.
    Segmentation(SegmentationArgs),
    /// Serve a scenario's simulated robot over ROS 2 (DDS), lock-stepped to its client: the topics,
    /// frames and QoS of `--ros2` (defaults otherwise), as `nudge run --robot ros2` expects them.
    /// Ends when the client has been silent for `--idle` seconds, or on Ctrl-C.
    SimBridge(SimBridgeArgs),
}

/// Which robot a run drives.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
enum RobotKind {
    /// The simulation, in this process.
    #[default]
    Sim,
    /// A robot over ROS 2 (DDS): a real one, or `nudge sim-bridge` in another process.
    Ros2,
}

#[derive(clap::Args, Debug)]
struct SimBridgeArgs {
    /// Scenario file (TOML); the paper's room when omitted.
    scenario: Option<PathBuf>,
    /// Seed of the world; the scenario's own seed when omitted.
    #[arg(long)]
    seed: Option<u64>,
    /// The ROS 2 graph (topics, frames, QoS, domain) as TOML; every field defaults.
    #[arg(long, value_name = "FILE.toml")]
    ros2: Option<PathBuf>,
    /// Seconds without a step request, once a client has asked, after which a lock-stepped bridge
    /// ends.
    #[arg(long, default_value_t = 5.0)]
    idle: f64,
    /// Run by itself at this many robot seconds per wall second instead of lock-stepped to a
    /// client (for ROS 2 clients other than nudge: teleoperation, RViz).
    #[arg(long, value_name = "FACTOR")]
    real_time_factor: Option<f64>,
    /// With --real-time-factor: end at this robot time (s); Ctrl-C otherwise.
    #[arg(long, value_name = "SECONDS", requires = "real_time_factor")]
    until: Option<f64>,
    /// Put a fault on the wire at a robot time, to test a client: KIND@SECONDS, KIND one of
    /// nan-wrench, clock-back, stale-camera-tf, quiet. Repeatable.
    #[arg(long, value_name = "KIND@SECONDS")]
    fault: Vec<crate::bridge::ScheduledFault>,
}

/// Candidate policy as typed on the command line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
enum Policy {
    /// The obstacle nearest the robot first (the paper's rule).
    #[default]
    Nearest,
    /// The obstacle whose removal opens the cheapest path first.
    Blocking,
}

impl From<Policy> for CandidatePolicy {
    fn from(p: Policy) -> Self {
        match p {
            Policy::Nearest => CandidatePolicy::Nearest,
            Policy::Blocking => CandidatePolicy::Blocking,
        }
    }
}

/// The policy's name as the command line and result lines spell it.
fn policy_word(p: CandidatePolicy) -> &'static str {
    match p {
        CandidatePolicy::Nearest => "nearest",
        CandidatePolicy::Blocking => "blocking",
    }
}

/// `--jobs`: a count of runs at once; 0 is refused (it would run nothing, or quietly one).
fn at_least_one_job() -> clap::builder::RangedU64ValueParser<usize> {
    clap::builder::RangedU64ValueParser::<usize>::new().range(1..)
}

/// Worker threads when `--jobs` is not given: one per core.
fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

#[derive(clap::Args, Debug, Default)]
struct RunArgs {
    /// Scenario file (TOML); the paper's room when omitted.
    scenario: Option<PathBuf>,
    /// Seed of the run; the scenario's own seed when omitted.
    #[arg(long)]
    seed: Option<u64>,
    /// Candidate policy.
    #[arg(long, value_enum, default_value = "nearest")]
    policy: Option<Policy>,
    /// Record the run to this MCAP file (open it in Foxglove).
    #[arg(long, value_name = "FILE.mcap")]
    record: Option<PathBuf>,
    /// Show every Nth pixel of every Nth row of the camera's clouds in the recording (1: all; by
    /// default a point per grid cell at 2 m, every fifth for the paper's camera). The replay tape
    /// keeps every point whatever this is.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=64))]
    record_cloud_stride: Option<u32>,
    /// Draw the run top-down into this PNG, with a force-over-time panel per push test.
    #[arg(long, value_name = "FILE.png")]
    map: Option<PathBuf>,
    /// Print only the summary, not the timeline.
    #[arg(long)]
    quiet: bool,
    /// The robot to drive: the simulation in this process, or a robot over ROS 2.
    #[arg(long, value_enum, default_value = "sim")]
    robot: RobotKind,
    /// With `--robot ros2`: the robot's ROS 2 graph (topics, frames, QoS, domain, use_sim_time) as
    /// TOML; every field defaults.
    #[arg(long, value_name = "FILE.toml")]
    ros2: Option<PathBuf>,
}

#[derive(clap::Args, Debug)]
struct CheckArgs {
    /// Scenario files, or folders (every *.toml in them, sorted by name).
    #[arg(required = true, value_name = "SCENARIO_OR_DIR")]
    scenarios: Vec<PathBuf>,
    /// Seed of every run; each scenario's own seed when omitted.
    #[arg(long)]
    seed: Option<u64>,
    /// Seeds per scenario: offset k runs with that seed + k, k = 0..N; one row each.
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..))]
    seeds: u64,
    /// Candidate policy.
    #[arg(long, value_enum, default_value = "nearest")]
    policy: Policy,
    /// Runs at once, at least 1 (default: one per core).
    #[arg(long, value_parser = at_least_one_job())]
    jobs: Option<usize>,
}

#[derive(clap::Args, Debug)]
struct SegmentationArgs {
    /// Scenario files, or folders (every *.toml in them, sorted by name).
    #[arg(required = true, value_name = "SCENARIO_OR_DIR")]
    scenarios: Vec<PathBuf>,
    /// Seeds per scenario: offset k looks with the scenario's seed + k, k = 0..N.
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..))]
    seeds: u64,
    /// Looks at once, at least 1 (default: one per core).
    #[arg(long, value_parser = at_least_one_job())]
    jobs: Option<usize>,
    /// Also print every seen object's score, worst first.
    #[arg(long)]
    objects: bool,
}

#[derive(clap::Args, Debug)]
struct BatchArgs {
    /// Folder of scenarios (every *.toml, sorted by name), or scenario files.
    #[arg(required = true, value_name = "DIR")]
    scenarios: Vec<PathBuf>,
    /// Seeds per scenario and policy: offset k runs with the scenario's seed + k, k = 0..N.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    seeds: u64,
    /// Runs at once, at least 1 (default: one per core).
    #[arg(long, value_name = "J", value_parser = at_least_one_job())]
    jobs: Option<usize>,
    /// Result file, one JSON line per run (default results.jsonl, or results.shard-I-of-N.jsonl).
    #[arg(long, value_name = "FILE.jsonl")]
    out: Option<PathBuf>,
    /// Run only this shard: runs whose index mod N is I (for Slurm or Kubernetes job arrays).
    #[arg(long, value_name = "I/N")]
    shard: Option<Shard>,
    /// Candidate policies, comma-separated; each scenario and seed runs with every one.
    #[arg(long, value_enum, value_delimiter = ',')]
    policy: Vec<Policy>,
}

#[derive(clap::Args, Debug)]
struct ReportArgs {
    /// Result files of `nudge batch` (shards are merged; repeated runs count once).
    #[arg(required = true, value_name = "RESULTS.jsonl")]
    files: Vec<PathBuf>,
    /// One row per family (a hand-made scenario is its own family) or per scenario.
    #[arg(long, value_enum, default_value = "family")]
    by: results::Group,
    /// Also write every run as one CSV row to this file.
    #[arg(long, value_name = "FILE.csv")]
    csv: Option<PathBuf>,
}

#[derive(clap::Args, Debug)]
struct GenerateArgs {
    /// Families to generate (each: what it varies and guarantees is in `nudge generate --help`'s
    /// list and the README).
    #[arg(required = true, value_enum, value_name = "FAMILY")]
    families: Vec<crate::generate::Family>,
    /// Scenarios per family.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=10_000))]
    count: u64,
    /// Generator seed: the same seed writes the same files.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Folder to write FAMILY-NNN.toml files into (made if missing).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
}

#[derive(clap::Args, Debug)]
struct InspectArgs {
    /// The MCAP recording.
    #[arg(value_name = "FILE.mcap")]
    file: PathBuf,
}

#[derive(clap::Args, Debug)]
struct ReplayArgs {
    /// A recording made by `nudge run --record`.
    #[arg(value_name = "FILE.mcap")]
    file: PathBuf,
    /// Change one executive setting before replaying (repeatable), to see where the change parts
    /// from the recorded run. Keys: force_limit (N, the push test's), clear_force_limit (N),
    /// push_speed (m/s), max_push_tests.
    #[arg(long, value_name = "KEY=VALUE")]
    set: Vec<crate::replay::Setting>,
}

/// Part `index` of `count` of a batch.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// Which part, from 0.
    pub index: usize,
    /// How many parts.
    pub count: usize,
}

impl Shard {
    /// True when run number `run` (in the batch's stable order) belongs to this shard.
    pub fn takes(&self, run: usize) -> bool {
        run % self.count == self.index
    }
}

impl FromStr for Shard {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let (i, n) = s
            .split_once('/')
            .ok_or_else(|| format!("'{s}' is not I/N (e.g. 0/4)"))?;
        let index: usize = i
            .trim()
            .parse()
            .map_err(|_| format!("shard index '{i}' is not a whole number"))?;
        let count: usize = n
            .trim()
            .parse()
            .map_err(|_| format!("shard count '{n}' is not a whole number"))?;
        if count == 0 {
            return Err("the shard count must be at least 1".into());
        }
        if index >= count {
            return Err(format!(
                "shard index {index} must be below the count {count} (0/{count} .. {}/{count})",
                count - 1
            ));
        }
        Ok(Self { index, count })
    }
}

/// Runs the parsed command; `nudge` alone runs the paper's room.
pub fn dispatch(cli: Cli) -> anyhow::Result<ExitCode> {
    match cli.command {
        Some(Command::Run(args)) => run::run(args),
        Some(Command::Check(args)) => check::check(args),
        Some(Command::Batch(args)) => batch::batch(args),
        Some(Command::Report(args)) => report::report(args),
        Some(Command::Inspect(args)) => inspect::inspect(args),
        Some(Command::Replay(args)) => replay::replay(args),
        Some(Command::Generate(args)) => generate::generate(args),
        Some(Command::Segmentation(args)) => segmentation::segmentation(args),
        Some(Command::SimBridge(args)) => sim_bridge::sim_bridge(args),
        None => run::run(RunArgs::default()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shard_specs_parse_or_say_what_is_wrong() {
        // Invariant: I/N with I < N parses; anything else is refused with a reason.
        assert_eq!("2/4".parse(), Ok(Shard { index: 2, count: 4 }));
        for (bad, why) in [
            ("4/4", "must be below"),
            ("1/0", "at least 1"),
            ("x/2", "not a whole number"),
            ("3", "is not I/N"),
            ("-1/2", "not a whole number"),
        ] {
            let err = bad.parse::<Shard>().expect_err(bad);
            assert!(err.contains(why), "{bad}: {err}");
        }
    }

    #[test]
    fn zero_jobs_is_refused_naming_the_argument() {
        // Invariant: `--jobs 0` (which would run nothing) is refused with a message naming --jobs,
        // for batch and check alike; `--jobs 1` parses.
        use clap::Parser;
        for command in ["batch", "check"] {
            let err =
                Cli::try_parse_from(["nudge", command, "scenarios", "--seeds", "1", "--jobs", "0"])
                    .expect_err(command)
                    .to_string();
            assert!(err.contains("--jobs"), "{command}: {err}");
            assert!(
                Cli::try_parse_from(["nudge", command, "scenarios", "--seeds", "1", "--jobs", "1"])
                    .is_ok(),
                "{command}"
            );
        }
    }
}
