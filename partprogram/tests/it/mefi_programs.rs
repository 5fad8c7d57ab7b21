//! Example programs of partprogram-structure-motion.md and partprogram-parameters-cycles.md with the
//! results the spec states.

use crate::common;

use common::*;
use partprogram::{Kind, PlanOptions};

fn plan(src: &str) -> partprogram::Plan {
    run(&mill(), src, PlanOptions::default())
}

fn xyz(c: &partprogram::Canon) -> (f64, f64, f64) {
    (end(c, 'X'), end(c, 'Y'), end(c, 'Z'))
}

#[test]
fn f01_f02_words_and_multi_line_blocks() {
    let p = plan(
        "%1\nN20 G1 X10.355 Y625.50 F300 S150 T12 M0\nN30 R1=100.\n R2=200.\n R3=300.\nN40 M30\n",
    );
    let c = &p.blocks[0];
    assert_eq!(
        (c.n, c.kind, end(c, 'X'), end(c, 'Y')),
        (Some(20), Kind::Linear, 10.355, 625.5)
    );
    assert_eq!((c.feed, c.s, c.t), (Some(300.0), Some(150.0), Some(12)));
    assert_eq!(c.m.iter().map(|m| m.m).collect::<Vec<_>>(), vec![0]);
    assert_eq!(
        (p.params[1], p.params[2], p.params[3]),
        (100_000, 200_000, 300_000)
    );
}

#[test]
fn f05_comments_end_at_the_quote_or_the_line() {
    let p = plan(
        "%1\nN30 X100 \"ЭТО КОММЕНТАРИЙ\" Y200 Z300\nN40 X1 \"ЭТО КОММЕНТАРИЙ Y7 Z8\nN50 M30\n",
    );
    assert_eq!(xyz(&p.blocks[0]), (100.0, 200.0, 300.0));
    assert_eq!(xyz(&p.blocks[1]), (1.0, 200.0, 300.0));
}

#[test]
fn f06_header_preamble_and_comment() {
    let p = plan(
        "garbage before the header\n%123456 \"КОММЕНТАРИЙ:\nN1 X5\nN2 M30\n*\nafter the end\n",
    );
    assert_eq!(end(&p.blocks[0], 'X'), 5.0);
    assert!(codes(&mill(), "N1 X5\n").contains(&2003));
    assert_eq!(codes(&mill(), "%0\nN1 M30\n"), vec![2003]);
}

#[test]
fn f07_subprograms_run_q_times_and_return() {
    let src = std::fs::read_to_string(machines().join("mill/nc/SUBPRG")).expect("SUBPRG");
    let p = plan(&src);
    let seq: Vec<(Option<u32>, f64, f64)> = p
        .blocks
        .iter()
        .map(|c| (c.n, end(c, 'X'), end(c, 'Y')))
        .collect();
    assert_eq!(
        seq,
        vec![
            (Some(10), 0.0, 0.0),
            (Some(20), 200.0, 0.0),
            (Some(510), 210.0, 0.0),
            (Some(510), 220.0, 0.0),
            (Some(610), 220.0, 50.0),
            (Some(310), 0.0, 0.0),
            (Some(320), 0.0, 0.0)
        ]
    );
    // N10 positions in rapid (G0); N20's G1 F300 is modal into the subprograms' moves.
    let kinds: Vec<(Kind, Option<f64>)> = p.blocks[..5].iter().map(|c| (c.kind, c.feed)).collect();
    assert_eq!(
        kinds,
        vec![
            (Kind::Rapid, None),
            (Kind::Linear, Some(300.0)),
            (Kind::Linear, Some(300.0)),
            (Kind::Linear, Some(300.0)),
            (Kind::Linear, Some(300.0)),
        ]
    );
    assert_eq!(p.blocks[2].unit.as_deref(), Some("sub100"));
}

#[test]
fn f08_substitution_and_the_decimal_point_rule() {
    let p = plan(
        "%1\nN620 G54 G0 X0 Y0 R1=864 R2=-0.864 R3=100000 R20=250 R31=1\nN630 GR31 XR1 YR2 M03 SR20 TR3\nN640 M30\n",
    );
    assert_eq!(
        (
            p.params[1],
            p.params[2],
            p.params[3],
            p.params[20],
            p.params[31]
        ),
        (864, -864, 100_000, 250, 1)
    );
    let c = &p.blocks[1];
    assert_eq!(
        (c.kind, end(c, 'X'), end(c, 'Y'), c.s, c.t),
        (Kind::Linear, 0.864, -0.864, Some(250.0), Some(100_000))
    );
    let p =
        plan("%1\nN10 G0 X100 N20 R10=100 N30 R11=100. N40 R12=0.100 N50 XR10 YR11 ZR12 N60 M30\n");
    assert_eq!(xyz(&p.blocks[0]), (100.0, 0.0, 0.0));
    assert_eq!(xyz(&p.blocks[1]), (0.1, 100.0, 0.1));
    let p = plan("%1\nN10 R20=0.120 R21=0.040 R22=12345.678 N20 SR20 GR21 TR22 X1 N30 M30\n");
    assert_eq!(
        (p.blocks[0].s, p.blocks[0].t),
        (Some(120.0), Some(12_345_678))
    );
}

#[test]
fn parameter_g_with_three_decades_is_a_run_time_error() {
    let (prog, _) = partprogram::compile(&mill(), "t", "%1\nN10 R10=123 N20 GR10\nN30 M30\n");
    let err =
        partprogram::plan(&prog.expect("compiles"), PlanOptions::default()).expect_err("fails");
    assert_eq!((err.1.code, err.1.line), (2502, 2));
}

#[test]
fn feed_units_follow_the_decimal_point_and_parameters() {
    let p = plan(
        "%1\nN10 G94 G1 X1 F300\nN20 X2 F0.3\nN30 R10=100 N40 X3 FR10\nN50 G95 S1000 X4 F200\nN60 X5 F0.2\nN70 M30\n",
    );
    let f: Vec<Option<f64>> = p
        .blocks
        .iter()
        .filter(|c| c.kind == Kind::Linear)
        .map(|c| c.feed)
        .collect();
    assert_eq!(
        f,
        vec![
            Some(300.0),
            Some(300.0),
            Some(100.0),
            Some(200.0),
            Some(200.0)
        ]
    );
}

#[test]
fn f09_f10_f11_zero_offsets() {
    let p = plan(
        "%1\nN1 G55 G92 X100.5 Y200. Z-300.650\nN2 G54 G0 X0 Y0 Z0\nN3 G55 X0 Y0 Z0\nN4 G58 G92 X5\nN5 G58 X1\nN6 X1\nN7 G55 G93 X+10.000\nN8 X10\nN9 M30\n",
    );
    let m: Vec<(Option<u32>, f64, f64, f64)> = p
        .blocks
        .iter()
        .filter(|c| c.kind == Kind::Rapid)
        .map(|c| (c.n, end(c, 'X'), end(c, 'Y'), end(c, 'Z')))
        .collect();
    assert_eq!(
        m,
        vec![
            (Some(2), 0.0, 0.0, 0.0),
            (Some(3), 100.5, 200.0, -300.65),
            (Some(5), 6.0, 200.0, -300.65),
            (Some(6), 101.5, 200.0, -300.65),
            (Some(8), 101.5, 200.0, -300.65)
        ]
    );
}

#[test]
fn f12_absolute_and_incremental_reach_the_same_point() {
    let a = plan("%1\nN1 G0 X50 Y20\nN10 G01 G90 X 90.000 Y 50.000 F100\nN12 M30\n");
    let b = plan("%1\nN1 G0 X50 Y20\nN11 G01 G91 X 40.000 Y 30.000 F100\nN12 M30\n");
    assert_eq!(xyz(&a.blocks[1]), (90.0, 50.0, 0.0));
    assert_eq!(xyz(&b.blocks[1]), (90.0, 50.0, 0.0));
}

#[test]
fn f13_circles_full_semicircle_and_the_inconsistent_arc() {
    let p = plan(
        "%1\nN1 G0 X200 Y250\nN19 G02 G90 X200.0 Y250.0 I200.0 F120\nN2 G91\nN3 G02 X0 Y0 I200.0\nN4 M30\n",
    );
    for c in &p.blocks[1..3] {
        assert_eq!(c.kind, Kind::ArcCw);
        assert_eq!((end(c, 'X'), end(c, 'Y')), (200.0, 250.0));
        assert_eq!(c.center, vec![('X', 400.0), ('Y', 250.0)]);
        assert_eq!(c.plane, partprogram::Plane::XY);
    }
    let p = plan("%1\nN1 G0 X100 Z500\nN20 G18 G03 G90 X100.0 Z100.0 I-200.0 F100\nN4 M30\n");
    let c = &p.blocks[1];
    assert_eq!(
        (c.kind, end(c, 'X'), end(c, 'Z')),
        (Kind::ArcCcw, 100.0, 100.0)
    );
    assert_eq!(c.center, vec![('Z', 300.0), ('X', 100.0)]);
    assert_eq!(c.plane.name(), "ZX");
    let (prog, _) = partprogram::compile(
        &mill(),
        "t",
        "%1\nN1 G0 X150 Z200\nN21 G18 G03 G90 X250.0 Z140.0 I-100.0 J-50.0 F100\nN2 M30\n",
    );
    let err =
        partprogram::plan(&prog.expect("compiles"), PlanOptions::default()).expect_err("7.56");
    assert_eq!(err.1.code, 2503);
}

#[test]
fn f31_dwell_is_q_times_10_ms() {
    let p = plan("%1\nN1 G04 Q10\nN2 G04 Q100\nN3 R29=250 N4 G04 QR29\nN5 M30\n");
    let d: Vec<Option<f64>> = p
        .blocks
        .iter()
        .filter(|c| c.kind == Kind::Dwell)
        .map(|c| c.dwell)
        .collect();
    assert_eq!(d, vec![Some(0.1), Some(1.0), Some(2.5)]);
}

#[test]
fn block_skip_mode_skips_marked_blocks() {
    let src = "%1\nN1 G0 X1\nN2 / X2\nN3 M30\n";
    let p = run(
        &mill(),
        src,
        PlanOptions {
            block_skip: true,
            ..PlanOptions::default()
        },
    );
    assert_eq!(p.blocks.iter().filter(|c| c.kind == Kind::Rapid).count(), 1);
    let p = run(&mill(), src, PlanOptions::default());
    assert_eq!(p.blocks.iter().filter(|c| c.kind == Kind::Rapid).count(), 2);
}

#[test]
fn g73_jump_repeats_q_plus_one_times() {
    let p = plan("%1\nN26 G91 G0 X1\nN54 G73 L26 Q3\nN60 M30\n");
    assert_eq!(p.blocks.iter().filter(|c| c.n == Some(26)).count(), 4);
    assert_eq!(end(&p.blocks[3], 'X'), 4.0);
}

fn drill_moves(p: &partprogram::Plan, unit: &str) -> Vec<(Kind, f64)> {
    p.blocks
        .iter()
        .filter(|c| c.unit.as_deref() == Some(unit) && c.kind != Kind::Dwell && c.kind != Kind::Aux)
        .map(|c| (c.kind, end(c, 'Z')))
        .collect()
}

#[test]
fn milling_g81_drills_at_every_block_until_g80() {
    let p = plan(
        "%1\nN20 X50 G0 N30 R26=400 R27=200 R30=5.0 R31=-85.0 R32=25.0 N40 M3 M41 N50 X100 G00 G81\nN60 X200 N70 X300 N80 X400\nN90 X500\nN100 X600 G80\nN110 M30\n",
    );
    let holes: Vec<f64> = p
        .blocks
        .iter()
        .filter(|c| c.unit.as_deref() == Some("L81") && c.kind == Kind::Linear)
        .map(|c| end(c, 'X'))
        .collect();
    assert_eq!(holes, vec![100.0, 200.0, 300.0, 400.0, 500.0]);
    let first = drill_moves(&p, "L81");
    assert_eq!(
        &first[..3],
        &[
            (Kind::Rapid, 5.0),
            (Kind::Linear, -85.0),
            (Kind::Rapid, 25.0)
        ]
    );
    let feed = p
        .blocks
        .iter()
        .find(|c| c.unit.as_deref() == Some("L81") && c.kind == Kind::Linear)
        .and_then(|c| c.feed);
    assert_eq!(feed, Some(400.0));
}

#[test]
fn milling_g82_restores_speed_and_modal_state_after_each_hole() {
    let p = plan(
        "%1\nN1 G00 G90 X100.\nN2 Z50. S100 M43 M04\nN3 R26=460 R27=1000 R29=300 R30=5. R31=-50. R32=30.\nN4 G82\nN5 G91 X100.\nN6 X100.\nN7 G90 Z500. M05 G80\nN8 M30\n",
    );
    let holes: Vec<f64> = p
        .blocks
        .iter()
        .filter(|c| c.unit.as_deref() == Some("L82") && c.kind == Kind::Dwell)
        .map(|c| end(c, 'X'))
        .collect();
    assert_eq!(holes, vec![100.0, 200.0, 300.0]);
    let dwell = p
        .blocks
        .iter()
        .find(|c| c.kind == Kind::Dwell)
        .and_then(|c| c.dwell);
    assert_eq!(dwell, Some(3.0));
    let n5 = p
        .blocks
        .iter()
        .find(|c| c.n == Some(5) && c.unit.is_none())
        .expect("N5");
    assert_eq!((n5.s, end(n5, 'X')), (Some(100.0), 200.0));
    let in_cycle = p
        .blocks
        .iter()
        .find(|c| c.unit.as_deref() == Some("L82"))
        .expect("cycle");
    assert_eq!(in_cycle.s, Some(1000.0));
}

#[test]
fn milling_g83_peck_drilling_trace() {
    let p = plan(
        "%1\nN1 G0 X0 Y0 R26=100 R27=500 R30=5. R31=-20. R28=8. R32=25.\nN2 G83\nN3 G80 M30\n",
    );
    assert_eq!(
        drill_moves(&p, "L83"),
        vec![
            (Kind::Rapid, 5.0),
            (Kind::Linear, -3.0),
            (Kind::Rapid, 5.0),
            (Kind::Rapid, -2.0),
            (Kind::Linear, -11.0),
            (Kind::Rapid, 5.0),
            (Kind::Rapid, -10.0),
            (Kind::Linear, -19.0),
            (Kind::Rapid, 5.0),
            (Kind::Rapid, -18.0),
            (Kind::Linear, -20.0),
            (Kind::Rapid, 25.0),
        ]
    );
    assert_eq!(
        (p.params[29], p.params[30], p.params[25]),
        (0, 5_000, 0),
        "R29, R30, R25 restored after the cycle"
    );
}

#[test]
fn milling_g86_chip_breaking_trace() {
    let p = plan(
        "%1\nN1 G0 X0 Y0 R26=100 R27=500 R30=5. R31=-20. R28=8. R29=50 R32=25.\nN2 G86\nN3 G80 M30\n",
    );
    let moves = drill_moves(&p, "L86");
    assert_eq!(
        moves,
        vec![
            (Kind::Rapid, 5.0),
            (Kind::Linear, -3.0),
            (Kind::Linear, -11.0),
            (Kind::Linear, -19.0),
            (Kind::Linear, -20.0),
            (Kind::Rapid, 25.0)
        ]
    );
    let dwells = p.blocks.iter().filter(|c| c.kind == Kind::Dwell).count();
    assert_eq!(dwells, 3);
}

#[test]
fn lathe_g81_longitudinal_roughing_with_two_finishing_passes() {
    let src = std::fs::read_to_string(machines().join("lathe/nc/G81ROUGH")).expect("G81ROUGH");
    let p = run(&lathe(), &src, PlanOptions::default());
    let cyc: Vec<&partprogram::Canon> = p
        .blocks
        .iter()
        .filter(|c| c.unit.as_deref() == Some("L81"))
        .collect();
    // 17 roughing cuts of 4 moves each, then 2 finishing passes of 5 moves each.
    assert_eq!(cyc.len(), 17 * 4 + 2 * 5);
    // The main program positions in rapid: N20 G0 X0 Z300, N30 X128 Z4 (G0 modal).
    let main: Vec<(Option<u32>, Kind, f64, f64)> = p
        .blocks
        .iter()
        .filter(|c| c.unit.is_none() && c.kind != Kind::Aux)
        .take(2)
        .map(|c| (c.n, c.kind, end(c, 'X'), end(c, 'Z')))
        .collect();
    assert_eq!(
        main,
        vec![
            (Some(20), Kind::Rapid, 0.0, 300.0),
            (Some(30), Kind::Rapid, 128.0, 4.0)
        ]
    );
    for k in 1..=17 {
        let cut = &cyc[(k - 1) * 4..k * 4];
        let x = 120.0 - 4.0 * k as f64;
        let z = um(-100.0 + 1.678 * k as f64);
        let back = if k == 1 {
            128.0
        } else {
            124.0 - 4.0 * k as f64
        };
        assert_eq!(
            (cut[0].kind, end(cut[0], 'X'), end(cut[0], 'Z')),
            (Kind::Rapid, x, 4.0),
            "cut {k}"
        );
        assert_eq!(
            (cut[1].kind, end(cut[1], 'X'), end(cut[1], 'Z')),
            (Kind::Linear, x, z),
            "cut {k}"
        );
        assert_eq!(
            (cut[2].kind, end(cut[2], 'X')),
            (Kind::Linear, back),
            "cut {k}"
        );
        assert_eq!(
            (cut[3].kind, end(cut[3], 'Z')),
            (Kind::Rapid, 4.0),
            "cut {k}"
        );
        assert_eq!(cut[1].feed, Some(200.0));
    }
    for pass in 0..2 {
        let f = &cyc[68 + pass * 5..68 + pass * 5 + 5];
        let got: Vec<(Kind, f64, f64)> = f
            .iter()
            .map(|c| (c.kind, end(c, 'X'), end(c, 'Z')))
            .collect();
        assert_eq!(
            got,
            vec![
                (Kind::Rapid, 50.0, 4.0),
                (Kind::Linear, 50.0, -70.635),
                (Kind::Linear, 120.0, -100.0),
                (Kind::Linear, 128.0, -100.0),
                (Kind::Rapid, 128.0, 4.0)
            ],
            "finishing pass {pass}"
        );
    }
    // After the cycle every parameter is restored.
    assert_eq!(
        (p.params[24], p.params[28], p.params[30], p.params[31]),
        (-8_000, 4_000, -70_000, -100_000)
    );
}

#[test]
fn helix_tows_z_by_the_lift_per_circle() {
    let p = plan(
        "%1\nN5 X0 Y0 Z0 G00\nN10 Z1.05 G10\nN50 G09 G02 X0 Y0 I100 G73 L50 Q20 F500\nN60 X200. Y0 I100\nN70 G98\nN80 M30\n",
    );
    let circles: Vec<f64> = p
        .blocks
        .iter()
        .filter(|c| c.n == Some(50))
        .map(|c| end(c, 'Z'))
        .collect();
    assert_eq!(circles.len(), 21);
    assert_eq!(circles[0], 1.05);
    assert_eq!(circles[20], 22.05);
    let n60 = p.blocks.iter().find(|c| c.n == Some(60)).expect("N60");
    assert_eq!(
        (end(n60, 'X'), end(n60, 'Y'), end(n60, 'Z')),
        (200.0, 0.0, 22.575)
    );
}

#[test]
fn thread_feed_is_lead_times_speed() {
    let p = plan("%1\nN1 G0 X20 Z5 S200 M03\nN2 G33 Z-40 F1.5\nN3 G0 X30\nN4 M30\n");
    let t = p.blocks.iter().find(|c| c.n == Some(2)).expect("N2");
    assert_eq!(
        (t.kind, t.thread, t.feed),
        (Kind::Linear, true, Some(300.0))
    );
}

#[test]
fn g33_without_f_cuts_with_the_lead_of_the_modal_f() {
    // F is one modal address (structure spec, address table): the lathe cycles G84-G87 program
    // `FR26` in a G00 block and `G33 IR27 ZR31` without F. R26=1.5 is r 1500, a lead of 1.5 mm;
    // at S200 the thread feed is 300 mm/min. The F of a G00 block stays the feed of later G01 (r 1500
    // as mm/min under G94); F in a G33 block is the lead only.
    let p = plan(
        "%1\nN1 R26=1.5\n G0 X20 Z5 S200 M03\nN2 FR26\nN3 G33 Z-40\nN4 G0 X30\nN5 G01 Z5\nN6 G33 Z-40 F2.0\nN7 G01 Z5\nN8 G33 Z-40\nN9 M30\n",
    );
    let feeds: Vec<(Option<u32>, bool, Option<f64>)> = p
        .blocks
        .iter()
        .filter(|c| c.kind == Kind::Linear)
        .map(|c| (c.n, c.thread, c.feed))
        .collect();
    assert_eq!(
        feeds,
        vec![
            (Some(3), true, Some(300.0)),
            (Some(5), false, Some(1500.0)),
            (Some(6), true, Some(400.0)),
            (Some(7), false, Some(1500.0)),
            (Some(8), true, Some(400.0)),
        ]
    );
}

#[test]
fn f26_f29_f30_length_correction_method_a() {
    let p = plan(
        "%1\nN1 G92 D1 R1=125.0 R2=80.0\nN2 G0 X0 Y0 &1000\nN3 X0 Y0 &100\nN4 G92 D2 R1=80.0 R2=50.0 R3=-5.0\nN5 X0 Y0 Z0 &2201 D2\nN6 X0 Y0 Z0 &0\nN7 M30\n",
    );
    let m: Vec<(f64, f64, f64)> = p
        .blocks
        .iter()
        .filter(|c| c.kind == Kind::Rapid)
        .map(xyz)
        .collect();
    assert_eq!(
        m,
        vec![
            (125.0, 0.0, 0.0),
            (0.0, 80.0, 0.0),
            (-80.0, -50.0, 0.0),
            (0.0, 0.0, 0.0)
        ]
    );
}

#[test]
fn g35_g36_g37_transformations() {
    let sub = "N1000 G79 L100\nN1010 G01 X0 Y0\nN1020 G01 X30 Y20\nN1030 G02 X50 Y24.849 I16.641 J-24.962\nN1040 G70\n";
    let p = plan(&format!(
        "%1\nN10 X0 Y0 F500\nN20 G71 L100\nN30 G35 Y0\nN40 G71 L100\nN50 G35\nN55 G36 X1.54 Y3.08\nN60 G71 L100\nN65 G36\nN66 G37 X100\nN70 G71 L100\nN99 M30\n{sub}"
    ));
    let arcs: Vec<(Kind, f64, f64, f64, f64)> = p
        .blocks
        .iter()
        .filter(|c| matches!(c.kind, Kind::ArcCw | Kind::ArcCcw))
        .map(|c| {
            (
                c.kind,
                end(c, 'X'),
                end(c, 'Y'),
                um(c.center[0].1),
                um(c.center[1].1),
            )
        })
        .collect();
    assert_eq!(
        arcs,
        vec![
            (Kind::ArcCw, 50.0, 24.849, 46.641, -4.962),
            (Kind::ArcCcw, 50.0, -24.849, 46.641, 4.962),
            (Kind::ArcCw, 25.0, 12.425, 23.321, -2.481),
            (Kind::ArcCw, 150.0, 24.849, 146.641, -4.962),
        ]
    );
}

#[test]
fn lathe_g83_deep_hole_drilling_retracts_to_ra() {
    let p = run(
        &lathe(),
        "%1\nN1 G0 X0 Z10\nN2 R26=100 R28=8. R30=5. R31=-20.\nN3 G83\nN4 G80\nN5 M30\n",
        PlanOptions::default(),
    );
    assert_eq!(
        drill_moves(&p, "L83"),
        vec![
            (Kind::Rapid, 5.0),
            (Kind::Linear, -3.0),
            (Kind::Rapid, 5.0),
            (Kind::Rapid, -2.0),
            (Kind::Linear, -11.0),
            (Kind::Rapid, 5.0),
            (Kind::Rapid, -10.0),
            (Kind::Linear, -19.0),
            (Kind::Rapid, 5.0),
            (Kind::Rapid, -18.0),
            (Kind::Linear, -20.0),
            (Kind::Rapid, 5.0),
        ]
    );
}

#[test]
fn lathe_g82_facing_roughing_first_cuts() {
    let p = run(
        &lathe(),
        "%1\nN1 G0 X100 Z2\nN2 R24=-2. R25=-2. R26=150 R27=0 R28=2. R29=1. R30=-40. R31=-6.\nN3 G82\nN4 G80\nN5 M30\n",
        PlanOptions::default(),
    );
    let cyc: Vec<(Kind, f64, f64)> = p
        .blocks
        .iter()
        .filter(|c| c.unit.as_deref() == Some("L82"))
        .map(|c| (c.kind, end(c, 'X'), end(c, 'Z')))
        .collect();
    // Zw = 0, first cut Z = -2, Xw = 98, X end = 58 shortened by 1 per cut.
    assert_eq!(
        &cyc[..4],
        &[
            (Kind::Linear, 100.0, -2.0),
            (Kind::Linear, 59.0, -2.0),
            (Kind::Linear, 59.0, 2.0),
            (Kind::Rapid, 100.0, 2.0)
        ]
    );
    assert_eq!(
        &cyc[4..6],
        &[(Kind::Linear, 100.0, -4.0), (Kind::Linear, 60.0, -4.0)]
    );
}

/// The error of planning `src` on the MEFI mill: (code, the text of the located word).
fn refused(src: &str) -> (u32, String) {
    let (p, diags) = partprogram::compile(&mill(), "t", src);
    if let Some(d) = diags.iter().find(|d| d.code == 2038) {
        return (d.code, src[d.span.clone()].to_string());
    }
    assert!(diags.is_empty(), "{diags:#?}");
    let Err((_, d)) = partprogram::plan(&p.expect("compiled"), PlanOptions::default()) else {
        panic!("planned: {src}")
    };
    (d.code, src[d.span.clone()].to_string())
}

#[test]
fn no_word_is_silently_ignored() {
    // Words a linear move would drop: refused at the word (2530 at run time, K H P at check time).
    for (word, code) in [
        ("I5", 2530),
        ("J5", 2530),
        ("L5", 2530),
        ("Q5", 2530),
        ("E5.0", 2530),
        ("K5", 2038),
        ("H5", 2038),
        ("P5", 2038),
        ("HR3", 2038),
    ] {
        let src = format!("%1\nN1 G01 X10 Y0 F100 {word}\nN2 M30\n");
        assert_eq!(refused(&src), (code, word.to_string()), "{word}");
    }
    // The same I/J mean the centre of an arc, and a modal G02 keeps them meaningful...
    let p = run(
        &mill(),
        "%1\nN1 G02 X10 Y0 I5 J0 F100\nN2 X0 Y0 I-5 J0\nN3 M30\n",
        PlanOptions::default(),
    );
    assert_eq!(p.blocks[1].kind, partprogram::Kind::ArcCw);
    assert_eq!(end(&p.blocks[1], 'X'), 0.0);
    // (a lone centre word under a modal G02 is a full circle), but not under a modal G01, nor in
    // a G04 dwell, whose time is Q.
    assert_eq!(
        refused("%1\nN1 G01 X10 Y0 F100\nN2 I1\nN3 M30\n"),
        (2530, "I1".into())
    );
    assert_eq!(refused("%1\nN1 G04 Q50 L2\nN2 M30\n"), (2530, "L2".into()));
}
