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
use trace::recover::recover;
use trace::{Trace, binary};

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

fn run_inner(args: &Args) -> Result<ExitCode, String> {
    let replayer = Controller::builder(&args.machine)
        .plc(args.plc.clone())
        .engine(controller::settings::Engine {
            kind: args.engine,
            flow: false,
        })
        .replayer()
        .map_err(|e| e.to_string())?;
    let bytes = std::fs::read(&args.trace).map_err(|e| format!("{}: {e}", args.trace.display()))?;
    let trace = if args.trace.extension().is_some_and(|e| e == "partial") {
        // What a crashed recording left: its complete records.
        let r = recover(&bytes).map_err(|e| format!("{}: {e}", args.trace.display()))?;
        eprintln!("{}: {}", args.trace.display(), r.summary());
        r.trace
    } else {
        Trace::from_bytes(&bytes).map_err(|e| format!("{}: {e}", args.trace.display()))?
    };
    let loaded = match replayer.compile(trace.tick_ms, 0) {
        Ok(l) => l,
        Err(diags) => {
            eprintln!("{diags}");
            return Ok(ExitCode::from(2));
        }
    };
    let total = trace.len_ticks();
    let bar = (std::io::stderr().is_terminal() && total >= 1 << 20).then(|| {
        let bar = indicatif::ProgressBar::new(total);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "replay {bar:40} {pos}/{len} ticks ({per_sec}, eta {eta})",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    });
    let start = std::time::Instant::now();
    let options = ReplayOptions {
        skip_idle: !args.no_skip,
        // A trace whose header names partprograms re-runs the kernel (set by `replay_trace`).
        drives_kernel: trace.part.is_some(),
    };
    let result = replayer.replay(&trace, loaded, options, |done| {
        if let Some(b) = &bar {
            b.set_position(done);
        }
    });
    let result = match result {
        Ok(r) => r,
        Err(e) => {
            if let Some(b) = bar {
                b.finish_and_clear();
            }
            eprintln!("{e}");
            return Ok(ExitCode::from(1));
        }
    };
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let elapsed = start.elapsed();
    if args.update {
        let out = if bytes.first() == Some(&b'{') {
            let mut v = Vec::new();
            result
                .actual
                .write_text(&mut v)
                .map_err(|e| e.to_string())?;
            v
        } else {
            binary::encode(&result.actual).map_err(|e| e.to_string())?
        };
        // Atomically: an interrupted update leaves the old golden trace, never half of the new one.
        runtime::atomic_file::write(&args.trace, &out)
            .map_err(|e| format!("{}: {e}", args.trace.display()))?;
        eprintln!(
            "{}: expectations updated ({total} ticks)",
            args.trace.display()
        );
        return Ok(ExitCode::SUCCESS);
    }
    if result.identical() {
        eprintln!(
            "{}: {total} ticks replayed ({} skipped as idle), outputs identical{} ({:.1?}, {:.0}x real time)",
            args.trace.display(),
            result.skipped,
            if trace.part.is_some() {
                ", kernel signals and axis positions identical"
            } else {
                ""
            },
            elapsed,
            (total as f64 * f64::from(trace.tick_ms) / 1e3) / elapsed.as_secs_f64().max(1e-9)
        );
        Ok(ExitCode::SUCCESS)
    } else {
        eprint!("{}", result.report(&trace, args.context));
        Ok(ExitCode::from(1))
    }
}
