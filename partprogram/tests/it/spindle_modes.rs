//! Constant surface speed in both dialects: MEFI KŘR G96 (S in tenths of m/min, G94/G95 cancel) and
//! Fanuc G96/G97 with the G50 S top speed, carried in the canonical blocks' `css`.

use crate::common;

use common::*;
use partprogram::{Dialect, MachineSpec, PlanOptions, compile, plan};

fn fanuc_lathe() -> MachineSpec {
    let mut m = MachineSpec::new(Dialect::Fanuc, &['X', 'Z']);
    m.diameter_x = true;
    m
}

#[test]
fn mefi_g96_carries_the_cutting_speed_and_the_program_zero_until_g94() {
    let p = run(
        &lathe(),
        "%1\nN1 G55 G92 X100 Z-50\nN2 G55 G96 S900 G1 X40 Z0 F200\nN3 Z-10\nN4 G94 S800 X60\nN5 M30\n",
        PlanOptions::default(),
    );
    let by_n = |n: u32| p.blocks.iter().find(|c| c.n == Some(n)).expect("block");
    let css = by_n(2).css.clone().expect("G96 active in N2");
    // S900 under KŘR is 90.0 m/min (000:1239); the zero of G55 is X100 Z-50 in the machine frame.
    assert_eq!(css.m_min, 90.0);
    assert_eq!(css.max_rpm, None);
    assert_eq!(css.origin, vec![('X', 100.0), ('Z', -50.0)]);
    assert!(css.diameter);
    assert_eq!(by_n(2).s, Some(900.0));
    assert_eq!(by_n(3).css.as_ref().map(|c| c.m_min), Some(90.0));
    assert_eq!(by_n(4).css, None);
    assert_eq!(by_n(4).s, Some(800.0));
    // X40 is a diameter: radius 20 mm, 90 000 mm/min / (2π·20 mm) = 716.197 rev/min.
    let rpm = css.rpm_at('X', 140.0);
    assert_eq!((rpm * 1000.0).round(), 716_197.0);
    assert_eq!(css.rpm_at('X', 100.0), f64::INFINITY);
}

#[test]
fn mefi_g97_feed_moves_are_refused_with_a_located_error() {
    let (prog, d) = compile(&lathe(), "test", "%1\nN1 G97 S900 G1 X40 F200\nN2 M30\n");
    let prog = prog.unwrap_or_else(|| panic!("{d:?}"));
    let Err((_, e)) = plan(&prog, PlanOptions::default()) else {
        panic!("G97 feed move planned")
    };
    assert_eq!(e.code, 2507);
    assert_eq!(e.line, 2);
    assert!(e.message.contains("G97"), "{}", e.message);
}

#[test]
fn fanuc_g96_in_m_min_with_g50_top_speed_and_g97_back_to_rpm() {
    let p = run(
        &fanuc_lathe(),
        "O0001\nG21 G50 S2500\nG96 S180 M03\nG00 X50. Z2.\nG01 X20. F300.\nG20 G96 S600\nG97 S1000\nM30\n",
        PlanOptions::default(),
    );
    let b = &p.blocks;
    // G50 S sets the top speed only: no spindle speed yet.
    assert_eq!(b[0].s, None);
    assert_eq!(b[0].css, None);
    let css = b[1].css.clone().expect("G96");
    assert_eq!((css.m_min, css.max_rpm), (180.0, Some(2500.0)));
    assert_eq!(css.origin, vec![('X', 0.0), ('Z', 0.0)]);
    assert_eq!(b[3].css.as_ref().map(|c| c.m_min), Some(180.0));
    // 600 ft/min = 182.88 m/min.
    assert_eq!(b[4].css.as_ref().map(|c| um(c.m_min)), Some(182.88));
    assert_eq!(b[5].css, None);
    assert_eq!(b[5].s, Some(1000.0));
}
