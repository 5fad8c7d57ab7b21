//! Differential tests of idle skipping: a replay that jumps over idle ticks gives the same records,
//! the same comparison and the same final image as a tick-by-tick replay, on random programs with
//! named and inline timers, ET reads, counters, one-shots, IF zones and a sliced SLOW part, driven
//! by sparse inputs.

use compiler::interface_map::InterfaceMap;
use proptest::prelude::*;

use crate::compiled::{EngineKind, compile};
use crate::config::RunConfig;
use crate::program::Loaded;
use crate::replay::{Replay, ReplayOptions, replay_keeping};
use crate::testkit::sig;
use trace::{TickRecord, Trace};

fn load(src: &str, tick_ms: u32, engine: EngineKind) -> Loaded {
    let cfg = RunConfig {
        a_inputs: vec![0, 1],
        a_outputs: vec![4, 5],
        spl: 64,
        // Every SLOW statement a slice of its own: cycles of several ticks.
        time_slow_ms: 0,
        ..RunConfig::default()
    };
    compile(
        "PLCPRG",
        src.as_bytes(),
        &cfg,
        &InterfaceMap::builtin(),
        tick_ms,
        engine,
    )
    .unwrap_or_else(|e| panic!("{src}\n{e}"))
}

/// The replay and the records it produced.
fn run(
    src: &str,
    tick_ms: u32,
    trace: &Trace,
    engine: EngineKind,
    skip_idle: bool,
) -> (Replay, Trace) {
    let options = ReplayOptions {
        skip_idle,
        ..ReplayOptions::default()
    };
    replay_keeping(trace, load(src, tick_ms, engine), &[], options, |_| {})
}

fn input_only(t: u64, inputs: &[(&str, u8)]) -> TickRecord {
    TickRecord {
        nodes_lost: Vec::new(),
        commands: Vec::new(),
        drives: Vec::new(),
        forced: Vec::new(),
        positions: Vec::new(),
        t,
        inputs: inputs.iter().map(|&(s, v)| (sig(s), v)).collect(),
        outputs: Vec::new(),
    }
}

#[test]
fn a_running_timer_is_jumped_to_the_tick_of_its_expiry_and_then_to_the_end() {
    // TON 500 ms at 10 ms: IN rises at tick 0 (ET 0), ET reaches 500 at tick 50 and Q sets U4A0.
    // Skipping: tick 1 shows ET +10 with nothing else changed, so ticks 2..=49 (48) are jumped with
    // ET advanced to 490; tick 50 runs and sets Q; tick 51 changes nothing, so ticks 52..=998
    // (947) are jumped and the last tick 999 runs.
    let src = "DEF T1 : TON(500ms)\nT1 = I0A0\nU4A0 = T1\n";
    let trace = Trace {
        part: None,
        tick_ms: 10,
        ticks: vec![input_only(0, &[("I0A0", 1)]), input_only(999, &[])],
    };
    for engine in [EngineKind::Jit, EngineKind::Interp] {
        let (skipping, skipped) = run(src, 10, &trace, engine, true);
        let (stepping, stepped) = run(src, 10, &trace, engine, false);
        assert_eq!(skipping.skipped, 995, "{engine:?}");
        assert_eq!(stepping.skipped, 0, "{engine:?}");
        let expected = vec![
            input_only(0, &[("I0A0", 1)]),
            TickRecord {
                nodes_lost: Vec::new(),
                commands: Vec::new(),
                drives: Vec::new(),
                forced: Vec::new(),
                positions: Vec::new(),
                t: 50,
                inputs: vec![],
                outputs: vec![(sig("U4A0"), 1)],
            },
            input_only(999, &[]),
        ];
        assert_eq!(skipped.ticks, expected, "{engine:?}");
        assert_eq!(stepped.ticks, expected, "{engine:?}");
        assert_eq!(skipping.image, stepping.image, "{engine:?}");
    }
}

#[test]
fn a_replay_that_drives_a_kernel_never_skips() {
    let src = "U4A0 = I0A0\n";
    let trace = Trace {
        part: None,
        tick_ms: 1,
        ticks: vec![input_only(0, &[("I0A0", 1)]), input_only(9_999, &[])],
    };
    let options = ReplayOptions {
        skip_idle: true,
        drives_kernel: true,
        ..ReplayOptions::default()
    };
    assert!(!options.skips());
    let (r, actual) = replay_keeping(
        &trace,
        load(src, 1, EngineKind::Interp),
        &[],
        options,
        |_| {},
    );
    assert_eq!(r.skipped, 0);
    let (free, free_actual) = run(src, 1, &trace, EngineKind::Interp, true);
    // Tick 1 shows an unchanged image: ticks 2..=9998 are jumped.
    assert_eq!(free.skipped, 9_997);
    assert_eq!(free_actual, actual);
}

fn bit() -> BoxedStrategy<String> {
    prop_oneof![
        3 => (0u8..6).prop_map(|n| format!("I0A{n}")),
        1 => (0u8..8).prop_map(|n| format!("U4A{n}")),
        1 => (0u8..4).prop_map(|n| format!("T{n}")),
        1 => Just("C0".to_string()),
        1 => (0u8..4, 0u32..250).prop_map(|(n, v)| format!("[T{n}.ET > {v}]")),
    ]
    .boxed()
}

fn cond() -> BoxedStrategy<String> {
    prop_oneof![
        2 => bit(),
        1 => bit().prop_map(|b| format!("/{b}")),
        1 => (bit(), bit()).prop_map(|(a, b)| format!("{a} * /{b}")),
        1 => (bit(), bit()).prop_map(|(a, b)| format!("{a} + {b}")),
    ]
    .boxed()
}

/// One statement; `TIMER`/`PULSE` are numbered by the caller (each has one driving statement).
fn statement() -> BoxedStrategy<String> {
    prop_oneof![
        4 => ((0u8..8), cond()).prop_map(|(n, c)| format!("U4A{n} = {c}")),
        3 => cond().prop_map(|c| format!("TIMER = {c}")),
        1 => ((0u8..8), proptest::sample::select(vec!["TON", "TOF", "TP"]), cond(), 0u32..90)
            .prop_map(|(n, k, c, ms)| format!("U5A{n} = {k}({c}, {ms}ms)")),
        1 => ((0u8..8), cond()).prop_map(|(n, c)| format!("PULSE = {c}\nU5A{n} = PULSE")),
        1 => cond().prop_map(|c| format!("C0 = {c}")),
        1 => cond().prop_map(|c| format!("C0.R = {c}")),
        1 => ((0u8..8), any::<bool>(), cond())
            .prop_map(|(n, s, c)| format!("{} U4A{n} = {c}", if s { "SET" } else { "RES" })),
        1 => (cond(), (0u8..8), cond(), (0u8..8), cond()).prop_map(|(z, a, x, b, y)| {
            format!("IF {z} THEN\nU5A{a} = {x}\nU4A{b} = TON({y}, 40ms)\nEND_IF")
        }),
    ]
    .boxed()
}

fn source() -> impl Strategy<Value = String> {
    (
        proptest::collection::vec(0usize..3, 4),
        proptest::collection::vec(0u32..300, 4),
        proptest::collection::vec(statement(), 1..10),
        proptest::collection::vec(statement(), 0..5),
    )
        .prop_map(|(kinds, presets, fast, slow)| {
            let mut text = String::new();
            for (i, (k, p)) in kinds.iter().zip(&presets).enumerate() {
                let kind = ["TON", "TOF", "TP"][*k];
                text.push_str(&format!("DEF T{i} : {kind}({p}ms)\n"));
            }
            text.push_str("DEF C0 : CTU(3)\n");
            let (mut timer, mut pulse) = (0, 0);
            let (mut count, mut reset) = (false, false);
            let mut emit = |stmts: Vec<String>, text: &mut String| {
                for s in stmts {
                    // A counter input has one driving statement: later ones are dropped.
                    let once = if s.starts_with("C0 =") {
                        &mut count
                    } else if s.starts_with("C0.R =") {
                        &mut reset
                    } else {
                        &mut false
                    };
                    if std::mem::replace(once, true)
                        && (s.starts_with("C0 =") || s.starts_with("C0.R ="))
                    {
                        continue;
                    }
                    let s = if s.starts_with("TIMER") {
                        if timer == 4 {
                            continue;
                        }
                        timer += 1;
                        s.replacen("TIMER", &format!("T{}", timer - 1), 1)
                    } else if s.starts_with("PULSE") {
                        pulse += 1;
                        s.replace("PULSE", &format!("P{pulse}"))
                    } else {
                        s
                    };
                    text.push_str(&s);
                    text.push('\n');
                }
            };
            emit(fast, &mut text);
            if !slow.is_empty() {
                text.push_str("$\n");
                emit(slow, &mut text);
            }
            text
        })
}

/// Sparse inputs: a few changes of I0A0..I0A5 with gaps of up to 300 ticks.
fn sparse_trace() -> impl Strategy<Value = Trace> {
    (
        proptest::collection::vec((1u64..300, 0u8..6, 0u8..2), 1..12),
        1u64..400,
        proptest::sample::select(vec![1u32, 5, 10]),
    )
        .prop_map(|(changes, tail, tick_ms)| {
            let mut ticks = Vec::new();
            let mut t = 0;
            for (gap, n, v) in changes {
                ticks.push(TickRecord {
                    nodes_lost: Vec::new(),
                    commands: Vec::new(),
                    drives: Vec::new(),
                    forced: Vec::new(),
                    positions: Vec::new(),
                    t,
                    inputs: vec![(sig(&format!("I0A{n}")), v)],
                    outputs: Vec::new(),
                });
                t += gap;
            }
            ticks.push(TickRecord {
                forced: Vec::new(),
                positions: Vec::new(),
                t: t + tail,
                ..TickRecord::default()
            });
            Trace {
                tick_ms,
                ticks,
                part: None,
            }
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn skipping_idle_ticks_gives_the_tick_by_tick_replay(src in source(), trace in sparse_trace()) {
        let (stepping, stepped) = run(&src, trace.tick_ms, &trace, EngineKind::Interp, false);
        for engine in [EngineKind::Interp, EngineKind::Jit] {
            let (skipping, skipped) = run(&src, trace.tick_ms, &trace, engine, true);
            prop_assert_eq!(&skipped, &stepped, "{:?}\n{}", engine, src);
            prop_assert_eq!(&skipping.image, &stepping.image, "{:?}\n{}", engine, src);
            prop_assert_eq!(skipping.comparator.total(), stepping.comparator.total());
        }
    }
}
