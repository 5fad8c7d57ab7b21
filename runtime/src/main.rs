//! The `ncplc` command-line tool: one subcommand per job, each in its own module under `cli/`.

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    runtime::cli::main(runtime::cli::Cli::parse())
}
