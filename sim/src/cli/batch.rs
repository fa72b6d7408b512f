//! `nudge batch`: every (scenario × policy × seed) run in parallel, one JSON line each, and a
//! summary table; `--shard i/n` keeps every run whose index mod n is i.
//!
//! Runs are numbered in a stable order: scenario files sorted by name, then the policies in the
//! order given, then seed offsets 0..N. Offset k runs with seed `scenario.seed + k`, so offset 0 is
//! the run `nudge run FILE` does.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};

use super::pool::{Cancel, Job, NotDone, run_all};
use super::results::{Group, RunLine, table};
use super::source::{Source, expand};
use super::{BatchArgs, EXIT_ABORTED, EXIT_INPUT, Shard};

pub(super) fn batch(args: BatchArgs) -> anyhow::Result<ExitCode> {
    let sources = expand(&args.scenarios)?
        .iter()
        .map(|p| Source::load(p))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let policies = if args.policy.is_empty() {
        vec![super::Policy::Nearest]
    } else {
        args.policy.clone()
    };
    let shard = args.shard.unwrap_or(Shard { index: 0, count: 1 });
    let jobs: Vec<Job<'_>> = all_jobs(&sources, &policies, args.seeds)
        .into_iter()
        .enumerate()
        .filter(|(i, _)| shard.takes(*i))
        .map(|(_, job)| job)
        .collect();
    let out_path = args.out.clone().unwrap_or_else(|| match args.shard {
        Some(s) => PathBuf::from(format!("results.shard-{}-of-{}.jsonl", s.index, s.count)),
        None => PathBuf::from("results.jsonl"),
    });
    let mut out = BufWriter::new(
        File::create(&out_path).with_context(|| format!("cannot create {}", out_path.display()))?,
    );
    let threads = args.jobs.unwrap_or_else(super::cores);
    eprintln!(
        "nudge batch: {} runs ({} scenarios × {} policies × {} seeds, shard {}/{}) on {threads} threads -> {}",
        jobs.len(),
        sources.len(),
        policies.len(),
        args.seeds,
        shard.index,
        shard.count,
        out_path.display()
    );
    let bar = ProgressBar::new(jobs.len() as u64).with_style(
        ProgressStyle::with_template(
            "{elapsed_precise} [{bar:30}] {pos}/{len} runs, eta {eta} {msg}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    let cancel = Cancel::default();
    let handler = cancel.clone();
    let _ = ctrlc::set_handler(move || handler.stop());
    // Each line is written as its run finishes, so a batch killed midway loses no finished run;
    // when the batch ends the file is rewritten in run order, so it is the same whatever order the
    // workers start and finish in.
    let mut finished: Vec<Option<RunLine>> = Vec::new();
    finished.resize_with(jobs.len(), || None);
    let mut failures = 0;
    let mut write_error: Option<std::io::Error> = None;
    run_all(&jobs, threads, &cancel, |i, result| {
        let line = match result {
            Ok(done) => {
                let line = RunLine::of(&jobs[i], &done);
                bar.set_message(format!(
                    "{} seed {}: {}",
                    line.scenario, line.seed, line.outcome
                ));
                Some(line)
            }
            Err(NotDone::Cancelled) => None,
            Err(NotDone::Failed(e)) => {
                failures += 1;
                bar.println(format!(
                    "nudge: {} seed {} failed: {e:#}",
                    jobs[i].file, jobs[i].seed
                ));
                None
            }
        };
        bar.inc(1);
        if let Some(line) = &line
            && write_error.is_none()
            && let Err(e) = write_line(line, &mut out)
        {
            write_error = Some(e);
        }
        if let Some(slot) = finished.get_mut(i) {
            *slot = line;
        }
    });
    bar.finish_and_clear();
    out.flush()
        .with_context(|| format!("cannot write {}", out_path.display()))?;
    drop(out);
    if let Some(e) = write_error {
        return Err(e).with_context(|| format!("cannot write {}", out_path.display()));
    }
    let lines: Vec<RunLine> = finished.into_iter().flatten().collect();
    if let Err(e) = rewrite_in_order(&out_path, &lines) {
        // The file still holds every line, in the order the runs finished.
        eprintln!(
            "nudge: {} holds its lines in finishing order: {e:#}",
            out_path.display()
        );
    }
    print!("{}", table(&lines, Group::Family));
    println!("{} result lines in {}", lines.len(), out_path.display());
    Ok(if cancel.is_stopped() {
        eprintln!(
            "nudge: batch cancelled after {} of {} runs",
            lines.len(),
            jobs.len()
        );
        ExitCode::from(EXIT_ABORTED)
    } else if failures > 0 {
        ExitCode::from(EXIT_INPUT)
    } else {
        ExitCode::SUCCESS
    })
}

/// Appends `line` to `out` as one JSON line and flushes it.
fn write_line(line: &RunLine, out: &mut impl Write) -> std::io::Result<()> {
    let json = serde_json::to_string(line).map_err(std::io::Error::other)?;
    writeln!(out, "{json}")?;
    out.flush()
}

/// Replaces `path` with `lines` in run order, through a file beside it renamed over it, so the
/// results are never half written.
fn rewrite_in_order(path: &std::path::Path, lines: &[RunLine]) -> anyhow::Result<()> {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".in-order");
    let sorted = path.with_file_name(name);
    let mut out = BufWriter::new(
        File::create(&sorted).with_context(|| format!("cannot create {}", sorted.display()))?,
    );
    for line in lines {
        write_line(line, &mut out).with_context(|| format!("cannot write {}", sorted.display()))?;
    }
    drop(out);
    std::fs::rename(&sorted, path).map_err(|e| {
        let _ = std::fs::remove_file(&sorted);
        anyhow::Error::new(e).context(format!(
            "cannot rename {} to {}",
            sorted.display(),
            path.display()
        ))
    })
}

/// Every run of the batch in its stable order: files, then policies, then seed offsets.
fn all_jobs<'a>(sources: &'a [Source], policies: &[super::Policy], seeds: u64) -> Vec<Job<'a>> {
    let mut jobs = Vec::new();
    for source in sources {
        for policy in policies {
            for k in 0..seeds {
                jobs.push(Job {
                    scenario: &source.scenario,
                    file: &source.file,
                    seed: source.scenario.seed.wrapping_add(k),
                    policy: (*policy).into(),
                });
            }
        }
    }
    jobs
}

#[cfg(test)]
mod tests {
    use super::super::policy_word;
    use super::*;

    #[test]
    fn shards_split_the_runs_without_overlap_or_gap() {
        // Invariant: the shards 0/n..n-1/n of a batch take every run exactly once, and offset k runs seed scenario.seed + k.
        let sources = vec![Source::default_room().expect("default room")];
        let policies = [
            super::super::Policy::Nearest,
            super::super::Policy::Blocking,
        ];
        let jobs = all_jobs(&sources, &policies, 5);
        assert_eq!(jobs.len(), 10);
        let seed = sources[0].scenario.seed;
        assert_eq!(jobs[0].seed, seed);
        assert_eq!(jobs[4].seed, seed + 4);
        assert_eq!(policy_word(jobs[5].policy), "blocking");
        let n = 3;
        let mut taken = vec![0; jobs.len()];
        for index in 0..n {
            let shard = Shard { index, count: n };
            for (i, t) in taken.iter_mut().enumerate() {
                if shard.takes(i) {
                    *t += 1;
                }
            }
        }
        assert!(taken.iter().all(|&t| t == 1), "{taken:?}");
    }
}
