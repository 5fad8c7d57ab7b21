//! The tool-correction request (m_request 10 of M06): the following blocks come from the plan
//! made with the correction table as it is when the function ends.

use std::sync::{Arc, Mutex};

use partprogram::canon::Kind::{Aux, Linear};

use super::fixture::{Bench, Plc, block, cnc};
use crate::state::Interp;

/// N10 X2; N20 M06; N30 X5; N40 M30, planned with an X length correction of `dx`.
fn part(dx: f64) -> Vec<partprogram::Canon> {
    vec![
        block(10, Linear, 2.0 + dx, &[], None, None),
        block(20, Aux, 2.0 + dx, &[6], None, None),
        block(30, Linear, 5.0 + dx, &[], None, None),
        block(40, Aux, 5.0 + dx, &[30], None, None),
    ]
}

/// The part planned without correction, re-planned by `replan` at the request, started (START
/// pressed at tick 1).
fn started(replan: crate::correction::Replanner) -> Bench {
    let mut b = Bench::new(cnc(false, 0, 0));
    // N30 ends at X5.5, beyond the fixture's LO1 (−5..3): no soft limits here.
    b.cnc.process_mut(1).expect("p1").cfg.axes[0].soft = (None, None);
    b.start_program(part(0.0));
    b.cnc
        .process_mut(1)
        .expect("process 1")
        .set_replanner(replan);
    b.run(1, &Plc::default());
    b.step(&Plc {
        start: 1,
        ..Plc::default()
    });
    b
}

fn run(
    table: Arc<Mutex<f64>>,
    plan: impl Fn(f64) -> Vec<partprogram::Canon> + Send + 'static,
) -> Vec<f64> {
    let t = Arc::clone(&table);
    let mut b = started(Box::new(move |name, skip| {
        assert_eq!((name, skip), ("test", false));
        Some(Ok(plan(*t.lock().expect("table"))))
    }));
    // The operator enters a new offset of +0.5 mm while N10 moves.
    b.run(2, &Plc::default());
    *table.lock().expect("table") = 0.5;
    let mut xs = Vec::new();
    for _ in 0..30 {
        b.step(&Plc::default());
        xs.push(b.cnc.processes()[0].set_points()[0]);
    }
    assert_eq!(b.cnc.processes()[0].state().interp, Interp::Idle);
    xs
}

#[test]
fn a_changed_offset_moves_the_following_block_by_exactly_the_difference() {
    let xs = run(Arc::new(Mutex::new(0.0)), part);
    // N10 ends at X2 (planned before the change); N30 ends at 5 + 0.5.
    assert!(xs.contains(&2.0));
    assert_eq!(xs.last(), Some(&5.5));
    // Without a change the plan is the same: N30 ends at X5.
    let xs = run(Arc::new(Mutex::new(0.0)), |_| part(0.0));
    assert_eq!(xs.last(), Some(&5.0));
}

#[test]
fn a_plan_with_other_blocks_is_a_stopping_alarm() {
    let table = Arc::new(Mutex::new(0.0));
    let t = Arc::clone(&table);
    let mut b = started(Box::new(move |_, _| {
        let mut p = part(*t.lock().expect("table"));
        p.pop();
        Some(Ok(p))
    }));
    b.run(20, &Plc::default());
    let p = &b.cnc.processes()[0];
    assert_eq!(
        p.alarms()[0].message,
        "process 1: tool-correction request (block 2): the program plans different blocks with the new corrections"
    );
    assert_eq!(p.set_points()[0], 2.0);
}
