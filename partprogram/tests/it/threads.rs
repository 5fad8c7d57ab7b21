//! Thread run-in `E` and run-out `J` of G33 with the slope from machine constant 8 or its parameters
//! (fixtures F17–F21 of the structure-motion spec).

use crate::common;

use common::*;
use partprogram::{Kind, MachineSpec, PlanOptions, compile, plan};

fn lathe_mc8(mc8: i64) -> MachineSpec {
    let mut m = lathe();
    m.thread_constant = mc8;
    m
}

/// (block number, kind, thread flag, X, Z) of every motion block.
fn moves(m: &MachineSpec, src: &str) -> Vec<(Option<u32>, Kind, bool, f64, f64)> {
    run(m, src, PlanOptions::default())
        .blocks
        .iter()
        .filter(|c| matches!(c.kind, Kind::Rapid | Kind::Linear))
        .map(|c| (c.n, c.kind, c.thread, end(c, 'X'), end(c, 'Z')))
        .collect()
}

#[test]
fn f19_run_out_of_12_mm_at_20_degrees_from_r04() {
    // MC 8 = 0 4 0 0 0 0 0 0: the run-out slope is in R04; R04=120.0 = axis 1 (X), +20°.
    let src = "%1\nN10 M03 S50\nN20 Z5. X64. R04=120.0\nN30 Z-100 F6.0 J12 G33\nN40\nN50 X64. Z-100. G0\nN60 M30\n";
    let got = moves(&lathe_mc8(4_000_000), src);
    // 64 + 2·12·tan 20° = 72.735 (X in diameter).
    assert_eq!(
        got,
        vec![
            (Some(20), Kind::Linear, false, 64.0, 5.0),
            (Some(30), Kind::Linear, true, 64.0, -88.0),
            (Some(30), Kind::Linear, true, 72.735, -100.0),
            (Some(50), Kind::Rapid, false, 64.0, -100.0),
        ]
    );
    let p = run(&lathe_mc8(4_000_000), src, PlanOptions::default());
    let t = p.blocks.iter().find(|c| c.thread).expect("thread");
    assert_eq!(t.feed, Some(300.0), "lead 6 mm × S50");
}

#[test]
fn f17_run_out_with_the_slope_in_machine_constant_8() {
    // MC 8 = -00112500: axis 1, 12.5°, negative (an internal thread).
    let src =
        "%1\nN10 M03 S50\nN20 Z5. X64.\nN30 Z-100 F6.0 J12 G33\nN40\nN50 X64. Z-100. G0\nN60 M30\n";
    let got = moves(&lathe_mc8(-112_500), src);
    // 64 − 2·12·tan 12.5° = 58.679.
    assert_eq!(got[2], (Some(30), Kind::Linear, true, 58.679, -100.0));
}

#[test]
fn f21_run_in_of_12_mm_at_18_degrees_from_r16() {
    // MC 8 = 1 5 1 6 0 0 0 0: run-out in R15, run-in in R16; only the run-in is used.
    let src = "%1\nN10 M04 S50\nN20 X71.798 Z-100. R16=118.0\nN30 Z3 F6.0 E12. G33\nN40\nN50 X64. Z3 G0\nN60 M30\n";
    let got = moves(&lathe_mc8(15_160_000), src);
    // The thread diameter 64 is reached after the run-in: 71.798 − 2·12·tan 18° = 64.000.
    assert_eq!(
        got,
        vec![
            (Some(20), Kind::Linear, false, 71.798, -100.0),
            (Some(30), Kind::Linear, true, 64.0, -88.0),
            (Some(30), Kind::Linear, true, 64.0, 3.0),
            (Some(50), Kind::Rapid, false, 64.0, 3.0),
        ]
    );
    // The verbatim F21 writes `E12` without a point, which S19 forbids (ambiguity A17).
    let verbatim = src.replace("E12.", "E12");
    assert_eq!(codes(&lathe_mc8(15_160_000), &verbatim), vec![2030]);
}

#[test]
fn conical_thread_with_run_in_and_run_out() {
    // MC 8 = 00112500: axis 1 (X), +12.5°, for both. From X30 Z0 to X40 Z-50, E5. J10.
    let src = "%1\nN10 M03 S100\nN20 G0 X30 Z0\nN30 X40 Z-50 F2.0 E5. J10 G33\nN40\nN50 G0 X50 Z-50\nN60 M30\n";
    let got = moves(&lathe_mc8(112_500), src);
    // Run-in shift 2·5·tan 12.5° = 2.217, run-out shift 2·10·tan 12.5° = 4.434 (diameter).
    assert_eq!(
        &got[1..4],
        &[
            (Some(30), Kind::Linear, true, 28.783, -5.0),
            (Some(30), Kind::Linear, true, 35.783, -40.0),
            (Some(30), Kind::Linear, true, 42.217, -50.0),
        ]
    );
}

#[test]
fn invalid_run_in_and_run_out_are_located_run_time_errors() {
    let fail = |m: &MachineSpec, src: &str| {
        let (prog, d) = compile(m, "t", src);
        assert!(d.is_empty(), "{d:?}");
        let (_, e) = plan(&prog.expect("compiles"), PlanOptions::default()).expect_err("fails");
        (e.code, e.line)
    };
    let src = "%1\nN10 M03 S50\nN20 Z5. X64.\nN30 Z-100 F6.0 J12 G33\nN40\nN50 M30\n";
    assert_eq!(fail(&lathe(), src), (2509, 4), "MC 8 not set");
    assert_eq!(
        fail(&lathe_mc8(4_000_000), src),
        (2509, 4),
        "R04 = 0 has no axis"
    );
    assert_eq!(
        fail(&lathe_mc8(161_000), src),
        (2509, 4),
        "61° is above 60°"
    );
    let long = "%1\nN20 Z5. X64.\nN30 Z-1 F6.0 E4. J3 G33\nN40\nN50 M30\n";
    assert_eq!(
        fail(&lathe_mc8(112_500), long),
        (2509, 3),
        "7 mm on a 6 mm thread"
    );
    let signs = "%1\nN20 Z5. X64. R15=120.0 R16=-118.0\nN30 Z-100 F6.0 E5. J5 G33\nN40\nN50 M30\n";
    assert_eq!(
        fail(&lathe_mc8(15_160_000), signs),
        (2509, 3),
        "signs differ"
    );
}

#[test]
fn machine_constants_in_tab0_rek_notation_set_the_slope_and_the_length_method() {
    use partprogram::LengthMethod;
    use partprogram::machine::{ConstantsError, UnknownLengthMethod, parse_constants};
    let text =
        "\" planner constants\nR8: -00112.500\nR329: 02000.000 \" method C\nR340: 00233.112\n\n";
    let c = parse_constants(text).expect("valid");
    assert_eq!(c, vec![(8, -112_500), (329, 2_000_000), (340, 233_112)]);
    let mut m = lathe();
    for (n, v) in c {
        m.set_constant(n, v).expect("known values");
    }
    assert_eq!(
        (m.thread_constant, m.length_method),
        (-112_500, LengthMethod::C)
    );
    assert_eq!(
        m.set_constant(329, 3_000_000),
        Err(ConstantsError::LengthMethod {
            constant: 329,
            source: UnknownLengthMethod("3".into())
        }),
        "decade 7 = 3 is no method"
    );
    let e = parse_constants("R8: 1.2.3\n").expect_err("two points");
    assert_eq!(
        e,
        ConstantsError::Syntax {
            line: 1,
            text: "R8: 1.2.3".into()
        }
    );
    assert_eq!(
        e.to_string(),
        "line 1: expected `R<n>: <value>`, found `R8: 1.2.3`"
    );
    assert!(parse_constants("X8: 1\n").is_err());
}

#[test]
fn f15_start_angle_i_is_carried_to_the_thread_block() {
    // `I180`: the thread starts 180° after the spindle's zero pulse (000:953–955); `I0.` at it.
    let src = "%1\nN10 Z205. X20.\nN20 M04 S500 Z200.0 F1.5 I180 G33\nN30 Z190. I0. G33\nN40 M30\n";
    let p = run(&lathe(), src, PlanOptions::default());
    let angles: Vec<(Option<u32>, f64)> = p
        .blocks
        .iter()
        .filter(|c| c.thread)
        .map(|c| (c.n, c.thread_angle))
        .collect();
    assert_eq!(angles, vec![(Some(20), 180.0), (Some(30), 0.0)]);
    let line = p.blocks[1].to_json_line();
    assert!(
        line.contains("\"thread\":true,\"thread_angle\":180"),
        "{line}"
    );
}
