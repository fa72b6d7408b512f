//! `nudge report`: merge result files (the shards of a batch), print the summary table per family
//! or scenario, and write the runs as CSV for a spreadsheet or DuckDB.

use std::collections::BTreeSet;
use std::process::ExitCode;

use super::ReportArgs;
use anyhow::Context;

use super::results::{RunLine, read, table};

pub(super) fn report(args: ReportArgs) -> anyhow::Result<ExitCode> {
    let mut seen = BTreeSet::new();
    let mut lines: Vec<RunLine> = Vec::new();
    let mut duplicates = 0;
    for path in &args.files {
        for line in read(path)? {
            // Overlapping shards or a file named twice must not count a run twice.
            if seen.insert(line.key()) {
                lines.push(line);
            } else {
                duplicates += 1;
            }
        }
    }
    if duplicates > 0 {
        eprintln!("nudge: {duplicates} duplicate runs ignored (same scenario, file, policy, seed)");
    }
    print!("{}", table(&lines, args.by));
    println!("{} runs from {} files", lines.len(), args.files.len());
    if let Some(path) = &args.csv {
        write_csv(path, &lines).with_context(|| format!("cannot write {}", path.display()))?;
        println!("{} rows in {}", lines.len(), path.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// One row per run with a header, every field of the result line (an absent value is empty).
fn write_csv(path: &std::path::Path, lines: &[RunLine]) -> anyhow::Result<()> {
    let mut out = csv::Writer::from_path(path)?;
    for line in lines {
        out.serialize(line)?;
    }
    out.flush()?;
    Ok(())
}
