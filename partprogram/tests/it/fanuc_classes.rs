//! The defect classes of issue 14 in the Fanuc/HAAS dialect, with hand-computed plans: full circles,
//! offsets written by the program (G10, G52, G92), canned-cycle repeats, subprograms after M30,
//! the arc feed under compensation, G28 without axis words, rounding to the resolution.

use crate::common;

use common::*;
use partprogram::{Canon, Dialect, Kind, MachineSpec, PlanOptions, compile};

fn haas() -> MachineSpec {
    MachineSpec::new(Dialect::Fanuc, &['X', 'Y', 'Z'])
}

fn plan(src: &str) -> Vec<Canon> {
    run(&haas(), src, PlanOptions::default()).blocks
}

fn xyz(c: &Canon) -> (f64, f64, f64) {
    (end(c, 'X'), end(c, 'Y'), end(c, 'Z'))
}

fn centre(c: &Canon) -> Vec<(char, f64)> {
    c.center.iter().map(|(a, v)| (*a, um(*v))).collect()
}

#[test]
fn a_full_circle_with_ij_and_no_end_point_is_cut() {
    let p = plan("O1\nG90 G00 X10. Y0\nG02 I-10. F100.\nM30\n");
    let arc = &p[1];
    assert_eq!(arc.kind, Kind::ArcCw);
    assert_eq!(xyz(arc), (10.0, 0.0, 0.0));
    assert_eq!(centre(arc), vec![('X', 0.0), ('Y', 0.0)]);
    assert_eq!(arc.feed, Some(100.0));
}

#[test]
fn a_full_circle_in_g18_takes_k_and_i() {
    // ZX plane: start Z5 X0, K-5 puts the centre at Z0 X0.
    let p = plan("O1\nG18 G00 X0 Z5.\nG03 K-5. F50.\nM30\n");
    assert_eq!(p[1].kind, Kind::ArcCcw);
    assert_eq!(xyz(&p[1]), (0.0, 0.0, 5.0));
    assert_eq!(centre(&p[1]), vec![('Z', 0.0), ('X', 0.0)]);
}

#[test]
fn a_full_circle_with_r_is_refused() {
    let (prog, _) = compile(&haas(), "t", "O1\nG00 X10.\nG02 R5. F100.\nM30\n");
    let Err(err) = partprogram::plan(&prog.expect("compiles"), PlanOptions::default()) else {
        panic!("R cannot make a full circle");
    };
    assert_eq!(err.1.code, 2503);
}

#[test]
fn g10_l2_writes_the_work_offsets_and_g91_adds_to_them() {
    let p = plan(
        "O1\nG90 G10 L2 P2 X100. Y50. Z-10.\nG55 G00 X0 Y0 Z0\nG91 G10 L2 P2 X10.\nG90 G00 X0\nG54 X0\nM30\n",
    );
    assert_eq!(xyz(&p[0]), (100.0, 50.0, -10.0));
    assert_eq!(xyz(&p[1]), (110.0, 50.0, -10.0));
    assert_eq!(xyz(&p[2]), (0.0, 50.0, -10.0));
}

#[test]
fn g10_l20_writes_the_g154_offsets_that_g110_and_g154_select() {
    let p = plan("O1\nG10 L20 P1 X5. Y6.\nG10 L20 P30 X7.\nG110 G00 X0 Y0\nG154 P30 X1.\nM30\n");
    assert_eq!(xyz(&p[0]), (5.0, 6.0, 0.0));
    // P30 has X7 and Y0: Y stays at the programmed 0 of the new system only when written.
    assert_eq!(xyz(&p[1]), (8.0, 6.0, 0.0));
}

#[test]
fn g10_with_an_unsupported_l_is_a_located_error() {
    let (prog, _) = compile(&haas(), "t", "O1\nG10 L3 P1 R2.\nM30\n");
    let Err(err) = partprogram::plan(&prog.expect("compiles"), PlanOptions::default()) else {
        panic!("L3 is refused");
    };
    assert_eq!((err.1.code, err.1.line), (2507, 2));
}

#[test]
fn g52_shifts_the_given_axes_and_g92_cancels_the_shift_of_its_axes() {
    let p = plan(
        "O1\nG10 L2 P1 X100.\nG52 X10. Y20.\nG00 X0 Y0\nG52 Y5.\nX1. Y1.\nG92 X0\nX2. Y2.\nM30\n",
    );
    assert_eq!(xyz(&p[0]), (110.0, 20.0, 0.0));
    // G52 Y5 keeps the X shift.
    assert_eq!(xyz(&p[1]), (111.0, 6.0, 0.0));
    // G92 X0 at machine X111: X zero there, the G52 X shift gone; Y keeps its G52 shift.
    assert_eq!(xyz(&p[2]), (113.0, 7.0, 0.0));
}

#[test]
fn a_canned_cycle_with_l_in_g91_drills_l_holes() {
    // Initial Z10, R-8 → R plane Z2, Z-7 → bottom Z-5; holes at X10, 20, 30 (G98: back to Z10).
    let p = plan("O1\nG00 X0 Y0 Z10.\nG91 G81 X10. R-8. Z-7. L3 F100.\nG80\nM30\n");
    let bottoms: Vec<(f64, f64, f64)> = p
        .iter()
        .filter(|c| c.kind == Kind::Linear)
        .map(xyz)
        .collect();
    assert_eq!(
        bottoms,
        vec![(10.0, 0.0, -5.0), (20.0, 0.0, -5.0), (30.0, 0.0, -5.0)]
    );
    let kinds: Vec<(Kind, f64, f64)> = p[1..6]
        .iter()
        .map(|c| (c.kind, end(c, 'X'), end(c, 'Z')))
        .collect();
    assert_eq!(
        kinds,
        vec![
            (Kind::Rapid, 10.0, 10.0),
            (Kind::Rapid, 10.0, 2.0),
            (Kind::Linear, 10.0, -5.0),
            (Kind::Rapid, 10.0, 10.0),
            (Kind::Rapid, 20.0, 10.0),
        ]
    );
}

#[test]
fn a_canned_cycle_with_l_in_g90_drills_the_same_hole_l_times() {
    let p = plan("O1\nG00 Z10.\nG90 G99 G81 X5. R2. Z-1. L2 F100.\nG80\nM30\n");
    let bottoms: Vec<(f64, f64, f64)> = p
        .iter()
        .filter(|c| c.kind == Kind::Linear)
        .map(xyz)
        .collect();
    assert_eq!(bottoms, vec![(5.0, 0.0, -1.0), (5.0, 0.0, -1.0)]);
}

#[test]
fn subprograms_after_m30_in_the_same_file_are_called() {
    let src = "O1000\nG90 G00 X0 Y0\nM98 P2001 L2\nM98 P2002\nM30\nO2001\nG91 G01 X1. F100.\nM99\nO2002 (second)\nG90 G00 Y7.\nM99\n";
    let p = plan(src);
    let got: Vec<(Option<String>, f64, f64)> = p
        .iter()
        .filter(|c| c.kind != Kind::Aux)
        .map(|c| (c.unit.clone(), end(c, 'X'), end(c, 'Y')))
        .collect();
    assert_eq!(
        got,
        vec![
            (None, 0.0, 0.0),
            (Some("O2001".into()), 1.0, 0.0),
            (Some("O2001".into()), 2.0, 0.0),
            (Some("O2002".into()), 2.0, 7.0),
        ]
    );
}

#[test]
fn a_program_number_defined_twice_in_a_file_warns() {
    let c = codes(&haas(), "O1\nM98 P5\nM30\nO5\nM99\nO5\nM99\n");
    assert_eq!(c, vec![2005]);
}

#[test]
fn the_fanuc_arc_feed_under_compensation_stays_the_programmed_feed() {
    // Radius 2 (G10 L12), G41 outside a circle of radius 10: the centre path has radius 12, but the
    // feed stays F100 (MEFI would write 100·12/10 = 120).
    let p = plan(
        "O1\nG10 L12 P1 R2.\nG00 X-20. Y10.\nG41 D1 G01 X0 Y10. F100.\nG02 X10. Y0 I0 J-10.\nG40 G01 X20. Y0\nM30\n",
    );
    let arc = p.iter().find(|c| c.kind == Kind::ArcCw).expect("arc");
    assert_eq!(arc.feed, Some(100.0));
    assert_eq!(centre(arc), vec![('X', 0.0), ('Y', 0.0)]);
    assert_eq!((end(arc, 'X'), end(arc, 'Y')), (12.0, 0.0));
}

#[test]
fn g28_without_axis_words_returns_every_axis_to_machine_zero() {
    let p = plan("O1\nG00 X10. Y20. Z30.\nG28\nM30\n");
    assert_eq!(p[1].kind, Kind::Rapid);
    assert_eq!(xyz(&p[1]), (0.0, 0.0, 0.0));
    assert_eq!(p.len(), 3);
}

#[test]
fn g28_with_axis_words_goes_through_the_intermediate_point() {
    let p = plan("O1\nG00 X10. Y20. Z30.\nG28 Z40.\nM30\n");
    assert_eq!(xyz(&p[1]), (10.0, 20.0, 40.0));
    assert_eq!(xyz(&p[2]), (10.0, 20.0, 0.0));
}

#[test]
fn coordinates_are_rounded_to_the_resolution_not_truncated() {
    let p = plan("O1\nG00 X1.2345 Y-1.2345 Z1.2344\nG20 X1.00005 Y0.00004\nM30\n");
    assert_eq!(xyz(&p[0]), (1.235, -1.235, 1.234));
    // inch: 1.0001 in = 25.40254 mm, 0.0000 in = 0.
    assert_eq!(p[1].end_of('X'), Some(1.0001 * 25.4));
    assert_eq!(p[1].end_of('Y'), Some(0.0));
}

#[test]
fn rotary_axes_stay_in_degrees_under_g20() {
    let m = MachineSpec::new(Dialect::Fanuc, &['X', 'Y', 'Z', 'A']);
    let p = run(&m, "O1\nG20 G00 X1. A90.\nM30\n", PlanOptions::default()).blocks;
    assert_eq!((end(&p[0], 'X'), end(&p[0], 'A')), (25.4, 90.0));
}

#[test]
fn a_repeat_count_beyond_32767_is_refused_not_run() {
    let (prog, _) = compile(
        &haas(),
        "t",
        "O1\nG00 Z10.\nG81 X1. Z-1. R2. L99999999 F100.\nM30\n",
    );
    let Err(err) = partprogram::plan(&prog.expect("compiles"), PlanOptions::default()) else {
        panic!("L99999999 is refused");
    };
    assert_eq!((err.1.code, err.1.line), (2502, 3));
}

#[test]
fn g04_x_is_a_dwell_in_seconds_not_a_move() {
    let p = plan("O1\nG00 X5.\nG04 X1.5\nG04 P250\nM30\n");
    assert_eq!(p[1].kind, Kind::Dwell);
    assert_eq!((end(&p[1], 'X'), p[1].dwell), (5.0, Some(1.5)));
    assert_eq!(p[2].dwell, Some(0.25));
}

#[test]
fn an_arc_with_both_r_and_centre_words_is_refused_at_the_centre_word() {
    // Fanuc would cut the R arc and drop I; a dropped word is refused (2530) at the word itself.
    let src = "O1\nG90 G00 X0 Y0\nG02 X10. Y0 R5. I5. F100.\nM30\n";
    let (prog, diags) = compile(&haas(), "test", src);
    assert!(diags.is_empty(), "{diags:#?}");
    let Err((_, d)) = partprogram::plan(&prog.expect("compiled"), PlanOptions::default()) else {
        panic!("planned an arc with R and I")
    };
    assert_eq!(d.code, 2530);
    assert_eq!(&src[d.span.clone()], "I5.");
    assert!(d.message.contains("given by its radius R"), "{}", d.message);
    // Either alone is an arc: R5 and I5 give the same half circle.
    for arc in ["G02 X10. Y0 R5. F100.", "G02 X10. Y0 I5. F100."] {
        let p = plan(&format!("O1\nG90 G00 X0 Y0\n{arc}\nM30\n"));
        assert_eq!(centre(&p[1]), vec![('X', 5.0), ('Y', 0.0)], "{arc}");
    }
}

#[test]
fn contradictory_m_codes_in_one_block_are_refused_at_the_second() {
    // M03 and M04 (spindle), M08 and M09 (coolant): 2007 at the second of the group.
    for (block, at) in [
        ("M03 M04", "M04"),
        ("M08 S100 M09", "M09"),
        ("M03 M08 M05", "M05"),
    ] {
        let src = format!("O1\nG90 G00 X0 Y0\n{block}\nM30\n");
        let (_, diags) = compile(&haas(), "test", &src);
        assert_eq!(diags.len(), 1, "{block}: {diags:#?}");
        assert_eq!(diags[0].code, 2007, "{block}");
        assert_eq!(&src[diags[0].span.clone()], at, "{block}");
    }
    // Codes of different groups stay one block: spindle, coolant and a stop.
    let p = plan("O1\nG90 G00 X0 Y0 M03 M08\nM05 M09 M30\n");
    assert_eq!(p[0].m.iter().map(|m| m.m).collect::<Vec<_>>(), vec![3, 8]);
}
