//! The seed fragments (docs/plc-language.md §1) compile unchanged, each with its ladder meaning.

use compiler::ir::{BinOp, CmpOp, Expr, Place, Stmt, Ty, Value};
use compiler::{MachineContext, compile};
use packets::Signal;

fn sig(s: &str) -> Signal {
    s.parse().expect("valid signal")
}

fn load(s: &str) -> Expr {
    Expr::Load(Place::Signal(sig(s)))
}

fn not(e: Expr) -> Expr {
    Expr::Not(Box::new(e))
}

fn bin(op: BinOp, a: Expr, b: Expr) -> Expr {
    Expr::Binary {
        op,
        ty: Ty::Bool,
        lhs: Box::new(a),
        rhs: Box::new(b),
    }
}

fn cmp_byte(s: &str, v: u8) -> Expr {
    Expr::Cmp {
        op: CmpOp::Eq,
        ty: Ty::Byte,
        lhs: Box::new(load(s)),
        rhs: Box::new(Expr::Const(Value::Byte(v))),
    }
}

fn one(src: &str) -> Stmt {
    let c = compile("seed", src.as_bytes(), &MachineContext::lathe_like());
    assert_eq!(c.diagnostics, vec![], "{src}");
    let p = c.program.expect("compiles");
    assert_eq!(p.fast.len(), 1, "{src}");
    p.fast[0].clone()
}

fn assign(target: &str, value: Expr) -> Stmt {
    Stmt::Assign {
        place: Place::Signal(sig(target)),
        value,
    }
}

#[test]
fn each_seed_statement_has_its_ladder_meaning() {
    assert_eq!(
        one(";comment line\nU180K0=I0K2"),
        assign("U180K0", load("I0K2"))
    );
    assert_eq!(one("U170K7=/I1A29"), assign("U170K7", not(load("I1A29"))));
    assert_eq!(
        one("U10K5=U150N0*/I150N1"),
        assign(
            "U10K5",
            bin(BinOp::And, load("U150N0"), not(load("I150N1")))
        )
    );
    assert_eq!(
        one("U150N2=/U250N0+U250N0"),
        assign(
            "U150N2",
            bin(BinOp::Or, not(load("U250N0")), load("U250N0"))
        )
    );
    let latch = bin(
        BinOp::Or,
        cmp_byte("W3K0", 0x91),
        bin(
            BinOp::And,
            bin(BinOp::And, load("U150N0"), not(cmp_byte("W3K0", 0x90))),
            not(load("I0K1")),
        ),
    );
    assert_eq!(
        one("U150N0=[W3K0=91H]+U150N0*/[W3K0=90H]*/I0K1"),
        assign("U150N0", latch)
    );
    assert_eq!(
        one("U10K10=I0K2*/U150N0"),
        assign("U10K10", bin(BinOp::And, load("I0K2"), not(load("U150N0"))))
    );
}

#[test]
fn the_whole_seed_block_compiles_with_pulse_pair() {
    let src = ";comment line\nU180K0=I0K2\nU170K7=/I1A29\nU10K5=U150N0*/I150N1\nU150N2=/U250N0+U250N0\n\
               U150N0=[W3K0=91H]+U150N0*/[W3K0=90H]*/I0K1\nU10K10=I0K2*/U150N0\nP2=U100K0\nU100K0=P2\n$\n";
    let c = compile("seed", src.as_bytes(), &MachineContext::lathe_like());
    assert_eq!(c.diagnostics, vec![]);
    let p = c.program.expect("compiles");
    assert_eq!(p.fast.len(), 8);
    assert!(p.slow.is_empty());
    assert_eq!(p.pulses.len(), 1);
    assert_eq!(p.pulses[0].n, 2);
    let pid = compiler::ir::PulseId(0);
    assert_eq!(
        p.fast[6],
        Stmt::Pulse {
            pulse: pid,
            input: load("U100K0")
        }
    );
    assert_eq!(p.fast[7], assign("U100K0", Expr::Pulse(pid)));
    assert_eq!(c.stats.statements, 8);
}

#[test]
fn seeds_compile_from_legacy_bytes_and_lower_case() {
    let src = b";\xcf\xf0\xe8\xe2\xe5\xf2 CP1251\r\nu170k7=/i1a29\r\n";
    let c = compile("seed", src, &MachineContext::lathe_like());
    assert_eq!(c.diagnostics, vec![]);
    assert_eq!(
        c.program.expect("compiles").fast[0],
        assign("U170K7", not(load("I1A29")))
    );
}

/// The example machines' contexts (their IOCFIL section 1).
fn example_ctx(inputs: &[u16], outputs: &[u16]) -> MachineContext {
    MachineContext {
        a_inputs: inputs.to_vec(),
        a_outputs: outputs.to_vec(),
        spl: 400,
        ..MachineContext::lathe_like()
    }
}

#[test]
fn example_lathe_program_compiles_without_diagnostics() {
    let src = include_bytes!("../../../plc-programs/lathe/MP0/PLCPRG");
    let c = compile("lathe/MP0/PLCPRG", src, &example_ctx(&[0, 1], &[4, 5]));
    assert_eq!(c.diagnostics, vec![]);
    let p = c.program.expect("compiles");
    assert_eq!(p.timers.len(), 6);
    assert!(!p.slow.is_empty());
}

#[test]
fn the_synthetic_benchmark_program_compiles() {
    let src = compiler::synth::synthetic_program(2_000);
    let ctx = MachineContext {
        spl: 5000,
        ..MachineContext::lathe_like()
    };
    let c = compile("synth", src.as_bytes(), &ctx);
    let errors: Vec<_> = c
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .take(3)
        .collect();
    assert!(errors.is_empty(), "{errors:?}");
    assert_eq!(c.stats.statements, 2_000);
    assert!(!c.program.expect("compiles").slow.is_empty());
}
