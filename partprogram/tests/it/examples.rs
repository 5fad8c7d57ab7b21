//! The example programs of the MEFI spec files with the results they state.

use crate::common;

use common::*;
use partprogram::{Backend, Kind, PlanOptions};

fn holes(p: &partprogram::Plan) -> Vec<(f64, f64)> {
    // A G81 run is rapid to RA, feed to RB, rapid to RC: the feed move marks a hole.
    p.blocks
        .iter()
        .filter(|c| c.unit.as_deref() == Some("L81") && c.kind == Kind::Linear)
        .map(|c| (end(c, 'X'), end(c, 'Y')))
        .collect()
}

#[test]
fn l9001_drills_twelve_holes_in_a_serpentine_and_restores_parameters() {
    for backend in [Backend::Native, Backend::Interpreter] {
        let src = std::fs::read_to_string(machines().join("mill/nc/GRID")).expect("GRID");
        let p = run(
            &mill(),
            &src,
            PlanOptions {
                backend,
                ..PlanOptions::default()
            },
        );
        let expected = vec![
            (0.0, 0.0),
            (100.0, 0.0),
            (200.0, 0.0),
            (300.0, 0.0),
            (300.0, 75.0),
            (200.0, 75.0),
            (100.0, 75.0),
            (0.0, 75.0),
            (0.0, 150.0),
            (100.0, 150.0),
            (200.0, 150.0),
            (300.0, 150.0),
        ];
        assert_eq!(holes(&p), expected, "{backend:?}");
        // The macro returns to the start point.
        let ret = p
            .blocks
            .iter()
            .rev()
            .find(|c| c.n == Some(1210))
            .expect("N1210 moves");
        assert_eq!((end(ret, 'X'), end(ret, 'Y')), (0.0, 0.0));
        // After N1230 every parameter equals its value at the SAVE in N1105.
        assert_eq!(p.params[9], 81);
        assert_eq!(p.params[10], 100_000);
        assert_eq!(p.params[11], 75_000);
        assert_eq!(p.params[12], 4);
        assert_eq!(p.params[13], 3);
        assert_eq!(p.params[14], 0);
        assert_eq!(p.params[5], 44_000_000);
        assert_eq!(p.params[6], 130_019);
        assert_eq!(p.params[7], -42_120_212);
        assert_eq!(p.params[8], -42_130_113);
        assert_eq!(p.params[18], 31);
        assert_eq!(p.params[21], 5, "R21 keeps its value from before the call");
    }
}
