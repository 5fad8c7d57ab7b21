//! Online change of a 1,000-statement program at a 1 ms real-time tick: edit-to-running latency
//! (target ≤ 250 ms) and missed ticks (target 0). Each iteration edits the source file (one
//! statement changes), and the scheduler keeps ticking until the new program runs.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use controller::settings::{Clock, Scan};
use controller::{Controller, Observer};
use criterion::{Criterion, criterion_group, criterion_main};
use runtime::online::Note;
use runtime::scheduler::Event;

/// Notices the swap and fails on a rejected change.
#[derive(Default)]
struct Swaps {
    swapped: bool,
}

impl Observer for Swaps {
    fn event(&mut self, e: &Event) {
        self.swapped |= matches!(e, Event::Swapped { .. });
    }

    fn note(&mut self, n: &Note) {
        if let Note::Rejected { diagnostics } = n {
            panic!("{diagnostics}");
        }
    }
}

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
    // As `ncplc run --plc SRC --tick-ms 1 --overrun-limit 0`: the first load on every core, online
    // changes on one thread beside the scan with the run's shared code cache.
    let mut ctl = Controller::builder(&dir)
        .plc(Some(src.clone()))
        .clock(Clock::Real { spin_us: 0 })
        .scan(Scan {
            tick_ms: Some(1),
            overrun_limit: 0,
            retain_file: Some(tmp.path().join("retain.bin")),
            ..Scan::default()
        })
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    // As `ncplc run`: the scan thread gets SCHED_FIFO after the helper threads started.
    ctl.enter_realtime();
    let mut variant = 0u64;
    let mut worst = Duration::ZERO;
    c.benchmark_group("online_change_1000_statements_1ms_tick")
        .sample_size(10)
        .bench_function("edit_to_running", |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                ctl.resync();
                for _ in 0..iters {
                    variant += 1;
                    let edited = Instant::now();
                    write_like_an_editor(&src, &program(variant));
                    let mut swaps = Swaps::default();
                    while !swaps.swapped {
                        ctl.step(&mut swaps);
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
        ctl.scheduler().stats.ticks,
        ctl.scheduler().stats.overruns,
        ctl.scheduler().stats.summary()
    );
}

fn write_like_an_editor(path: &Path, text: &str) {
    let tmp = path.with_extension("swp");
    std::fs::write(&tmp, text).unwrap_or_else(|e| panic!("{e}"));
    std::fs::rename(&tmp, path).unwrap_or_else(|e| panic!("{e}"));
}

criterion_group!(benches, bench);
criterion_main!(benches);
