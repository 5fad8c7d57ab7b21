//! `ncplc plot trace FILE --signals A,B,… [--from T --to T] [--machine DIR] -o out.svg|png`: a
//! trace as a timing diagram. Signals are addresses (`I0A3`) or, with `--machine`, names of the
//! interface map and of the PLC program's `DEF` aliases (the lanes are then labelled by name).

use std::path::PathBuf;
use std::process::ExitCode;

use packets::Signal;

use controller::machine::Machine;
use plot::{self, timing::TimingDiagram};
use trace::reader::Reader;

/// Arguments of `ncplc plot`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// What to plot.
    #[command(subcommand)]
    pub what: What,
}

/// The plots.
#[derive(Debug, clap::Subcommand)]
pub enum What {
    /// A trace file as a timing diagram.
    Trace {
        /// The trace (text or binary).
        file: PathBuf,
        /// Comma-separated signals (addresses, or names with --machine).
        #[arg(long, value_delimiter = ',', required = true)]
        signals: Vec<String>,
        /// First tick shown (`120`, or a time: `1.5s`, `300ms`).
        #[arg(long)]
        from: Option<String>,
        /// Last tick shown (default: the trace's last).
        #[arg(long)]
        to: Option<String>,
        /// The machine whose names label the lanes.
        #[arg(long)]
        machine: Option<PathBuf>,
        /// Output file (.svg or .png).
        #[arg(short = 'o', long = "output")]
        output: PathBuf,
    },
}

/// Runs `ncplc plot`.
pub fn run(args: Args) -> ExitCode {
    match run_inner(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            eprintln!("error: {msg}");
            ExitCode::from(2)
        }
    }
}

/// A tick number or a time (`1.5s`, `300ms`) converted with `tick_ms`.
pub fn parse_tick(text: &str, tick_ms: u32) -> Result<u64, String> {
    let bad = || format!("`{text}` is not a tick number or a time such as 1.5s or 300ms");
    let ms = if let Some(v) = text.strip_suffix("ms") {
        v.parse::<f64>().map_err(|_| bad())?
    } else if let Some(v) = text.strip_suffix('s') {
        v.parse::<f64>().map_err(|_| bad())? * 1000.0
    } else {
        return text.parse().map_err(|_| bad());
    };
    if !(ms.is_finite() && ms >= 0.0) {
        return Err(bad());
    }
    Ok((ms / f64::from(tick_ms.max(1))).floor() as u64)
}

fn run_inner(args: Args) -> Result<(), String> {
    let What::Trace {
        file,
        signals,
        from,
        to,
        machine,
        output,
    } = args.what;
    let located = |e: trace::TraceError| format!("{}: {e}", file.display());
    let reader = Reader::open(&file).map_err(located)?;
    let tick_ms = reader.header().tick_ms;
    let catalog = match &machine {
        Some(dir) => {
            let m = Machine::open(dir, None).map_err(|e| e.to_string())?;
            let source = m.read_source().map_err(|e| e.to_string())?;
            Some(controller::hmi_link::catalog::build(&m, &source))
        }
        None => None,
    };
    let mut lanes: Vec<(Signal, String)> = Vec::new();
    for name in &signals {
        let name = name.trim();
        let sig = match &catalog {
            Some(c) => c.resolve(name),
            None => name.parse().ok(),
        }
        .ok_or_else(|| match &catalog {
            Some(_) => {
                format!("--signals: `{name}` is neither a signal address nor a name of the machine")
            }
            None => {
                format!("--signals: `{name}` is not a signal address (give --machine to use names)")
            }
        })?;
        let label = match catalog
            .as_ref()
            .and_then(|c| c.names.iter().find(|n| n.signal == sig || n.name == name))
        {
            Some(n) => format!("{} {sig}", n.name),
            None => sig.to_string(),
        };
        lanes.push((sig, label));
    }
    let from = match &from {
        Some(t) => parse_tick(t, tick_ms).map_err(|e| format!("--from: {e}"))?,
        None => 0,
    };
    let to = match &to {
        Some(t) => Some(parse_tick(t, tick_ms).map_err(|e| format!("--to: {e}"))?),
        None => None,
    };
    if let Some(to) = to
        && from > to
    {
        return Err(format!("--from {from} is after --to {to}"));
    }
    let title = file.file_name().map_or_else(
        || file.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    // Read record by record, up to `--to` (the whole trace without it).
    let chart = TimingDiagram::new(title, tick_ms, reader, &lanes, from, to).map_err(located)?;
    let to = chart.to;
    if from > to {
        return Err(format!("--from {from} is after --to {to}"));
    }
    plot::write(&chart, &output).map_err(|e| e.to_string())?;
    eprintln!(
        "{}: {} signals, ticks {from}..={to}",
        output.display(),
        lanes.len()
    );
    Ok(())
}
