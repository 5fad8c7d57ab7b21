//! Semantic checks: every diagnostic code the checker produces, with its exact location, and the
//! IR that good statements become.

use compiler::ir::{Expr, Place, Stmt, TimerKind, Ty, Value};
use compiler::{MachineContext, compile};

/// `(code, line, column)` of every diagnostic.
fn diags(src: &str) -> Vec<(u32, u32, u32)> {
    diags_with(src, &MachineContext::lathe_like())
}

fn diags_with(src: &str, ctx: &MachineContext) -> Vec<(u32, u32, u32)> {
    compile("t.plc", src.as_bytes(), ctx)
        .diagnostics
        .iter()
        .map(|d| (d.code, d.line, d.column))
        .collect()
}

fn program(src: &str) -> compiler::ir::Program {
    let c = compile("t.plc", src.as_bytes(), &MachineContext::lathe_like());
    assert!(
        c.diagnostics.iter().all(|d| !d.is_error()),
        "{:?}",
        c.diagnostics
    );
    c.program.expect("compiles")
}

#[test]
fn signal_rules_against_iocfil() {
    assert_eq!(
        diags(
            "U4A0=I0A0\nU4A1=I2A0\nU4A2=I4A0\nU0A3=I0A1\nI0A4=I0A2\nU4A5=I0K32\nU4A6=[W0K4=0]\nU4A7=I256K0"
        ),
        vec![
            (1104, 2, 6),
            (1105, 3, 6),
            (1106, 4, 1),
            (1107, 5, 1),
            (1102, 6, 6),
            (1103, 7, 7),
            (1101, 8, 6),
        ]
    );
    // Connector 2 becomes usable once IOCFIL declares it.
    let mut ctx = MachineContext::lathe_like();
    ctx.a_inputs.push(2);
    assert_eq!(diags_with("U4A1=I2A0", &ctx), vec![]);
}

#[test]
fn declarations_duplicates_reserved_and_predeclared() {
    let src = "DEF A1 = I0A0\nDEF A1 = I0A1\nDEF TON = I0A2\nDEF FOLD = U10K5\nDEF MFIN = U12K0\nDEF X : FOO\nU4A0=A1+X";
    assert_eq!(
        diags(src),
        vec![
            (1201, 2, 5),
            (1202, 3, 5),
            (1206, 4, 5),
            (1205, 5, 5),
            (1204, 6, 9)
        ]
    );
}

#[test]
fn spl_limit_names_the_value_that_fits() {
    let mut ctx = MachineContext::lathe_like();
    ctx.spl = 1;
    let c = compile("t.plc", b"DEF A = I0A0\nDEF B = I0A1\nU4A0=A*B", &ctx);
    assert_eq!(c.diagnostics.len(), 1);
    assert_eq!(
        (
            c.diagnostics[0].code,
            c.diagnostics[0].line,
            c.diagnostics[0].column
        ),
        (1203, 2, 5)
    );
    assert!(
        c.diagnostics[0].hint.contains("SPL=2"),
        "{}",
        c.diagnostics[0].hint
    );
    // Predeclared names do not count.
    assert_eq!(diags_with("DEF A = I0A0\nFOLD=A*MSTB", &ctx), vec![]);
}

#[test]
fn types_literals_and_conversions() {
    let src = "DEF B : BYTE\nDEF D : DINT\nB = 300\nB = D\nB = BYTE(D)\nD = B + 1\nU4A0 = I0A0 / I0A1\nU4A1 = B\nD = 2.5\nU4A2 = [B = TRUE]";
    assert_eq!(
        diags(src),
        vec![
            (1302, 3, 5),
            (1305, 4, 5),
            (1303, 7, 8),
            (1301, 8, 8),
            (1301, 9, 5),
            (1301, 10, 13)
        ]
    );
}

#[test]
fn literals_take_the_other_operands_type() {
    let p = program("DEF B : BYTE\nB = B + 1");
    let b = p.vars[0].offset;
    assert_eq!(p.vars[0].ty, Ty::Byte);
    let Stmt::Assign {
        value: Expr::Binary { ty, rhs, .. },
        ..
    } = &p.fast[0]
    else {
        panic!("{:?}", p.fast[0])
    };
    assert_eq!(*ty, Ty::Byte);
    assert_eq!(**rhs, Expr::Const(Value::Byte(1)));
    assert!(b >= packets::PACKETS_LEN);
}

#[test]
fn timers_counters_and_pulses() {
    let src = "DEF T1 : TON(50ms)\nDEF C : CTU(3)\nT1 = I0A0\nC = I0A1\nC.R = I0A2\nU4A0 = T1 + C\nU4A1 = [T1.ET > 20] + [C.CV = 2]\nU4A2 = TOF(I0A3, 1.5s)";
    let p = program(src);
    assert_eq!(p.timers.len(), 2);
    assert_eq!(
        (p.timers[0].kind, p.timers[0].preset_ms),
        (TimerKind::Ton, 50)
    );
    assert_eq!(
        (
            p.timers[1].kind,
            p.timers[1].preset_ms,
            p.timers[1].name.as_str()
        ),
        (TimerKind::Tof, 1500, "TOF@8:8")
    );
    assert_eq!(p.counters[0].preset, 3);
    // The inline timer is driven right before the statement that reads it.
    assert!(matches!(p.fast[5], Stmt::Timer { .. }));
    assert!(matches!(
        p.fast[6],
        Stmt::Assign {
            place: Place::Signal(_),
            value: Expr::TimerQ(_)
        }
    ));
}

#[test]
fn stateful_misuse() {
    let src = "DEF T1 : TON(50ms)\nDEF C : CTD(3)\nP1 = I0A0\nP1 = I0A1\nSET T1 = I0A0\nC.R = I0A0\nU4A0 = T1.XX + C\nU4A1 = P1024\nDEF T2 : TON(-1)\nT2 = 1";
    assert_eq!(
        diags(src),
        vec![
            (1401, 4, 1),
            (1402, 5, 5),
            (1311, 6, 3),
            (1310, 7, 11),
            (1108, 8, 8),
            (1209, 9, 14)
        ]
    );
}

#[test]
fn warnings_for_unused_and_never_written() {
    let src = "DEF A : BOOL\nDEF OUT = U4A0\nDEF SPARE = I0A5\nDEF T1 : TON(1s)\nU4A1 = A + OUT + T1 + P7";
    let c = compile("t.plc", src.as_bytes(), &MachineContext::lathe_like());
    let got: Vec<_> = c
        .diagnostics
        .iter()
        .map(|d| (d.code, d.line, d.is_error()))
        .collect();
    assert_eq!(
        got,
        vec![
            (1501, 1, false),
            (1501, 2, false),
            (1502, 3, false),
            (1501, 4, false),
            (1503, 5, false)
        ]
    );
    assert!(c.program.is_some(), "warnings do not stop the build");
}

#[test]
fn views_bits_and_if_zones() {
    let src = "DEF DAC : WORD AT W4A2\nDEF BAD : DWORD AT W4A1\nDEF W : INT AT U4A0\nDAC = 1000\nDAC.15 = I0A0\nW4A0.3 = 1\nIF I0A1 THEN\nSET U5A0 = I0A2\nELSE\nRES U5A0 = 1\nEND_IF";
    assert_eq!(diags(src), vec![(1110, 2, 20), (1111, 3, 16)]);
    let p = program(
        "DEF DAC : WORD AT W4A2\nDAC = 1000\nDAC.15 = I0A0\nIF I0A1 THEN\nSET U5A0 = I0A2\nEND_IF",
    );
    assert_eq!(p.fast.len(), 3);
    let Stmt::Assign { place, .. } = &p.fast[1] else {
        panic!()
    };
    assert_eq!(*place, Place::Signal("U4A31".parse().expect("signal")));
}

#[test]
fn all_errors_of_a_file_come_at_once_with_hints() {
    let src = "U4A0 = I0A0 §\nU4A1 = UNKNOWN\nU9A0 = 1\nDEF B : BYTE\nB = -1\n";
    let c = compile("t.plc", src.as_bytes(), &MachineContext::lathe_like());
    let got: Vec<_> = c.diagnostics.iter().map(|d| (d.code, d.line)).collect();
    assert_eq!(got, vec![(1001, 1), (1207, 2), (1104, 3), (1302, 5)]);
    assert!(c.diagnostics.iter().all(|d| !d.hint.is_empty()));
    assert!(c.program.is_none());
}

#[test]
fn every_code_is_documented_in_the_table() {
    let doc = include_str!("../../DIAGNOSTICS.md");
    for (code, _) in compiler::sema::codes::ALL {
        assert!(
            doc.contains(&format!("| {code} |")),
            "code {code} missing from DIAGNOSTICS.md"
        );
        assert!((1000..2000).contains(code));
    }
    let rows = doc.lines().filter(|l| l.starts_with("| 1")).count();
    assert_eq!(rows, compiler::sema::codes::ALL.len());
}

#[test]
fn constant_expressions_take_the_targets_type() {
    // Two literals fold to one, which then takes the target's type (docs/plc-language.md §4.2).
    let p =
        program("W100K0 = 0 + 0\nW100K1 = 200 + 55\nW100K2 = 0FH & 3CH\nU100K0 = TRUE * /FALSE\n");
    let consts: Vec<&Expr> = p
        .fast
        .iter()
        .map(|s| match s {
            Stmt::Assign { value, .. } => value,
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(
        consts,
        vec![
            &Expr::Const(Value::Byte(0)),
            &Expr::Const(Value::Byte(255)),
            &Expr::Const(Value::Byte(0x0c)),
            &Expr::Const(Value::Bool(true)),
        ]
    );
    // A folded constant that does not fit the target is reported where the expression starts.
    assert_eq!(diags("W100K0 = 200 + 100\n"), vec![(1302, 1, 10)]);
    // Division by a literal zero is not folded: it stays run-time arithmetic (0 and the fault flag).
    assert!(
        diags("DEF D : DINT\nD = 7 / 0\nW100K0 = BYTE(D)\n")
            .iter()
            .all(|&(c, _, _)| c != 1302)
    );
}

/// After a syntax error, usage is unknown: no "never used" for a name the unreadable line uses.
#[test]
fn no_usage_warnings_after_a_syntax_error() {
    let src = "DEF SPARE = I0A5\nU4A1 = SPARE +\n";
    let c = compile("t.plc", src.as_bytes(), &MachineContext::lathe_like());
    let got: Vec<_> = c
        .diagnostics
        .iter()
        .map(|d| (d.code, d.line, d.column, d.is_error()))
        .collect();
    assert_eq!(got, vec![(1003, 3, 1, true)]);
    // The same name really unused, in a program without syntax errors, is still reported.
    assert_eq!(diags("DEF SPARE = I0A5\nU4A1 = I0A0\n"), vec![(1502, 1, 5)]);
}

/// A timer preset below the logic tick (10 ms in `lathe_like`) runs out at the first tick: 1504.
#[test]
fn timer_shorter_than_the_tick_warns() {
    let src = "DEF T1 : TON(5ms)\nDEF T2 : TOF(10ms)\nT1 = I0A0\nT2 = I0A1\nU4A0 = T1 + T2";
    let c = compile("t.plc", src.as_bytes(), &MachineContext::lathe_like());
    let got: Vec<_> = c
        .diagnostics
        .iter()
        .map(|d| {
            (
                d.code,
                d.line,
                d.column,
                d.message.as_str(),
                d.hint.as_str(),
            )
        })
        .collect();
    assert_eq!(
        got,
        vec![(
            1504,
            1,
            14,
            "TON preset 5 ms is shorter than the logic tick of 10 ms: it runs out at the first tick",
            "timers count whole ticks; use a preset of at least 10 ms"
        )]
    );
    assert!(c.program.is_some(), "a warning does not stop the build");
}

/// An undefined name gets "did you mean" with the nearest defined, predeclared or function name.
#[test]
fn undefined_name_suggests_the_nearest_one() {
    let src = "DEF START_PB = I0A3\nU4A0 = STRAT_PB\nSTART_BP = 1";
    let c = compile("t.plc", src.as_bytes(), &MachineContext::lathe_like());
    let got: Vec<_> = c
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .map(|d| {
            (
                d.code,
                d.line,
                d.column,
                d.message.as_str(),
                d.hint.as_str(),
            )
        })
        .collect();
    assert_eq!(
        got,
        vec![
            (
                1207,
                2,
                8,
                "`STRAT_PB` is not defined",
                "did you mean `START_PB`? define it (`DEF STRAT_PB = <signal>` or `DEF STRAT_PB : <type>`) or use a predeclared interface name"
            ),
            (
                1207,
                3,
                1,
                "`START_BP` is not defined",
                "did you mean `START_PB`? define it first: `DEF START_BP = <signal>` or `DEF START_BP : <type>`"
            ),
        ]
    );
}

/// An empty or comment-only program compiles with one warning saying so (every output stays 0).
#[test]
fn empty_program_warns() {
    for (src, what) in [
        ("", "is empty"),
        ("; only a comment\n", "has no statements"),
    ] {
        let c = compile("t.plc", src.as_bytes(), &MachineContext::lathe_like());
        let got: Vec<_> = c
            .diagnostics
            .iter()
            .map(|d| (d.code, d.line, d.column, d.message.clone(), d.is_error()))
            .collect();
        assert_eq!(
            got,
            vec![(
                1505,
                1,
                1,
                format!("the PLC program {what}: every output stays 0"),
                false
            )]
        );
        assert!(c.program.is_some());
    }
}

/// A misspelled keyword gets "did you mean" (`ENDIF` alone on its line reads as the start of an
/// assignment, so the parser stops at the end of that line).
#[test]
fn misspelled_keyword_suggests_the_keyword() {
    let src = "IF I0A0 THEN\nU4A0 = 1\nENDIF\n";
    let c = compile("t.plc", src.as_bytes(), &MachineContext::lathe_like());
    let got: Vec<_> = c
        .diagnostics
        .iter()
        .map(|d| (d.code, d.line, d.column, d.message.clone(), d.hint.clone()))
        .collect();
    assert_eq!(
        got,
        vec![
            (
                1008,
                1,
                1,
                "`IF` without `END_IF`".to_string(),
                "add an `END_IF` line after the block".to_string()
            ),
            (
                1003,
                3,
                6,
                "unexpected end of line".to_string(),
                "did you mean `END_IF`? expected `=`, `.`".to_string()
            ),
        ]
    );
}
