//! Command-line interface: argument types and dispatch; each subcommand lives in its own module.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

pub mod build;
pub mod check;
pub mod nc;
pub mod nc_run;
pub mod part_run;
pub mod replay;
pub mod run;
pub mod trace;

/// ncplc: a soft CNC logic controller for NC-xxx style machines.
#[derive(Debug, Parser)]
#[command(name = "ncplc", version, about = "ncplc: a soft CNC logic controller for NC-xxx style machines", long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Read and validate a machine's characterization files (FCRSYS, AXCFIL, PGCFIL, IOCFIL).
    Check(check::Args),
    /// Compile the machine's PLC program and report diagnostics.
    Build(build::Args),
    /// Run the machine's logic in the cyclic runtime.
    Run(run::Args),
    /// Replay a recorded I/O trace and compare the outputs.
    Replay(replay::Args),
    /// Work with trace files.
    Trace(trace::Args),
    /// Check and plan partprograms.
    Nc(nc::Args),
}

/// Runs the parsed command line and returns the process exit code.
pub fn main(cli: Cli) -> ExitCode {
    match cli.command {
        Command::Check(a) => check::run(a),
        Command::Build(a) => build::run(a),
        Command::Run(a) => run::run(a),
        Command::Replay(a) => replay::run(a),
        Command::Trace(a) => trace::run(a),
        Command::Nc(a) => nc::run(a),
    }
}
