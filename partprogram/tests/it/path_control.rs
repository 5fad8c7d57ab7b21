//! Exact stop and blending tolerance in the canonical blocks: Fanuc G09/G61/G64 P, MEFI G98/G24/G23.

use crate::common;

use common::*;
use partprogram::{Dialect, MachineSpec, PlanOptions};

fn haas() -> MachineSpec {
    MachineSpec::new(Dialect::Fanuc, &['X', 'Y', 'Z'])
}

fn flags(src: &str, m: &MachineSpec) -> Vec<(f64, bool, Option<f64>)> {
    run(m, src, PlanOptions::default())
        .blocks
        .iter()
        .map(|c| (end(c, 'X'), c.exact_stop, c.tolerance))
        .collect()
}

#[test]
fn fanuc_g09_stops_one_block_g61_stops_until_g64_and_g64_p_sets_the_tolerance() {
    let src = "O1\nG21 G90 G01 X1. F100\nG09 X2.\nX3.\nG61 X4.\nX5.\nG64 P0.02 X6.\nX7.\nG64 X8.\nG20 G64 P0.001 X0.5\nM30\n";
    assert_eq!(
        flags(src, &haas()),
        vec![
            (1.0, false, None),
            (2.0, true, None),
            (3.0, false, None),
            (4.0, true, None),
            (5.0, true, None),
            (6.0, false, Some(0.02)),
            (7.0, false, Some(0.02)),
            (8.0, false, None),
            // inch: 0.001 in = 0.0254 mm, X0.5 in = 12.7 mm
            (12.7, false, Some(0.0254)),
            (12.7, false, Some(0.0254)),
        ]
    );
}

#[test]
fn the_json_line_carries_exact_stop_and_tolerance_only_when_set() {
    let p = run(
        &haas(),
        "O1\nG01 X1. F100\nG09 X2.\nG64 P0.01 X3.\nM30\n",
        PlanOptions::default(),
    );
    let lines: Vec<String> = p.blocks.iter().map(|c| c.to_json_line()).collect();
    assert!(!lines[0].contains("exact_stop") && !lines[0].contains("tolerance"));
    // The modal record is always the last field.
    let modal = r#","modal":["G90","G94","G54","G40","G49"]}"#;
    assert!(
        lines[1].ends_with(&format!(",\"exact_stop\":true{modal}")),
        "{}",
        lines[1]
    );
    assert!(
        lines[2].ends_with(&format!(",\"tolerance\":0.01{modal}")),
        "{}",
        lines[2]
    );
}

#[test]
fn mefi_g98_and_g24_ramp_to_a_stop_and_g23_connects_smoothly() {
    let src = "%1\nN1 G90 G01 X1000 F100\nN2 G23 X2000\nN3 X3000\nN4 G24 X4000\nN5 G23 X5000\nN6 G98 X6000\nN7 M30\n";
    let got: Vec<(f64, bool)> = flags(src, &mill())
        .into_iter()
        .map(|(x, e, t)| {
            assert_eq!(t, None);
            (x, e)
        })
        .collect();
    assert_eq!(
        got,
        vec![
            (1000.0, true),
            (2000.0, false),
            (3000.0, false),
            (4000.0, true),
            (5000.0, false),
            (6000.0, true),
            (6000.0, true),
        ]
    );
}

fn contour(src: &str, m: &MachineSpec) -> Vec<(f64, bool)> {
    run(m, src, PlanOptions::default())
        .blocks
        .iter()
        .map(|c| (end(c, 'X'), c.modal.contour))
        .collect()
}

#[test]
fn fanuc_g05_1_q1_and_g08_p1_switch_contour_control_on_until_q0_or_p0() {
    let src = "O1\nG21 G90 G01 X1. F100\nG05.1 Q1\nX2.\nX3.\nG05.1 Q0\nX4.\nG08 P1\nX5.\nG08 P0 X6.\nM30\n";
    assert_eq!(
        contour(src, &haas()),
        vec![
            (1.0, false),
            (2.0, true),
            (3.0, true),
            (4.0, false),
            (5.0, true),
            (6.0, false),
            (6.0, false),
        ]
    );
}

#[test]
fn mefi_g23_is_contour_control_and_g24_g98_end_it() {
    let src = "%1\nN1 G90 G01 X1000 F100\nN2 G23 X2000\nN3 X3000\nN4 G24 X4000\nN5 G23 X5000\nN6 G98 X6000\nN7 M30\n";
    let got: Vec<bool> = contour(src, &mill()).into_iter().map(|(_, c)| c).collect();
    assert_eq!(got, vec![false, true, true, false, true, false, false]);
}

#[test]
fn a_g05_1_or_g08_with_another_q_or_p_is_a_located_error() {
    for (src, want) in [
        (
            "O1\nG01 X1. F100\nG05.1 Q2\nM30\n",
            "G05.1 takes Q1 (contour control on) or Q0 (off), found Q 2",
        ),
        (
            "O1\nG01 X1. F100\nG05.1\nM30\n",
            "G05.1 takes Q1 (contour control on) or Q0 (off), found Q none",
        ),
        (
            "O1\nG01 X1. F100\nG08 P3\nM30\n",
            "G08 takes P1 (contour control on) or P0 (off), found P 3",
        ),
    ] {
        let (prog, diags) = partprogram::compile(&haas(), "test", src);
        assert!(diags.is_empty(), "{diags:#?}");
        let prog = prog.expect("compiles");
        let Err((_, d)) = partprogram::plan(&prog, PlanOptions::default()) else {
            panic!("{src}: planned")
        };
        assert_eq!(d.code, 2507, "{src}");
        assert_eq!(d.line, 3, "{src}");
        assert_eq!(d.message, want);
    }
}
