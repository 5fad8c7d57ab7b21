//! The servo loop in a process: velocity feed-forward in AUTO unless UEP = 1, none in a jog, and
//! the SRV limit each case is checked against. The fixture's X moves 1 mm per 10 ms tick
//! (100 mm/s); here with KV 20 and SRV 0.5 / 1 / 2 mm. Without feed-forward the error after n
//! ticks of motion from rest is e = (v/KV)·(1 − qⁿ) = 5·(1 − e^(−0.2·n)) mm: 0.906, 1.648, 2.256
//! (beyond 2 mm at the third tick); with Kvff = 1 it stays 0, with Kvff 0.9 it is a tenth of it.

use detmath::Det as _;
use partprogram::canon::Kind::{Aux, Linear};

use super::fixture::{Bench, Plc, axis_x, block, cnc_with_axis};
use crate::following::{Limit, SrvLimits};
use crate::{Command, Mode};

fn bench(kvff: f64) -> Bench {
    let axis = crate::config::AxisConfig {
        kv: 20.0,
        kvff,
        srv: SrvLimits {
            standby: 0.5,
            vff: 1.0,
            no_vff: 2.0,
        },
        ..axis_x()
    };
    Bench::new(cnc_with_axis(false, 0, 0, None, axis))
}

/// N10 G01 X3, N20 M30 in AUTO, started; runs 40 ticks.
fn auto_run(b: &mut Bench) {
    b.start_program(vec![
        block(10, Linear, 3.0, &[], None, None),
        block(20, Aux, 3.0, &[30], None, None),
    ]);
    b.run(1, &Plc::default());
    b.step(&Plc {
        start: 1,
        ..Plc::default()
    });
    b.run(40, &Plc::default());
}

fn alarms(b: &Bench) -> Vec<String> {
    b.cnc.processes()[0]
        .alarms()
        .iter()
        .map(|a| a.message.clone())
        .collect()
}

fn peak(b: &Bench) -> crate::following::Peak {
    b.cnc.processes()[0].following_peaks()[0]
        .1
        .expect("checked")
}

#[test]
fn auto_with_feed_forward_has_no_lag_and_checks_the_vff_limit() {
    let mut b = bench(1.0);
    auto_run(&mut b);
    assert_eq!(alarms(&b), Vec::<String>::new());
    let p = peak(&b);
    assert!(p.error < 1e-12, "{p:?}");
    assert_eq!(b.cnc.processes()[0].set_points(), [3.0]);
    // Kvff 0.9: e = 0.5·(1 − qⁿ), largest at the third tick of motion, checked against VFF.
    let mut b = bench(0.9);
    auto_run(&mut b);
    let p = peak(&b);
    assert!(
        (p.error - 0.5 * (1.0 - (-0.6f64).dexp())).abs() < 1e-9,
        "{p:?}"
    );
    assert_eq!((p.limit, p.allowed), (Limit::Vff, 1.0));
    assert_eq!(alarms(&b), Vec::<String>::new());
}

#[test]
fn auto_with_uep_1_checks_the_no_vff_limit() {
    let mut b = bench(1.0);
    b.cnc.process_mut(1).expect("p1").set_uep(true);
    auto_run(&mut b);
    assert_eq!(
        alarms(&b),
        [
            "process 1: following error of axis X: 2.256 mm exceeds SRV no-VFF limit 2 mm (moving without feed-forward)"
        ]
    );
    let p = peak(&b);
    assert!(
        (p.error - 5.0 * (1.0 - (-0.6f64).dexp())).abs() < 1e-9,
        "{p:?}"
    );
}

#[test]
fn a_jog_has_no_feed_forward_and_alarms_beyond_the_no_vff_limit() {
    let mut b = bench(1.0);
    b.cnc
        .process_mut(1)
        .expect("p1")
        .command(Command::SetMode(Mode::Manu));
    b.run(2, &Plc::default());
    let plus = Plc {
        jog: (1, 0),
        ..Plc::default()
    };
    b.run(6, &plus);
    assert_eq!(
        alarms(&b),
        [
            "process 1: following error of axis X: 2.256 mm exceeds SRV no-VFF limit 2 mm (moving without feed-forward)"
        ]
    );
    assert!(!b.cnc.processes()[0].status().on);
}

#[test]
fn at_rest_the_stand_by_limit_applies_after_five_time_constants() {
    // Kvff 0.9 leaves 0.2256 mm at the stop, decaying by q = e^(−0.2) per tick; 5/KV = 25 ticks
    // later the axis is at rest: stand-by limit, error 0.2256·e^(−5).
    let mut b = bench(0.9);
    auto_run(&mut b);
    let st = b.cnc.processes()[0].status();
    assert_eq!(
        (st.axes[0].limit, st.axes[0].limit_mm),
        (Limit::Standby, 0.5)
    );
    assert!((st.axes[0].largest - 0.5 * (1.0 - (-0.6f64).dexp())).abs() < 1e-9);
}
