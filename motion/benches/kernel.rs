//! Motion kernel benchmarks: virtual-time speed on 100,000 blocks (criterion), and printed
//! before it, the per-tick cost distribution (push + tick, p50/p99/p99.99/max) on a
//! 150,000-segment CAM path and the time / lower-bound ratio of the programs.

use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, criterion_group};
use motion::{Kernel, Move, bound::lower_bound, cam, samples};

/// Runs to idle on the benchmark mill; returns the number of ticks.
fn run(moves: &[Move], start: [f64; 3]) -> u64 {
    samples::ticks_to_idle(samples::mill(), moves, start).expect("the sample runs")
}

/// Runs to idle like [`run`], setting both overrides (unchanged) before every tick.
fn run_with_overrides(moves: &[Move], start: [f64; 3]) -> u64 {
    let mut k = Kernel::new(samples::mill(), &start).expect("config");
    let (mut next, mut n) = (0, 0);
    loop {
        while next < moves.len() && k.space() > 0 {
            k.push(moves[next].clone()).expect("accepted");
            next += 1;
        }
        if next >= moves.len() && k.is_idle() {
            return n;
        }
        k.set_feed_override(100);
        k.set_rapid_override(100);
        k.tick();
        n += 1;
    }
}

fn per_tick_cost() {
    let moves = samples::cam(375);
    let mut k = Kernel::new(samples::mill(), &samples::start("cam")).expect("config");
    let mut h = hdrhistogram::Histogram::<u64>::new(3).expect("histogram");
    let mut next = 0;
    loop {
        let t0 = Instant::now();
        while next < moves.len() && k.space() > 0 {
            k.push(moves[next].clone()).expect("accepted");
            next += 1;
        }
        if next >= moves.len() && k.is_idle() {
            break;
        }
        black_box(k.tick());
        let ns = t0.elapsed().as_nanos() as u64;
        h.record(ns.max(1)).expect("record");
    }
    println!(
        "per tick (push + tick), {} segments, {} ticks: p50 {:.2} µs, p99 {:.2} µs, p99.99 {:.2} µs, max {:.2} µs",
        moves.len(),
        h.len(),
        h.value_at_quantile(0.5) as f64 / 1e3,
        h.value_at_quantile(0.99) as f64 / 1e3,
        h.value_at_quantile(0.9999) as f64 / 1e3,
        h.max() as f64 / 1e3
    );
}

fn ratios() {
    for (name, moves) in [
        ("squares", samples::squares()),
        ("circles", samples::circles()),
        ("zigzag", samples::zigzag()),
        ("chord_circle", samples::chord_circle()),
        ("spiral", samples::spiral()),
        ("cam", samples::cam(20)),
    ] {
        let start = samples::start(name);
        let t = run(&moves, start) as f64 * 0.001;
        let lb = lower_bound(&samples::mill(), &start, &moves);
        println!(
            "{name:>12}: {t:8.3} s, lower bound {lb:8.3} s, ratio {:.4}",
            t / lb
        );
    }
}

/// The CAM set (issue 22) with contour control: time / bound.
fn cam_ratios() {
    for p in cam::set() {
        let t = samples::ticks_to_idle_with(samples::mill(), &p.moves, p.start, true)
            .expect("the program runs") as f64
            * 0.001;
        let lb = lower_bound(&samples::mill(), &p.start, &p.moves);
        println!(
            "{:>32}: {t:8.3} s, lower bound {lb:8.3} s, ratio {:.4}",
            p.name,
            t / lb
        );
    }
}

fn virtual_time(c: &mut Criterion) {
    let moves = samples::cam(250);
    let ticks = run(&moves, samples::start("cam"));
    println!(
        "100k blocks: {} blocks, {} ticks = {:.1} s of motion",
        moves.len(),
        ticks,
        ticks as f64 * 0.001
    );
    let mut g = c.benchmark_group("kernel");
    g.sample_size(10);
    g.bench_function("virtual_time_100k_blocks", |b| {
        b.iter(|| run(black_box(&moves), samples::start("cam")))
    });
    // The same 100,250 blocks rounded to 0.001 mm under contour control (smoothing and
    // complex speed): planning stays linear in the blocks.
    let rounded = cam::raster(250, 0.1, 3, 6000.0);
    let smooth = |m: &[Move]| {
        samples::ticks_to_idle_with(samples::mill(), m, rounded.start, true).expect("runs")
    };
    println!(
        "100k blocks under contour control: {} blocks, {:.1} s of motion",
        rounded.moves.len(),
        smooth(&rounded.moves) as f64 * 0.001
    );
    g.bench_function("virtual_time_100k_blocks_contour", |b| {
        b.iter(|| smooth(black_box(&rounded.moves)))
    });
    g.finish();
}

criterion_group!(benches, virtual_time);

fn main() {
    // Instruction counts: `valgrind --tool=callgrind <bench binary>` with this set runs one
    // 10,025-segment CAM program and nothing else (`MOTION_BENCH_ONE_RUN=250`: 100,250 segments,
    // for `/usr/bin/time`'s CPU time on a loaded machine, where wall-clock time is the load's).
    if let Some(rows) = std::env::var_os("MOTION_BENCH_ONE_RUN") {
        let rows = rows.to_str().and_then(|r| r.parse().ok()).unwrap_or(25);
        if std::env::var_os("MOTION_BENCH_CONTOUR").is_some() {
            // `MOTION_BENCH_CONTOUR=1`: the rounded raster under contour control.
            let p = cam::raster(rows, 0.1, 3, 6000.0);
            let ticks = samples::ticks_to_idle_with(samples::mill(), &p.moves, p.start, true)
                .expect("runs");
            println!("ticks {ticks}");
            return;
        }
        let moves = samples::cam(rows);
        // `MOTION_BENCH_OVERRIDES=1`: the feed and rapid overrides are set (unchanged, 100 %)
        // before every tick, as the CNC kernel does each logic tick.
        let ticks = if std::env::var_os("MOTION_BENCH_OVERRIDES").is_some() {
            run_with_overrides(&moves, samples::start("cam"))
        } else {
            run(&moves, samples::start("cam"))
        };
        println!("ticks {ticks}");
        return;
    }
    ratios();
    cam_ratios();
    per_tick_cost();
    benches();
    Criterion::default().configure_from_args().final_summary();
}
