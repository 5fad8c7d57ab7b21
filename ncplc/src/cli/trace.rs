//! `ncplc trace`: convert trace files (`dump` binary → text, `pack` text → binary).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use trace::{Trace, binary};

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
    #[command(after_help = crate::cli::output::EXIT_CODES_HELP)]
    Dump {
        /// The trace file.
        file: PathBuf,
    },
    /// Convert a trace to the binary form.
    #[command(after_help = crate::cli::output::EXIT_CODES_HELP)]
    Pack {
        /// The trace file.
        file: PathBuf,
        /// The binary file to write.
        out: PathBuf,
    },
    /// Read the complete records of a crashed recording (`FILE.partial`), dropping the torn tail.
    ///
    /// Without OUT, prints the records in the text form; with OUT, writes them there (binary when
    /// OUT ends in `.ptrace` or `.bin`). What was kept and dropped goes to stderr.
    #[command(after_help = crate::cli::output::EXIT_CODES_HELP)]
    Recover {
        /// The partial trace file.
        file: PathBuf,
        /// The trace file to write.
        out: Option<PathBuf>,
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
                runtime::atomic_file::write(&out, &bytes)
                    .map_err(|e| format!("{}: {e}", out.display()))
            }),
        TraceCommand::Recover { file, out } => recover_file(&file, out.as_deref()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("{e}");
            ExitCode::from(2)
        }
    }
}

fn recover_file(file: &Path, out: Option<&Path>) -> Result<(), String> {
    let bytes = std::fs::read(file).map_err(|e| format!("{}: {e}", file.display()))?;
    let r = trace::recover::recover(&bytes).map_err(|e| format!("{}: {e}", file.display()))?;
    eprintln!("{}: {}", file.display(), r.summary());
    match out {
        None => {
            let stdout = std::io::stdout();
            let mut lock = std::io::BufWriter::new(stdout.lock());
            r.trace.write_text(&mut lock).map_err(|e| e.to_string())?;
            lock.flush().map_err(|e| e.to_string())
        }
        Some(out) => {
            let binary = matches!(
                out.extension().and_then(|e| e.to_str()),
                Some("ptrace" | "bin")
            );
            let bytes = if binary {
                binary::encode(&r.trace).map_err(|e| e.to_string())?
            } else {
                let mut v = Vec::new();
                r.trace.write_text(&mut v).map_err(|e| e.to_string())?;
                v
            };
            runtime::atomic_file::write(out, &bytes).map_err(|e| format!("{}: {e}", out.display()))
        }
    }
}
