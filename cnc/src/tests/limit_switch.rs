//! Hardware limit switches (MFC): the simulated switch presses the input (normally closed: 0 on
//! the switch), moving further onto it stops the process with an alarm once, and after RESET the
//! axis may leave the switch but not run onto it again.

use partprogram::canon::Kind::Linear;

use super::fixture::{Bench, Plc, block, cnc, sig};
use crate::state::Interp;

const ALARM: &str = "process 1: axis X ran onto its + hardware limit switch (MFC I3A0)";

/// Axis X wired to MFC I3A0 (+) and I3A1 (−), the + switch pressed from X3.5 on (the machine
/// scale is the controller's here), no soft limits.
fn bench() -> Bench {
    let mut b = Bench::new(cnc(false, 0, 0));
    let p = b.cnc.process_mut(1).expect("p1");
    p.cfg.axes[0].soft = (None, None);
    p.cfg.axes[0].limit_inputs = (Some(sig("I3A0")), Some(sig("I3A1")));
    p.place_limit_switches(0, Some(3.5), None);
    b
}

/// Loads `x` as one G01 block and presses START (the test interpolator moves 1 mm per tick).
fn go(b: &mut Bench, x: f64) {
    b.start_program(vec![block(10, Linear, x, &[], None, None)]);
    b.run(1, &Plc::default());
    b.step(&Plc {
        start: 1,
        ..Plc::default()
    });
}

#[test]
fn running_onto_the_switch_stops_with_an_alarm_and_reset_lets_the_axis_leave() {
    let mut b = bench();
    b.step(&Plc::default());
    assert_eq!(
        sig("I3A0").read(&b.image),
        1,
        "released: the NC contact conducts"
    );
    assert_eq!(
        sig("I3A1").read(&b.image),
        0,
        "no − switch simulated: never written"
    );
    go(&mut b, 10.0);
    let mut xs = Vec::new();
    for _ in 0..8 {
        b.step(&Plc::default());
        xs.push(b.cnc.processes()[0].set_points()[0]);
    }
    // X 1, 2, 3, 4: at 4 the switch is pressed while X still rises: stop there, at once with
    // this interpolator, and stay.
    assert_eq!(xs, [1.0, 2.0, 3.0, 4.0, 4.0, 4.0, 4.0, 4.0]);
    let p = &b.cnc.processes()[0];
    let alarms: Vec<&str> = p.alarms().iter().map(|a| a.message.as_str()).collect();
    assert_eq!(alarms, [ALARM]);
    assert_eq!(p.state().interp, Interp::Idle);
    assert_eq!(sig("I3A0").read(&b.image), 0, "on the switch");
    // RESET (ERS edge), then a block away from the switch: no alarm; the contact closes again
    // once X is below 3.5.
    b.step(&Plc {
        ers: 1,
        ..Plc::default()
    });
    b.step(&Plc::default());
    assert!(b.cnc.processes()[0].alarms().is_empty());
    go(&mut b, 0.0);
    b.run(6, &Plc::default());
    let p = &b.cnc.processes()[0];
    assert_eq!(p.set_points(), &[0.0]);
    assert!(p.alarms().is_empty(), "{:?}", p.alarms());
    assert_eq!(sig("I3A0").read(&b.image), 1);
    // Onto it again: the same alarm, the same stop.
    go(&mut b, 10.0);
    b.run(8, &Plc::default());
    let p = &b.cnc.processes()[0];
    assert_eq!(p.set_points(), &[4.0]);
    assert_eq!(p.alarms().len(), 1);
    assert_eq!(p.alarms()[0].message, ALARM);
}
