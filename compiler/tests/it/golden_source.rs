//! Source-level golden tests: PLC statement text is compiled by the front end and run on both
//! engines; hand-computed expectations give the exact tick at which every element switches
//! (docs/plc-language.md §4.1) and the images must agree bit for bit after every tick.

use std::sync::Arc;

use compiler::ir::{FAULT_DIV_ZERO, HDR_FAULTS, Program};
use compiler::{Engine, Interpreter, MachineContext, compile};
use packets::Signal;

fn build(src: &str, ctx: &MachineContext) -> Program {
    let c = compile("golden", src.as_bytes(), ctx);
    match c.program {
        Some(p) => p,
        None => panic!("does not compile: {:#?}", c.diagnostics),
    }
}

fn sig(s: &str) -> Signal {
    s.parse().expect("signal")
}

/// Runs both engines for as many ticks as `inputs` has rows; row `t` lists `(signal, value)`
/// written before tick `t`. Returns the values of `probes` after every tick.
fn run(p: Program, inputs: &[&[(&str, u8)]], probes: &[&str]) -> Vec<Vec<u8>> {
    let p = Arc::new(p);
    let mut interp = Interpreter::new(p.clone());
    let mut jit = compiler::jit::compile(&p).expect("jit");
    let (mut a, mut b) = (p.new_image(), p.new_image());
    let mut out = Vec::new();
    for (t, row) in inputs.iter().enumerate() {
        for &(s, v) in row.iter() {
            sig(s).write(&mut a, v);
            sig(s).write(&mut b, v);
        }
        interp.tick(&mut a);
        jit.tick(&mut b);
        let diff: Vec<_> = (0..a.len())
            .filter(|&i| a[i] != b[i])
            .map(|i| (i, a[i], b[i]))
            .collect();
        assert!(
            diff.is_empty(),
            "engines differ after tick {t}: (offset, interp, jit) {diff:?}"
        );
        out.push(probes.iter().map(|s| sig(s).read(&a)).collect());
    }
    out
}

fn column(rows: &[Vec<u8>], i: usize) -> Vec<u8> {
    rows.iter().map(|r| r[i]).collect()
}

/// A level input held per tick: `levels[t]` for signal `s`.
fn levels<'a>(s: &'a str, levels: &[u8]) -> Vec<Vec<(&'a str, u8)>> {
    levels.iter().map(|&v| vec![(s, v)]).collect()
}

fn rows<'a>(v: &'a [Vec<(&'a str, u8)>]) -> Vec<&'a [(&'a str, u8)]> {
    v.iter().map(Vec::as_slice).collect()
}

#[test]
fn seed_pulse_clears_a_cnc_bit_one_scan_after_it_appeared() {
    let p = build("P2=U100K0\nU100K0=P2\n", &MachineContext::lathe_like());
    let input: Vec<Vec<(&str, u8)>> = vec![
        vec![],
        vec![("U100K0", 1)],
        vec![],
        vec![],
        vec![("U100K0", 1)],
        vec![],
    ];
    let got = run(p, &rows(&input), &["U100K0"]);
    assert_eq!(column(&got, 0), vec![0, 1, 0, 0, 1, 0]);
}

#[test]
fn seed_self_latch_on_m91_off_on_m90_or_reset() {
    let p = build(
        "U150N0=[W3K0=91H]+U150N0*/[W3K0=90H]*/I0K1\n",
        &MachineContext::lathe_like(),
    );
    let m = |v: u8, r: u8| vec![("W3K0", v), ("I0K1", r)];
    let input = vec![
        m(0, 0),
        m(0x91, 0),
        m(0, 0),
        m(0x90, 0),
        m(0x91, 0),
        m(0, 1),
        m(0, 0),
    ];
    let got = run(p, &rows(&input), &["U150N0"]);
    assert_eq!(column(&got, 0), vec![0, 1, 1, 0, 1, 0, 0]);
}

#[test]
fn seed_fragments_compute_their_ladder_meaning() {
    let src = ";comment line\nU180K0=I0K2\nU170K7=/I1A29\nU10K5=U150N0*/I150N1\nU150N2=/U250N0+U250N0\nU10K10=I0K2*/U150N0\n$\n";
    let p = build(src, &MachineContext::lathe_like());
    let input = vec![
        vec![("I0K2", 1), ("I1A29", 1), ("U150N0", 1)],
        vec![("I0K2", 0), ("I1A29", 0), ("I150N1", 1)],
    ];
    let got = run(
        p,
        &rows(&input),
        &["U180K0", "U170K7", "U10K5", "U150N2", "U10K10"],
    );
    assert_eq!(got, vec![vec![1, 0, 1, 1, 0], vec![0, 1, 0, 1, 0]]);
}

#[test]
fn named_ton_switches_at_the_fifth_execution() {
    let p = build(
        "DEF T1 : TON(50ms)\nT1 = I0A0\nU4A0 = T1\nU4A1 = [T1.ET >= 30]\n",
        &MachineContext::lathe_like(),
    );
    let input = levels("I0A0", &[0, 1, 1, 1, 1, 1, 1, 1, 0, 1]);
    let got = run(p, &rows(&input), &["U4A0", "U4A1"]);
    assert_eq!(column(&got, 0), vec![0, 0, 0, 0, 0, 0, 1, 1, 0, 0]);
    assert_eq!(column(&got, 1), vec![0, 0, 0, 0, 1, 1, 1, 1, 0, 0]);
}

#[test]
fn inline_tof_holds_five_executions_and_tp_is_one_preset_long() {
    let src = "U4A0 = TOF(I0A0, 50ms)\nU4A1 = TP(I0A1, 30ms)\n";
    let p = build(src, &MachineContext::lathe_like());
    let tof = [1, 1, 0, 0, 0, 0, 0, 0, 0];
    let tp = [1, 0, 1, 0, 0, 1, 1, 0, 0];
    let input: Vec<Vec<(&str, u8)>> = (0..9)
        .map(|t| vec![("I0A0", tof[t]), ("I0A1", tp[t])])
        .collect();
    let got = run(p, &rows(&input), &["U4A0", "U4A1"]);
    assert_eq!(column(&got, 0), vec![1, 1, 1, 1, 1, 1, 1, 0, 0]);
    assert_eq!(column(&got, 1), vec![1, 1, 1, 0, 0, 1, 1, 1, 0]);
}

#[test]
fn timer_preset_rounds_up_to_whole_ticks() {
    // 41 ms with a 10 ms tick is 50 ms: five executions.
    let p = build("U4A0 = TON(I0A0, 41ms)\n", &MachineContext::lathe_like());
    let got = run(p, &rows(&levels("I0A0", &[1, 1, 1, 1, 1, 1])), &["U4A0"]);
    assert_eq!(column(&got, 0), vec![0, 0, 0, 0, 0, 1]);
}

#[test]
fn ctu_and_ctd_switch_at_the_preset() {
    let src = "DEF C : CTU(3)\nDEF D : CTD(2)\nC = I0A0\nC.R = I0A1\nD.LD = I0A2\nD = I0A0\nU4A0 = C\nU4A1 = D\nU4A2 = [C.CV = 1]\n";
    let p = build(src, &MachineContext::lathe_like());
    let cnt = [1, 0, 1, 0, 1, 0, 0, 1, 0];
    let rst = [0, 0, 0, 0, 0, 1, 0, 0, 0];
    let ld = [1, 0, 0, 0, 0, 0, 0, 0, 0];
    let input: Vec<Vec<(&str, u8)>> = (0..9)
        .map(|t| vec![("I0A0", cnt[t]), ("I0A1", rst[t]), ("I0A2", ld[t])])
        .collect();
    let got = run(p, &rows(&input), &["U4A0", "U4A1", "U4A2"]);
    // CTU: 1, 1, 2, 2, 3 (Q), reset at 5, 1 at 7.
    assert_eq!(column(&got, 0), vec![0, 0, 0, 0, 1, 0, 0, 0, 0]);
    assert_eq!(column(&got, 2), vec![1, 1, 0, 0, 0, 0, 0, 1, 1]);
    // CTD: loaded to 2 at tick 0 (no count while LD), 1 at 2, 0 at 4 (Q), -1 at 7.
    assert_eq!(column(&got, 1), vec![0, 0, 0, 0, 1, 1, 1, 1, 1]);
}

#[test]
fn if_zone_freezes_a_timer_and_keeps_coils() {
    let src = "IF I0A1 THEN\nU4A0 = TON(I0A0, 30ms)\nU4A1 = I0A0\nEND_IF\n";
    let p = build(src, &MachineContext::lathe_like());
    let zone = [1, 1, 0, 0, 1, 1, 0];
    let input: Vec<Vec<(&str, u8)>> = (0..7)
        .map(|t| vec![("I0A0", 1), ("I0A1", zone[t])])
        .collect();
    let got = run(p, &rows(&input), &["U4A0", "U4A1"]);
    // Executions at ticks 0, 1, 4, 5: ET 0, 10, 20, 30 → Q at tick 5; frozen outside the zone.
    assert_eq!(column(&got, 0), vec![0, 0, 0, 0, 0, 1, 1]);
    assert_eq!(column(&got, 1), vec![1, 1, 1, 1, 1, 1, 1]);
}

#[test]
fn slow_part_runs_one_slice_per_tick() {
    let ctx = MachineContext {
        time_slow_ms: 0,
        ..MachineContext::lathe_like()
    };
    let src = "U4A0 = I0A0\n$\nU4A1 = I0A0\nU4A2 = I0A0\nU4A3 = I0A0\n";
    let p = build(src, &ctx);
    assert_eq!(p.slow.len(), 3);
    let got = run(
        p,
        &rows(&levels("I0A0", &[1, 1, 1, 0, 0, 0])),
        &["U4A0", "U4A1", "U4A2", "U4A3"],
    );
    assert_eq!(
        got,
        vec![
            vec![1, 1, 0, 0],
            vec![1, 1, 1, 0],
            vec![1, 1, 1, 1],
            vec![0, 0, 1, 1],
            vec![0, 0, 0, 1],
            vec![0, 0, 0, 0],
        ]
    );
}

#[test]
fn integer_division_by_zero_yields_zero_and_the_fault_flag() {
    let src = "DEF X : INT := 100\nDEF Z : INT\nDEF Q : INT := 7\nQ = X / Z\nU4A0 = [Q = 0]\n";
    let p = build(src, &MachineContext::lathe_like());
    let p = Arc::new(p);
    let mut image = p.new_image();
    compiler::jit::compile(&p).expect("jit").tick(&mut image);
    assert_eq!(sig("U4A0").read(&image), 1);
    let faults = u32::from_le_bytes(
        image[HDR_FAULTS..HDR_FAULTS + 4]
            .try_into()
            .expect("4 bytes"),
    );
    assert_eq!(faults, FAULT_DIV_ZERO);
    let mut image2 = p.new_image();
    Interpreter::new(p.clone()).tick(&mut image2);
    assert_eq!(image, image2);
}
