//! Command-line interface: `nudge run`.

mod run;
mod timeline;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use nudge_executive::CandidatePolicy;

/// Exit code: bad input (files, flags).
pub const EXIT_INPUT: u8 = 1;
/// Exit code: the run ended in NoPathToGoal.
pub const EXIT_NO_PATH: u8 = 3;
/// Exit code: the run was aborted (robot failure, limit, Ctrl-C).
pub const EXIT_ABORTED: u8 = 4;

/// nudge: a humanoid reaches a goal among unknown obstacles, pushing them to learn which move.
#[derive(Parser, Debug)]
#[command(name = "nudge", version, about)]
pub struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run one scenario (the paper's room when none is given) and print its timeline and summary.
    Run(RunArgs),
}

/// Candidate policy as typed on the command line.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum Policy {
    /// The obstacle nearest the robot first (the paper's rule).
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
    /// Print only the summary, not the timeline.
    #[arg(long)]
    quiet: bool,
}

/// Runs the parsed command; `nudge` alone runs the paper's room.
pub fn dispatch(cli: Cli) -> anyhow::Result<ExitCode> {
    match cli.command {
        Some(Command::Run(args)) => run::run(args),
        None => run::run(RunArgs::default()),
    }
}
