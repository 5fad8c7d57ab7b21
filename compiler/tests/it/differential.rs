//! Differential test: random well-typed IR programs covering every construct (all types, all
//! operators and conversions, BCD/BIN/LIMIT, views, variable bits, SET/RES, pulses, all timer and
//! counter kinds, nested IF zones, SLOW slices) and random input sequences; the JIT and the
//! interpreter must give bit-identical images after every tick.

use std::sync::Arc;

use compiler::ir::{
    BinOp, CmpOp, CounterId, CounterKind, Expr, Place, Program, ProgramBuilder, PulseId, Stmt,
    TimerId, TimerKind, Ty, UnOp, Value, VarId,
};
use compiler::jit::JitOptions;
use compiler::{Engine, Interpreter};
use packets::Signal;
use proptest::prelude::*;

const TYPES: [Ty; 8] = [
    Ty::Bool,
    Ty::Byte,
    Ty::Word,
    Ty::Dword,
    Ty::Int,
    Ty::Dint,
    Ty::Real,
    Ty::Lreal,
];
const INT: [Ty; 5] = [Ty::Byte, Ty::Word, Ty::Dword, Ty::Int, Ty::Dint];
/// Bytes the random inputs poke: A connectors 0, 1, 4, 5 and K connectors 100..103.
const POKE: [usize; 32] = [
    0, 1, 2, 3, 4, 5, 6, 7, 16, 17, 18, 19, 20, 21, 22, 23, 528, 529, 530, 531, 532, 533, 534, 535,
    536, 537, 538, 539, 540, 541, 542, 543,
];

fn sig(s: &str) -> Signal {
    s.parse().expect("signal")
}

/// The places of a type (variables are declared in `TYPES` order, two per type).
fn places(ty: Ty) -> Vec<Place> {
    let var = |k: u32| {
        Place::Var(VarId(
            2 * TYPES.iter().position(|&t| t == ty).expect("type") as u32 + k,
        ))
    };
    let mut v = vec![var(0), var(1)];
    let view = |s: &str| Place::View { at: sig(s), ty };
    match ty {
        Ty::Bool => {
            for s in [
                "I0A0", "I0A3", "I1A9", "U4A0", "U4A7", "U5A12", "U100K0", "U101K31",
            ] {
                v.push(Place::Signal(sig(s)));
            }
            v.push(Place::VarBit {
                var: VarId(2),
                bit: 3,
            });
            v.push(Place::VarBit {
                var: VarId(10),
                bit: 31,
            });
        }
        Ty::Byte => v.extend(
            ["W0A0", "W1A2", "W4A1", "W4A3", "W5A1", "W102K3"].map(|s| Place::Signal(sig(s))),
        ),
        Ty::Word | Ty::Int => v.extend([view("W4A2"), view("W100K1")]),
        Ty::Dword | Ty::Dint | Ty::Real => v.extend([view("W5A0"), view("W102K0")]),
        Ty::Lreal => {}
    }
    v
}

fn value(ty: Ty) -> BoxedStrategy<Value> {
    let special32 = prop_oneof![
        any::<u32>().prop_map(f32::from_bits),
        Just(0.0f32),
        Just(-0.0f32),
        Just(f32::NAN),
        Just(f32::from_bits(0x7FA0_0001)),
        Just(f32::from_bits(0xFFC0_1234)),
        Just(f32::INFINITY),
        Just(f32::NEG_INFINITY),
        (-1000i32..1000).prop_map(|i| i as f32 / 4.0),
        Just(3.0e9f32),
        Just(-3.0e9f32),
    ];
    match ty {
        Ty::Bool => any::<bool>().prop_map(Value::Bool).boxed(),
        Ty::Byte => prop_oneof![any::<u8>(), 0u8..10]
            .prop_map(Value::Byte)
            .boxed(),
        Ty::Word => prop_oneof![any::<u16>(), 0u16..20]
            .prop_map(Value::Word)
            .boxed(),
        Ty::Dword => prop_oneof![any::<u32>(), 0u32..40]
            .prop_map(Value::Dword)
            .boxed(),
        Ty::Int => prop_oneof![any::<i16>(), -5i16..20, Just(i16::MIN), Just(-1)]
            .prop_map(Value::Int)
            .boxed(),
        Ty::Dint => prop_oneof![any::<i32>(), -5i32..40, Just(i32::MIN), Just(-1)]
            .prop_map(Value::Dint)
            .boxed(),
        Ty::Real => special32.prop_map(Value::Real).boxed(),
        Ty::Lreal => prop_oneof![
            any::<u64>().prop_map(f64::from_bits),
            Just(f64::NAN),
            Just(f64::from_bits(0xFFF4_0000_0000_0001)),
            Just(f64::INFINITY),
            Just(-0.0f64),
            Just(1e300),
            (-1000i32..1000).prop_map(|i| f64::from(i) / 8.0),
        ]
        .prop_map(Value::Lreal)
        .boxed(),
    }
}

fn b(e: Expr) -> Box<Expr> {
    Box::new(e)
}

fn leaf(ty: Ty) -> BoxedStrategy<Expr> {
    let consts = value(ty).prop_map(Expr::Const);
    let loads = proptest::sample::select(places(ty)).prop_map(Expr::Load);
    match ty {
        Ty::Bool => prop_oneof![
            consts,
            loads,
            (0u32..4).prop_map(|i| Expr::Pulse(PulseId(i))),
            (0u32..6).prop_map(|i| Expr::TimerQ(TimerId(i))),
            (0u32..4).prop_map(|i| Expr::CounterQ(CounterId(i))),
        ]
        .boxed(),
        Ty::Dint => prop_oneof![
            consts,
            loads,
            (0u32..6).prop_map(|i| Expr::TimerEt(TimerId(i))),
            (0u32..4).prop_map(|i| Expr::CounterCv(CounterId(i))),
        ]
        .boxed(),
        _ => prop_oneof![consts, loads].boxed(),
    }
}

fn expr(ty: Ty, depth: u32) -> BoxedStrategy<Expr> {
    if depth == 0 {
        return leaf(ty);
    }
    let d = depth - 1;
    let any_ty = proptest::sample::select(TYPES.to_vec());
    let composite: BoxedStrategy<Expr> = match ty {
        Ty::Bool => prop_oneof![
            expr(Ty::Bool, d).prop_map(|a| Expr::Not(b(a))),
            (
                proptest::sample::select(vec![BinOp::And, BinOp::Or, BinOp::Xor]),
                expr(Ty::Bool, d),
                expr(Ty::Bool, d)
            )
                .prop_map(|(op, l, r)| Expr::Binary {
                    op,
                    ty: Ty::Bool,
                    lhs: b(l),
                    rhs: b(r)
                }),
            (
                any_ty.clone(),
                proptest::sample::select(vec![
                    CmpOp::Eq,
                    CmpOp::Ne,
                    CmpOp::Lt,
                    CmpOp::Le,
                    CmpOp::Gt,
                    CmpOp::Ge
                ])
            )
                .prop_flat_map(move |(t, op)| (expr(t, d), expr(t, d)).prop_map(
                    move |(l, r)| Expr::Cmp {
                        op,
                        ty: t,
                        lhs: b(l),
                        rhs: b(r)
                    }
                )),
            proptest::sample::select(INT.to_vec()).prop_flat_map(move |t| (
                expr(t, d),
                0..t.bits() as u8
            )
                .prop_map(move |(v, bit)| Expr::BitOf {
                    ty: t,
                    value: b(v),
                    bit
                })),
            any_ty
                .clone()
                .prop_flat_map(move |t| expr(t, d).prop_map(move |a| Expr::Convert {
                    from: t,
                    to: Ty::Bool,
                    arg: b(a)
                })),
        ]
        .boxed(),
        _ => {
            let mut ops = vec![
                BinOp::Add,
                BinOp::Sub,
                BinOp::Mul,
                BinOp::Div,
                BinOp::Min,
                BinOp::Max,
            ];
            let mut unops = vec![UnOp::Neg, UnOp::Abs];
            if ty.is_int() {
                ops.extend([
                    BinOp::Mod,
                    BinOp::BitAnd,
                    BinOp::BitOr,
                    BinOp::BitXor,
                    BinOp::Shl,
                    BinOp::Shr,
                ]);
                unops.push(UnOp::BitNot);
            }
            let bin = (proptest::sample::select(ops), expr(ty, d), expr(ty, d)).prop_map(
                move |(op, l, r)| Expr::Binary {
                    op,
                    ty,
                    lhs: b(l),
                    rhs: b(r),
                },
            );
            let un = (proptest::sample::select(unops), expr(ty, d))
                .prop_map(move |(op, a)| Expr::Unary { op, ty, arg: b(a) });
            let conv = any_ty.prop_flat_map(move |t| {
                expr(t, d).prop_map(move |a| Expr::Convert {
                    from: t,
                    to: ty,
                    arg: b(a),
                })
            });
            let limit =
                (expr(ty, d), expr(ty, d), expr(ty, d)).prop_map(move |(lo, x, hi)| Expr::Limit {
                    ty,
                    lo: b(lo),
                    x: b(x),
                    hi: b(hi),
                });
            if ty.is_int() {
                let bcd = (any::<bool>(), expr(ty, d)).prop_map(move |(bcd, a)| {
                    if bcd {
                        Expr::Bcd { ty, arg: b(a) }
                    } else {
                        Expr::Bin { ty, arg: b(a) }
                    }
                });
                prop_oneof![3 => bin, 1 => un, 2 => conv, 1 => limit, 1 => bcd].boxed()
            } else {
                prop_oneof![3 => bin, 1 => un, 2 => conv, 1 => limit].boxed()
            }
        }
    };
    prop_oneof![1 => leaf(ty), 2 => composite].boxed()
}

fn stmt(depth: u32) -> BoxedStrategy<Stmt> {
    let ty = proptest::sample::select(TYPES.to_vec());
    let assign = ty
        .prop_flat_map(|t| (proptest::sample::select(places(t)), expr(t, 3)))
        .prop_map(|(place, value)| Stmt::Assign { place, value });
    let bool_place = proptest::sample::select(places(Ty::Bool));
    let set_res = (any::<bool>(), bool_place, expr(Ty::Bool, 2)).prop_map(|(set, place, cond)| {
        if set {
            Stmt::Set { place, cond }
        } else {
            Stmt::Res { place, cond }
        }
    });
    let stateful = (0u32..4, 0u32..6, expr(Ty::Bool, 2)).prop_map(|(kind, i, input)| match kind {
        0 => Stmt::Pulse {
            pulse: PulseId(i % 4),
            input,
        },
        1 => Stmt::Timer {
            timer: TimerId(i),
            input,
        },
        2 => Stmt::CounterCount {
            counter: CounterId(i % 4),
            input,
        },
        _ => Stmt::CounterReset {
            counter: CounterId(i % 4),
            input,
        },
    });
    let flat = prop_oneof![4 => assign, 1 => set_res, 3 => stateful].boxed();
    if depth == 0 {
        return flat;
    }
    let zone = (
        expr(Ty::Bool, 2),
        proptest::collection::vec(stmt(depth - 1), 0..4),
        proptest::collection::vec(stmt(depth - 1), 0..3),
    )
        .prop_map(|(cond, then_, else_)| Stmt::If { cond, then_, else_ });
    prop_oneof![5 => flat, 1 => zone].boxed()
}

fn program() -> impl Strategy<Value = Program> {
    let inits = TYPES
        .iter()
        .flat_map(|&t| [value(t), value(t)])
        .collect::<Vec<_>>();
    (
        inits,
        proptest::collection::vec(0u64..80, 6),
        proptest::collection::vec(-2i32..5, 4),
        proptest::collection::vec(stmt(2), 1..10),
        proptest::collection::vec(stmt(1), 0..6),
        prop_oneof![Just(0u32), Just(1u32)],
        1u32..25,
    )
        .prop_map(|(inits, presets, pvs, fast, slow, time_slow, tick)| {
            let mut pb = ProgramBuilder::new(tick, time_slow);
            for (i, init) in inits.into_iter().enumerate() {
                pb.var(&format!("v{i}"), init.ty(), Some(init), i % 5 == 4);
            }
            let kinds = [TimerKind::Ton, TimerKind::Tof, TimerKind::Tp];
            for (i, preset) in presets.into_iter().enumerate() {
                pb.timer(&format!("t{i}"), kinds[i % 3], preset);
            }
            for (i, pv) in pvs.into_iter().enumerate() {
                let kind = if i % 2 == 0 {
                    CounterKind::Ctu
                } else {
                    CounterKind::Ctd
                };
                pb.counter(&format!("c{i}"), kind, pv);
            }
            for n in [0, 2, 7, 1023] {
                pb.pulse(n);
            }
            pb.finish(fast, slow)
                .expect("generated programs are well typed")
        })
}

fn inputs() -> impl Strategy<Value = Vec<Vec<(usize, u8)>>> {
    proptest::collection::vec(
        proptest::collection::vec((proptest::sample::select(POKE.to_vec()), any::<u8>()), 0..6),
        1..24,
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 160, ..ProptestConfig::default() })]

    #[test]
    fn jit_and_interpreter_agree_bit_for_bit(p in program(), ticks in inputs()) {
        let p = Arc::new(p);
        let mut interp = Interpreter::new(p.clone());
        let mut jit = compiler::jit::compile(&p).expect("jit compiles every valid program");
        // One function per statement, optimized, other register allocator, every IF zone
        // if-converted (the default converts small ones and branches around larger ones), loaded
        // values and constants reused across the whole block (the default: one statement on).
        let opts = JitOptions { opt_level: "speed", regalloc: "backtracking", chunk_cost: 1, threads: 3, if_convert_cost: u32::MAX, cache_window: u32::MAX };
        let mut jit2 = compiler::jit::compile_with(&p, &opts).expect("jit compiles every valid program");
        let mut a = p.new_image();
        let mut c = p.new_image();
        let mut d = p.new_image();
        for (t, pokes) in ticks.iter().enumerate() {
            for &(at, v) in pokes {
                a[at] = v;
                c[at] = v;
                d[at] = v;
            }
            interp.tick(&mut a);
            jit.tick(&mut c);
            jit2.tick(&mut d);
            prop_assert!(c == d, "tick {t}: the two JIT configurations differ");
            if a != c {
                let diff: Vec<_> = (0..a.len()).filter(|&i| a[i] != c[i]).map(|i| (i, a[i], c[i])).collect();
                prop_assert!(false, "tick {t}: (offset, interp, jit) {diff:?}\n{p:#?}");
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// The online-change code cache never changes what is compiled: after a cache was filled by
    /// one program, compiling another (a random one, or the same one with its FAST statements
    /// reordered and a SLOW slice dropped: same declarations, so functions are found by their
    /// statements) gives machine code equal byte for byte to compiling it without the cache.
    #[test]
    fn the_code_cache_gives_the_code_of_an_uncached_compile(
        a in program(),
        b in program(),
        chunk_cost in proptest::sample::select(vec![1u32, 3, 2000]),
    ) {
        use compiler::jit::{CodeCache, compile_cached, compile_with};
        let opts = JitOptions { chunk_cost, threads: 1, ..JitOptions::default() };
        let mut edited = a.clone();
        edited.fast.reverse();
        if edited.slow.len() > 1 {
            edited.slow.pop();
        }
        for next in [&a, &b, &edited, &a] {
            let mut cache = CodeCache::new();
            compile_cached(&a, &opts, &mut cache).expect("first compile");
            let cached = compile_cached(next, &opts, &mut cache).expect("cached compile");
            let fresh = compile_with(next, &opts).expect("uncached compile");
            prop_assert_eq!(cached.machine_code(), fresh.machine_code());
            prop_assert_eq!(cached.function_count(), cache.len());
            prop_assert_eq!(cache.reused() + cache.compiled(), cache.len());
        }
        // Recompiling the same program reuses every function.
        let mut cache = CodeCache::new();
        compile_cached(&edited, &opts, &mut cache).expect("first compile");
        compile_cached(&edited, &opts, &mut cache).expect("second compile");
        prop_assert_eq!(cache.compiled(), 0);
    }
}

/// Equal statements over other declarations (here a timer preset) are not equal code: the cache
/// must not hand out the code of the first program's function.
#[test]
fn the_code_cache_tells_equal_statements_over_other_declarations_apart() {
    use compiler::jit::{CodeCache, compile_cached, compile_with};
    let with_preset = |ms: u64| {
        let mut pb = ProgramBuilder::new(10, 5);
        let t = pb.timer("t", TimerKind::Ton, ms);
        let fast = vec![
            Stmt::Timer {
                timer: t,
                input: Expr::Load(Place::Signal(sig("I0A0"))),
            },
            Stmt::Assign {
                place: Place::Signal(sig("U4A0")),
                value: Expr::TimerQ(t),
            },
        ];
        pb.finish(fast, vec![]).expect("valid")
    };
    let (a, b) = (with_preset(20), with_preset(50));
    let opts = JitOptions::default();
    let mut cache = CodeCache::new();
    compile_cached(&a, &opts, &mut cache).expect("a");
    let cached = compile_cached(&b, &opts, &mut cache).expect("b");
    assert_eq!((cache.reused(), cache.compiled()), (0, 1));
    let fresh = compile_with(&b, &opts).expect("b uncached");
    assert_eq!(cached.machine_code(), fresh.machine_code());
    assert_ne!(
        cached.machine_code(),
        compile_with(&a, &opts).expect("a uncached").machine_code()
    );
}

#[test]
fn short_images_are_left_untouched() {
    let mut pb = ProgramBuilder::new(10, 5);
    let v = pb.var("x", Ty::Dint, Some(Value::Dint(5)), false);
    let fast = vec![Stmt::Assign {
        place: Place::Var(v),
        value: Expr::Const(Value::Dint(9)),
    }];
    let p = Arc::new(pb.finish(fast, vec![]).expect("valid"));
    let mut short = vec![0u8; p.image_len() - 1];
    compiler::jit::compile(&p).expect("jit").tick(&mut short);
    Interpreter::new(p.clone()).tick(&mut short);
    assert!(short.iter().all(|&b| b == 0));
}

#[test]
fn programs_can_be_recompiled_and_dropped_repeatedly() {
    fn assert_send<T: Send>(_: &T) {}
    let mut pb = ProgramBuilder::new(10, 5);
    let t = pb.timer("t", TimerKind::Ton, 20);
    let fast = vec![
        Stmt::Timer {
            timer: t,
            input: Expr::Load(Place::Signal(sig("I0A0"))),
        },
        Stmt::Assign {
            place: Place::Signal(sig("U4A0")),
            value: Expr::TimerQ(t),
        },
    ];
    let p = pb.finish(fast, vec![]).expect("valid");
    let mut image = p.new_image();
    sig("I0A0").write(&mut image, 1);
    for _ in 0..30 {
        let mut jit = compiler::jit::compile(&p).expect("jit");
        assert_send(&jit);
        jit.tick(&mut image);
    }
    // 30 executions with IN held: ET saturated at the preset, Q on.
    assert_eq!(sig("U4A0").read(&image), 1);
    assert_eq!(image[p.timers[0].offset], 20);
}

#[test]
fn emit_clif_lists_one_function_per_part() {
    let pb = ProgramBuilder::new(10, 0);
    let x = || Stmt::Assign {
        place: Place::Signal(sig("U4A0")),
        value: Expr::Load(Place::Signal(sig("I0A0"))),
    };
    let p = pb.finish(vec![x()], vec![x(), x()]).expect("valid");
    let clif = compiler::jit::emit_clif(&p).expect("clif");
    assert_eq!(clif.matches("function u0:").count(), 3);
    assert!(clif.contains("; FAST, function part0"));
    assert!(clif.contains("; SLOW slice 1, function part2"));
    assert!(clif.contains("load.i8 notrap little"));
}

#[path = "../../benches/support/gcc_scan.rs"]
mod gcc_scan;

/// The C back end compiled by gcc, or `None` (with a message) when gcc is not installed.
fn gcc(p: &Program) -> Option<gcc_scan::GccScan> {
    match gcc_scan::GccScan::build(&compiler::cgen::emit_c(p), &["-O2"]) {
        Ok(g) => Some(g),
        Err(e) if e.starts_with("gcc not available") => {
            eprintln!("skipped: {e}");
            None
        }
        Err(e) => panic!("{e}\n{}", compiler::cgen::emit_c(p)),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    #[test]
    fn the_c_back_end_agrees_with_the_interpreter_bit_for_bit(p in program(), ticks in inputs()) {
        let Some(native) = gcc(&p) else { return Ok(()) };
        let p = Arc::new(p);
        let mut interp = Interpreter::new(p.clone());
        let mut a = p.new_image();
        let mut c = p.new_image();
        for (t, pokes) in ticks.iter().enumerate() {
            for &(at, v) in pokes {
                a[at] = v;
                c[at] = v;
            }
            interp.tick(&mut a);
            native.tick(&mut c);
            if a != c {
                let diff: Vec<_> = (0..a.len()).filter(|&i| a[i] != c[i]).map(|i| (i, a[i], c[i])).collect();
                prop_assert!(false, "tick {t}: (offset, interp, C) {diff:?}\n{}", compiler::cgen::emit_c(&p));
            }
        }
    }
}

#[test]
fn the_c_back_end_runs_the_synthetic_program_like_the_interpreter() {
    let ctx = compiler::MachineContext {
        spl: 256,
        ..compiler::MachineContext::lathe_like()
    };
    let src = compiler::synth::synthetic_program(400);
    let p = compiler::compile("synth", src.as_bytes(), &ctx)
        .program
        .expect("the synthetic program compiles");
    let Some(native) = gcc(&p) else { return };
    let p = Arc::new(p);
    let mut interp = Interpreter::new(p.clone());
    let mut a = p.new_image();
    let mut c = p.new_image();
    let mut x: u32 = 7;
    for t in 0..300 {
        // Pseudo-random input bytes of packets A and K (CNC→PLC) every third tick.
        if t % 3 == 0 {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            let at = (x % 1152) as usize;
            a[at] = (x >> 16) as u8;
            c[at] = (x >> 16) as u8;
        }
        interp.tick(&mut a);
        native.tick(&mut c);
        assert!(
            a == c,
            "tick {t}: the C back end departs from the interpreter"
        );
    }
    // The program did something: some output bytes are set.
    assert!(a[..packets::PACKETS_LEN].iter().any(|&b| b != 0));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Power flow (`ir::flow`): the instrumented program leaves the original image exactly as
    /// the plain one does, and the JIT and the interpreter write the same flow area.
    #[test]
    fn power_flow_changes_nothing_and_both_engines_write_the_same_flow(p in program(), ticks in inputs()) {
        let n = compiler::ir::flow::count(&p.fast)
            + p.slow.iter().map(|s| compiler::ir::flow::count(s)).sum::<usize>();
        let mut lined = p.clone();
        lined.lines = (1..=n as u32).collect();
        let (f, map) = compiler::ir::flow::instrument(&lined).expect("instruments");
        prop_assert_eq!(map.slots.len(), n);
        prop_assert!(map.area.0 >= p.image_len && map.area.1 == f.image_len);
        let (p, f) = (Arc::new(p), Arc::new(f));
        let mut plain = Interpreter::new(p.clone());
        let mut interp = Interpreter::new(f.clone());
        let mut jit = compiler::jit::compile(&f).expect("jit compiles the instrumented program");
        let mut a = p.new_image();
        let mut b = f.new_image();
        let mut c = f.new_image();
        for (t, pokes) in ticks.iter().enumerate() {
            for &(at, v) in pokes {
                a[at] = v;
                b[at] = v;
                c[at] = v;
            }
            plain.tick(&mut a);
            interp.tick(&mut b);
            jit.tick(&mut c);
            prop_assert!(a[..] == b[..p.image_len], "tick {}: the flow changed the program's image", t);
            prop_assert!(b == c, "tick {}: the JIT's flow differs from the interpreter's", t);
        }
    }
}
