//! Command-line interface: argument types and dispatch; each subcommand lives in its own module.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

pub mod build;
pub mod check;
pub mod check_files;
pub mod check_plc;
pub mod fmt;
pub mod hmi_args;
pub mod nc;
pub mod nc_plot;
pub mod nc_run;
pub mod output;
pub mod plot;
pub mod replay;
pub mod run;
pub mod test;
pub mod trace;

/// ncplc: a soft CNC logic controller for NC-xxx style machines.
#[derive(Debug, Parser)]
#[command(name = "ncplc", version, about = "ncplc: a soft CNC logic controller for NC-xxx style machines", long_about = None, after_help = output::EXIT_CODES_HELP)]
pub struct Cli {
    /// Colour diagnostics: auto (when stderr is a terminal and NO_COLOR is unset), always, never.
    #[arg(long, value_enum, global = true, default_value_t = output::Color::Auto)]
    pub color: output::Color,
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Read and validate a machine: its characterization files (FCRSYS, AXCFIL, PGCFIL, IOCFIL) and every other file `run` reads (maps, sim.toml, tables, the PLC program).
    #[command(after_help = output::EXIT_CODES_HELP)]
    Check(check::Args),
    /// Compile the machine's PLC program and report diagnostics.
    #[command(after_help = output::EXIT_CODES_HELP)]
    Build(build::Args),
    /// Run the machine's logic in the cyclic runtime.
    #[command(after_help = output::EXIT_CODES_HELP)]
    Run(Box<run::Args>),
    /// Replay a recorded I/O trace and compare the outputs.
    #[command(after_help = output::EXIT_CODES_HELP)]
    Replay(replay::Args),
    /// Work with trace files.
    #[command(after_help = output::EXIT_CODES_HELP)]
    Trace(trace::Args),
    /// Check and plan partprograms.
    #[command(after_help = output::EXIT_CODES_HELP)]
    Nc(nc::Args),
    /// Draw plots (timing diagrams of traces) as SVG or PNG.
    Plot(plot::Args),
    /// Replay every golden trace of a machine (CI): one line per trace, JUnit XML, exit 1 on divergence.
    Test(test::Args),
    /// Serve the PLC language to an editor (Language Server Protocol over stdin/stdout).
    Lsp,
    /// Format a PLC source in place (layout only; `--check`: exit 1 when it is not formatted).
    Fmt {
        /// The PLC source.
        file: std::path::PathBuf,
        /// Only check; write nothing.
        #[arg(long)]
        check: bool,
    },
}

/// Runs the parsed command line and returns the process exit code.
pub fn main(cli: Cli) -> ExitCode {
    output::init(cli.color);
    if !matches!(cli.command, Command::Run(_)) {
        output::quiet_sigpipe();
    }
    match cli.command {
        Command::Check(a) => check::run(a),
        Command::Build(a) => build::run(a),
        Command::Run(a) => run::run(*a),
        Command::Replay(a) => replay::run(a),
        Command::Trace(a) => trace::run(a),
        Command::Nc(a) => nc::run(a),
        Command::Plot(a) => plot::run(a),
        Command::Test(a) => test::run(a),
        Command::Lsp => match plc_lsp::serve_stdio() {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("ncplc lsp: {e}");
                ExitCode::from(2)
            }
        },
        Command::Fmt { file, check } => fmt::run(&file, check),
    }
}
