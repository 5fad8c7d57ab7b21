//! Axes on bus drives (`crate::bus`): the set points go out, the actual positions come from the
//! drive's answers, each answer checked against the set point it answers. The fixture's X moves
//! 1 mm per 10 ms tick (one interpolation tick per logic tick) with SRV 0.5 / 1 / 2 mm; the drive
//! here is an ideal follower answering `lag` ticks after the set point.

use partprogram::canon::Kind::{Aux, Linear};

use super::fixture::{Bench, Plc, axis_x, block, cnc_with_axis};
use crate::following::{Limit, SrvLimits};

fn bench() -> Bench {
    let axis = crate::config::AxisConfig {
        kv: 20.0,
        srv: SrvLimits {
            standby: 0.5,
            vff: 1.0,
            no_vff: 2.0,
        },
        ..axis_x()
    };
    let mut b = Bench::new(cnc_with_axis(false, 0, 0, None, axis));
    b.cnc
        .process_mut(1)
        .expect("p1")
        .attach_bus(&['X'], false)
        .expect("X is an axis");
    b
}

/// N10 G01 X3, N20 M30 in AUTO, started, for 12 ticks; the drive answers each step with the set
/// point of `lag` steps before (`None`: it never answers healthily), the answers said to be
/// `age` steps old. Returns the actual position of X after each step.
fn run(lag: usize, age: usize, answer: bool) -> (Bench, Vec<f64>) {
    let mut b = bench();
    b.start_program(vec![
        block(10, Linear, 3.0, &[], None, None),
        block(20, Aux, 3.0, &[30], None, None),
    ]);
    let mut sent: Vec<f64> = Vec::new();
    let mut actual = Vec::new();
    for t in 0..14 {
        let plc = Plc {
            start: u8::from(t == 1),
            ..Plc::default()
        };
        let value = sent.len().checked_sub(lag).map(|i| sent[i]);
        let p = b.cnc.process_mut(1).expect("p1");
        assert!(p.bus_feedback('X', &[value.filter(|_| answer)], age));
        b.step(&plc);
        let p = &b.cnc.processes()[0];
        sent.extend_from_slice(p.bus_set_points('X').expect("on the bus"));
        actual.push(p.actual_positions().next().expect("X").1);
    }
    (b, actual)
}

#[test]
fn the_actual_position_is_the_drives_answer_checked_against_the_set_point_it_answers() {
    let (b, actual) = run(1, 1, true);
    // The set points of steps 0.. are 0, 0, 1, 2, 3, 3, … (START in step 1, X moves from step 2);
    // the drive's answer to each is the actual position one step later.
    assert_eq!(
        actual,
        [
            0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 3.0, 3.0, 3.0, 3.0, 3.0, 3.0, 3.0, 3.0
        ]
    );
    let p = b.cnc.processes()[0].following_peaks()[0]
        .1
        .expect("checked");
    assert_eq!(p.error, 0.0);
    assert!(b.cnc.processes()[0].alarms().is_empty());
    assert!(b.cnc.processes()[0].bus_command().enable);
}

#[test]
fn a_late_answer_is_paired_by_its_age() {
    // Two steps late and said so: no error.
    let (b, actual) = run(2, 2, true);
    assert_eq!(&actual[..7], [0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 3.0]);
    let p = b.cnc.processes()[0].following_peaks()[0]
        .1
        .expect("checked");
    assert_eq!(p.error, 0.0);
    // Two steps late but taken as the previous step's: 1 mm apart while X moves 1 mm per tick.
    let (b, _) = run(2, 1, true);
    let p = b.cnc.processes()[0].following_peaks()[0]
        .1
        .expect("checked");
    assert_eq!((p.error, p.limit, p.allowed), (1.0, Limit::Vff, 1.0));
}

#[test]
fn without_a_healthy_answer_the_axis_stays_and_is_not_checked() {
    let (b, actual) = run(1, 1, false);
    assert!(actual.iter().all(|&x| x == 0.0), "{actual:?}");
    assert_eq!(b.cnc.processes()[0].following_peaks()[0].1, None);
    assert!(b.cnc.processes()[0].alarms().is_empty());
}
