//! Replay speed: 1,000,000 ticks of 1 ms of the example lathe (target: ≤ 1 s, i.e. ≥ 1,000× real
//! time), JIT and interpreter. The trace is recorded first from the lathe's simulated machine
//! (`sim.toml`, repeating schedule) in virtual time; both go through `Controller::builder`.

use std::path::{Path, PathBuf};

use controller::control::Quiet;
use controller::settings::{Clock, Engine, EngineKind, Recording, Scan};
use controller::{Builder, Controller};
use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use runtime::replay::replay;
use trace::Trace;

const TICKS: u64 = 1_000_000;

fn lathe() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../plc-programs/lathe")
}

fn lathe_with(engine: EngineKind) -> Builder {
    Controller::builder(lathe()).engine(Engine {
        kind: engine,
        flow: false,
    })
}

/// Records `TICKS` ticks of 1 ms of the lathe in virtual time, as `ncplc run --virtual-time
/// --tick-ms 1 --ticks N --record FILE --no-watch` does.
fn record(dir: &Path) -> Trace {
    let path = dir.join("lathe.ptrace");
    let mut c = lathe_with(EngineKind::Jit)
        .clock(Clock::Virtual)
        .record(Some(Recording {
            path: path.clone(),
            flush_ms: 1000,
        }))
        .scan(Scan {
            ticks: Some(TICKS),
            tick_ms: Some(1),
            overrun_limit: 0,
            watch: false,
            ..Scan::default()
        })
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    c.run(&mut Quiet);
    c.finish().unwrap_or_else(|e| panic!("{e}"));
    Trace::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn bench(c: &mut Criterion) {
    let tmp = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let trace = record(tmp.path());
    eprintln!(
        "lathe trace: {} ticks, {} records",
        trace.len_ticks(),
        trace.ticks.len()
    );
    let mut g = c.benchmark_group("replay_lathe_1M_ticks");
    g.sample_size(10);
    for engine in [EngineKind::Jit, EngineKind::Interp] {
        let replayer = lathe_with(engine)
            .replayer()
            .unwrap_or_else(|e| panic!("{e}"));
        let t_init = &replayer.machine().config.t_init;
        g.bench_function(format!("{engine:?}").to_lowercase(), |b| {
            b.iter_batched(
                || replayer.compile(1, 1).unwrap_or_else(|e| panic!("{e}")),
                |loaded| {
                    let r = replay(&trace, loaded, t_init, |_| {});
                    assert!(r.identical());
                    r
                },
                BatchSize::PerIteration,
            )
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
