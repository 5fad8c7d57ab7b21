//! Jogging against the soft limits (LO1 of the fixture's X: −5 … 3 mm; 1 mm per tick).

use super::fixture::{Bench, Plc, cnc};
use crate::{Command, Mode};

fn in_mode(mode: Mode) -> Bench {
    let mut b = Bench::new(cnc(false, 0, 0));
    b.cnc
        .process_mut(1)
        .expect("p1")
        .command(Command::SetMode(mode));
    b.run(2, &Plc::default());
    b
}

fn x(b: &Bench) -> f64 {
    b.cnc.processes()[0].set_points()[0]
}

#[test]
fn continuous_jog_stops_at_the_soft_limit_and_when_released() {
    let mut b = in_mode(Mode::Manu);
    let plus = Plc {
        jog: (1, 0),
        ..Plc::default()
    };
    b.step(&plus); // the scan raises JOGP1
    let xs: Vec<f64> = (0..5)
        .map(|_| {
            b.step(&plus);
            x(&b)
        })
        .collect();
    assert_eq!(xs, [1.0, 2.0, 3.0, 3.0, 3.0]);
    let minus = Plc {
        jog: (0, 1),
        ..Plc::default()
    };
    b.step(&minus); // X = 3 still: the scan switches to JOGM1
    b.step(&minus); // the jog + (already ended) is replaced: X = 2
    b.step(&Plc::default()); // X = 1; the scan releases the bit
    b.step(&Plc::default()); // released: aborted
    assert_eq!(x(&b), 1.0);
    b.step(&Plc::default());
    assert_eq!(x(&b), 1.0);
}

#[test]
fn incremental_jog_moves_one_step_per_edge_clipped_at_the_limit() {
    let mut b = in_mode(Mode::Manj);
    let press = Plc {
        jog: (0, 1),
        jinc: 4,
        ..Plc::default()
    };
    let release = Plc {
        jinc: 4,
        ..Plc::default()
    };
    for _ in 0..7 {
        b.step(&press);
        b.step(&press);
        b.step(&release);
    }
    // Seven presses of −1 mm from 0, the limit at −5.
    b.run(3, &release);
    assert_eq!(x(&b), -5.0);
}

#[test]
fn jog_bits_do_nothing_outside_manual_modes() {
    let mut b = in_mode(Mode::Auto);
    let plus = Plc {
        jog: (1, 0),
        ..Plc::default()
    };
    b.run(4, &plus);
    assert_eq!(x(&b), 0.0);
}
