//! `ncplc trace`: convert trace files (`dump` binary → text, `pack` text → binary).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use runtime::atomic_file::Pending;
use trace::binary::BinaryWriter;
use trace::reader::Reader;
use trace::text::TextWriter;
use trace::{PartHeader, TickRecord, TraceError, TraceSink};

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
        TraceCommand::Dump { file } => dump(&file),
        TraceCommand::Pack { file, out } => pack(&file, &out),
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

/// Prints `file` in the text form, record by record.
fn dump(file: &Path) -> Result<(), String> {
    let located = |e: TraceError| format!("{}: {e}", file.display());
    let reader = Reader::open(file).map_err(located)?;
    let stdout = std::io::stdout();
    let lock = std::io::BufWriter::new(stdout.lock());
    let h = reader.header().clone();
    let mut w =
        TextWriter::with_part(lock, h.tick_ms, h.part.as_ref()).map_err(|e| e.to_string())?;
    for r in reader {
        w.record(&r.map_err(located)?).map_err(|e| e.to_string())?;
    }
    w.get_mut().flush().map_err(|e| e.to_string())
}

/// Writes `file` in the binary form to `out`, record by record (`out` is replaced at the end).
fn pack(file: &Path, out: &Path) -> Result<(), String> {
    let located = |e: TraceError| format!("{}: {e}", file.display());
    let reader = Reader::open(file).map_err(located)?;
    let h = reader.header().clone();
    let mut w = TraceFile::create(out, h.tick_ms, h.part.as_ref(), true)?;
    for r in reader {
        w.record(&r.map_err(located)?).map_err(|e| e.to_string())?;
    }
    w.finish().map_err(|e| e.to_string())
}

/// The complete records of `file`, read one at a time, printed as text or written to `out`.
fn recover_file(file: &Path, out: Option<&Path>) -> Result<(), String> {
    let name = file.display();
    let size = std::fs::metadata(file).map_or(0, |m| m.len());
    let input = std::fs::File::open(file).map_err(|e| format!("{name}: {e}"))?;
    let mut reader = Reader::recovering(std::io::BufReader::with_capacity(1 << 16, input))
        .map_err(|e| format!("{name}: {e}"))?;
    let h = reader.header().clone();
    let mut sink: Box<dyn TraceSink> = match out {
        None => {
            let stdout = std::io::BufWriter::new(std::io::stdout());
            let w = TextWriter::with_part(stdout, h.tick_ms, h.part.as_ref());
            Box::new(w.map_err(|e| e.to_string())?)
        }
        Some(out) => {
            let binary = matches!(
                out.extension().and_then(|e| e.to_str()),
                Some("ptrace" | "bin")
            );
            Box::new(TraceFile::create(out, h.tick_ms, h.part.as_ref(), binary)?)
        }
    };
    let (mut n, mut last) = (0, None);
    while let Some(Ok(r)) = reader.next() {
        sink.record(&r).map_err(|e| e.to_string())?;
        n += 1;
        last = Some(r.t);
    }
    let dropped = size.saturating_sub(reader.complete_bytes());
    eprintln!("{name}: {}", trace::recover::summary(n, last, dropped));
    sink.finish().map_err(|e| e.to_string())
}

/// A trace file being written record by record: it replaces its path only at
/// [`TraceSink::finish`], so an error or interruption leaves the old file (`trace pack`,
/// `trace recover OUT`, `replay --update`).
pub(crate) struct TraceFile {
    sink: Box<dyn TraceSink>,
    pending: Option<Pending>,
    name: String,
}

impl TraceFile {
    /// Starts the file that will replace `path`, in the binary form or the text one.
    pub(crate) fn create(
        path: &Path,
        tick_ms: u32,
        part: Option<&PartHeader>,
        binary: bool,
    ) -> Result<TraceFile, String> {
        let name = path.display().to_string();
        let io = |e: std::io::Error| format!("{name}: {e}");
        let mut pending = Pending::create(path).map_err(io)?;
        let out = std::io::BufWriter::new(pending.file().try_clone().map_err(io)?);
        let sink: Box<dyn TraceSink> = if binary {
            let w = BinaryWriter::with_part(out, tick_ms, part);
            Box::new(w.map_err(|e| format!("{name}: {e}"))?)
        } else {
            let w = TextWriter::with_part(out, tick_ms, part);
            Box::new(w.map_err(|e| format!("{name}: {e}"))?)
        };
        Ok(TraceFile {
            sink,
            pending: Some(pending),
            name,
        })
    }

    /// An error of this file, named.
    fn named(&self, e: impl std::fmt::Display) -> TraceError {
        TraceError::Io(std::io::Error::other(format!("{}: {e}", self.name)))
    }
}

impl TraceSink for TraceFile {
    fn record(&mut self, r: &TickRecord) -> Result<(), TraceError> {
        self.sink.record(r).map_err(|e| self.named(e))
    }

    fn flush(&mut self) -> Result<(), TraceError> {
        self.sink.flush().map_err(|e| self.named(e))
    }

    /// Flushes the records and puts the file in place (once).
    fn finish(&mut self) -> Result<(), TraceError> {
        self.flush()?;
        match self.pending.take() {
            Some(p) => p.commit().map_err(|e| self.named(e)),
            None => Ok(()),
        }
    }
}
