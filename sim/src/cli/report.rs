//! `nudge report`: merge result files (the shards of a batch) and print the summary table.

use std::collections::BTreeSet;
use std::process::ExitCode;

use super::ReportArgs;
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
    print!("{}", table(&lines));
    println!("{} runs from {} files", lines.len(), args.files.len());
    Ok(ExitCode::SUCCESS)
}
