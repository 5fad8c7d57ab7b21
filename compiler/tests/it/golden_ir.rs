//! Golden tests written against the IR: hand-computed tick-by-tick expectations for timers,
//! counters, pulses, SET/RES, IF zones, SLOW slicing and arithmetic, checked on both engines
//! (which must also agree bit for bit on the whole image after every tick).

use std::sync::Arc;

use compiler::ir::{
    BinOp, CmpOp, CounterKind, Expr, FAULT_DIV_ZERO, HDR_FAULTS, Place, Program, ProgramBuilder,
    Stmt, TimerKind, Ty, Value,
};
use compiler::{Engine, Interpreter};
use packets::Signal;

fn sig(s: &str) -> Signal {
    s.parse().expect("signal")
}
fn load(s: &str) -> Expr {
    Expr::Load(Place::Signal(sig(s)))
}
fn assign(s: &str, value: Expr) -> Stmt {
    Stmt::Assign {
        place: Place::Signal(sig(s)),
        value,
    }
}
fn not(e: Expr) -> Expr {
    Expr::Not(Box::new(e))
}
fn bin(op: BinOp, ty: Ty, a: Expr, b: Expr) -> Expr {
    Expr::Binary {
        op,
        ty,
        lhs: Box::new(a),
        rhs: Box::new(b),
    }
}

/// Runs `ticks` ticks on both engines; before tick `t`, `inputs(t, image)` writes the inputs.
/// After every tick the images must be identical; returns `probe(image)` per tick.
fn run<T>(
    p: Program,
    ticks: usize,
    inputs: impl Fn(usize, &mut [u8]),
    probe: impl Fn(&[u8]) -> T,
) -> Vec<T> {
    let p = Arc::new(p);
    let mut interp = Interpreter::new(p.clone());
    let mut jit = compiler::jit::compile(&p).expect("jit");
    let mut a = p.new_image();
    let mut b = p.new_image();
    let mut out = Vec::new();
    for t in 0..ticks {
        inputs(t, &mut a);
        inputs(t, &mut b);
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
        out.push(probe(&a));
    }
    out
}

fn bit(image: &[u8], s: &str) -> u8 {
    sig(s).read(image)
}

fn i32_at(image: &[u8], at: usize) -> i32 {
    i32::from_le_bytes([image[at], image[at + 1], image[at + 2], image[at + 3]])
}

/// A one-timer program: `t = I0A0`, `U4A0 = t`.
fn timer_program(kind: TimerKind, preset: u64) -> (Program, usize) {
    let mut b = ProgramBuilder::new(10, 5);
    let t = b.timer("t", kind, preset);
    let fast = vec![
        Stmt::Timer {
            timer: t,
            input: load("I0A0"),
        },
        assign("U4A0", Expr::TimerQ(t)),
    ];
    let p = b.finish(fast, vec![]).expect("valid");
    let at = p.timers[0].offset;
    (p, at)
}

fn drive(pattern: &'static [u8]) -> impl Fn(usize, &mut [u8]) {
    move |t, m| sig("I0A0").write(m, pattern.get(t).copied().unwrap_or(0))
}

#[test]
fn ton_rises_at_the_fifth_execution_after_the_input() {
    let (p, at) = timer_program(TimerKind::Ton, 50);
    let input: &[u8] = &[0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 0, 1];
    let got = run(p, 12, drive(input), |m| (bit(m, "U4A0"), i32_at(m, at)));
    let q: Vec<u8> = got.iter().map(|g| g.0).collect();
    let et: Vec<i32> = got.iter().map(|g| g.1).collect();
    assert_eq!(q, vec![0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 0, 0]);
    assert_eq!(et, vec![0, 0, 0, 10, 20, 30, 40, 50, 50, 50, 0, 0]);
}

#[test]
fn ton_preset_rounds_up_and_zero_preset_follows_input() {
    let (p, _) = timer_program(TimerKind::Ton, 41);
    assert_eq!(p.timers[0].preset_ms, 50);
    let (p, _) = timer_program(TimerKind::Ton, 0);
    let got = run(p, 4, drive(&[1, 1, 0, 1]), |m| bit(m, "U4A0"));
    assert_eq!(got, vec![1, 1, 0, 1]);
}

#[test]
fn tof_holds_for_five_executions_after_the_fall() {
    let (p, at) = timer_program(TimerKind::Tof, 50);
    let input: &[u8] = &[0, 1, 1, 0, 0, 0, 0, 0, 0, 0];
    let got = run(p, 10, drive(input), |m| (bit(m, "U4A0"), i32_at(m, at)));
    let q: Vec<u8> = got.iter().map(|g| g.0).collect();
    assert_eq!(q, vec![0, 1, 1, 1, 1, 1, 1, 1, 0, 0]);
    let et: Vec<i32> = got.iter().map(|g| g.1).collect();
    assert_eq!(et, vec![0, 0, 0, 0, 10, 20, 30, 40, 50, 50]);
}

#[test]
fn tof_zero_preset_follows_input() {
    let (p, _) = timer_program(TimerKind::Tof, 0);
    let got = run(p, 4, drive(&[1, 0, 1, 0]), |m| bit(m, "U4A0"));
    assert_eq!(got, vec![1, 0, 1, 0]);
}

#[test]
fn tp_pulse_is_exactly_preset_over_tick_executions() {
    let (p, at) = timer_program(TimerKind::Tp, 30);
    // Rises at 1; changes during the pulse are ignored; the rise at 4 (the end tick) starts nothing;
    // the rise at 6 starts a new pulse.
    let input: &[u8] = &[0, 1, 0, 0, 1, 0, 1, 1, 1, 1, 1];
    let got = run(p, 11, drive(input), |m| (bit(m, "U4A0"), i32_at(m, at)));
    let q: Vec<u8> = got.iter().map(|g| g.0).collect();
    assert_eq!(q, vec![0, 1, 1, 1, 0, 0, 1, 1, 1, 0, 0]);
    let et: Vec<i32> = got.iter().map(|g| g.1).collect();
    assert_eq!(et, vec![0, 0, 10, 20, 30, 0, 0, 10, 20, 30, 30]);
}

#[test]
fn tp_zero_preset_gives_no_pulse() {
    let (p, _) = timer_program(TimerKind::Tp, 0);
    let got = run(p, 3, drive(&[1, 0, 1]), |m| bit(m, "U4A0"));
    assert_eq!(got, vec![0, 0, 0]);
}

#[test]
fn ctu_counts_rising_edges_to_the_preset_and_resets() {
    let mut b = ProgramBuilder::new(10, 5);
    let c = b.counter("c", CounterKind::Ctu, 3);
    let fast = vec![
        Stmt::CounterReset {
            counter: c,
            input: load("I0A1"),
        },
        Stmt::CounterCount {
            counter: c,
            input: load("I0A0"),
        },
        assign("U4A0", Expr::CounterQ(c)),
    ];
    let p = b.finish(fast, vec![]).expect("valid");
    let at = p.counters[0].offset;
    let count: &[u8] = &[1, 1, 0, 1, 0, 1, 0, 1, 0, 1, 1];
    let reset: &[u8] = &[0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 0];
    let got = run(
        p,
        11,
        |t, m| {
            sig("I0A0").write(m, count[t]);
            sig("I0A1").write(m, reset[t]);
        },
        |m| (i32_at(m, at), bit(m, "U4A0")),
    );
    // The rise at 9 is blocked by R; at 10 the input stays 1 (no rise).
    assert_eq!(
        got.iter().map(|g| g.0).collect::<Vec<_>>(),
        vec![1, 1, 1, 2, 2, 3, 3, 4, 0, 0, 0]
    );
    assert_eq!(
        got.iter().map(|g| g.1).collect::<Vec<_>>(),
        vec![0, 0, 0, 0, 0, 1, 1, 1, 0, 0, 0]
    );
}

#[test]
fn ctd_reads_q_before_loading_and_counts_down_to_zero() {
    let mut b = ProgramBuilder::new(10, 5);
    let c = b.counter("c", CounterKind::Ctd, 2);
    let fast = vec![
        assign("U4A1", Expr::CounterQ(c)),
        Stmt::CounterReset {
            counter: c,
            input: load("I0A1"),
        },
        Stmt::CounterCount {
            counter: c,
            input: load("I0A0"),
        },
        assign("U4A0", Expr::CounterQ(c)),
    ];
    let p = b.finish(fast, vec![]).expect("valid");
    let at = p.counters[0].offset;
    let count: &[u8] = &[0, 0, 1, 0, 1, 0, 1, 0];
    let load_: &[u8] = &[0, 1, 0, 0, 0, 0, 0, 0];
    let got = run(
        p,
        8,
        |t, m| {
            sig("I0A0").write(m, count[t]);
            sig("I0A1").write(m, load_[t]);
        },
        |m| (bit(m, "U4A1"), i32_at(m, at), bit(m, "U4A0")),
    );
    assert_eq!(got[0], (1, 0, 1), "an unloaded CTD reads Q = 1");
    assert_eq!(
        got.iter().map(|g| g.1).collect::<Vec<_>>(),
        vec![0, 2, 1, 1, 0, 0, -1, -1]
    );
    assert_eq!(
        got.iter().map(|g| g.2).collect::<Vec<_>>(),
        vec![1, 0, 0, 0, 1, 1, 1, 1]
    );
}

#[test]
fn pulse_lasts_one_scan_and_clears_a_cnc_bit() {
    // P2=U100K0 then U100K0=P2: a bit the CNC sets is cleared one scan after it appeared.
    let mut b = ProgramBuilder::new(10, 5);
    let p2 = b.pulse(2);
    let fast = vec![
        Stmt::Pulse {
            pulse: p2,
            input: load("U100K0"),
        },
        assign("U100K0", Expr::Pulse(p2)),
    ];
    let p = b.finish(fast, vec![]).expect("valid");
    let at = p.pulses[0].offset;
    let got = run(
        p,
        5,
        |t, m| {
            if t == 1 {
                sig("U100K0").write(m, 1);
            }
        },
        |m| (bit(m, "U100K0"), m[at] & 1),
    );
    assert_eq!(got, vec![(0, 0), (1, 1), (0, 0), (0, 0), (0, 0)]);
}

#[test]
fn self_latch_holds_m91_until_m90_or_reset() {
    // U150N0=[W3K0=91H]+U150N0*/[W3K0=90H]*/I0K1
    let eq = |v: u8| Expr::Cmp {
        op: CmpOp::Eq,
        ty: Ty::Byte,
        lhs: Box::new(load("W3K0")),
        rhs: Box::new(Expr::Const(Value::Byte(v))),
    };
    let and = |a, b| bin(BinOp::And, Ty::Bool, a, b);
    let hold = and(and(load("U150N0"), not(eq(0x90))), not(load("I0K1")));
    let fast = vec![assign("U150N0", bin(BinOp::Or, Ty::Bool, eq(0x91), hold))];
    let p = ProgramBuilder::new(10, 5)
        .finish(fast, vec![])
        .expect("valid");
    let mcode: &[u8] = &[0, 0x91, 0, 0x45, 0x90, 0, 0x91, 0, 0];
    let reset: &[u8] = &[0, 0, 0, 0, 0, 0, 0, 1, 0];
    let got = run(
        p,
        9,
        |t, m| {
            sig("W3K0").write(m, mcode[t]);
            sig("I0K1").write(m, reset[t]);
        },
        |m| bit(m, "U150N0"),
    );
    assert_eq!(got, vec![0, 1, 1, 1, 0, 0, 1, 0, 0]);
}

#[test]
fn set_and_res_write_only_when_true_and_the_later_wins() {
    let fast = vec![
        Stmt::Set {
            place: Place::Signal(sig("U4A0")),
            cond: load("I0A0"),
        },
        Stmt::Res {
            place: Place::Signal(sig("U4A0")),
            cond: load("I0A1"),
        },
    ];
    let p = ProgramBuilder::new(10, 5)
        .finish(fast, vec![])
        .expect("valid");
    let set: &[u8] = &[0, 1, 0, 1, 0];
    let res: &[u8] = &[0, 0, 0, 1, 1];
    let got = run(
        p,
        5,
        |t, m| {
            sig("I0A0").write(m, set[t]);
            sig("I0A1").write(m, res[t]);
        },
        |m| bit(m, "U4A0"),
    );
    assert_eq!(got, vec![0, 1, 1, 0, 0]);
}

#[test]
fn if_zone_freezes_its_timer_and_keeps_its_coils() {
    let mut b = ProgramBuilder::new(10, 5);
    let t = b.timer("t", TimerKind::Ton, 30);
    let zone = Stmt::If {
        cond: load("I0A1"),
        then_: vec![
            Stmt::Timer {
                timer: t,
                input: load("I0A0"),
            },
            assign("U4A0", Expr::TimerQ(t)),
        ],
        else_: vec![assign("U4A1", load("I0A0"))],
    };
    let p = b.finish(vec![zone], vec![]).expect("valid");
    let at = p.timers[0].offset;
    let zone_on: &[u8] = &[1, 1, 0, 0, 0, 1, 1, 0];
    let got = run(
        p,
        8,
        |t, m| {
            sig("I0A0").write(m, 1);
            sig("I0A1").write(m, zone_on[t]);
        },
        |m| (i32_at(m, at), bit(m, "U4A0"), bit(m, "U4A1")),
    );
    assert_eq!(
        got.iter().map(|g| g.0).collect::<Vec<_>>(),
        vec![0, 10, 10, 10, 10, 20, 30, 30]
    );
    assert_eq!(
        got.iter().map(|g| g.1).collect::<Vec<_>>(),
        vec![0, 0, 0, 0, 0, 0, 1, 1]
    );
    assert_eq!(
        got.iter().map(|g| g.2).collect::<Vec<_>>(),
        vec![0, 0, 1, 1, 1, 1, 1, 1]
    );
}

#[test]
fn slow_slices_run_round_robin() {
    // time_slow 0 → budget 0 → one statement per slice: three slices.
    let inc = |s: &str| {
        let v = bin(BinOp::Add, Ty::Byte, load(s), Expr::Const(Value::Byte(1)));
        assign(s, v)
    };
    let slow = vec![inc("W10K0"), inc("W10K1"), inc("W10K2")];
    let p = ProgramBuilder::new(10, 0)
        .finish(vec![inc("W10K3")], slow)
        .expect("valid");
    assert_eq!(p.slow.len(), 3);
    let got = run(p, 7, |_, _| {}, |m| [0, 1, 2, 3].map(|i| m[128 + 40 + i]));
    assert_eq!(got[0], [1, 0, 0, 1]);
    assert_eq!(got[2], [1, 1, 1, 3]);
    assert_eq!(got[6], [3, 2, 2, 7]);
}

#[test]
fn integer_division_by_zero_gives_zero_and_sets_the_fault_flag() {
    let mut b = ProgramBuilder::new(10, 5);
    let x = b.var("x", Ty::Int, Some(Value::Int(-32768)), false);
    let q = b.var("q", Ty::Int, None, false);
    let r = b.var("r", Ty::Int, None, false);
    let d = b.var("d", Ty::Int, None, false);
    let vx = || Expr::Load(Place::Var(x));
    let fast = vec![
        Stmt::Assign {
            place: Place::Var(q),
            value: bin(BinOp::Div, Ty::Int, vx(), Expr::Const(Value::Int(-1))),
        },
        Stmt::Assign {
            place: Place::Var(r),
            value: bin(BinOp::Mod, Ty::Int, vx(), Expr::Const(Value::Int(-1))),
        },
        Stmt::Assign {
            place: Place::Var(d),
            value: bin(BinOp::Div, Ty::Int, vx(), Expr::Load(Place::Var(r))),
        },
    ];
    let p = b.finish(fast, vec![]).expect("valid");
    let offs: Vec<usize> = p.vars.iter().map(|v| v.offset).collect();
    let got = run(
        p,
        1,
        |_, _| {},
        |m| {
            let rd = |i: usize| i16::from_le_bytes([m[offs[i]], m[offs[i] + 1]]);
            (rd(1), rd(2), rd(3), i32_at(m, HDR_FAULTS) as u32)
        },
    );
    assert_eq!(got[0], (-32768, 0, 0, FAULT_DIV_ZERO));
}

#[test]
fn bcd_bin_and_byte_wrap() {
    let mut b = ProgramBuilder::new(10, 5);
    let w = b.var("w", Ty::Word, Some(Value::Word(1234)), false);
    let fast = vec![
        Stmt::Assign {
            place: Place::View {
                at: sig("W20K0"),
                ty: Ty::Word,
            },
            value: Expr::Bcd {
                ty: Ty::Word,
                arg: Box::new(Expr::Load(Place::Var(w))),
            },
        },
        assign(
            "W20K2",
            Expr::Bin {
                ty: Ty::Byte,
                arg: Box::new(Expr::Const(Value::Byte(0x1A))),
            },
        ),
        assign(
            "W20K3",
            bin(
                BinOp::Add,
                Ty::Byte,
                Expr::Const(Value::Byte(200)),
                Expr::Const(Value::Byte(100)),
            ),
        ),
    ];
    let p = b.finish(fast, vec![]).expect("valid");
    let got = run(p, 1, |_, _| {}, |m| [0, 1, 2, 3].map(|i| m[128 + 80 + i]));
    assert_eq!(got[0], [0x34, 0x12, 20, 44]);
}

#[test]
fn float_nan_results_are_canonical_and_min_max_follow_the_documented_order() {
    let mut b = ProgramBuilder::new(10, 5);
    let x = b.var(
        "x",
        Ty::Real,
        Some(Value::Real(f32::from_bits(0x7FA0_0001))),
        false,
    );
    let inf = b.var("inf", Ty::Lreal, Some(Value::Lreal(f64::INFINITY)), false);
    let r = b.var("r", Ty::Real, None, false);
    let d = b.var("d", Ty::Lreal, None, false);
    let m = b.var("m", Ty::Real, None, false);
    let lx = || Expr::Load(Place::Var(x));
    let li = || Expr::Load(Place::Var(inf));
    let fast = vec![
        Stmt::Assign {
            place: Place::Var(r),
            value: bin(BinOp::Add, Ty::Real, lx(), Expr::Const(Value::Real(1.0))),
        },
        Stmt::Assign {
            place: Place::Var(d),
            value: bin(BinOp::Sub, Ty::Lreal, li(), li()),
        },
        // MIN(NaN, 2.0): `if b < a {b} else {a}` keeps the NaN operand a as it is.
        Stmt::Assign {
            place: Place::Var(m),
            value: bin(BinOp::Min, Ty::Real, lx(), Expr::Const(Value::Real(2.0))),
        },
    ];
    let p = b.finish(fast, vec![]).expect("valid");
    let (ro, dof, mo) = (
        p.vars[r.0 as usize].offset,
        p.vars[d.0 as usize].offset,
        p.vars[m.0 as usize].offset,
    );
    let got = run(
        p,
        1,
        |_, _| {},
        |im| {
            let d = u64::from_le_bytes(im[dof..dof + 8].try_into().expect("8 bytes"));
            (i32_at(im, ro) as u32, d, i32_at(im, mo) as u32)
        },
    );
    assert_eq!(got[0], (0x7FC0_0000, 0x7FF8_0000_0000_0000, 0x7FA0_0001));
}

#[test]
fn a_byte_store_inside_a_view_is_seen_by_the_next_view_load() {
    // The JIT forwards loads and stores within a block; a store to one byte of a DWORD view (or
    // to a bit of a DINT variable) must invalidate what it knows about the whole view.
    let mut b = ProgramBuilder::new(10, 5);
    let x = b.var("x", Ty::Dint, None, false);
    let before = b.var("before", Ty::Dword, None, false);
    let after = b.var("after", Ty::Dword, None, false);
    let vx = b.var("vx", Ty::Dint, None, false);
    let view = || {
        Expr::Load(Place::View {
            at: sig("W102K0"),
            ty: Ty::Dword,
        })
    };
    let lx = || Expr::Load(Place::Var(x));
    let fast = vec![
        Stmt::Assign {
            place: Place::Var(before),
            value: view(),
        },
        assign("W102K3", Expr::Const(Value::Byte(0xAB))),
        Stmt::Assign {
            place: Place::Var(after),
            value: view(),
        },
        Stmt::Assign {
            place: Place::Var(x),
            value: bin(BinOp::Add, Ty::Dint, lx(), Expr::Const(Value::Dint(1))),
        },
        Stmt::Set {
            place: Place::VarBit { var: x, bit: 31 },
            cond: Expr::Const(Value::Bool(true)),
        },
        Stmt::Assign {
            place: Place::Var(vx),
            value: lx(),
        },
    ];
    let p = b.finish(fast, vec![]).expect("valid");
    let offs: Vec<usize> = p.vars.iter().map(|v| v.offset).collect();
    let got = run(
        p,
        1,
        |_, m| sig("W102K0").write(m, 0x11),
        |m| {
            (
                i32_at(m, offs[1]) as u32,
                i32_at(m, offs[2]) as u32,
                i32_at(m, offs[3]),
            )
        },
    );
    assert_eq!(got[0], (0x11, 0xAB00_0011, i32::MIN + 1));
}
