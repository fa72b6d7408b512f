//! The `nudge` command: run scenarios in the simulation.

use std::process::ExitCode;

use clap::Parser;
use nudge_sim::cli;

fn main() -> ExitCode {
    let args = cli::Cli::parse();
    match cli::dispatch(args) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("nudge: {}", message(&e));
            ExitCode::from(cli::EXIT_INPUT)
        }
    }
}

/// The error and its causes on one line, skipping a cause its parent's message already ends with.
fn message(e: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in e.chain() {
        let part = cause.to_string();
        if !text.ends_with(&part) {
            if !text.is_empty() {
                text.push_str(": ");
            }
            text.push_str(&part);
        }
    }
    text
}
