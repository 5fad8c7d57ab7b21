//! Replay speed on generated programs, side by side in one run (issue 15, items 4 and 5):
//! - the bare scan of a 10,000-statement program against a replay tick of it (no skipping, an
//!   input change every 16 ticks): the replay loop's own work per tick;
//! - a 1,000-statement program over 1,000,000 ticks of 1 ms with sparse inputs (one K bit
//!   toggled about every 1,000 ticks), tick by tick and skipping idle ticks; both must give the
//!   recorded trace. Target ≥ 1,000× real time (≤ 1 s), goal 10,000× (≤ 100 ms).

use std::hint::black_box;

use compiler::MachineContext;
use compiler::synth::synthetic_program;
use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use packets::Signal;
use runtime::compiled::{EngineKind, load};
use runtime::program::Loaded;
use runtime::replay::{ReplayOptions, replay_keeping, replay_with};
use trace::{TickRecord, Trace};

fn ctx() -> MachineContext {
    MachineContext {
        spl: 256,
        tick_ms: 1,
        ..MachineContext::lathe_like()
    }
}

fn program(statements: usize) -> compiler::ir::Program {
    let src = synthetic_program(statements);
    compiler::compile("synth", src.as_bytes(), &ctx())
        .program
        .unwrap_or_else(|| panic!("the synthetic program compiles"))
}

fn loaded(p: &compiler::ir::Program) -> Loaded {
    load(p.clone(), EngineKind::Jit).unwrap_or_else(|e| panic!("{e}"))
}

/// `ticks` ticks with an input bit of `I100K0..I249K31` set or cleared every `gap` ticks (on
/// average; xorshift-spaced when `jitter`).
fn inputs(ticks: u64, gap: u64, jitter: bool) -> Trace {
    let mut x: u32 = 2463534242;
    let mut rnd = |m: u32| {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        x % m
    };
    let mut recs = Vec::new();
    let mut t = 0;
    while t < ticks - 1 {
        let s: Signal = format!("I{}K{}", 100 + rnd(150), rnd(32))
            .parse()
            .unwrap_or_else(|e| panic!("{e:?}"));
        recs.push(TickRecord {
            nodes_lost: Vec::new(),
            forced: Vec::new(),
            positions: Vec::new(),
            commands: Vec::new(),
            drives: Vec::new(),
            t,
            inputs: vec![(s, u8::from(rnd(2) == 1))],
            outputs: Vec::new(),
        });
        t += if jitter {
            1 + u64::from(rnd(2 * gap as u32))
        } else {
            gap
        };
    }
    recs.push(TickRecord {
        forced: Vec::new(),
        positions: Vec::new(),
        t: ticks - 1,
        ..TickRecord::default()
    });
    Trace {
        tick_ms: 1,
        ticks: recs,
        part: None,
    }
}

const NO_SKIP: ReplayOptions = ReplayOptions {
    skip_idle: false,
    drives_kernel: false,
    context: 3,
};
const SKIP: ReplayOptions = ReplayOptions {
    skip_idle: true,
    drives_kernel: false,
    context: 3,
};

fn scan_vs_replay_tick(c: &mut Criterion) {
    const TICKS: u64 = 4_096;
    let p = program(10_000);
    let trace = inputs(TICKS, 16, false);
    let mut g = c.benchmark_group("replay_tick_10k_statements_4096_ticks");
    g.sample_size(10);
    g.bench_function("bare_scan", |b| {
        b.iter_batched(
            || {
                let l = loaded(&p);
                let mut image = vec![0u8; l.meta.image_len()];
                l.meta.init_image(&mut image);
                (l, image)
            },
            |(mut l, mut image)| {
                for t in 0..TICKS {
                    // The same input writes as the replay, so both run the same logic.
                    if t % 16 == 0
                        && let Some(r) = trace.ticks.get((t / 16) as usize)
                    {
                        for (s, v) in &r.inputs {
                            s.write(&mut image, *v);
                        }
                    }
                    l.logic.tick(black_box(&mut image));
                }
                image
            },
            BatchSize::PerIteration,
        )
    });
    g.bench_function("replay", |b| {
        b.iter_batched(
            || loaded(&p),
            |l| replay_with(&trace, l, &[], NO_SKIP, |_| {}),
            BatchSize::PerIteration,
        )
    });
    g.finish();
}

fn replay_1m(c: &mut Criterion) {
    const TICKS: u64 = 1_000_000;
    let p = program(1_000);
    // The expectations: a tick-by-tick replay's records.
    let mut trace = inputs(TICKS, 1_000, true);
    trace = replay_keeping(&trace, loaded(&p), &[], NO_SKIP, |_| {}).1;
    let (check, actual) = replay_keeping(&trace, loaded(&p), &[], SKIP, |_| {});
    assert!(check.identical());
    assert_eq!(actual, trace);
    eprintln!(
        "1,000 statements, {TICKS} ticks: {} records, {} ticks skipped as idle",
        trace.ticks.len(),
        check.skipped
    );
    let mut g = c.benchmark_group("replay_1k_statements_1M_ticks");
    g.sample_size(10);
    for (name, options) in [("tick_by_tick", NO_SKIP), ("skip_idle", SKIP)] {
        g.bench_function(name, |b| {
            b.iter_batched(
                || loaded(&p),
                |l| {
                    let r = replay_with(&trace, l, &[], options, |_| {});
                    assert!(r.identical());
                    r
                },
                BatchSize::PerIteration,
            )
        });
    }
    g.finish();
}

criterion_group!(benches, scan_vs_replay_tick, replay_1m);
criterion_main!(benches);
