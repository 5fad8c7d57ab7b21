//! Tests of the scheduler with hand-written programs: recording, replay, overrun trips, swaps.

use std::sync::mpsc;
use std::time::Instant;

use packets::PACKETS_LEN;

use crate::{CncSignals, Sim};
use runtime::clock::{Clock, VirtualClock};
use runtime::image::Image;
use runtime::program::Loaded;
use runtime::replay::{ReplayOptions, replay_keeping, replay_with};
use runtime::retain::RetainRecord;
use runtime::scheduler::{Event, Scheduler, Settings, Swap};
use runtime::testkit::{FixedMeta, loaded, sig};
use trace::{MemorySink, Trace};

/// U4A0 = TON(I0A0, 3 ticks) with the timer's tick count in image byte PACKETS_LEN;
/// MFIN (U11K0) = MSTB (I1K0).
fn program(preset: u8) -> Loaded {
    let meta = FixedMeta {
        image_len: PACKETS_LEN + 4,
        written: vec![sig("U4A0"), sig("U11K0")],
        retain: PACKETS_LEN + 1..PACKETS_LEN + 2,
        layout: 1,
    };
    loaded(
        move |img: &mut [u8]| {
            let on = sig("I0A0").read(img) == 1;
            img[PACKETS_LEN] = if on {
                img[PACKETS_LEN].saturating_add(1)
            } else {
                0
            };
            sig("U4A0").write(img, u8::from(img[PACKETS_LEN] > preset));
            let stb = sig("I1K0").read(img);
            sig("U11K0").write(img, stb);
            img[PACKETS_LEN + 1] = img[PACKETS_LEN + 1].wrapping_add(stb);
        },
        meta,
    )
}

const SCRIPT: &str =
    "[[at]]\ntick = 2\nset = { I0A0 = 1 }\nm = [3]\n[[at]]\ntick = 12\nset = { I0A0 = 0 }\n";

fn sim() -> Box<Sim> {
    let script = Sim::parse_script(SCRIPT).expect("script");
    Box::new(Sim::new(script, CncSignals::default(), 10).expect("sim"))
}

fn settings() -> Settings {
    Settings {
        tick_ns: 10_000_000,
        overrun_limit: 3,
    }
}

fn record(ticks: u64) -> Trace {
    let sink = MemorySink::default();
    let mut s = Scheduler::new(
        Image::new(0, &[]),
        program(3),
        sim(),
        Box::new(VirtualClock::new()),
        settings(),
    );
    s.record_to(Box::new(sink.clone()));
    s.run(Some(ticks), |_| true);
    s.finish().expect("finish");
    let ticks = sink.0.lock().expect("lock").clone();
    Trace {
        tick_ms: 10,
        ticks,
        part: None,
    }
}

#[test]
fn recording_holds_inputs_and_changed_outputs() {
    let trace = record(20);
    let mut text = Vec::new();
    trace.write_text(&mut text).expect("text");
    assert_eq!(
        String::from_utf8(text).expect("utf8"),
        "{\"format\":\"ncplc-trace\",\"version\":1,\"tick_ms\":10}\n\
         {\"t\":2,\"in\":{\"I0A0\":1,\"W3K0\":3}}\n\
         {\"t\":3,\"in\":{\"I1K0\":1},\"out\":{\"U11K0\":1}}\n\
         {\"t\":4,\"in\":{\"I1K0\":0},\"out\":{\"U11K0\":0}}\n\
         {\"t\":5,\"out\":{\"U4A0\":1}}\n\
         {\"t\":12,\"in\":{\"I0A0\":0},\"out\":{\"U4A0\":0}}\n\
         {\"t\":19}\n"
    );
}

#[test]
fn replay_of_a_recording_is_identical_and_a_changed_program_diverges() {
    let trace = record(20);
    let (same, actual) = replay_keeping(&trace, program(3), &[], ReplayOptions::default(), |_| {});
    assert!(same.identical(), "{}", same.report());
    assert_eq!(actual, trace);
    let options = ReplayOptions {
        context: 2,
        ..ReplayOptions::default()
    };
    let changed = replay_with(&trace, program(4), &[], options, |_| {});
    assert!(!changed.identical());
    // The records of ticks 3..=7 around the first divergence (tick 5), of both sides: the
    // replay kept them as it went.
    assert_eq!(
        changed.report(),
        "replay diverges from the trace (1 divergence(s)); first ones:\n\
         \x20     tick  signal    expected    actual\n\
         \x20        5  U4A0             1         0\n\
         context, ticks 3..=7:\n\
         \x20 trace (expected):\n\
         \x20   {\"t\":3,\"in\":{\"I1K0\":1},\"out\":{\"U11K0\":1}}\n\
         \x20   {\"t\":4,\"in\":{\"I1K0\":0},\"out\":{\"U11K0\":0}}\n\
         \x20   {\"t\":5,\"out\":{\"U4A0\":1}}\n\
         \x20 replay (actual):\n\
         \x20   {\"t\":3,\"in\":{\"I1K0\":1},\"out\":{\"U11K0\":1}}\n\
         \x20   {\"t\":4,\"in\":{\"I1K0\":0},\"out\":{\"U11K0\":0}}\n\
         \x20   {\"t\":6,\"out\":{\"U4A0\":1}}\n"
    );
}

/// A clock on which every tick takes `cost` ns of work (virtual, but not marked virtual).
struct SlowClock {
    now: u64,
    cost: u64,
}

impl Clock for SlowClock {
    fn now_ns(&mut self) -> u64 {
        self.now += self.cost;
        self.now
    }
    fn sleep_until(&mut self, deadline_ns: u64) -> u64 {
        self.now = self.now.max(deadline_ns);
        self.now
    }
    fn is_virtual(&self) -> bool {
        false
    }
}

#[test]
fn consecutive_overruns_trip_the_safe_state() {
    let meta = FixedMeta {
        image_len: PACKETS_LEN,
        written: vec![sig("U4A0")],
        retain: 0..0,
        layout: 0,
    };
    let prog = loaded(|img: &mut [u8]| sig("U4A0").write(img, 1), meta);
    let clock = SlowClock {
        now: 0,
        cost: 15_000_000,
    };
    let mut s = Scheduler::new(Image::new(0, &[]), prog, sim(), Box::new(clock), settings());
    s.run(Some(2), |_| true);
    assert!(!s.tripped());
    assert_eq!(sig("U4A0").read(s.image().bytes()), 1);
    s.run(Some(1), |_| true);
    assert!(s.tripped());
    assert_eq!(sig("U4A0").read(s.image().bytes()), 0);
    assert_eq!(s.stats.overruns, 3);
    let events = s.take_events();
    assert_eq!(
        events,
        vec![Event::Alarm(
            "3 consecutive overruns at tick 2: outputs in safe state, logic halted".into()
        )]
    );
    s.run(Some(2), |_| true);
    assert_eq!(sig("U4A0").read(s.image().bytes()), 0);
}

#[test]
fn swap_keeps_state_and_misses_no_tick() {
    let (tx, rx) = mpsc::channel();
    let mut s = Scheduler::new(
        Image::new(0, &[]),
        program(3),
        sim(),
        Box::new(VirtualClock::new()),
        settings(),
    );
    s.accept_swaps(rx);
    s.run(Some(5), |_| true);
    let counter_before = s.image().bytes()[PACKETS_LEN];
    assert_eq!(counter_before, 3);
    tx.send(Swap {
        loaded: program(5),
        noticed: Instant::now(),
        modified: None,
    })
    .expect("send");
    s.run(Some(1), |_| true);
    assert_eq!(s.image().bytes()[PACKETS_LEN], 4);
    assert!(matches!(
        s.take_events().as_slice(),
        [Event::Swapped { tick: 5, .. }]
    ));
    assert_eq!(s.tick_count(), 6);
}

#[test]
fn retain_snapshots_follow_changes() {
    let saved = std::sync::Arc::new(std::sync::Mutex::new(Vec::<RetainRecord>::new()));
    let keep = saved.clone();
    let mut s = Scheduler::new(
        Image::new(0, &[]),
        program(3),
        sim(),
        Box::new(VirtualClock::new()),
        settings(),
    );
    s.retain_to(Box::new(move |r| keep.lock().expect("lock").push(r)));
    s.run(Some(10), |_| true);
    let saved = saved.lock().expect("lock");
    // The retain byte counts strobe ticks: MSTB is up during tick 3 only.
    assert_eq!(
        saved
            .iter()
            .map(|r| (r.seq, r.retain.clone()))
            .collect::<Vec<_>>(),
        vec![(1, vec![1])]
    );
}
