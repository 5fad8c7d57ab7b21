//! `ncplc replay`: re-apply a trace's inputs in virtual time and compare the outputs.
//!
//! Exit 0 when identical, 1 with a divergence report otherwise, 2 on errors. `--update`
//! rewrites the trace's expectations with what the program produces now.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

use controller::Controller;
use runtime::compiled::EngineKind;
use runtime::replay::ReplayOptions;
use std::cell::Cell;

use trace::TickRecord;
use trace::reader::{Header, Reader};
use trace::recover::summary;

use trace::TraceSink;

use crate::cli::trace::TraceFile;

/// Arguments of `ncplc replay`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The machine directory.
    pub machine: PathBuf,
    /// The trace (text or binary).
    pub trace: PathBuf,
    /// The engine.
    #[arg(long, value_enum, default_value = "jit")]
    pub engine: EngineKind,
    /// Use this PLC source instead of the machine's.
    #[arg(long)]
    pub plc: Option<PathBuf>,
    /// Rewrite the trace's outputs with the replay's.
    #[arg(long)]
    pub update: bool,
    /// Run every tick, also those in which nothing can change (idle ticks are skipped by default;
    /// the result is the same either way).
    #[arg(long)]
    pub no_skip: bool,
    /// Ticks of context shown around the first divergence.
    #[arg(long, default_value_t = 3)]
    pub context: u64,
}

/// Runs `ncplc replay`.
pub fn run(args: Args) -> ExitCode {
    match run_inner(&args) {
        Ok(code) => code,
        Err(msg) => {
            eprintln!("{msg}");
            ExitCode::from(2)
        }
    }
}

/// A trace's records, one at a time; an error ends them.
type Records<'a> = Box<dyn Iterator<Item = Result<TickRecord, String>> + 'a>;

/// The trace's records, read one at a time (`read_at` hears the bytes read, `failed` the error
/// that ended the reading): of the file, or the complete records of a `.partial` file a crashed
/// recording left.
fn open_records<'a>(
    path: &'a std::path::Path,
    read_at: &'a Cell<u64>,
    failed: &'a Cell<Option<String>>,
) -> Result<(Header, Records<'a>), String> {
    let name = path.display();
    let located = move |e: trace::TraceError| format!("{}: {e}", path.display());
    if path.extension().is_some_and(|e| e == "partial") {
        // What a crashed recording left: its complete records, read one at a time like a trace;
        // what was kept and dropped is said once they are read.
        let size = std::fs::metadata(path).map_or(0, |m| m.len());
        let file = std::fs::File::open(path).map_err(|e| format!("{name}: {e}"))?;
        let mut reader = Reader::recovering(std::io::BufReader::with_capacity(1 << 16, file))
            .map_err(&located)?;
        let header = reader.header().clone();
        let (mut n, mut last, mut ended) = (0, None, false);
        let records = std::iter::from_fn(move || {
            if ended {
                return None;
            }
            read_at.set(reader.bytes_read());
            match reader.next() {
                Some(Ok(r)) => {
                    n += 1;
                    last = Some(r.t);
                    Some(Ok(r))
                }
                _ => {
                    ended = true;
                    let dropped = size.saturating_sub(reader.complete_bytes());
                    eprintln!("{}: {}", path.display(), summary(n, last, dropped));
                    None
                }
            }
        });
        return Ok((header, Box::new(records)));
    }
    let mut reader = Reader::open(path).map_err(&located)?;
    let header = reader.header().clone();
    let records = std::iter::from_fn(move || {
        let r = reader.next();
        read_at.set(reader.bytes_read());
        r.map(|r| {
            r.map_err(|e| {
                let e = located(e);
                failed.set(Some(e.clone()));
                e
            })
        })
    });
    Ok((header, Box::new(records)))
}

fn run_inner(args: &Args) -> Result<ExitCode, String> {
    let replayer = Controller::builder(&args.machine)
        .plc(args.plc.clone())
        .engine(controller::settings::Engine {
            kind: args.engine,
            flow: false,
        })
        .replayer()
        .map_err(|e| e.to_string())?;
    let name = args.trace.display();
    // The bytes read so far, for the bar, and the error that ended the reading, if any.
    let read = Cell::new(0u64);
    let read_error: Cell<Option<String>> = Cell::new(None);
    let (header, records) = open_records(&args.trace, &read, &read_error)?;
    let loaded = match replayer.compile(header.tick_ms, 0) {
        Ok(l) => l,
        Err(diags) => {
            eprintln!("{diags}");
            return Ok(ExitCode::from(2));
        }
    };
    let size = std::fs::metadata(&args.trace).map_or(0, |m| m.len());
    let bar = (std::io::stderr().is_terminal() && size >= 8 << 20).then(|| {
        let bar = indicatif::ProgressBar::new(size);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "replay {bar:40} {percent}% of the trace, tick {msg} (eta {eta})",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    });
    let options = ReplayOptions {
        skip_idle: !args.no_skip,
        // A trace whose header names partprograms re-runs the kernel (set by `replay_trace`).
        drives_kernel: header.part.is_some(),
        context: args.context,
    };
    let start = std::time::Instant::now();
    let progress = |done: u64| {
        if let Some(b) = &bar {
            b.set_position(read.get());
            b.set_message(done.to_string());
        }
    };
    // `--update` writes the replay's records as they are made into a file that replaces the
    // trace only when the whole replay succeeded: an interrupted update leaves the old trace.
    let mut update = if args.update {
        let part = header.part.as_ref();
        Some(TraceFile::create(
            &args.trace,
            header.tick_ms,
            part,
            !header.text,
        )?)
    } else {
        None
    };
    let mut sink = |r: &TickRecord| match update.as_mut() {
        Some(u) => u.record(r).map_err(|e| e.to_string()),
        None => Ok(()),
    };
    let result = replayer.replay(&header, records, loaded, options, &mut sink, progress);
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let result = match result {
        Ok(r) => r,
        Err(e) => {
            eprintln!("{e}");
            // A trace that cannot be read is an error (2); a replay that cannot go on is a
            // divergence (1).
            let code = if read_error.take().is_some() { 2 } else { 1 };
            return Ok(ExitCode::from(code));
        }
    };
    let elapsed = start.elapsed();
    let total = result.ticks;
    if let Some(mut u) = update {
        u.finish().map_err(|e| e.to_string())?;
        eprintln!("{name}: expectations updated ({total} ticks)");
        return Ok(ExitCode::SUCCESS);
    }
    if result.identical() {
        eprintln!(
            "{name}: {total} ticks replayed ({} skipped as idle), outputs identical{} ({:.1?}, {:.0}x real time)",
            result.skipped,
            if header.part.is_some() {
                ", kernel signals and axis positions identical"
            } else {
                ""
            },
            elapsed,
            (total as f64 * f64::from(header.tick_ms) / 1e3) / elapsed.as_secs_f64().max(1e-9)
        );
        Ok(ExitCode::SUCCESS)
    } else {
        eprint!("{}", result.report());
        Ok(ExitCode::from(1))
    }
}
