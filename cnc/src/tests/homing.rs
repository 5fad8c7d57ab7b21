//! The MCZ homing cycle on the fixture's X (1 mm per tick): switch edge at 7.5 on the machine's
//! scale, + search, reference marks every 5 mm.

use super::fixture::{Bench, Plc, cnc, sig};
use crate::config::HomeConfig;
use crate::state::Interp;
use crate::{Command, Mode};

fn homing_bench(start: f64) -> Bench {
    let mut c = cnc(false, 0, 0);
    let p = c.process_mut(1).expect("p1");
    let mut cfg = p.cfg.clone();
    cfg.axes[0].needs_homing = true;
    cfg.axes[0].home = Some(HomeConfig {
        input: Some(sig("I0A8")),
        negative: false,
        speed: 200.0,
        mark_pitch: 5.0,
    });
    p.homed = false;
    p.homed_axes = vec![false];
    p.cfg = cfg;
    p.place_axis(0, start, Some(7.5));
    p.command(Command::SetMode(Mode::Home));
    let mut b = Bench::new(c);
    b.run(1, &Plc::default());
    b.step(&Plc {
        start: 1,
        ..Plc::default()
    });
    b
}

fn watch(b: &mut Bench, n: usize) -> Vec<(f64, u8)> {
    (0..n)
        .map(|_| {
            b.step(&Plc::default());
            (
                b.cnc.processes()[0].set_points()[0],
                sig("I0A8").read(&b.image),
            )
        })
        .collect()
}

#[test]
fn homing_finds_the_switch_leaves_it_and_stops_on_the_mark() {
    let mut b = homing_bench(2.0);
    assert_eq!(b.cnc.process_mut(1).expect("p1").state().mode, Mode::Home);
    let seen = watch(&mut b, 13);
    assert_eq!(
        seen,
        vec![
            (0.0, 1), // t2 START: stage 1 towards +
            (1.0, 1),
            (2.0, 1),
            (3.0, 1),
            (4.0, 1),
            (5.0, 1),
            (6.0, 0), // t8 machine 8 ≥ 7.5: switch pressed, stop
            (6.0, 0), // t9 reverse
            (5.0, 1), // t10 machine 7: left the switch; next mark at 5
            (4.0, 1),
            (3.0, 1), // t12 machine 5: the mark
            (0.0, 1), // t13 the mark is coordinate 0
            (0.0, 1), // t14 every axis homed
        ]
    );
    let p = &b.cnc.processes()[0];
    assert!(p.state().homed);
    assert_eq!(p.state().interp, Interp::Idle);
    assert_eq!(p.drives[0].machine_position(), 5.0);
}

#[test]
fn homing_with_the_switch_already_pressed_skips_stage_one() {
    let mut b = homing_bench(9.0);
    let seen = watch(&mut b, 7);
    assert_eq!(
        seen,
        vec![
            (0.0, 0),  // t2 pressed at start: reverse at once
            (-1.0, 0), // machine 8
            (-2.0, 1), // machine 7: left; mark at 5
            (-3.0, 1),
            (-4.0, 1), // machine 5: the mark
            (0.0, 1),
            (0.0, 1),
        ]
    );
    assert!(b.cnc.processes()[0].state().homed);
}

#[test]
fn auto_is_refused_until_homed() {
    let mut b = homing_bench(2.0);
    let p = b.cnc.process_mut(1).expect("p1");
    assert_eq!(
        crate::state::decide(&p.state(), Command::SetMode(Mode::Auto)),
        Err(crate::Reject::NotHomed)
    );
    b.run(14, &Plc::default());
    let p = b.cnc.process_mut(1).expect("p1");
    assert_eq!(
        crate::state::decide(&p.state(), Command::SetMode(Mode::Auto)),
        Ok(())
    );
}

/// The same cycle on a bus drive: the switch is the drive's `60FDh` bit 2 and the mark is what
/// the drive's touch probe latched. The test's drive answers each step with the previous step's
/// set point (its position 0 stands at machine 2); its switch is pressed from machine 7.5 up;
/// armed, its probe stores the exact drive position of the first mark (every 5 mm of the
/// machine; none when not `marks`) its move crosses. Per step: (set point sent, probe armed,
/// actual X).
fn home_on_a_drive(steps: usize, marks: bool) -> (Bench, Vec<(f64, bool, f64)>) {
    let mut c = cnc(false, 0, 0);
    let p = c.process_mut(1).expect("p1");
    p.attach_bus(&['X'], false).expect("X");
    let mut cfg = p.cfg.clone();
    cfg.axes[0].needs_homing = true;
    cfg.axes[0].home = Some(HomeConfig {
        input: Some(sig("I0A8")),
        negative: false,
        speed: 200.0,
        mark_pitch: 5.0,
    });
    p.homed = false;
    p.homed_axes = vec![false];
    p.cfg = cfg;
    p.command(Command::SetMode(Mode::Home));
    let mut b = Bench::new(c);
    let (start, edge, pitch) = (2.0, 7.5, 5.0);
    let (mut drive, mut latched): (f64, Option<f64>) = (0.0, None);
    let mut seen = Vec::new();
    for t in 0..steps {
        let p = b.cnc.process_mut(1).expect("p1");
        assert!(p.bus_feedback('X', &[Some(drive)], 1));
        assert!(p.bus_home('X', start + drive >= edge, latched));
        b.step(&Plc {
            start: u8::from(t == 1),
            ..Plc::default()
        });
        let p = &b.cnc.processes()[0];
        let sent = p.bus_set_points('X').expect("on the bus")[0];
        // The drive moves to `sent` with the probe as ordered for these SYNCs.
        let armed = p.bus_probe('X');
        if !armed {
            latched = None;
        } else if latched.is_none() && marks {
            let (from, to) = (start + drive, start + sent);
            let mark = ((from / pitch).ceil() - 1.0) * pitch;
            if to < from && mark >= to && mark < from {
                latched = Some(mark - start);
            }
        }
        drive = sent;
        let x = p.actual_positions().next().expect("X").1;
        seen.push((sent, armed, x));
    }
    (b, seen)
}

#[test]
fn homing_on_a_drive_takes_the_switch_from_its_inputs_and_the_mark_from_its_probe() {
    let (b, seen) = home_on_a_drive(20, true);
    assert_eq!(
        seen,
        vec![
            (0.0, false, 0.0), // t0
            (0.0, false, 0.0), // t1 START
            (0.0, false, 0.0),
            (1.0, false, 0.0), // t3 stage 1 towards +
            (2.0, false, 1.0),
            (3.0, false, 2.0),
            (4.0, false, 3.0),
            (5.0, false, 4.0),
            (6.0, false, 5.0), // t8 drive 6 = machine 8 ≥ 7.5
            (7.0, false, 6.0), // t9 the answer says pressed: stop
            (7.0, false, 7.0),
            (6.0, false, 7.0),  // t11 back
            (5.0, false, 6.0),  // t12 the answer 6 = machine 8: still pressed
            (4.0, true, 5.0),   // t13 the answer 5 = machine 7: left; the probe is armed
            (3.0, true, 4.0),   // t14 drive 4 → 3 crosses machine 5: latched drive 3
            (2.0, false, 3.0),  // t15 the latch arrives: stop, disarm
            (2.0, false, -1.0), // t16 at rest: drive 3 is coordinate 0, drive 2 is −1
            (2.0, false, -1.0),
            (2.0, false, -1.0),
            (2.0, false, -1.0),
        ]
    );
    let p = &b.cnc.processes()[0];
    assert!(p.state().homed);
    assert_eq!(p.state().interp, Interp::Idle);
}

#[test]
fn a_drive_that_latches_no_mark_ends_homing_with_an_alarm() {
    // The search for the mark is the rest of the 1000 mm move back: then the alarm.
    let (b, seen) = home_on_a_drive(1030, false);
    let p = &b.cnc.processes()[0];
    assert!(!p.state().homed);
    assert_eq!(
        p.alarms()[0].message,
        "process 1: homing of axis X: the drive latched no reference mark (touch probe 60B9h) within the search move"
    );
    assert!(!seen.last().expect("steps").1, "disarmed");
}
