//! The `nudge` command: run scenarios in the simulation.

use std::process::ExitCode;

use clap::Parser;

mod cli;

fn main() -> ExitCode {
    let args = cli::Cli::parse();
    match cli::dispatch(args) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("nudge: {e}");
            ExitCode::from(cli::EXIT_INPUT)
        }
    }
}
