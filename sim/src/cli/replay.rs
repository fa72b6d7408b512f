//! `nudge replay`: the current executive on a recording's inputs; match or the first divergence.

use std::process::ExitCode;

use crate::replay::replay_file;

use super::{EXIT_DIVERGED, ReplayArgs, policy_word};

pub(super) fn replay(args: ReplayArgs) -> anyhow::Result<ExitCode> {
    let r = replay_file(&args.file, &args.set)?;
    println!(
        "replay: {} ({} attached), seed {}, policy {}, recorded by nudge {}",
        r.scenario,
        r.scenario_file,
        r.seed,
        policy_word(r.policy),
        r.version
    );
    for s in &args.set {
        println!("setting: {s:?}");
    }
    match &r.divergence {
        None => {
            let outcome = if r.outcome_recorded {
                "same outcome"
            } else {
                "outcome not compared (the recorded run has no summary)"
            };
            println!(
                "match: {} calls, {} transitions, {outcome} ({} after {:.1} s robot time)",
                r.calls,
                r.transitions,
                r.report.outcome.name(),
                r.report.robot_time
            );
            Ok(ExitCode::SUCCESS)
        }
        Some(d) => {
            println!(
                "{d}\n  ({} calls and {} transitions matched before it, of {} tape entries)",
                r.calls, r.transitions, r.entries
            );
            Ok(ExitCode::from(EXIT_DIVERGED))
        }
    }
}
