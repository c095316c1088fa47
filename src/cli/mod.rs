//! The command line: argument parsing (clap) and dispatch to `app`.
//!
//! Input: `argv`. Output: an exit code. stdout carries data (tables, JSON); stderr carries
//! progress and errors. Exit codes: 0 done (per-question failures are data), 1 user or data
//! error, 2 usage or internal error.

mod args;
mod bench_args;
mod report_args;

pub use args::{Cli, Command};

use std::process::ExitCode;

use clap::Parser;

use crate::app;

/// Parses `argv` and runs the command.
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(error) => {
            // clap prints help and version to stdout with exit 0, usage errors to stderr with 2.
            let _ = error.print();
            return ExitCode::from(u8::try_from(error.exit_code()).unwrap_or(2));
        }
    };
    app::execute(cli.into_request())
}
