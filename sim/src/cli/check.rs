//! `nudge check`: run scenarios and compare each with its `[expect]` block and the force limits.

use std::path::PathBuf;
use std::process::ExitCode;

use crate::score::{Outcome, compare};

use super::pool::{Cancel, Done, Job, run_all};
use super::source::{Source, expand};
use super::{CheckArgs, EXIT_FAILED};

/// How far over the force limit in force (a push test's, a clearing stroke's) the hand may press,
/// as a share of it: the guard stops a move within one control period of the limit, and what the
/// force rises in that period is the tolerance (10 %), not an impact at speed.
const FORCE_TOLERANCE: f64 = 1.1;

/// What one scenario's check came to.
enum Row {
    /// Met its `[expect]` block.
    Pass { summary: String },
    /// Differed from it; each difference in words.
    Fail {
        summary: String,
        differences: Vec<String>,
    },
    /// Has no `[expect]` block: ran, but nothing to compare.
    NoExpect { summary: String },
    /// Could not be loaded or run.
    Error(String),
}

pub(super) fn check(args: CheckArgs) -> anyhow::Result<ExitCode> {
    let files = expand(&args.scenarios)?;
    let loaded: Vec<(PathBuf, anyhow::Result<Source>)> = files
        .into_iter()
        .map(|f| {
            let source = Source::load(&f);
            (f, source)
        })
        .collect();
    let policy = args.policy.into();
    // One row per (file, seed offset), in that order; a file that did not load is one row.
    let mut labels: Vec<String> = Vec::new();
    let mut rows: Vec<Option<Row>> = Vec::new();
    let mut jobs: Vec<(usize, Job<'_>)> = Vec::new();
    for (path, source) in &loaded {
        let name = path.display().to_string();
        let s = match source {
            Ok(s) => s,
            Err(e) => {
                labels.push(name);
                rows.push(Some(Row::Error(format!("{e:#}"))));
                continue;
            }
        };
        let first = args.seed.unwrap_or(s.scenario.seed);
        for k in 0..args.seeds {
            let seed = first.wrapping_add(k);
            labels.push(if args.seeds > 1 {
                format!("{name} seed {seed}")
            } else {
                name.clone()
            });
            jobs.push((
                rows.len(),
                Job {
                    scenario: &s.scenario,
                    file: &s.file,
                    seed,
                    policy,
                },
            ));
            rows.push(None);
        }
    }
    let cancel = Cancel::default();
    let handler = cancel.clone();
    let _ = ctrlc::set_handler(move || handler.stop());
    let (indices, jobs): (Vec<usize>, Vec<Job<'_>>) = jobs.into_iter().unzip();
    run_all(
        &jobs,
        args.jobs.unwrap_or_else(super::cores),
        &cancel,
        |j, result| {
            let row = match result {
                Ok(done) => row(&jobs[j], &done),
                Err(e) => Row::Error(format!("{e:#}")),
            };
            rows[indices[j]] = Some(row);
        },
    );
    let failed = print_table(&labels, &rows);
    Ok(if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(EXIT_FAILED)
    })
}

/// What a finished run came to against its scenario's `[expect]` block.
fn row(job: &Job<'_>, done: &Done) -> Row {
    let outcome = Outcome::of(&done.report.outcome);
    let summary = format!(
        "{}, {} push tests, {:.1} s",
        outcome.word(),
        done.report.knowledge.push_tests,
        done.report.robot_time
    );
    let Some(expect) = &job.scenario.expect else {
        return Row::NoExpect { summary };
    };
    let mut differences: Vec<String> = compare(expect, outcome, &done.scored)
        .iter()
        .map(ToString::to_string)
        .collect();
    if let Some(share) = done.force_share.filter(|s| *s > FORCE_TOLERANCE) {
        differences.push(format!(
            "the hand pressed {:.0} % over the force limit in force",
            (share - 1.0) * 100.0
        ));
    }
    if differences.is_empty() {
        Row::Pass { summary }
    } else {
        Row::Fail {
            summary,
            differences,
        }
    }
}

/// Prints one line per run (or file that did not load) and the totals; returns how many failed
/// (errors and cancelled included).
fn print_table(labels: &[String], rows: &[Option<Row>]) -> usize {
    let mut failed = 0;
    let mut unchecked = 0;
    let width = labels.iter().map(String::len).max().unwrap_or(8).max(8);
    println!("{:<width$}  result    what happened", "scenario");
    for (name, row) in labels.iter().zip(rows) {
        match row {
            Some(Row::Pass { summary }) => println!("{name:<width$}  pass      {summary}"),
            Some(Row::Fail {
                summary,
                differences,
            }) => {
                failed += 1;
                println!(
                    "{name:<width$}  FAIL      {summary}: {}",
                    differences.join("; ")
                );
            }
            Some(Row::NoExpect { summary }) => {
                unchecked += 1;
                println!("{name:<width$}  no-expect {summary} (no [expect] block)");
            }
            Some(Row::Error(e)) => {
                failed += 1;
                println!("{name:<width$}  ERROR     {e}");
            }
            None => {
                failed += 1;
                println!("{name:<width$}  ERROR     not run (cancelled)");
            }
        }
    }
    let passed = rows.len() - failed - unchecked;
    println!("\n{passed} passed, {failed} failed, {unchecked} without [expect]");
    failed
}
