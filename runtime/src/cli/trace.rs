//! `ncplc trace`: convert trace files (`dump` binary → text, `pack` text → binary).

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use crate::trace::{Trace, binary};

/// Arguments of `ncplc trace`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// What to do.
    #[command(subcommand)]
    pub command: TraceCommand,
}

/// `ncplc trace` subcommands.
#[derive(Debug, clap::Subcommand)]
pub enum TraceCommand {
    /// Print a trace (binary or text) in the text form.
    Dump {
        /// The trace file.
        file: PathBuf,
    },
    /// Convert a trace to the binary form.
    Pack {
        /// The trace file.
        file: PathBuf,
        /// The binary file to write.
        out: PathBuf,
    },
}

/// Runs `ncplc trace`.
pub fn run(args: Args) -> ExitCode {
    let result = match args.command {
        TraceCommand::Dump { file } => Trace::load(&file)
            .map_err(|e| format!("{}: {e}", file.display()))
            .and_then(|t| {
                let stdout = std::io::stdout();
                let mut lock = std::io::BufWriter::new(stdout.lock());
                t.write_text(&mut lock).map_err(|e| e.to_string())?;
                lock.flush().map_err(|e| e.to_string())
            }),
        TraceCommand::Pack { file, out } => Trace::load(&file)
            .map_err(|e| format!("{}: {e}", file.display()))
            .and_then(|t| binary::encode(&t).map_err(|e| e.to_string()))
            .and_then(|bytes| {
                crate::atomic_file::write(&out, &bytes)
                    .map_err(|e| format!("{}: {e}", out.display()))
            }),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("{e}");
            ExitCode::from(2)
        }
    }
}
