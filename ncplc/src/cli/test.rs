//! `ncplc test <machine> [TRACE…] [--junit FILE]`: replays every golden trace of a machine (its
//! `traces/` folder, or the traces given) on all cores, prints one line per trace and exits 1 when
//! any replay diverges (2 when a trace or the program cannot be loaded). `--junit` writes the
//! results as JUnit XML for CI systems. `--shard K/N` replays only the K-th of N disjoint shares of
//! the traces (see `shard`), so the machines of a CI matrix split one fleet of golden traces.

mod shard;

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use controller::Controller;
use controller::replayer::Replayer;
use runtime::compiled::EngineKind;
use runtime::replay::ReplayOptions;
pub use shard::{Shard, ShardError};
use trace::reader::Reader;

/// Arguments of `ncplc test`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The machine directory.
    pub machine: PathBuf,
    /// Traces to replay (default: every file in `<machine>/traces/`).
    pub traces: Vec<PathBuf>,
    /// The engine.
    #[arg(long, value_enum, default_value = "jit")]
    pub engine: EngineKind,
    /// Write the results as JUnit XML to this file.
    #[arg(long, value_name = "FILE")]
    pub junit: Option<PathBuf>,
    /// Replays at once (default: the number of cores).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Replay only shard K of N (1 ≤ K ≤ N): the traces sorted by path, trace i to shard i mod N.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<Shard>,
}

/// How one trace fared.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// Identical outputs.
    Pass,
    /// The outputs diverge: the first line and the whole report.
    Diverged(String, String),
    /// The trace or the program could not be loaded.
    Error(String),
}

/// One trace's result.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The trace as named on the line.
    pub name: String,
    /// Ticks replayed.
    pub ticks: u64,
    /// The verdict.
    pub verdict: Verdict,
    /// Replay time (wall clock, for the report only).
    pub elapsed: Duration,
}

/// Runs `ncplc test`.
pub fn run(args: Args) -> ExitCode {
    match run_inner(args) {
        Ok(code) => code,
        Err(msg) => {
            eprintln!("error: {msg}");
            ExitCode::from(2)
        }
    }
}

fn golden_traces(machine: &Path) -> Result<Vec<PathBuf>, String> {
    let dir = machine.join("traces");
    let entries =
        std::fs::read_dir(&dir).map_err(|e| format!("{}: {e} (give the traces)", dir.display()))?;
    let mut out: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.is_file() && !p.to_string_lossy().ends_with(".partial"))
        .collect();
    out.sort();
    if out.is_empty() {
        return Err(format!("{}: no traces", dir.display()));
    }
    Ok(out)
}

/// Replays `path` against the machine's program.
pub fn test_one(replayer: &Replayer, path: &Path) -> Outcome {
    let start = Instant::now();
    let name = path.display().to_string();
    let outcome = |ticks, verdict| Outcome {
        name: name.clone(),
        ticks,
        verdict,
        elapsed: start.elapsed(),
    };
    let reader = match Reader::open(path) {
        Ok(r) => r,
        Err(e) => return outcome(0, Verdict::Error(e.to_string())),
    };
    let header = reader.header().clone();
    let loaded = match replayer.compile(header.tick_ms, 1) {
        Ok(l) => l,
        Err(e) => return outcome(0, Verdict::Error(e)),
    };
    let records = reader.map(|r| r.map_err(|e| e.to_string()));
    let options = ReplayOptions::default();
    let result = match replayer.replay(&header, records, loaded, options, &mut |_| Ok(()), |_| {}) {
        Ok(r) => r,
        Err(e) => return outcome(0, Verdict::Error(e)),
    };
    let ticks = result.ticks;
    if result.identical() {
        outcome(ticks, Verdict::Pass)
    } else {
        let report = result.report();
        let first = report.lines().next().unwrap_or("diverges").to_string();
        outcome(ticks, Verdict::Diverged(first, report))
    }
}

fn run_inner(args: Args) -> Result<ExitCode, String> {
    let replayer = Controller::builder(&args.machine)
        .engine(controller::settings::Engine {
            kind: args.engine,
            flow: false,
        })
        .replayer()
        .map_err(|e| e.to_string())?;
    let traces = if args.traces.is_empty() {
        golden_traces(&args.machine)?
    } else {
        args.traces.clone()
    };
    let all = traces.len();
    let traces = match args.shard {
        Some(shard) => shard.select(traces),
        None => traces,
    };
    let jobs = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .clamp(1, traces.len().max(1));
    let bar = std::io::stderr().is_terminal().then(|| {
        let bar = indicatif::ProgressBar::new(traces.len() as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template("test {bar:40} {pos}/{len} traces")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    });
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<Outcome>>> = Mutex::new(vec![None; traces.len()]);
    let start = Instant::now();
    std::thread::scope(|s| {
        for _ in 0..jobs {
            s.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let Some(path) = traces.get(i) else { break };
                    let o = test_one(&replayer, path);
                    if let Ok(mut r) = results.lock() {
                        r[i] = Some(o);
                    }
                    if let Some(b) = &bar {
                        b.inc(1);
                    }
                }
            });
        }
    });
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let outcomes: Vec<Outcome> = results
        .into_inner()
        .map_err(|_| "a replay thread panicked".to_string())?
        .into_iter()
        .flatten()
        .collect();
    let (mut passed, mut diverged, mut errors) = (0, 0, 0);
    for o in &outcomes {
        match &o.verdict {
            Verdict::Pass => {
                passed += 1;
                println!("ok       {}  ({} ticks)", o.name, o.ticks);
            }
            Verdict::Diverged(first, _) => {
                diverged += 1;
                println!("DIVERGES {}  {first}", o.name);
            }
            Verdict::Error(e) => {
                errors += 1;
                println!("ERROR    {}  {e}", o.name);
            }
        }
    }
    let share = match args.shard {
        Some(shard) => format!("shard {shard}: {} of {all}", outcomes.len()),
        None => outcomes.len().to_string(),
    };
    println!(
        "{share} traces on {jobs} threads: {passed} identical, {diverged} diverging, {errors} errors ({:.2} s)",
        start.elapsed().as_secs_f64()
    );
    if let Some(path) = &args.junit {
        let suite = args
            .machine
            .file_name()
            .map_or_else(|| "machine".into(), |n| n.to_string_lossy().into_owned());
        runtime::atomic_file::write(path, junit_xml(&suite, &outcomes).as_bytes())
            .map_err(|e| format!("--junit {}: {e}", path.display()))?;
    }
    Ok(if errors > 0 {
        ExitCode::from(2)
    } else if diverged > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

/// Escapes text for XML attributes and content.
fn xml(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if (c as u32) < 0x20 && !matches!(c, '\n' | '\t' | '\r') => {}
            c => out.push(c),
        }
    }
    out
}

/// The results as one JUnit `<testsuite>` named `suite`, one `<testcase>` per trace.
pub fn junit_xml(suite: &str, outcomes: &[Outcome]) -> String {
    let failures = outcomes
        .iter()
        .filter(|o| matches!(o.verdict, Verdict::Diverged(..)))
        .count();
    let errors = outcomes
        .iter()
        .filter(|o| matches!(o.verdict, Verdict::Error(_)))
        .count();
    // A fold from +0.0: an empty `sum()` of f64 is -0.0, which would print as `time="-0.000"`.
    let total = outcomes
        .iter()
        .fold(0.0, |t, o| t + o.elapsed.as_secs_f64());
    let mut s = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites>\n  <testsuite name=\"ncplc test {}\" tests=\"{}\" failures=\"{failures}\" errors=\"{errors}\" time=\"{total:.3}\">\n",
        xml(suite),
        outcomes.len()
    );
    for o in outcomes {
        s.push_str(&format!(
            "    <testcase classname=\"{}\" name=\"{}\" time=\"{:.3}\"",
            xml(suite),
            xml(&o.name),
            o.elapsed.as_secs_f64()
        ));
        match &o.verdict {
            Verdict::Pass => s.push_str("/>\n"),
            Verdict::Diverged(first, report) => s.push_str(&format!(
                ">\n      <failure message=\"{}\">{}</failure>\n    </testcase>\n",
                xml(first),
                xml(report)
            )),
            Verdict::Error(e) => s.push_str(&format!(
                ">\n      <error message=\"{}\"/>\n    </testcase>\n",
                xml(e)
            )),
        }
    }
    s.push_str("  </testsuite>\n</testsuites>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn junit_lists_each_trace_with_its_failure_escaped() {
        let o = |name: &str, verdict| Outcome {
            name: name.into(),
            ticks: 10,
            verdict,
            elapsed: Duration::from_millis(250),
        };
        let xml = junit_xml(
            "lathe",
            &[
                o("traces/a.jsonl", Verdict::Pass),
                o(
                    "traces/b.jsonl",
                    Verdict::Diverged("first at tick 3".into(), "U4A0 <1> & more".into()),
                ),
                o(
                    "traces/c.jsonl",
                    Verdict::Error("line 2: \"t\" missing".into()),
                ),
            ],
        );
        assert_eq!(
            xml,
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites>\n  <testsuite name=\"ncplc test lathe\" tests=\"3\" failures=\"1\" errors=\"1\" time=\"0.750\">\n\
             \x20   <testcase classname=\"lathe\" name=\"traces/a.jsonl\" time=\"0.250\"/>\n\
             \x20   <testcase classname=\"lathe\" name=\"traces/b.jsonl\" time=\"0.250\">\n      <failure message=\"first at tick 3\">U4A0 &lt;1&gt; &amp; more</failure>\n    </testcase>\n\
             \x20   <testcase classname=\"lathe\" name=\"traces/c.jsonl\" time=\"0.250\">\n      <error message=\"line 2: &quot;t&quot; missing\"/>\n    </testcase>\n\
             \x20 </testsuite>\n</testsuites>\n"
        );
    }
}
