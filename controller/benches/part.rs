//! Part runs (issue 11 targets): a 10-minute mill part through kernel + logic + plant in virtual
//! time (target ≤ 1 s), and the kernel's cost per logic tick (one process, the lathe part;
//! target p99 ≤ 20 µs), printed as p50/p99/max beside criterion's mean. Both controllers are built
//! as `ncplc run … --program … --until-end --virtual-time` builds them.

use std::sync::{Arc, Mutex};
use std::time::Instant;

mod common;

use controller::{Controller, Quiet};
use criterion::{Criterion, criterion_group, criterion_main};
use packets::PacketIo;

/// Runs `c` to the end of its part (at most 200,000 ticks) and returns the ticks run.
fn run_to_end(mut c: Controller) -> u64 {
    c.run(&mut Quiet);
    let ticks = c.scheduler().tick_count();
    assert!(ticks < 200_000, "the part did not end");
    ticks
}

fn bench(c: &mut Criterion) {
    let tmp = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let mill =
        common::machine_with_program("mill", tmp.path(), "BENCH", &common::long_mill_program());
    let ticks = run_to_end(common::part_controller(&mill, "BENCH", None, None));
    eprintln!(
        "long mill part: {ticks} ticks = {:.1} s machine time (10 ms tick)",
        ticks as f64 * 10.0 / 1000.0
    );
    let mut g = c.benchmark_group("part_run");
    g.sample_size(10);
    g.bench_function("mill_10min_part_kernel_logic_plant", |b| {
        b.iter(|| run_to_end(common::part_controller(&mill, "BENCH", None, None)))
    });
    g.finish();

    // The kernel's cost per logic tick: `latch_inputs` of the part run's I/O (the part script's
    // inputs, then `Cnc::step`: 5 interpolation ticks, drives, spindle, handshakes) over the
    // lathe part, timed per tick.
    let times = Arc::new(Mutex::new(Vec::new()));
    let timed = Arc::clone(&times);
    let wrap: controller::WrapIo = Box::new(move |inner, _cnc| {
        Box::new(Timed {
            inner,
            times: timed,
        })
    });
    let lathe = common::machine_dir("lathe");
    run_to_end(common::part_controller(&lathe, "PART1", None, Some(wrap)));
    let mut times = times.lock().map(|v| v.clone()).unwrap_or_default();
    times.sort_unstable();
    let q = |f: f64| times[((times.len() - 1) as f64 * f) as usize] as f64 / 1000.0;
    eprintln!(
        "kernel latch per logic tick (lathe PART1, {} ticks): p50 {:.2} µs  p99 {:.2} µs  max {:.2} µs",
        times.len(),
        q(0.5),
        q(0.99),
        q(1.0)
    );
}

/// Times every `latch_inputs` of the wrapped I/O.
struct Timed {
    inner: Box<dyn PacketIo>,
    times: Arc<Mutex<Vec<u64>>>,
}

impl PacketIo for Timed {
    fn name(&self) -> &str {
        "timed"
    }
    fn latch_inputs(&mut self, tick: u64, packets: &mut [u8]) {
        let t = Instant::now();
        self.inner.latch_inputs(tick, packets);
        let ns = t.elapsed().as_nanos() as u64;
        if let Ok(mut v) = self.times.lock() {
            v.push(ns);
        }
    }
    fn publish_outputs(&mut self, tick: u64, packets: &[u8]) {
        self.inner.publish_outputs(tick, packets);
    }
    fn take_alarms(&mut self) -> Vec<packets::IoAlarm> {
        self.inner.take_alarms()
    }
    fn safe_state(&mut self) {
        self.inner.safe_state();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
