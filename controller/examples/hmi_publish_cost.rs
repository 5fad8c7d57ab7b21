//! The scan thread's cost of the web HMI in instructions (the callgrind companion of the
//! `hmi_cost` bench): the lathe runs PART1 (kernel + JIT logic + plant, virtual time; built as
//! `ncplc run plc-programs/lathe --program PART1 --virtual-time --hmi` builds it) for 1,000 ticks,
//! then `N` more ticks (`ticks`) and `N` publishes (`publishes`).
//! `valgrind --tool=callgrind --toggle-collect='*publishes*' target/debug/examples/hmi_publish_cost 200`
//! counts the publishes only (divide by N), `--toggle-collect='*hmi_publish_cost::ticks*'` the plain ticks.

#[path = "../benches/common/mod.rs"]
mod common;

use controller::{Controller, Quiet};

/// `n` ticks, the HMI serviced after each (which publishes every 25 ms of wall time).
#[inline(never)]
fn warm_up(c: &mut Controller, n: u64) {
    for _ in 0..n {
        c.step(&mut Quiet);
    }
}

/// `n` plain ticks of a controller without HMI: the scan cost a publish is compared with.
#[inline(never)]
fn ticks(c: &mut Controller, n: u64) {
    for _ in 0..n {
        c.step(&mut Quiet);
    }
}

/// `n` publishes of the current state.
#[inline(never)]
fn publishes(c: &mut Controller, n: u64) {
    for _ in 0..n {
        std::hint::black_box(c.publish_hmi());
    }
}

fn main() {
    let n: u64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(200);
    let tmp = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let lathe = common::machine_dir("lathe");
    let mut plain = common::part_controller(&lathe, "PART1", None, None);
    let mut served =
        common::part_controller(&lathe, "PART1", Some(common::bench_hmi(tmp.path())), None);
    warm_up(&mut plain, 1_000);
    warm_up(&mut served, 1_000);
    ticks(&mut plain, n);
    publishes(&mut served, n);
    println!(
        "tick {}: {n} ticks and {n} publishes",
        plain.scheduler().tick_count()
    );
}
