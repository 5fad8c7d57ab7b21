//! Differential test for the JIT's bit-level code shapes: rungs over a few bytes of bits (several
//! coils in one byte, reads of bits written by the statements just before, SET/RES, bits of
//! variables and of integer expressions), small and nested IF zones, and one-shots and timers
//! driven by rungs. The interpreter and three JIT configurations (IF zones if-converted by the
//! default rule, never, always) must give bit-identical images after every tick.

use std::sync::Arc;

use compiler::ir::{
    BinOp, CmpOp, Expr, Place, Program, ProgramBuilder, PulseId, Stmt, TimerId, TimerKind, Ty,
    Value, VarId,
};
use compiler::jit::JitOptions;
use compiler::{Engine, Interpreter};
use packets::Signal;
use proptest::prelude::*;

fn sig(s: &str) -> Signal {
    s.parse().expect("signal")
}

/// BOOL places packed into few bytes: U4A0..7 (image byte 16), U100K0..15 (bytes 528, 529), the
/// bits of BYTE variable 0, three bits of DINT variable 1, BOOL variable 2.
fn bool_places() -> Vec<Place> {
    let mut v: Vec<Place> = (0..8)
        .map(|i| Place::Signal(sig(&format!("U4A{i}"))))
        .collect();
    v.extend((0..16).map(|i| Place::Signal(sig(&format!("U100K{i}")))));
    v.extend((0..8).map(|bit| Place::VarBit { var: VarId(0), bit }));
    v.extend([3u8, 9, 31].map(|bit| Place::VarBit { var: VarId(1), bit }));
    v.push(Place::Var(VarId(2)));
    v
}

fn b(e: Expr) -> Box<Expr> {
    Box::new(e)
}

fn leaf() -> BoxedStrategy<Expr> {
    let bit_of = |ty: Ty, value: Expr, bits: u8| {
        (0..bits).prop_map(move |bit| Expr::BitOf {
            ty,
            value: b(value.clone()),
            bit,
        })
    };
    let word = Expr::Load(Place::View {
        at: sig("W100K0"),
        ty: Ty::Word,
    });
    prop_oneof![
        6 => proptest::sample::select(bool_places()).prop_map(Expr::Load),
        1 => any::<bool>().prop_map(|v| Expr::Const(Value::Bool(v))),
        1 => (0u32..2).prop_map(|i| Expr::Pulse(PulseId(i))),
        1 => (0u32..2).prop_map(|i| Expr::TimerQ(TimerId(i))),
        1 => bit_of(Ty::Byte, Expr::Load(Place::Var(VarId(0))), 8),
        1 => bit_of(Ty::Dint, Expr::Load(Place::Var(VarId(1))), 32),
        1 => bit_of(Ty::Word, word, 16),
        1 => (0u8..4).prop_map(|k| Expr::Cmp {
            op: CmpOp::Eq,
            ty: Ty::Byte,
            lhs: b(Expr::Load(Place::Signal(sig("W100K0")))),
            rhs: b(Expr::Const(Value::Byte(k))),
        }),
    ]
    .boxed()
}

fn rung() -> BoxedStrategy<Expr> {
    leaf()
        .prop_recursive(4, 24, 2, |inner| {
            prop_oneof![
                inner.clone().prop_map(|a| Expr::Not(b(a))),
                (
                    proptest::sample::select(vec![BinOp::And, BinOp::Or, BinOp::Xor]),
                    inner.clone(),
                    inner
                )
                    .prop_map(|(op, l, r)| Expr::Binary {
                        op,
                        ty: Ty::Bool,
                        lhs: b(l),
                        rhs: b(r)
                    }),
            ]
        })
        .boxed()
}

fn stmt() -> BoxedStrategy<Stmt> {
    let place = || proptest::sample::select(bool_places());
    let flat = prop_oneof![
        6 => (place(), rung()).prop_map(|(place, value)| Stmt::Assign { place, value }),
        1 => (place(), rung()).prop_map(|(place, cond)| Stmt::Set { place, cond }),
        1 => (place(), rung()).prop_map(|(place, cond)| Stmt::Res { place, cond }),
        1 => (0u32..2, rung()).prop_map(|(i, input)| Stmt::Pulse { pulse: PulseId(i), input }),
        1 => (0u32..2, rung()).prop_map(|(i, input)| Stmt::Timer { timer: TimerId(i), input }),
    ];
    flat.prop_recursive(2, 24, 4, |inner| {
        (
            rung(),
            proptest::collection::vec(inner.clone(), 0..5),
            proptest::collection::vec(inner, 0..3),
        )
            .prop_map(|(cond, then_, else_)| Stmt::If { cond, then_, else_ })
    })
    .boxed()
}

fn program() -> impl Strategy<Value = Program> {
    (
        any::<u8>(),
        any::<i32>(),
        any::<bool>(),
        proptest::collection::vec(stmt(), 1..16),
    )
        .prop_map(|(v0, v1, v2, fast)| {
            let mut pb = ProgramBuilder::new(10, 0);
            pb.var("b", Ty::Byte, Some(Value::Byte(v0)), false);
            pb.var("d", Ty::Dint, Some(Value::Dint(v1)), false);
            pb.var("x", Ty::Bool, Some(Value::Bool(v2)), false);
            pb.pulse(0);
            pb.pulse(1);
            pb.timer("t0", TimerKind::Ton, 20);
            pb.timer("t1", TimerKind::Tp, 30);
            pb.finish(fast, Vec::new())
                .expect("generated programs are well typed")
        })
}

/// Pokes into the bit bytes (16, 528, 529) between ticks.
fn inputs() -> impl Strategy<Value = Vec<Vec<(usize, u8)>>> {
    proptest::collection::vec(
        proptest::collection::vec(
            (
                proptest::sample::select(vec![16usize, 528, 529]),
                any::<u8>(),
            ),
            0..3,
        ),
        1..12,
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn bit_code_agrees_with_the_interpreter(p in program(), ticks in inputs()) {
        let p = Arc::new(p);
        let mut interp = Interpreter::new(p.clone());
        // IF zones: default, never and always if-converted; loaded values and constants reused
        // one statement on (default), only within their statement, and across the whole block.
        let mut jits = [(24, 1), (0, 0), (u32::MAX, u32::MAX)].map(|(if_convert_cost, cache_window)| {
            let opts = JitOptions { if_convert_cost, cache_window, ..JitOptions::default() };
            compiler::jit::compile_with(&p, &opts).expect("jit compiles every valid program")
        });
        let mut want = p.new_image();
        let mut got = [p.new_image(), p.new_image(), p.new_image()];
        for (t, pokes) in ticks.iter().enumerate() {
            for &(at, v) in pokes {
                want[at] = v;
                for g in &mut got {
                    g[at] = v;
                }
            }
            interp.tick(&mut want);
            for (i, (jit, g)) in jits.iter_mut().zip(&mut got).enumerate() {
                jit.tick(g);
                if *g != want {
                    let diff: Vec<_> = (0..want.len())
                        .filter(|&o| want[o] != g[o])
                        .map(|o| (o, want[o], g[o]))
                        .collect();
                    prop_assert!(false, "JIT {i}, tick {t}: (offset, interp, jit) {diff:?}\n{p:#?}");
                }
            }
        }
    }
}

#[test]
fn coils_of_one_byte_become_one_store() {
    let load = |s: &str| Expr::Load(Place::Signal(sig(s)));
    let coil = |s: &str, value: Expr| Stmt::Assign {
        place: Place::Signal(sig(s)),
        value,
    };
    let and = |l: Expr, r: Expr| Expr::Binary {
        op: BinOp::And,
        ty: Ty::Bool,
        lhs: b(l),
        rhs: b(r),
    };
    // Each coil after the first reads a bit written just before it.
    let fast = vec![
        coil("U4A0", load("I0A0")),
        coil("U4A1", and(load("I0A1"), load("U4A0"))),
        coil("U4A2", Expr::Not(b(load("U4A1")))),
        coil("U4A3", and(load("I0A3"), load("U4A2"))),
    ];
    let p = Arc::new(
        ProgramBuilder::new(10, 0)
            .finish(fast, Vec::new())
            .expect("valid"),
    );
    let clif = compiler::jit::emit_clif(&p).expect("clif");
    let stores: Vec<&str> = clif.lines().filter(|l| l.contains("store ")).collect();
    assert_eq!(stores.len(), 1, "{clif}");
    assert!(stores[0].ends_with("v0+16"), "{}", stores[0]);
    let mut interp = Interpreter::new(p.clone());
    let mut jit = compiler::jit::compile(&p).expect("jit");
    for input in 0..16u8 {
        let (mut want, mut got) = (p.new_image(), p.new_image());
        want[0] = input;
        got[0] = input;
        interp.tick(&mut want);
        jit.tick(&mut got);
        assert_eq!(got, want, "input {input:#06b}");
    }
}
