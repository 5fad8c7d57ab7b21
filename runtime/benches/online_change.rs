//! Online change of a 1,000-statement program at a 1 ms real-time tick: edit-to-running latency
//! (target ≤ 250 ms) and missed ticks (target 0). Each iteration edits the source file (one
//! statement changes), and the scheduler keeps ticking until the new program runs.

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use runtime::clock::RealClock;
use runtime::compiled::EngineKind;
use runtime::image::Image;
use runtime::io::{IoKind, open_io};
use runtime::machine::Machine;
use runtime::online;
use runtime::scheduler::{Event, Scheduler, Settings};

/// A 1,000-statement program for the lathe's connectors; `variant` changes one statement.
fn program(variant: u64) -> String {
    let mut s =
        String::from("; generated: 1,000 statements\nDEF t1 : TON(200ms)\nDEF c1 : CTU(10)\n");
    for i in 0..996u32 {
        let c = 100 + i / 32;
        let n = i % 32;
        s.push_str(&format!(
            "U{c}K{n} = I0A{} * /I1A{} + U{c}K{n} * /I0K1\n",
            i % 32,
            (i + 1) % 32
        ));
    }
    s.push_str("t1 = I0A0\nc1 = t1\n");
    s.push_str(&format!("U4A0 = [W3K0 = {}H]\n", variant % 90 + 1));
    s
}

fn bench(c: &mut Criterion) {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../plc-programs/lathe");
    let tmp = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let src: PathBuf = tmp.path().join("PLCPRG");
    std::fs::write(&src, program(0)).unwrap_or_else(|e| panic!("{e}"));
    let machine = Machine::open(&dir, Some(&src)).unwrap_or_else(|e| panic!("{e}"));
    let compile = machine.compile_fn(EngineKind::Jit, 1);
    let loaded = compile(program(0).as_bytes()).unwrap_or_else(|e| panic!("{e}"));
    let image = Image::new(loaded.meta.image_len(), &machine.config.t_init);
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
    let mut sched = Scheduler::new(image, loaded, io, Box::new(RealClock::new()), settings);
    let (swap_tx, swap_rx) = mpsc::channel();
    let (note_tx, note_rx) = mpsc::channel();
    sched.accept_swaps(swap_rx);
    let _w = online::watch(&src, program(0).into_bytes(), compile, swap_tx, note_tx)
        .unwrap_or_else(|e| panic!("{e}"));
    // As `ncplc run`: the scan thread gets SCHED_FIFO after the helper threads started.
    if let Some(w) = runtime::clock::enable_realtime(80).warning() {
        eprintln!("warning: {w}");
    }
    let mut variant = 0u64;
    let mut worst = Duration::ZERO;
    c.benchmark_group("online_change_1000_statements_1ms_tick")
        .sample_size(10)
        .bench_function("edit_to_running", |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                sched.resync();
                for _ in 0..iters {
                    variant += 1;
                    let edited = Instant::now();
                    write_like_an_editor(&src, &program(variant));
                    loop {
                        sched.step();
                        let swapped = sched
                            .take_events()
                            .into_iter()
                            .any(|e| matches!(e, Event::Swapped { .. }));
                        for n in note_rx.try_iter() {
                            if let online::Note::Rejected { diagnostics } = n {
                                panic!("{diagnostics}");
                            }
                        }
                        if swapped {
                            break;
                        }
                        assert!(edited.elapsed() < Duration::from_secs(10), "no swap");
                    }
                    let lat = edited.elapsed();
                    worst = worst.max(lat);
                    total += lat;
                }
                total
            })
        });
    eprintln!(
        "online change: {} ticks, {} overruns (missed ticks), worst edit-to-running {worst:.1?}\n{}",
        sched.stats.ticks,
        sched.stats.overruns,
        sched.stats.summary()
    );
}

fn write_like_an_editor(path: &Path, text: &str) {
    let tmp = path.with_extension("swp");
    std::fs::write(&tmp, text).unwrap_or_else(|e| panic!("{e}"));
    std::fs::rename(&tmp, path).unwrap_or_else(|e| panic!("{e}"));
}

criterion_group!(benches, bench);
criterion_main!(benches);
