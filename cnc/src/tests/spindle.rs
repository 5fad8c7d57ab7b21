//! Spindle: G96 recomputed from the X radius every tick with FG96, the G50 S clamp, and gear
//! ranges with the GEARREQ/GEARACK handshake and the alarm for an S no range reaches.

use partprogram::Css;
use partprogram::canon::Kind::{Aux, Linear};

use super::fixture::{Bench, Plc, block, cnc_with, sig};
use crate::config::SpindleConfig;
use crate::state::Interp;

fn spindle(ranges: &[f64]) -> SpindleConfig {
    SpindleConfig {
        name: 'S',
        vmax: ranges[0],
        ranges: ranges.to_vec(),
        master: 'X',
        accel: 1e12,
        max_deviation: 0.1,
        at_speed_signal: None,
        limit_speed: 20.0,
        stopped_signal: None,
    }
}

/// 90 m/min with the rotation axis at X = −100 (radius = |X + 100|).
fn css(max_rpm: Option<f64>) -> Css {
    Css {
        m_min: 90.0,
        max_rpm,
        origin: vec![('X', -100.0)],
        diameter: false,
    }
}

fn with_css(mut c: partprogram::Canon, v: Option<Css>) -> partprogram::Canon {
    c.css = v;
    c
}

fn target(b: &Bench) -> f64 {
    b.cnc.processes()[0]
        .spindle
        .as_ref()
        .map_or(f64::NAN, |s| s.target())
}

fn start(b: &mut Bench, blocks: Vec<partprogram::Canon>) {
    // The parts run to X−50, beyond the fixture's LO1 (−5..3): no soft limits here.
    b.cnc.process_mut(1).expect("p1").cfg.axes[0].soft = (None, None);
    b.start_program(blocks);
    b.run(1, &Plc::default());
    b.step(&Plc {
        start: 1,
        ..Plc::default()
    });
    b.step(&Plc::default()); // t2: START seen, N10 fetched
}

/// N10 G96 S900 M03 at X0; N20 G01 X−50; N30 M30 without G96.
fn css_part(max_rpm: Option<f64>) -> Vec<partprogram::Canon> {
    vec![
        with_css(
            block(10, Aux, 0.0, &[3], Some(900.0), None),
            Some(css(max_rpm)),
        ),
        with_css(
            block(20, Linear, -50.0, &[], Some(900.0), None),
            Some(css(max_rpm)),
        ),
        block(30, Aux, -50.0, &[30], Some(900.0), None),
    ]
}

#[test]
fn g96_follows_the_radius_every_tick_and_raises_fg96() {
    let mut b = Bench::new(cnc_with(false, 0, 0, Some(spindle(&[3000.0]))));
    assert_eq!(sig("I9K26").read(&b.image), 0);
    start(&mut b, css_part(None));
    // t2: N10 fetched, G96 active.
    assert_eq!(sig("I9K26").read(&b.image), 1);
    let mut checked = 0;
    for _ in 0..80 {
        let x = b.cnc.processes()[0].set_points()[0];
        b.step(&Plc::default());
        if b.cnc.processes()[0].css.is_some() && b.cnc.processes()[0].spindle_dir == 1 {
            // The reference of a tick comes from the set point before it: 90 000 / (2π·r).
            let r = (x + 100.0).abs();
            let want = 90_000.0 / (2.0 * std::f64::consts::PI * r);
            assert!(
                (target(&b) - want).abs() < 1e-9,
                "x {x}: {} vs {want}",
                target(&b)
            );
            assert_eq!(sig("I9K26").read(&b.image), 1);
            checked += 1;
        }
    }
    // r = 100 at X0 (450/π = 143.239 rev/min) down to r = 50 at X−50 (900/π = 286.479).
    assert!(checked > 50, "{checked}");
    assert_eq!(b.cnc.processes()[0].state().interp, Interp::Idle);
    assert_eq!(sig("I9K26").read(&b.image), 0);
    // After M30 the law is direct rev/min again: S900 → 900 rev/min.
    assert_eq!(target(&b), 900.0);
}

#[test]
fn g96_stops_at_the_g50_top_speed_and_at_the_range_vmax() {
    let mut b = Bench::new(cnc_with(false, 0, 0, Some(spindle(&[3000.0]))));
    let mut part = css_part(Some(200.0));
    part[2] = with_css(
        block(30, Aux, -50.0, &[0], Some(900.0), None),
        Some(css(Some(200.0))),
    );
    start(&mut b, part);
    b.run(70, &Plc::default());
    // Stopped by M00 at X−50: 286.479 rev/min wanted, G50 S200 holds it at 200.
    assert_eq!(b.cnc.processes()[0].set_points()[0], -50.0);
    assert_eq!(b.cnc.processes()[0].state().interp, Interp::Paused);
    assert_eq!(target(&b), 200.0);

    let mut b = Bench::new(cnc_with(false, 0, 0, Some(spindle(&[250.0]))));
    let mut part = css_part(None);
    part[2] = with_css(
        block(30, Aux, -50.0, &[0], Some(900.0), None),
        Some(css(None)),
    );
    start(&mut b, part);
    b.run(70, &Plc::default());
    // The only range reaches 250 rev/min.
    assert_eq!(target(&b), 250.0);
}

#[test]
fn a_new_range_is_requested_and_s_waits_for_gearack() {
    let mut b = Bench::new(cnc_with(false, 0, 0, Some(spindle(&[500.0, 2000.0]))));
    start(
        &mut b,
        vec![
            block(10, Aux, 0.0, &[3], Some(1200.0), None),
            block(20, Aux, 0.0, &[30], Some(1200.0), None),
        ],
    );
    // t2: S1200 needs range 2 (GM1 500 < 1200 ≤ GM2 2000); SSTB stays low while GEARACK = 0.
    assert_eq!(sig("W8K0").read(&b.image), 2);
    let rows = b.run(5, &Plc::default());
    assert!(rows.iter().all(|r| r[1] == 0), "{rows:?}");
    sig("W47K2").write(&mut b.out, 2);
    // The tick GEARACK = 2 is seen the S code goes out, the strobe the tick after.
    assert_eq!(b.step(&Plc::default())[1], 0);
    assert_eq!(sig("W4K0").read(&b.image), 0xB0);
    assert_eq!(b.step(&Plc::default())[1], 1);
    b.run(8, &Plc::default());
    assert_eq!(b.cnc.processes()[0].counters().ended, 1);
    assert_eq!(target(&b), 1200.0);
    // The PLC shifts back to range 1: the plant's top speed follows it.
    sig("W47K2").write(&mut b.out, 1);
    b.step(&Plc::default());
    assert_eq!(target(&b), 500.0);
}

#[test]
fn an_s_no_range_reaches_is_a_stopping_alarm_naming_the_block() {
    let mut b = Bench::new(cnc_with(false, 0, 0, Some(spindle(&[500.0, 2000.0]))));
    start(&mut b, vec![block(10, Aux, 0.0, &[3], Some(2500.0), None)]);
    let alarms: Vec<String> = b.cnc.processes()[0]
        .alarms()
        .iter()
        .map(|a| a.message.clone())
        .collect();
    assert_eq!(
        alarms,
        ["process 1: S2500 beyond every gear range (top 2000 rev/min) (block 1 (N10))"]
    );
    assert_eq!(b.cnc.processes()[0].state().interp, Interp::Idle);
    assert_eq!(b.run(3, &Plc::default()), vec![[0, 0, 0, 1, 0]; 3]);

    // M41 fixes range 1: S1200 is beyond it.
    let mut b = Bench::new(cnc_with(false, 0, 0, Some(spindle(&[500.0, 2000.0]))));
    start(
        &mut b,
        vec![block(10, Aux, 0.0, &[41, 3], Some(1200.0), None)],
    );
    assert_eq!(
        b.cnc.processes()[0].alarms()[0].message,
        "process 1: S1200 beyond range 1 (GM1 500 rev/min) (block 1 (N10))"
    );
}

#[test]
fn an_unanswered_gear_request_times_out_with_an_alarm() {
    let mut b = Bench::new(cnc_with(false, 4, 0, Some(spindle(&[500.0, 2000.0]))));
    start(&mut b, vec![block(10, Aux, 0.0, &[3], Some(1200.0), None)]);
    // Waited at t2, t3, t4: no alarm yet; the fourth tick (t5) reaches the timeout of 4.
    b.run(2, &Plc::default());
    assert!(b.cnc.processes()[0].alarms().is_empty());
    b.run(1, &Plc::default());
    assert_eq!(
        b.cnc.processes()[0].alarms()[0].message,
        "process 1: gear range 2 not engaged (GEARACK) within the strobe timeout (block 1 (N10))"
    );
}
