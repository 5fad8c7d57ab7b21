//! Fanuc Macro B golden programs with hand-computed plans, the null and function rules, and every
//! located error, each run on both back ends.

use partprogram::{Backend, Canon, Dialect, Kind, MachineSpec, PlanOptions, compile, plan};

fn haas() -> MachineSpec {
    MachineSpec::new(Dialect::Fanuc, &['X', 'Y', 'Z'])
}

fn xyz(c: &Canon) -> (Kind, f64, f64, f64) {
    let e = |a: char| {
        c.end
            .iter()
            .find(|(x, _)| *x == a)
            .map_or(f64::NAN, |p| p.1)
    };
    (c.kind, e('X'), e('Y'), e('Z'))
}

/// Plans `src` with both back ends, checks that they agree bit for bit and returns the plan.
fn both(src: &str) -> partprogram::Plan {
    let (prog, diags) = compile(&haas(), "t", src);
    let prog = prog.unwrap_or_else(|| panic!("{diags:#?}"));
    let run = |backend| {
        plan(
            &prog,
            PlanOptions {
                backend,
                ..PlanOptions::default()
            },
        )
        .unwrap_or_else(|(_, d)| panic!("{backend:?}: {d}"))
    };
    let a = run(Backend::Interpreter);
    let b = run(Backend::Native);
    assert_eq!(a.blocks, b.blocks);
    let diff: Vec<(usize, f64, f64)> = (0..a.macro_vars.len().max(b.macro_vars.len()))
        .filter(|&i| {
            a.macro_vars.get(i).map(|x| x.to_bits()) != b.macro_vars.get(i).map(|x| x.to_bits())
        })
        .map(|i| (i, a.macro_vars[i], b.macro_vars[i]))
        .collect();
    assert!(diff.is_empty(), "#n, interpreter, native: {diff:?}");
    assert_eq!(a.executed, b.executed);
    b
}

/// The run-time error (code, message, line) of `src` on both back ends (they must agree).
fn run_error(src: &str, opts: PlanOptions) -> (u32, String, u32) {
    let (prog, diags) = compile(&haas(), "t", src);
    let prog = prog.unwrap_or_else(|| panic!("{diags:#?}"));
    let run = |backend| match plan(&prog, PlanOptions { backend, ..opts }) {
        Ok(_) => panic!("{backend:?}: no error"),
        Err((_, d)) => (d.code, d.message, d.line),
    };
    let a = run(Backend::Interpreter);
    assert_eq!(a, run(Backend::Native));
    a
}

fn static_codes(src: &str) -> Vec<(u32, u32)> {
    let (_, diags) = compile(&haas(), "t", src);
    diags.iter().map(|d| (d.code, d.line)).collect()
}

const BOLT: &str = "O1000 (bolt circle via G65)
G21 G17 G90 G54
G00 Z10.
G65 P9010 X50. Y20. R30. A0 B90. K4 Z-5.
G00 Z10.
M30
O9010 (X Y centre, R radius, A start angle, B step, K count, Z depth)
#10 = 1
WHILE [#10 LE #6] DO1
#11 = #1 + [#10 - 1] * #2
G00 X[#24 + #18 * COS[#11]] Y[#25 + #18 * SIN[#11]]
G01 Z#26 F100.
G00 Z2.
#10 = #10 + 1
END1
M99
";

#[test]
fn bolt_circle_via_g65_drills_four_holes_at_90_degrees() {
    let p = both(BOLT);
    let got: Vec<_> = p.blocks.iter().map(xyz).collect();
    let mut want = vec![(Kind::Rapid, 0.0, 0.0, 10.0)];
    // Centre (50, 20), radius 30, angles 0, 90, 180, 270.
    // The first hole is approached at Z10, the others at the Z2 retract of the previous one.
    for (k, (x, y)) in [(80.0, 20.0), (50.0, 50.0), (20.0, 20.0), (50.0, -10.0)]
        .into_iter()
        .enumerate()
    {
        want.push((Kind::Rapid, x, y, if k == 0 { 10.0 } else { 2.0 }));
        want.push((Kind::Linear, x, y, -5.0));
        want.push((Kind::Rapid, x, y, 2.0));
    }
    want.push((Kind::Rapid, 50.0, -10.0, 10.0));
    want.push((Kind::Aux, 50.0, -10.0, 10.0));
    assert_eq!(got, want);
    // The G65 level's locals are gone after M99: #10 of the main program is null again.
    assert!(p.macro_vars[10].is_nan() && p.macro_vars[24].is_nan());
}

const POCKET: &str = "O2000 (zigzag pocket)
G00 X0 Y0 Z1.
G01 Z-2. F200.
#1 = 0
#2 = 5.
WHILE [#1 LE 20.] DO1
G01 X40. Y#1
#1 = #1 + #2
IF [#1 GT 20.] GOTO 10
G01 X0 Y#1
#1 = #1 + #2
END1
N10 G00 Z5.
M30
";

#[test]
fn pocket_loop_with_while_and_goto_out_of_the_loop() {
    let p = both(POCKET);
    let got: Vec<_> = p.blocks.iter().map(xyz).collect();
    let want = vec![
        (Kind::Rapid, 0.0, 0.0, 1.0),
        (Kind::Linear, 0.0, 0.0, -2.0),
        (Kind::Linear, 40.0, 0.0, -2.0),
        (Kind::Linear, 0.0, 5.0, -2.0),
        (Kind::Linear, 40.0, 10.0, -2.0),
        (Kind::Linear, 0.0, 15.0, -2.0),
        (Kind::Linear, 40.0, 20.0, -2.0),
        (Kind::Rapid, 40.0, 20.0, 5.0),
        (Kind::Aux, 40.0, 20.0, 5.0),
    ];
    assert_eq!(got, want);
    assert_eq!(p.macro_vars[1], 25.0);
}

const PROBE: &str = "O3000 (probing arithmetic with system variables)
G10 L2 P1 X100. Y50. Z-20.
G54 G00 X10. Y5.
#100 = #5021
#101 = #5001
#102 = #5222
#5221 = #5221 + 2.5
G00 X0 Y0
#103 = [#100 - #101] / 4
G00 X#103 Y[ROUND[#102 / 3]]
#104 = ATAN[1]/[-1]
G00 X#104
M30
";

#[test]
fn probing_arithmetic_reads_positions_and_writes_the_g54_offset() {
    let p = both(PROBE);
    // #5021 machine X = 100 + 10, #5001 work X = 10, #5222 G54 Y = 50.
    assert_eq!(&p.macro_vars[100..105], &[110.0, 10.0, 50.0, 25.0, 135.0]);
    let got: Vec<_> = p.blocks.iter().map(|c| (xyz(c).1, xyz(c).2)).collect();
    // G54 X becomes 102.5: X0 → 102.5; X25 → 127.5, Y ROUND[16.667] = 17 → 67; X135 → 237.5.
    assert_eq!(
        got,
        vec![
            (110.0, 55.0),
            (102.5, 50.0),
            (127.5, 67.0),
            (237.5, 67.0),
            (237.5, 67.0)
        ]
    );
}

#[test]
fn null_rules_copy_null_read_it_as_zero_and_drop_null_words() {
    let p = both(
        "O1\nG00 X7. Y8.\n#2 = #1\n#3 = #1 + 1\nIF [#2 EQ #0] THEN #4 = 1\nIF [#3 EQ #0] THEN #5 = 1\n\
         IF [#2 EQ 0] THEN #6 = 1\nIF [#2 GE 0] THEN #7 = 1\nG00 X#2 Y#3\nM30\n",
    );
    let v = &p.macro_vars;
    assert!(v[2].is_nan());
    assert_eq!(v[3], 1.0);
    assert_eq!(v[4], 1.0);
    assert!(v[5].is_nan() && v[6].is_nan());
    assert_eq!(v[7], 1.0);
    // X#2 is null: the X word is not commanded, X stays at 7.
    assert_eq!(xyz(&p.blocks[1]), (Kind::Rapid, 7.0, 1.0, 0.0));
}

#[test]
fn functions_and_operators_give_fanucs_values() {
    let exprs = [
        ("FIX[-1.2]", -1.0),
        ("FUP[-1.2]", -2.0),
        ("FUP[1.2]", 2.0),
        ("ROUND[2.5]", 3.0),
        ("ROUND[-2.5]", -3.0),
        ("BCD[25]", 37.0),
        ("BIN[37]", 25.0),
        ("7 MOD 3", 1.0),
        ("-7 MOD 3", -1.0),
        ("5 AND 3", 1.0),
        ("5 OR 3", 7.0),
        ("5 XOR 3", 6.0),
        ("SQRT[16]", 4.0),
        ("ABS[-3]", 3.0),
        ("ASIN[1]", 90.0),
        ("ACOS[0]", 90.0),
        ("ATAN[-1]/[-1]", 225.0),
        ("ATAN[1,0]", 90.0),
        ("LN[1]", 0.0),
        ("EXP[0]", 1.0),
        ("SIN[30]", 0.49999999999999994),
        ("2 + 3 * 4", 14.0),
        ("[2 + 3] * 4", 20.0),
        ("10 / 4", 2.5),
        ("3 GT 2", 1.0),
        ("3 LE 2", 0.0),
        ("[1 EQ 1] AND [2 NE 3]", 1.0),
    ];
    let mut src = String::from("O1\n");
    for (i, (e, _)) in exprs.iter().enumerate() {
        src.push_str(&format!("#{} = {e}\n", 500 + i));
    }
    src.push_str("M30\n");
    let p = both(&src);
    for (i, (e, want)) in exprs.iter().enumerate() {
        assert_eq!(p.macro_vars[500 + i], *want, "{e}");
    }
}

#[test]
fn nested_loops_and_computed_variables() {
    // Three nested loops fill #100..#111 with i*10 + j*3 + k via #[…].
    let p = both(
        "O1\n#1 = 0\nWHILE [#1 LT 2] DO1\n#2 = 0\nWHILE [#2 LT 3] DO2\n#3 = 0\nWHILE [#3 LT 2] DO3\n\
         #[100 + #1 * 6 + #2 * 2 + #3] = #1 * 10 + #2 * 3 + #3\n#3 = #3 + 1\nEND3\n#2 = #2 + 1\nEND2\n\
         #1 = #1 + 1\nEND1\nM30\n",
    );
    let want = [
        0.0, 1.0, 3.0, 4.0, 6.0, 7.0, 10.0, 11.0, 13.0, 14.0, 16.0, 17.0,
    ];
    assert_eq!(&p.macro_vars[100..112], &want);
}

#[test]
fn m99_p_returns_to_a_block_of_the_caller_and_m98_keeps_the_locals() {
    let p = both("O1\n#1 = 3.\nM98 P20\nG00 X1.\nN5 G00 Y#1\nM30\nO20\nG00 X#1\n#1 = 4.\nM99 P5\n");
    let got: Vec<_> = p.blocks.iter().map(|c| (xyz(c).1, xyz(c).2)).collect();
    // O20 moves X3, sets #1 = 4 (the caller's local: M98 opens no level), returns to N5: Y4; X1 skipped.
    assert_eq!(got, vec![(3.0, 0.0), (3.0, 4.0), (3.0, 4.0)]);
}

#[test]
fn g65_l_repeats_start_from_the_arguments() {
    let p = both("O1\nG65 P30 L3 A2.\nM30\nO30\n#1 = #1 + 1\n#100 = #100 + #1\nM99\n");
    // Each repetition: #1 = 2 + 1 = 3, so #100 = 9.
    assert_eq!(p.macro_vars[100], 9.0);
}

#[test]
fn division_by_zero_is_located() {
    let e = run_error("O1\n#1 = 0\n#2 = 5 / #1\nM30\n", PlanOptions::default());
    assert_eq!(e, (2531, "division by zero".to_string(), 3));
    let e = run_error("O1\n#2 = 5 MOD 0.2\nM30\n", PlanOptions::default());
    assert_eq!(e.0, 2531);
    let e = run_error("O1\n#2 = SQRT[-1]\nM30\n", PlanOptions::default());
    assert_eq!(
        e.1,
        "value out of range (SQRT, LN, ASIN, ACOS, BIN, BCD argument or overflow)"
    );
    assert_eq!(e.2, 2);
}

#[test]
fn runaway_loop_stops_at_the_block_limit() {
    let opts = PlanOptions {
        max_blocks: 1000,
        ..PlanOptions::default()
    };
    let e = run_error(
        "O1\n#1 = 0\nWHILE [1 EQ 1] DO1\n#1 = #1 + 1\nEND1\nM30\n",
        opts,
    );
    assert_eq!(e.0, 2504);
    // 1 block before the loop, then 3 per pass: block 1001 is the WHILE of pass 334 (line 3).
    assert_eq!(e.2, 3);
}

#[test]
fn static_errors_are_located() {
    // Bad nesting: END without DO, DO without END, overlapping, reused number, depth 4.
    assert_eq!(static_codes("O1\nEND1\nM30\n"), vec![(2037, 2)]);
    assert_eq!(
        static_codes("O1\nWHILE [1 EQ 1] DO2\nM30\n"),
        vec![(2037, 2)]
    );
    assert_eq!(
        static_codes("O1\nDO1\nDO2\nEND1\nEND2\nM30\n"),
        vec![(2037, 4), (2037, 5)]
    );
    assert_eq!(
        static_codes("O1\nDO1\nDO1\nEND1\nEND1\nM30\n"),
        vec![(2037, 3)]
    );
    // GOTO to a missing N.
    assert_eq!(static_codes("O1\nGOTO 50\nM30\n"), vec![(2018, 2)]);
    // Variables out of range; expression in G; syntax.
    assert_eq!(static_codes("O1\n#2000 = 1\nM30\n"), vec![(2011, 2)]);
    assert_eq!(static_codes("O1\n#1 = 1\nG#1 X1.\nM30\n"), vec![(2010, 3)]);
    assert_eq!(static_codes("O1\n#1 = [1 + 2\nM30\n"), vec![(2002, 2)]);
    assert_eq!(static_codes("O1\nG65 P77\nM30\n"), vec![(2019, 2)]);
    // A number with two points (found by the fanuc_macro fuzz target: the fraction's second
    // point overflowed the digit arithmetic).
    assert_eq!(
        static_codes("O1\nG01 X2.52.5 WHILE [1 EQ 1] DO1\nEND1\nM30\n"),
        vec![(2002, 2), (2037, 3)]
    );
    assert_eq!(static_codes("O1\nG01 X2.52.5\nM30\n"), vec![(2013, 2)]);
}

#[test]
fn run_time_variable_and_target_errors_are_located() {
    let e = run_error("O1\n#1 = 5000\n#2 = #[#1]\nM30\n", PlanOptions::default());
    assert_eq!(e, (2531, "variable #5000 does not exist".to_string(), 3));
    let e = run_error("O1\n#1 = 7\nGOTO #1\nM30\n", PlanOptions::default());
    assert_eq!((e.0, e.2), (2505, 3));
    let e = run_error("O1\n#5021 = 1\nM30\n", PlanOptions::default());
    assert_eq!(e, (2531, "variable #5021 cannot be written".to_string(), 2));
    let e = run_error(
        "O1\n#3000 = 12 (TOOL BROKEN)\nM30\n",
        PlanOptions::default(),
    );
    assert_eq!(
        e,
        (2531, "macro alarm #3000 = 12: TOOL BROKEN".to_string(), 2)
    );
}

#[test]
fn macro_runs_are_compiled_natively() {
    let (prog, _) = compile(&haas(), "t", POCKET);
    let code = prog.and_then(|p| p.macro_native).expect("native code");
    // Runs: #1..WHILE (lines 4–6), #1 = …/IF (8–9), #1 = …/END (11–12).
    assert_eq!(code.run_count(), 3);
}

#[test]
fn round_is_half_away_from_zero_at_the_edges_in_both_back_ends() {
    // The largest double below 0.5, halves, −0.3 (→ −0), odd integers above 2^52 and the halves
    // of 2^51..2^52 (the two places where `trunc(x + 0.5)` would be wrong).
    let p = both(
        "O1\n#100 = 0.49999999999999994\n#101 = -0.5\n#102 = 2.5\n#103 = -0.3\n\
         #104 = 4503599627370497\n#105 = 2251799813685248.5\n#106 = -2251799813685248.5\n\
         #1 = 100\nWHILE [#1 LE 106] DO1\n#[#1 + 400] = ROUND[#[#1]]\n#1 = #1 + 1\nEND1\nM30\n",
    );
    let got: Vec<u64> = p.macro_vars[500..507].iter().map(|v| v.to_bits()).collect();
    let want: Vec<u64> = [
        0.0,
        -1.0,
        3.0,
        -0.0,
        4_503_599_627_370_497.0,
        2_251_799_813_685_249.0,
        -2_251_799_813_685_249.0,
    ]
    .iter()
    .map(|v: &f64| v.to_bits())
    .collect();
    assert_eq!(got, want);
}

#[test]
fn computed_numbers_and_plain_variables_meet_in_one_native_run() {
    // One native run with computed numbers and five plain variables: a computed write to #2 is
    // seen by a plain read, a plain write by a computed read (the run keeps no variable in a
    // register that a computed number could miss).
    let src = "O1\n#1 = 2\n#2 = 5\n#[#1] = 7\n#3 = #2 + 1\n#2 = 9\n#4 = #[#1]\n\
               #[#1 - 1] = #4 * 2\n#5 = #1\nM30\n";
    let (prog, _) = compile(&haas(), "t", src);
    let code = prog.and_then(|p| p.macro_native).expect("native code");
    assert_eq!(code.run_count(), 1);
    let p = both(src);
    assert_eq!(&p.macro_vars[1..6], &[18.0, 9.0, 8.0, 9.0, 18.0]);
}

#[test]
fn computed_and_system_variables_run_natively_in_one_run() {
    // Squares into #100..#104 through #[…], the G54 X offset counted up by 1.5 per pass, a read of
    // #9999 (nonexistent) after the loop: one native run; the error is the interpreter's.
    let src = "O1\n#1 = 0\nWHILE [#1 LT 5] DO1\n#[100 + #1] = #1 * #1\n#5221 = #5221 + 1.5\n\
               #2 = #[100 + #1] + ROUND[#5221] + [#1 MOD 3]\n#1 = #1 + 1\nEND1\nG00 X#104 Y#2\nM30\n";
    let (prog, _) = compile(&haas(), "t", src);
    let code = prog.and_then(|p| p.macro_native).expect("native code");
    assert_eq!(code.run_count(), 1);
    let p = both(src);
    assert_eq!(&p.macro_vars[100..105], &[0.0, 1.0, 4.0, 9.0, 16.0]);
    // Last pass: #1 = 4, #104 = 16, #5221 = 7.5 → ROUND 8, 4 MOD 3 = 1: #2 = 25.
    assert_eq!(p.macro_vars[2], 25.0);
    assert_eq!(p.executed, 1 + 5 * 6 + 1 + 1 + 1);
    // X16 in G54 (X offset 7.5) is machine X 23.5.
    assert_eq!(xyz(&p.blocks[0]), (Kind::Rapid, 23.5, 25.0, 0.0));
    let e = run_error(
        "O1\n#1 = 9899\n#2 = #[#1 + 100]\nM30\n",
        PlanOptions::default(),
    );
    assert_eq!(e, (2531, "variable #9999 does not exist".to_string(), 3));
}

#[test]
fn g10_l11_l13_wear_adds_to_the_geometry_and_the_variables_see_both() {
    // H1 length 10 (L10) + wear -0.5 (L11, then G91 adds -0.25): G43 H1 Z0 is machine Z 9.25.
    // D1 radius 2 (L12) + wear 0.5 (#2601): G41 on the line Y10 → centre Y 10 + 2.5 = 12.5.
    let p = both(
        "O1\nG10 L10 P1 R10.\nG10 L11 P1 R-0.5\nG91 G10 L11 P1 R-0.25\nG90\nG10 L12 P1 R2.\n#2601 = 0.5\n\
         #100 = #2001\n#101 = #2201\n#102 = #2401\n#103 = #2601\n\
         G43 H1 G00 Z0\nG00 X-10. Y0\nG41 D1 G01 X0 Y10. F100.\nX20.\nG40 G49 G00 Z50.\nM30\n",
    );
    assert_eq!(&p.macro_vars[100..104], &[10.0, -0.75, 2.0, 0.5]);
    assert_eq!(xyz(&p.blocks[0]), (Kind::Rapid, 0.0, 0.0, 9.25));
    let x20 = p
        .blocks
        .iter()
        .find(|c| xyz(c).1 == 20.0)
        .expect("the X20 line");
    assert_eq!(xyz(x20), (Kind::Linear, 20.0, 12.5, 9.25));
}

#[test]
fn modal_information_variables_read_the_current_g_codes_and_words() {
    // #4001 motion, #4002 plane, #4003 G90/91, #4006 G20/21, #4007 G40/41/42, #4008 G43/44/49,
    // #4009 cycle, #4010 G98/99, #4014 work system, #4109 F, #4111 H, #4119 S, #4120 T, #4130 G154 P;
    // #4201+ the same (a plan buffers nothing).
    let p = both(
        "O1\nG18 G91 G01 X0 F250. S1200 T7\nG99 G55\n\
         #100 = #4001\n#101 = #4002\n#102 = #4003\n#103 = #4006\n#104 = #4007\n#105 = #4008\n\
         #106 = #4009\n#107 = #4010\n#108 = #4014\n#109 = #4109\n#110 = #4111\n#111 = #4119\n\
         #112 = #4120\n#113 = #4130\n#114 = #4201\nG154 P12\n#115 = #4014\n#116 = #4130\nM30\n",
    );
    assert_eq!(
        &p.macro_vars[100..117],
        &[
            1.0, 18.0, 91.0, 21.0, 40.0, 49.0, 80.0, 99.0, 55.0, 250.0, 0.0, 1200.0, 7.0, 0.0, 1.0,
            154.0, 12.0
        ]
    );
    // #4004 (G22/G23, not modelled) does not exist; the modal variables are read only.
    assert_eq!(static_codes("O1\n#1 = #4004\nM30\n"), vec![(2011, 2)]);
    let e = run_error("O1\n#1 = 4001\n#[#1] = 1\nM30\n", PlanOptions::default());
    assert_eq!(e, (2531, "variable #4001 cannot be written".to_string(), 3));
}

#[test]
fn modal_information_b_m_n_and_o_numbers() {
    // #4113 the last M (M97–M99 are calls, not M codes), #4114 the N of the latest block with
    // one (the reading block's own included; native loops with N labels keep it too), #4115 the
    // executing program's O number, #4102 null (B is never a second auxiliary function here).
    let p = both(
        "O1234\nN5 G00 X0 Y0 M08\n#100 = #4113\n#101 = #4114\nN7 #102 = #4114\n#103 = #4115\n\
         #104 = #4102\nIF [#104 EQ #0] THEN #105 = 1\n#1 = 0\nN20 #1 = #1 + 1\nIF [#1 LT 3] GOTO 20\n\
         #106 = #4314\nM98 P2000\n#108 = #4115\n#109 = #4113\n#110 = #4114\nM30\n\
         O2000\nN40 #107 = #4115\nM09\nM99\n",
    );
    let v = &p.macro_vars;
    assert!(v[104].is_nan());
    let got: Vec<f64> = [100, 101, 102, 103, 105, 106, 107, 108, 109, 110]
        .iter()
        .map(|&i| v[i])
        .collect();
    assert_eq!(
        got,
        vec![8.0, 5.0, 7.0, 1234.0, 1.0, 20.0, 2000.0, 1234.0, 9.0, 40.0]
    );
    // Before any M, N: null.
    let p = both(
        "O1\n#100 = #4113\n#101 = #4114\nIF [#100 EQ #0] THEN #102 = 1\nIF [#101 EQ #0] THEN #103 = 1\nM30\n",
    );
    assert_eq!(&p.macro_vars[102..104], &[1.0, 1.0]);
}

#[test]
fn g65_argument_specification_ii_binds_i_j_k_sets() {
    // I1 K3 I4 J5 (Fanuc's example): #4 = 1, #6 = 3, #7 = 4, #8 = 5; A #1; the tenth set's K is #33.
    // D6 then I7 J8 K9 I10: D is #7 (spec I), the second set's I (#7) comes later and wins.
    let p = both(
        "O1\nG65 P9000 A2. I1. K3. I4. J5.\nG65 P9001 D6. I7. J8. K9. I10.\n\
         G65 P9002 I1 I2 I3 I4 I5 I6 I7 I8 I9 I10 K33.\nM30\n\
         O9000\n#100 = #1\n#101 = #4\n#102 = #5\n#103 = #6\n#104 = #7\n#105 = #8\nM99\n\
         O9001\n#106 = #7\n#107 = #10\nM99\nO9002\n#108 = #31\n#109 = #33\nM99\n",
    );
    let v = &p.macro_vars;
    // #5 (J of the first set) was not given: null.
    assert_eq!(
        (v[100], v[101], v[103], v[104], v[105]),
        (2.0, 1.0, 3.0, 4.0, 5.0)
    );
    assert!(v[102].is_nan() && v[107].is_nan());
    assert_eq!((v[106], v[108], v[109]), (10.0, 10.0, 33.0));
}

mod differential {
    //! Random macro programs: the native back end must give the interpreter's plan, variables (bit
    //! for bit, null included), block count and errors.
    use super::*;
    use proptest::prelude::*;

    fn var() -> impl Strategy<Value = String> {
        // Computed numbers (plain, #0, system, nonexistent) and system variables run natively too.
        prop::sample::select(vec![
            "#1",
            "#2",
            "#3",
            "#4",
            "#100",
            "#500",
            "#0",
            "#30",
            "#[#1]",
            "#[100 + #2]",
            "#[#3 / 2]",
            "#5221",
            "#2001",
            "#5001",
            "#5041",
            "#4113",
            "#4114",
            "#4314",
            "#4115",
            "#[4114 + #2]",
        ])
        .prop_map(str::to_string)
    }

    fn expr() -> impl Strategy<Value = String> {
        let leaf = prop_oneof![
            (-50i32..50).prop_map(|v| v.to_string()),
            (-500i32..500).prop_map(|v| format!("{}", f64::from(v) / 7.0)),
            Just("0".to_string()),
            var(),
        ];
        leaf.prop_recursive(3, 16, 2, |inner| {
            let ops = prop::sample::select(vec![
                "+", "-", "*", "/", "MOD", "AND", "OR", "XOR", "EQ", "NE", "GT", "GE", "LT", "LE",
            ]);
            let funcs = prop::sample::select(vec![
                "SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "SQRT", "ABS", "ROUND", "FIX", "FUP",
                "LN", "EXP", "BIN", "BCD",
            ]);
            prop_oneof![
                (inner.clone(), ops, inner.clone()).prop_map(|(a, o, b)| format!("[{a} {o} {b}]")),
                (funcs, inner.clone()).prop_map(|(f, a)| format!("{f}[{a}]")),
                (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("ATAN[{a}]/[{b}]")),
                inner.prop_map(|a| format!("-{a}")),
            ]
        })
    }

    fn stmt() -> impl Strategy<Value = String> {
        let target = prop::sample::select(vec![
            "#1",
            "#2",
            "#3",
            "#4",
            "#100",
            "#500",
            "#[#1 + 100]",
            "#[#4]",
            "#5222",
            "#2001",
            "#2401",
        ]);
        prop_oneof![
            4 => (target.clone(), expr()).prop_map(|(t, e)| format!("{t} = {e}\n")),
            1 => (expr(), target.clone(), expr()).prop_map(|(c, t, e)| format!("IF [{c}] THEN {t} = {e}\n")),
            1 => expr().prop_map(|c| format!("IF [{c}] GOTO 90\n")),
            1 => (1u8..6, target, expr()).prop_map(|(k, t, e)| {
                format!("#9 = 0\nWHILE [#9 LT {k}] DO1\n{t} = {e}\n#9 = #9 + 1\nEND1\n")
            }),
            1 => (expr(), var()).prop_map(|(x, y)| format!("G01 X[{x}] Y{y} F100.\n")),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 160, .. ProptestConfig::default() })]

        #[test]
        fn native_matches_interpreter(stmts in proptest::collection::vec(stmt(), 1..10)) {
            let mut src = String::from("O1\n");
            // Every other statement numbered: #4114 reads the latest N in both back ends.
            for (i, s) in stmts.iter().enumerate() {
                if i % 2 == 0 {
                    src.push_str(&format!("N{} ", i + 1));
                }
                src.push_str(s);
            }
            src.push_str("N90 G00 X#1 Y#2\nM30\n");
            let (prog, diags) = compile(&haas(), "diff", &src);
            let prog = prog.unwrap_or_else(|| panic!("{src}\n{diags:?}"));
            let run = |backend| match plan(&prog, PlanOptions { backend, ..PlanOptions::default() }) {
                Ok(p) => Ok((p.blocks, p.macro_vars.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), p.executed)),
                Err((b, d)) => Err((b, d.code, d.message, d.line)),
            };
            let a = run(Backend::Interpreter);
            let b = run(Backend::Native);
            prop_assert_eq!(a, b, "{}", src);
        }
    }
}
