//! Replay speed: 1,000,000 ticks of 1 ms of the example lathe (target: ≤ 1 s, i.e. ≥ 1,000× real
//! time), JIT and interpreter. The trace is recorded first from the lathe's simulated machine
//! (`sim.toml`, repeating schedule) in virtual time.

use std::path::PathBuf;

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use runtime::clock::VirtualClock;
use runtime::compiled::EngineKind;
use runtime::image::Image;
use runtime::io::{IoKind, open_io};
use runtime::machine::Machine;
use runtime::replay::replay;
use runtime::scheduler::{Scheduler, Settings};
use runtime::trace::{MemorySink, Trace};

const TICKS: u64 = 1_000_000;

fn lathe() -> Machine {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../plc-programs/lathe");
    Machine::open(&dir, None).unwrap_or_else(|e| panic!("{e}"))
}

fn record(machine: &Machine) -> Trace {
    let compile = machine.compile_fn(EngineKind::Jit, 1);
    let loaded = compile(&machine.read_source().unwrap_or_else(|e| panic!("{e}")))
        .unwrap_or_else(|e| panic!("{e}"));
    let mut image = Image::new(loaded.meta.image_len(), &machine.config.t_init);
    loaded.meta.init_image(image.bytes_mut());
    let io = open_io(
        IoKind::Sim,
        &machine.dir,
        &machine.declared_connectors(),
        machine.script.clone(),
        machine.signals.clone(),
        1,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let settings = Settings {
        tick_ns: 1_000_000,
        overrun_limit: 0,
    };
    let mut s = Scheduler::new(image, loaded, io, Box::new(VirtualClock::new()), settings);
    let sink = MemorySink::default();
    s.record_to(Box::new(sink.clone()));
    s.run(Some(TICKS), |_| true);
    s.finish().unwrap_or_else(|e| panic!("{e}"));
    let ticks = sink.0.lock().map(|v| v.clone()).unwrap_or_default();
    Trace {
        tick_ms: 1,
        ticks,
        part: None,
    }
}

fn bench(c: &mut Criterion) {
    let machine = lathe();
    let trace = record(&machine);
    eprintln!(
        "lathe trace: {} ticks, {} records",
        trace.len_ticks(),
        trace.ticks.len()
    );
    let mut g = c.benchmark_group("replay_lathe_1M_ticks");
    g.sample_size(10);
    for engine in [EngineKind::Jit, EngineKind::Interp] {
        let compile = machine.compile_fn(engine, 1);
        let source = machine.read_source().unwrap_or_else(|e| panic!("{e}"));
        g.bench_function(format!("{engine:?}").to_lowercase(), |b| {
            b.iter_batched(
                || compile(&source).unwrap_or_else(|e| panic!("{e}")),
                |loaded| {
                    let r = replay(&trace, loaded, &machine.config.t_init, |_| {});
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
