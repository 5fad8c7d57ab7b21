//! The scan thread's cost of the web HMI in instructions (the callgrind companion of the
//! `hmi_cost` bench): the lathe runs PART1 (kernel + JIT logic + plant, virtual time) for 1,000
//! ticks with the HMI linked, then `N` more ticks (`ticks`) and `N` publishes (`publishes`).
//! `valgrind --tool=callgrind --toggle-collect='*publishes*' target/debug/examples/hmi_publish_cost 200`
//! counts the publishes only (divide by N), `--toggle-collect='*hmi_publish_cost::ticks*'` the plain ticks.

#[path = "../benches/common/mod.rs"]
mod common;

use std::path::PathBuf;

use controller::hmi_link::HmiLink;
use controller::machine::Machine;
use runtime::scheduler::Scheduler;

/// `n` ticks with the HMI serviced after each (which publishes every 25 ms of wall time).
#[inline(never)]
fn warm_up(s: &mut Scheduler, link: &mut HmiLink, n: u64) {
    let until = s.tick_count() + n;
    s.run(Some(until), |s| {
        link.service(s);
        true
    });
}

/// `n` plain ticks: the scan cost a publish is compared with.
#[inline(never)]
fn ticks(s: &mut Scheduler, n: u64) {
    let until = s.tick_count() + n;
    s.run(Some(until), |_| true);
}

/// `n` publishes of the current state.
#[inline(never)]
fn publishes(s: &Scheduler, link: &mut HmiLink, n: u64) {
    for _ in 0..n {
        link.publish(std::hint::black_box(s));
    }
}

fn main() {
    let n: u64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(200);
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../plc-programs/lathe");
    let m = Machine::open(&dir, None).unwrap_or_else(|e| panic!("{e}"));
    let source = m.read_source().unwrap_or_else(|e| panic!("{e}"));
    let text = std::fs::read_to_string(m.dir.join("nc/PART1")).unwrap_or_else(|e| panic!("{e}"));
    let (mut s, cnc) = common::part_scheduler(&m, "PART1", &text, |io| Box::new(io));
    let mut link = common::hmi_link(&m, &source, &text, cnc);
    warm_up(&mut s, &mut link, 1_000);
    ticks(&mut s, n);
    publishes(&s, &mut link, n);
    println!("tick {}: {n} ticks and {n} publishes", s.tick_count());
}
