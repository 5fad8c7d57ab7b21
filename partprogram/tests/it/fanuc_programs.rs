//! Example programs of gcode-haas-fanuc.md: O00023, the G13 pockets and the G7.1 cylinder interpolation.

use crate::common;

use common::*;
use partprogram::{Dialect, Kind, MachineSpec, PlanOptions, compile};

fn haas() -> MachineSpec {
    let mut m = MachineSpec::new(Dialect::Fanuc, &['X', 'Y', 'Z']);
    m.macro_dir = machines().join("mill/macros");
    m
}

fn fanuc_lathe() -> MachineSpec {
    let mut m = MachineSpec::new(Dialect::Fanuc, &['X', 'Z', 'C']);
    m.diameter_x = true;
    m
}

fn file(path: &str) -> String {
    std::fs::read_to_string(machines().join(path)).expect("fixture")
}

#[test]
fn fx04_o00023_drills_and_countersinks_four_holes_then_mills_the_square() {
    let p = run(&haas(), &file("mill/nc/O00023.nc"), PlanOptions::default());
    // Holes: the feed move to the final depth of each cycle.
    let bottoms: Vec<(f64, f64, f64)> = p
        .blocks
        .iter()
        .filter(|c| {
            c.kind == Kind::Linear
                && ((end(c, 'Z') == -16.0 && c.feed == Some(125.0)) || end(c, 'Z') == -7.0)
        })
        .map(|c| (end(c, 'X'), end(c, 'Y'), end(c, 'Z')))
        .collect();
    let holes = [(-37.5, 37.5), (-37.5, -37.5), (37.5, -37.5), (37.5, 37.5)];
    let mut want: Vec<(f64, f64, f64)> = holes.iter().map(|&(x, y)| (x, y, -16.0)).collect();
    want.extend(holes.iter().map(|&(x, y)| (x, y, -7.0)));
    assert_eq!(bottoms, want);
    // G73 pecks of 5 from the R plane Z2 and G99 return to the R plane.
    let first: Vec<(Kind, f64)> = p
        .blocks
        .iter()
        .skip_while(|c| !(c.kind == Kind::Rapid && end(c, 'Z') == 2.0))
        .take(8)
        .map(|c| (c.kind, end(c, 'Z')))
        .collect();
    assert_eq!(
        first,
        vec![
            (Kind::Rapid, 2.0),
            (Kind::Linear, -3.0),
            (Kind::Rapid, -2.5),
            (Kind::Linear, -8.0),
            (Kind::Rapid, -7.5),
            (Kind::Linear, -13.0),
            (Kind::Rapid, -12.5),
            (Kind::Linear, -16.0)
        ]
    );
    let after_first_hole = p
        .blocks
        .iter()
        .skip_while(|c| end(c, 'Z') != -16.0)
        .nth(1)
        .expect("retract");
    assert_eq!(
        (after_first_hole.kind, end(after_first_hole, 'Z')),
        (Kind::Rapid, 2.0)
    );
    // G82 dwells 0.5 s at the bottom of each hole.
    let dwells: Vec<Option<f64>> = p
        .blocks
        .iter()
        .filter(|c| c.kind == Kind::Dwell)
        .map(|c| c.dwell)
        .collect();
    assert_eq!(dwells, vec![Some(0.5); 4]);
    // The square contour with G41 D03 at F300.
    let square: Vec<(f64, f64)> = p
        .blocks
        .iter()
        .filter(|c| c.kind == Kind::Linear && c.feed == Some(300.0) && end(c, 'Z') == -16.0)
        .map(|c| (end(c, 'X'), end(c, 'Y')))
        .collect();
    assert_eq!(
        square,
        vec![
            (-58.0, 50.0),
            (50.0, 50.0),
            (50.0, -50.0),
            (-50.0, -50.0),
            (-50.0, 57.0),
            (-58.0, 58.0)
        ]
    );
    // G28 G91 Z0 sends Z to machine zero; the program ends with T1 M06 and M30.
    let last = p.blocks.last().expect("blocks");
    assert_eq!(last.m.iter().map(|m| m.m).collect::<Vec<_>>(), vec![30]);
    assert_eq!(
        p.blocks
            .windows(2)
            .filter(|w| w[1].kind == Kind::Rapid
                && end(&w[1], 'Z') == 0.0
                && end(&w[0], 'Z') == 25.0)
            .count(),
        3
    );
}

#[test]
fn fx04_block_delete_skips_the_optional_holes() {
    let p = run(
        &haas(),
        &file("mill/nc/O00023.nc"),
        PlanOptions {
            block_skip: true,
            ..PlanOptions::default()
        },
    );
    let bottoms = p
        .blocks
        .iter()
        .filter(|c| c.kind == Kind::Linear && end(c, 'Z') == -16.0 && c.feed == Some(125.0))
        .count();
    assert_eq!(bottoms, 2);
}

#[test]
fn fx15_g13_pocket_one_pass_ccw_radius_12_at_depth() {
    let p = run(&haas(), &file("mill/nc/O00050.nc"), PlanOptions::default());
    let arcs: Vec<&partprogram::Canon> =
        p.blocks.iter().filter(|c| c.kind == Kind::ArcCcw).collect();
    assert_eq!(arcs.len(), 1);
    let a = arcs[0];
    assert_eq!((end(a, 'X'), end(a, 'Y'), end(a, 'Z')), (62.0, 50.0, -12.0));
    assert_eq!(a.center, vec![('X', 50.0), ('Y', 50.0)]);
    assert_eq!(a.feed, Some(250.0));
    // The tool stays at depth until N17 lifts it; N18 G53 goes to machine Y0 Z0.
    let n18 = p.blocks.iter().find(|c| c.n == Some(18)).expect("N18");
    assert_eq!(
        (end(n18, 'X'), end(n18, 'Y'), end(n18, 'Z')),
        (50.0, 0.0, 0.0)
    );
}

#[test]
fn fx16_g13_roughing_spiral_with_k_and_q() {
    let src =
        "N23 G90 G54 G00 X50. Y50.\nN26 G01 Z-12. F150.\nN27 G13 I5. K12. Q3. D01 F250.\nN30 M30\n";
    let p = run(&haas(), src, PlanOptions::default());
    let radii: Vec<f64> = p
        .blocks
        .iter()
        .filter(|c| c.kind == Kind::ArcCcw)
        .map(|c| um(end(c, 'X') - 50.0))
        .collect();
    assert_eq!(radii, vec![5.0, 8.0, 11.0, 12.0]);
    let z = p
        .blocks
        .iter()
        .find(|c| c.n == Some(26))
        .map(|c| (end(c, 'Z'), c.feed));
    assert_eq!(z, Some((-12.0, Some(150.0))));
}

#[test]
fn fx20_g71_cylinder_interpolation_converts_degrees_on_the_development() {
    // The spec's O1000 (a C axis under M21) is a fixture here: the bundled lathe has no C axis.
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/O1000-cylinder.nc");
    let src = std::fs::read_to_string(path).expect("fixture");
    let p = run(&fanuc_lathe(), &src, PlanOptions::default());
    let arcs: Vec<(Option<u32>, Kind, f64, f64)> = p
        .blocks
        .iter()
        .filter(|c| matches!(c.kind, Kind::ArcCw | Kind::ArcCcw))
        .map(|c| (c.n, c.kind, um(c.center[0].1), um(c.center[1].1)))
        .collect();
    // Centres from the spec table, C in degrees (5 millidegree tolerance), Z in mm.
    let want = [
        (120, Kind::ArcCw, 102.957, -25.0),
        (140, Kind::ArcCcw, 257.04, -40.0),
        (160, Kind::ArcCcw, 462.958, -40.0),
        (180, Kind::ArcCw, 617.041, -25.0),
    ];
    assert_eq!(arcs.len(), 4);
    for (got, w) in arcs.iter().zip(want) {
        assert_eq!((got.0, got.1), (Some(w.0), w.1));
        assert!(
            (got.2 - w.2).abs() < 0.005,
            "N{} centre C {} vs {}",
            w.0,
            got.2,
            w.2
        );
        assert!(
            (got.3 - w.3).abs() < 0.005,
            "N{} centre Z {} vs {}",
            w.0,
            got.3,
            w.3
        );
    }
    assert!(
        p.blocks
            .iter()
            .filter(|c| c.n == Some(120))
            .all(|c| c.plane.name() == "YZ")
    );
    // Unit conversion of 004:56-61: 10 mm on Ø50 is 22.918° (22.935° with the rounded factor 0.436).
    let factor = 50.0 * std::f64::consts::PI / 360.0;
    assert!(((10.0 / factor) - 22.918).abs() < 0.001);
    let n190 = p.blocks.iter().find(|c| c.n == Some(190)).expect("N190");
    assert_eq!(
        (end(n190, 'C'), end(n190, 'X'), end(n190, 'Z')),
        (720.0, 30.0, -15.0)
    );
}

#[test]
fn fanuc_subprogram_calls_and_diagnostics() {
    let src = "O1\nN1 G90 G00 X0 Y0 Z5\nN2 M97 P100 L2\nN3 M30\nN100 G91 X10\nN110 M99\n";
    let p = run(&haas(), src, PlanOptions::default());
    let xs: Vec<f64> = p
        .blocks
        .iter()
        .filter(|c| c.kind == Kind::Rapid)
        .map(|c| end(c, 'X'))
        .collect();
    assert_eq!(xs, vec![0.0, 10.0, 20.0]);
    let c = |s: &str| {
        compile(&haas(), "t", s)
            .1
            .iter()
            .map(|d| d.code)
            .collect::<Vec<_>>()
    };
    assert_eq!(c("O1\nN1 M97 P5\nN2 M30\n"), vec![2018]);
    assert_eq!(c("O1\nN1 M98 P77\nN2 M30\n"), vec![2019]);
    assert_eq!(c("O1\nN1 G1 G2 X1\nN2 M30\n"), vec![2007]);
    assert_eq!(c("O1\nN1 G5.5 X1\nN2 M30\n"), vec![2015]);
    assert_eq!(c("O1\nN1 Q1 Q2\nN2 M30\n"), vec![2006]);
}

#[test]
fn fanuc_arcs_with_r_choose_the_short_or_long_way_and_ij_centres() {
    let p = run(
        &haas(),
        "G90 G00 X0 Y0\nG02 X10 Y10 R10 F100\nG00 X0 Y0\nG02 X10 Y10 R-10\nG00 X0 Y0\nG03 X10 Y10 I10 J0\nM30\n",
        PlanOptions::default(),
    );
    let arcs: Vec<Vec<(char, f64)>> = p
        .blocks
        .iter()
        .filter(|c| matches!(c.kind, Kind::ArcCw | Kind::ArcCcw))
        .map(|c| c.center.iter().map(|(a, v)| (*a, um(*v))).collect())
        .collect();
    assert_eq!(
        arcs,
        vec![
            vec![('X', 10.0), ('Y', 0.0)],
            vec![('X', 0.0), ('Y', 10.0)],
            vec![('X', 10.0), ('Y', 0.0)]
        ]
    );
}
