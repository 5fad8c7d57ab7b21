//! ZONE2 and CUB on the fixture's X (LO1 −5 … 3 mm, LO2 −8 … 6 mm; 1 mm per tick).

use partprogram::canon::Kind::Linear;

use super::fixture::{Bench, Plc, block, cnc};
use crate::{Command, Mode};

fn x(b: &Bench) -> f64 {
    b.cnc.processes()[0].set_points()[0]
}

/// Runs `N10 G01 X<to>` with the PLC's ZONE2 and CUB levels.
fn run_to(to: f64, zone2: u8, cub: u8) -> Bench {
    let mut b = Bench::new(cnc(false, 0, 0));
    b.cnc.process_mut(1).expect("p1").cfg.axes[0].cub = Some((1.0, 2.0, 0.25));
    b.start_program(vec![block(10, Linear, to, &[], None, None)]);
    let plc = Plc {
        zone2,
        cub,
        ..Plc::default()
    };
    b.run(1, &plc);
    b.step(&Plc { start: 1, ..plc });
    b.run(12, &plc);
    b
}

#[test]
fn a_block_beyond_lo1_is_refused_before_motion() {
    let b = run_to(4.0, 0, 0);
    assert_eq!(x(&b), 0.0);
    let a = &b.cnc.processes()[0].alarms()[0];
    assert_eq!(
        a.message,
        "process 1: block 1 (N10) refused: axis X would reach 4.0000 mm, beyond the LO1 limit 3.0000 mm"
    );
    assert!(a.stopping);
}

#[test]
fn zone2_selects_lo2_which_allows_it() {
    let b = run_to(4.0, 1, 0);
    assert_eq!(x(&b), 4.0);
    assert!(b.cnc.processes()[0].alarms().is_empty());
    let b = run_to(-7.0, 1, 0);
    assert_eq!(x(&b), -7.0);
    let b = run_to(7.0, 1, 0);
    assert_eq!(
        b.cnc.processes()[0].alarms()[0].message,
        "process 1: block 1 (N10) refused: axis X would reach 7.0000 mm, beyond the LO2 limit 6.0000 mm"
    );
}

#[test]
fn cub_refuses_a_path_through_the_box_only_while_on() {
    // The box on X is (1 + 0.25, 2 − 0.25): the line 0 → 3 enters it at X 1.25.
    let b = run_to(3.0, 0, 1);
    assert_eq!(x(&b), 0.0);
    assert_eq!(
        b.cnc.processes()[0].alarms()[0].message,
        "process 1: block 1 (N10) refused: the path enters the CUB protected box (X 1.25..1.75) at X 1.25"
    );
    // Up to the space: X 1.25 is allowed.
    let b = run_to(1.25, 0, 1);
    assert_eq!(x(&b), 1.25);
    let b = run_to(3.0, 0, 0);
    assert_eq!(x(&b), 3.0);
}

#[test]
fn a_jog_stops_at_the_active_zone_and_at_the_box() {
    let mut b = Bench::new(cnc(false, 0, 0));
    let p = b.cnc.process_mut(1).expect("p1");
    p.cfg.axes[0].cub = Some((1.0, 2.0, 0.25));
    p.command(Command::SetMode(Mode::Manu));
    b.run(2, &Plc::default());
    let jog = |cub, zone2| Plc {
        jog: (1, 0),
        cub,
        zone2,
        ..Plc::default()
    };
    b.run(8, &jog(1, 0));
    assert_eq!(x(&b), 1.25); // the box's face
    b.run(2, &Plc::default());
    b.run(10, &jog(0, 1));
    assert_eq!(x(&b), 6.0); // LO2's + limit
}
