//! Handwheel channel 1 on the fixture's X (LO1 −5 … 3 mm, LO2 −8 … 6 mm; MAN 1000 mm/min,
//! 1000 mm/s²): the counter is the packet-A byte W2A0.

use partprogram::canon::Kind::Linear;

use super::fixture::{Bench, Plc, block, cnc};
use crate::{Command, Mode};

fn x(b: &Bench) -> f64 {
    b.cnc.processes()[0].set_points()[0]
}

fn manual() -> Bench {
    let mut b = Bench::new(cnc(false, 0, 0));
    b.cnc
        .process_mut(1)
        .expect("p1")
        .command(Command::SetMode(Mode::Manu));
    b.run(2, &Plc::default());
    b
}

/// COMU = 1, HW_ON1 = 1, HW_AXIS1 = 1 (X), HW_SCALE low nibble `scale`, counter `wheel`.
fn wheel(scale: u8, wheel: u8) -> Plc {
    Plc {
        comu: 1,
        hw: (1, 1, scale),
        wheel,
        ..Plc::default()
    }
}

#[test]
fn pulses_times_the_step_is_the_distance_and_the_limit_stops_it() {
    let mut b = manual();
    b.run(2, &wheel(1, 0)); // the PLC enables channel 1 at 10 µm per pulse
    b.step(&wheel(1, 120)); // +120 pulses
    b.step(&wheel(1, 220)); // +100 pulses
    b.run(40, &wheel(1, 220));
    // 220 pulses × 10 µm = 2.2 mm, exactly.
    assert_eq!(x(&b), 2.2);
    assert!(b.cnc.processes()[0].state().moving.eq(&false));

    // COMU = 0: 30 pulses turned meanwhile are dropped, also when COMU returns.
    let off = Plc {
        comu: 0,
        ..wheel(1, 220)
    };
    b.step(&off);
    b.run(3, &Plc { wheel: 250, ..off });
    b.run(10, &wheel(1, 250));
    assert_eq!(x(&b), 2.2);

    // 100 µm per pulse: +20 pulses (250 → 14 wraps) = 2 mm, clipped at LO1's 3 mm.
    b.step(&wheel(2, 250));
    b.run(40, &wheel(2, 14));
    assert_eq!(x(&b), 3.0);

    // ZONE2 = 1 selects LO2 (up to 6 mm): +10 pulses count on from the limit: 4 mm.
    let zone2 = |w| Plc {
        zone2: 1,
        ..wheel(2, w)
    };
    b.step(&zone2(14));
    b.run(40, &zone2(24));
    assert_eq!(x(&b), 4.0);
    assert!(b.cnc.processes()[0].alarms().is_empty());
}

#[test]
fn feed_hold_stops_a_handwheel_move_and_drops_the_rest() {
    let mut b = manual();
    // FOLD = 1: 20 pulses turned are dropped (X stays 0, also after FOLD returns to 0).
    let held = |w| Plc {
        fold: 1,
        ..wheel(2, w)
    };
    b.run(2, &held(236));
    b.run(5, &held(0));
    b.run(20, &wheel(2, 0));
    assert_eq!(x(&b), 0.0);
    // FOLD during a move: the move stops on the way and the rest is dropped.
    b.step(&wheel(2, 20)); // +20 × 100 µm = 2 mm
    b.step(&wheel(2, 20));
    let hold = Plc {
        fold: 1,
        ..wheel(2, 20)
    };
    b.run(40, &hold);
    let stopped = x(&b);
    // Stopped on the way: 0 < X < 2, at rest.
    assert!(stopped > 0.0 && stopped < 2.0, "X = {stopped}");
    b.run(20, &wheel(2, 20));
    assert_eq!(x(&b), stopped);
}

#[test]
fn a_bad_scale_code_raises_an_alarm_and_does_not_move() {
    let mut b = manual();
    b.run(2, &wheel(3, 0));
    b.run(10, &wheel(3, 50));
    assert_eq!(x(&b), 0.0);
    let a = b.cnc.processes()[0].alarms();
    assert_eq!(
        a[0].message,
        "process 1: handwheel channel 1: scale code 3 in HW_SCALE is not 0, 1 or 2"
    );
    assert!(!a[0].stopping);
}

#[test]
fn pulses_turned_while_a_program_runs_are_dropped() {
    let mut b = manual();
    let p = b.cnc.process_mut(1).expect("p1");
    p.load("test", vec![block(10, Linear, -3.0, &[], None, None)])
        .expect("idle");
    p.command(Command::SetMode(Mode::Auto));
    b.run(1, &wheel(1, 0));
    b.step(&Plc {
        start: 1,
        ..wheel(1, 0)
    });
    // +100 pulses × 10 µm while N10 moves X to −3 (1 mm per tick), then the program ends.
    b.run(10, &wheel(1, 100));
    assert_eq!(b.cnc.processes()[0].state().interp, crate::Interp::Idle);
    assert_eq!(x(&b), -3.0);
    b.run(10, &wheel(1, 100));
    assert_eq!(x(&b), -3.0);
}

#[test]
fn an_axis_outside_pgcfil_mas_is_refused_with_an_alarm() {
    let mut b = manual();
    b.cnc
        .process_mut(1)
        .expect("p1")
        .set_manual_axes(Some(vec!['Z']));
    b.run(2, &wheel(1, 0));
    b.run(10, &wheel(1, 50));
    assert_eq!(x(&b), 0.0);
    assert_eq!(
        b.cnc.processes()[0].alarms()[0].message,
        "process 1: handwheel channel 1: axis X is not in PGCFIL MAS (the axes of manual moves)"
    );
}
