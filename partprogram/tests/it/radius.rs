//! Tool radius compensation G40/G41/G42 on the planned path, with hand-computed coordinates: squares
//! on both sides in both corner modes, a line-arc-line contour with the arc feed of structure spec §13.6,
//! a negative radius, the located errors 2510/2511, and the HAAS examples of gcode-haas-fanuc.md §10.2.

use crate::common;
use detmath::Det as _;

use common::*;
use partprogram::radius::{Corners, RadiusOptions};
use partprogram::{Dialect, Kind, MachineSpec, Plan, PlanOptions, compile, plan};

use Kind::{ArcCcw as Ccw, ArcCw as Cw, Linear as Lin, Rapid};

/// (N, kind, X, Y, arc centre (X, Y)) of every motion block, coordinates rounded to µm.
type Step = (Option<u32>, Kind, f64, f64, Option<(f64, f64)>);

fn steps(p: &Plan) -> Vec<Step> {
    p.blocks
        .iter()
        .filter(|c| {
            matches!(
                c.kind,
                Kind::Rapid | Kind::Linear | Kind::ArcCw | Kind::ArcCcw
            )
        })
        .map(|c| {
            let centre = if c.center.is_empty() {
                None
            } else {
                let get = |a: char| c.center.iter().find(|x| x.0 == a).map(|x| um(x.1));
                Some((get('X').unwrap_or(f64::NAN), get('Y').unwrap_or(f64::NAN)))
            };
            (c.n, c.kind, end(c, 'X'), end(c, 'Y'), centre)
        })
        .collect()
}

fn opts(corners: Corners) -> PlanOptions {
    PlanOptions {
        radius: RadiusOptions {
            corners,
            ..RadiusOptions::default()
        },
        ..PlanOptions::default()
    }
}

/// Plans and returns the located error (code, line).
fn fails(m: &MachineSpec, src: &str, o: PlanOptions) -> (u32, u32) {
    let (prog, diags) = compile(m, "test", src);
    let Some(prog) = prog else {
        panic!("compile failed: {diags:#?}")
    };
    match plan(&prog, o) {
        Ok(_) => panic!("planned without error"),
        Err((_, d)) => (d.code, d.line),
    }
}

fn square(g: u16, r: &str) -> String {
    format!(
        "%1\nN10 G92 D1 R0={r}\nN20 G0 X-20 Y0\nN30 G1 G{g} D1 X0 Y0 F100\nN40 Y20\nN45 Z-2\n\
         N50 X20\nN60 Y0\nN70 X0\nN80 G40 X-20 Y0\nN90 M30\n"
    )
}

#[test]
fn square_g41_outside_corners_with_inserted_arcs() {
    let p = run(&mill(), &square(41, "5."), PlanOptions::default());
    assert_eq!(
        steps(&p),
        vec![
            (Some(20), Rapid, -20.0, 0.0, None),
            (Some(30), Lin, -5.0, 0.0, None),
            (Some(40), Lin, -5.0, 20.0, None),
            (Some(45), Lin, -5.0, 20.0, None),
            (Some(50), Cw, 0.0, 25.0, Some((0.0, 20.0))),
            (Some(50), Lin, 20.0, 25.0, None),
            (Some(60), Cw, 25.0, 20.0, Some((20.0, 20.0))),
            (Some(60), Lin, 25.0, 0.0, None),
            (Some(70), Cw, 20.0, -5.0, Some((20.0, 0.0))),
            (Some(70), Lin, 0.0, -5.0, None),
            (Some(80), Lin, -20.0, 0.0, None),
        ]
    );
    // The Z plunge between N40 and N50 keeps its place and Z stays down on the inserted arc.
    assert_eq!(end(&p.blocks[3], 'Z'), -2.0);
    assert_eq!(end(&p.blocks[4], 'Z'), -2.0);
    // Inserted arcs run at the feed of the block they lead into; M30 is still the last block.
    assert_eq!(p.blocks[4].feed, Some(100.0));
    assert_eq!(p.blocks.last().map(|c| c.kind), Some(Kind::Aux));
}

#[test]
fn square_g41_outside_corners_at_the_intersection_of_equidistants() {
    let p = run(&mill(), &square(41, "5."), opts(Corners::Intersection));
    assert_eq!(
        steps(&p),
        vec![
            (Some(20), Rapid, -20.0, 0.0, None),
            (Some(30), Lin, -5.0, 0.0, None),
            (Some(40), Lin, -5.0, 25.0, None),
            (Some(45), Lin, -5.0, 25.0, None),
            (Some(50), Lin, 25.0, 25.0, None),
            (Some(60), Lin, 25.0, -5.0, None),
            (Some(70), Lin, 0.0, -5.0, None),
            (Some(80), Lin, -20.0, 0.0, None),
        ]
    );
}

const SQUARE_INSIDE: [Step; 8] = [
    (Some(20), Rapid, -20.0, 0.0, None),
    (Some(30), Lin, 5.0, 0.0, None),
    (Some(40), Lin, 5.0, 15.0, None),
    (Some(45), Lin, 5.0, 15.0, None),
    (Some(50), Lin, 15.0, 15.0, None),
    (Some(60), Lin, 15.0, 5.0, None),
    (Some(70), Lin, 0.0, 5.0, None),
    (Some(80), Lin, -20.0, 0.0, None),
];

#[test]
fn square_g42_inside_corners_are_intersections_in_both_modes() {
    for mode in [Corners::Arc, Corners::Intersection] {
        let p = run(&mill(), &square(42, "5."), opts(mode));
        assert_eq!(steps(&p), SQUARE_INSIDE.to_vec(), "{mode:?}");
    }
}

#[test]
fn negative_radius_swaps_the_side() {
    let p = run(&mill(), &square(41, "-5."), PlanOptions::default());
    assert_eq!(steps(&p), SQUARE_INSIDE.to_vec());
}

#[test]
fn d0_and_g40_leave_the_path_unchanged() {
    let src = square(41, "5.").replace("G41 D1", "G41 D0");
    let p = run(&mill(), &src, PlanOptions::default());
    let xy: Vec<(f64, f64)> = steps(&p).iter().map(|s| (s.2, s.3)).collect();
    assert_eq!(
        xy,
        vec![
            (-20.0, 0.0),
            (0.0, 0.0),
            (0.0, 20.0),
            (0.0, 20.0),
            (20.0, 20.0),
            (20.0, 0.0),
            (0.0, 0.0),
            (-20.0, 0.0)
        ]
    );
}

fn line_arc_line(g: u16) -> String {
    format!(
        "%1\nN10 G92 D1 R0=2.\nN20 G0 X0 Y-10\nN30 G1 G{g} D1 X0 Y0 F100\nN40 X10\n\
         N50 G3 X20 Y10 I0 J10\nN60 G1 Y20\nN70 G40 X30 Y20\nN80 M30\n"
    )
}

#[test]
fn line_arc_line_outside_of_the_arc_gets_a_larger_arc_and_feed() {
    let p = run(&mill(), &line_arc_line(42), PlanOptions::default());
    assert_eq!(
        steps(&p),
        vec![
            (Some(20), Rapid, 0.0, -10.0, None),
            (Some(30), Lin, 0.0, -2.0, None),
            (Some(40), Lin, 10.0, -2.0, None),
            (Some(50), Ccw, 22.0, 10.0, Some((10.0, 10.0))),
            (Some(60), Lin, 22.0, 20.0, None),
            (Some(70), Lin, 30.0, 20.0, None),
        ]
    );
    // G3 with G42: F·(R + Kor)/R = 100 · 12/10.
    let feeds: Vec<Option<f64>> = p.blocks.iter().map(|c| c.feed.map(um)).collect();
    assert_eq!(feeds[3], Some(120.0));
    assert_eq!(feeds[4], Some(100.0));
}

#[test]
fn line_arc_line_inside_of_the_arc_gets_a_smaller_arc_and_feed() {
    let p = run(&mill(), &line_arc_line(41), PlanOptions::default());
    assert_eq!(
        steps(&p)[1..],
        [
            (Some(30), Lin, 0.0, 2.0, None),
            (Some(40), Lin, 10.0, 2.0, None),
            (Some(50), Ccw, 18.0, 10.0, Some((10.0, 10.0))),
            (Some(60), Lin, 18.0, 20.0, None),
            (Some(70), Lin, 30.0, 20.0, None),
        ]
    );
    // G3 with G41: F·(R − Kor)/R = 100 · 8/10; disabled (MC R168 d5 = 1) it stays F.
    assert_eq!(p.blocks[3].feed.map(um), Some(80.0));
    let o = PlanOptions {
        radius: RadiusOptions {
            adapt_arc_feed: false,
            ..RadiusOptions::default()
        },
        ..PlanOptions::default()
    };
    assert_eq!(
        run(&mill(), &line_arc_line(41), o).blocks[3].feed,
        Some(100.0)
    );
}

/// Figure 5 of the manual: a G2 arc and a line turning left with a large tool on the G42 side.
const ARC_THEN_LINE: &str = "%1\nN10 G92 D1 R0=8.\nN20 G0 X-30 Y-20\nN30 G1 G42 D1 X-10 Y-20 F100\n\
N40 Y-10\nN50 G2 X0 Y0 I10 J0\nN60 G1 Y10\nN70 G40 X-10 Y20\nN80 M30\n";

#[test]
fn arc_insertion_resolves_the_large_tool_on_the_g42_side() {
    let p = run(&mill(), ARC_THEN_LINE, PlanOptions::default());
    assert_eq!(
        steps(&p),
        vec![
            (Some(20), Rapid, -30.0, -20.0, None),
            (Some(30), Lin, -2.0, -20.0, None),
            (Some(40), Lin, -2.0, -10.0, None),
            (Some(50), Cw, 0.0, -8.0, Some((0.0, -10.0))),
            (Some(60), Ccw, 8.0, 0.0, Some((0.0, 0.0))),
            (Some(60), Lin, 8.0, 10.0, None),
            (Some(70), Lin, -10.0, 20.0, None),
        ]
    );
    // G2 with G42: F·(R − Kor)/R = 100 · 2/10.
    assert_eq!(p.blocks[3].feed.map(um), Some(20.0));
}

#[test]
fn intersection_mode_reports_equidistants_not_found_at_the_block() {
    let (code, line) = fails(&mill(), ARC_THEN_LINE, opts(Corners::Intersection));
    assert_eq!((code, line), (2510, 6));
    let (prog, _) = compile(&mill(), "test", ARC_THEN_LINE);
    let Err((blocks, d)) = plan(&prog.expect("compiles"), opts(Corners::Intersection)) else {
        panic!("no error")
    };
    assert_eq!(
        d.message,
        "radius compensation: intersection of equidistants not found between N50 and N60"
    );
    // Blocks up to the one before the failing arc were planned.
    assert_eq!(blocks.last().and_then(|c| c.n), Some(40));
}

#[test]
fn inside_corner_without_intersection_is_an_error_in_both_modes() {
    // Line +X into a G3 arc of radius 8 turning left: the G41 equidistants (y = 5 and the circle of
    // radius 3 about (2, 0)) do not meet.
    let src = "%1\nN10 G92 D1 R0=5.\nN20 G0 X-10 Y0\nN30 G1 G41 D1 X0 Y0 F100\nN40 X10\n\
               N50 G3 X2 Y8 I-8 J0\nN60 G1 G40 X-10 Y8\nN70 M30\n";
    for mode in [Corners::Arc, Corners::Intersection] {
        assert_eq!(fails(&mill(), src, opts(mode)), (2510, 5), "{mode:?}");
    }
}

#[test]
fn arc_smaller_than_the_tool_on_its_inside_is_an_error() {
    let src = "%1\nN10 G92 D1 R0=5.\nN20 G0 X0 Y-10\nN30 G1 G41 D1 X0 Y0 F100\nN40 X10\n\
               N50 G3 X14 Y4 I0 J4\nN60 G1 G40 Y20\nN70 M30\n";
    assert_eq!(fails(&mill(), src, PlanOptions::default()), (2510, 6));
}

#[test]
fn g41_g42_or_g40_on_an_arc_is_an_error() {
    // Written in the G02/G03 block: a compile-time error in both dialects (S15).
    let on = "%1\nN10 G92 D1 R0=5.\nN20 G0 X0 Y-10\nN30 G2 G41 D1 X10 Y0 I10 J0 F100\nN40 M30\n";
    assert_eq!(codes(&mill(), on), vec![2035]);
    let fanuc = "%\nO1\nG00 X0 Y-10.\nG03 G40 X10. Y0 I10. J0 F100.\nM30\n%\n";
    assert_eq!(codes(&haas(), fanuc), vec![2035]);
    // With a modal arc: a run-time error located at the block.
    let on = "%1\nN10 G92 D1 R0=5.\nN20 G0 X0 Y-10\nN30 G2 X10 Y0 I10 J0 F100\n\
              N40 G41 D1 X20 Y-10 I0 J-10\nN50 M30\n";
    assert_eq!(fails(&mill(), on, PlanOptions::default()), (2511, 5));
    let off = "%1\nN10 G92 D1 R0=1.\nN20 G0 X0 Y-10\nN30 G1 G41 D1 X0 Y0 F100\nN40 X10\n\
               N50 G3 X20 Y10 I0 J10\nN60 G40 X30 Y20 I10 J0\nN70 M30\n";
    assert_eq!(fails(&mill(), off, PlanOptions::default()), (2511, 7));
}

#[test]
fn plane_change_while_active_is_an_error() {
    let src = "%1\nN10 G92 D1 R0=1.\nN20 G0 X0 Y-10\nN30 G1 G41 D1 X0 Y0 F100\nN40 X10\n\
               N50 G18 X20 Z5\nN60 M30\n";
    assert_eq!(fails(&mill(), src, PlanOptions::default()), (2511, 6));
    // Also when the block with the new plane moves only out of the old plane.
    let z_only = src.replace("N50 G18 X20 Z5", "N50 G18 Z5");
    assert_eq!(fails(&mill(), &z_only, PlanOptions::default()), (2511, 6));
}

#[test]
fn program_end_without_g40_ends_on_the_perpendicular() {
    let src = "%1\nN10 G92 D1 R0=3.\nN20 G0 X0 Y0\nN30 G1 G42 D1 X10 F50\nN40 X20\nN50 M30\n";
    let p = run(&mill(), src, PlanOptions::default());
    let xy: Vec<(f64, f64)> = steps(&p).iter().map(|s| (s.2, s.3)).collect();
    assert_eq!(xy, vec![(0.0, 0.0), (10.0, -3.0), (20.0, -3.0)]);
}

#[test]
fn g40_without_motion_cancels_on_the_next_motion_in_the_plane() {
    let src = "%1\nN10 G92 D1 R0=3.\nN20 G0 X0 Y0\nN30 G1 G42 D1 X10 F50\nN40 X20\nN50 G40\n\
               N55 Z-1\nN60 Y10\nN70 M30\n";
    let p = run(&mill(), src, PlanOptions::default());
    let path: Vec<(Option<u32>, f64, f64, f64)> = p
        .blocks
        .iter()
        .filter(|c| c.kind != Kind::Aux)
        .map(|c| (c.n, end(c, 'X'), end(c, 'Y'), end(c, 'Z')))
        .collect();
    assert_eq!(
        path,
        vec![
            (Some(20), 0.0, 0.0, 0.0),
            (Some(30), 10.0, -3.0, 0.0),
            (Some(40), 20.0, -3.0, 0.0),
            (Some(55), 20.0, -3.0, -1.0),
            (Some(60), 20.0, 10.0, -1.0),
        ]
    );
}

#[test]
fn mirror_of_one_plane_axis_swaps_the_side() {
    // G35 X0 mirrors X: the clockwise G41 square becomes counter-clockwise in the machine frame and
    // the tool stays outside, i.e. the machine path is the mirror of the unmirrored one.
    let src = square(41, "5.").replace("N20 G0", "N15 G35 X0\nN20 G0");
    let p = run(&mill(), &src, PlanOptions::default());
    assert_eq!(
        steps(&p),
        vec![
            (Some(20), Rapid, 20.0, 0.0, None),
            (Some(30), Lin, 5.0, 0.0, None),
            (Some(40), Lin, 5.0, 20.0, None),
            (Some(45), Lin, 5.0, 20.0, None),
            (Some(50), Ccw, 0.0, 25.0, Some((0.0, 20.0))),
            (Some(50), Lin, -20.0, 25.0, None),
            (Some(60), Ccw, -25.0, 20.0, Some((-20.0, 20.0))),
            (Some(60), Lin, -25.0, 0.0, None),
            (Some(70), Ccw, -20.0, -5.0, Some((-20.0, 0.0))),
            (Some(70), Lin, 0.0, -5.0, None),
            (Some(80), Lin, 20.0, 0.0, None),
        ]
    );
}

#[test]
fn lathe_radius_compensation_in_zx_with_diameter_x() {
    // G18 on a lathe: first axis Z, second X (a diameter). Face down −X, then turn along −Z with G42:
    // the tool centre stays 0.8 mm off the contour, i.e. 1.6 mm on the diameter.
    let src = "%1\nN10 G92 D1 R0=0.8\nN20 G0 X60 Z2\nN30 G1 G42 D1 X40 Z2 F100\nN40 Z-20\n\
               N50 X60\nN60 G40 X70 Z-20\nN70 M30\n";
    let p = run(&lathe(), src, PlanOptions::default());
    let xz: Vec<(Kind, f64, f64)> = p
        .blocks
        .iter()
        .filter(|c| c.kind != Kind::Aux)
        .map(|c| (c.kind, end(c, 'X'), end(c, 'Z')))
        .collect();
    // Direction −Z in the (Z, X) plane: the right of (−1, 0) is (0, +1), i.e. +X (radius 20.8).
    // N50 turns into +X: a right turn, inside for G42 → the intersection at Z −19.2.
    assert_eq!(
        xz,
        vec![
            (Rapid, 60.0, 2.0),
            (Lin, 41.6, 2.0),
            (Lin, 41.6, -19.2),
            (Lin, 60.0, -19.2),
            (Lin, 70.0, -20.0),
        ]
    );
}

fn haas() -> MachineSpec {
    MachineSpec::new(Dialect::Fanuc, &['X', 'Y', 'Z'])
}

#[test]
fn haas_o00023_square_with_g41_d03() {
    // gcode-haas-fanuc.md FX-04, with the D03 radius of the 12 mm end mill set by G10 L12.
    let text = std::fs::read_to_string(machines().join("mill/nc/O00023.nc")).expect("O00023");
    let text = text.replace("N3 (SET", "G10 L12 P3 R6. ;\nN3 (SET");
    let p = run(&haas(), &text, PlanOptions::default());
    let contour: Vec<(Kind, f64, f64)> = p
        .blocks
        .iter()
        .filter(|c| c.feed == Some(300.0) && end(c, 'Z') == -16.0)
        .map(|c| (c.kind, end(c, 'X'), end(c, 'Y')))
        .collect();
    assert_eq!(
        contour,
        vec![
            (Lin, -58.0, 56.0),
            (Lin, 50.0, 56.0),
            (Cw, 56.0, 50.0),
            (Lin, 56.0, -50.0),
            (Cw, 50.0, -56.0),
            (Lin, -50.0, -56.0),
            (Cw, -56.0, -50.0),
            (Lin, -56.0, 57.0),
            (Lin, -58.0, 58.0),
        ]
    );
    // Without G10 the register is 0 and the contour is the programmed one.
    let p = run(
        &haas(),
        &std::fs::read_to_string(machines().join("mill/nc/O00023.nc")).expect("O00023"),
        opts(Corners::Intersection),
    );
    assert_eq!(
        p.blocks
            .iter()
            .filter(|c| c.feed == Some(300.0) && end(c, 'Z') == -16.0)
            .count(),
        6
    );
}

#[test]
fn haas_g12_g13_pockets_subtract_the_tool_radius() {
    // G13 implies G41, G12 implies G42: the tool centre runs on radius − D (002:1798–1807).
    let src =
        "%\nO1\nG10 L12 P1 R4. ;\nG00 X0 Y0 Z1. ;\nG13 I10. K20. Q5. Z-5. D01 F200. ;\nM30 ;\n%\n";
    let p = run(&haas(), src, PlanOptions::default());
    let circles: Vec<(Kind, f64, f64)> = p
        .blocks
        .iter()
        .filter(|c| matches!(c.kind, Kind::ArcCw | Kind::ArcCcw))
        .map(|c| (c.kind, end(c, 'X'), end(c, 'Y')))
        .collect();
    assert_eq!(
        circles,
        vec![(Ccw, 6.0, 0.0), (Ccw, 11.0, 0.0), (Ccw, 16.0, 0.0)]
    );
    // D00 programs the pocket without compensation; a tool wider than the pocket is an error.
    let d0 = src.replace("D01", "D00");
    let p = run(&haas(), &d0, PlanOptions::default());
    let last_arc = p
        .blocks
        .iter()
        .rev()
        .find(|c| c.kind == Kind::ArcCcw)
        .expect("arc");
    assert_eq!(end(last_arc, 'X'), 20.0);
    let wide = src.replace("R4.", "R25.");
    assert_eq!(fails(&haas(), &wide, PlanOptions::default()), (2510, 5));
}

#[test]
fn haas_fx06_contour_with_a_slanted_side() {
    // FX-06 (002:1305–1314) verbatim after a start position and D01 = 5 mm. Every corner of the
    // clockwise contour is outside for G41: each line ends on its perpendicular, an arc about the
    // corner leads to the next. The slanted side has the unit left normal (−40, 14.559)/L,
    // L = √(14.559² + 40²) = 42.567176…, so its offset ends are P + 5·(−0.939691, 0.342024).
    let src = "%\nO6\nG10 L12 P1 R5. ;\nG00 X-8. Y-6. ;\n(ABSOLUTE)\nG01 G41 X0 Y-6. D01 F300.\n\
               G90 Y45 (absolute)\nY45.\nX14.559 Y85.\nX50.\nY0\nX0\nG40 X-8. Y-6.\nM30 ;\n%\n";
    let p = run(&haas(), src, PlanOptions::default());
    let path: Vec<Step> = steps(&p)
        .into_iter()
        .map(|s| (None, s.1, s.2, s.3, s.4))
        .collect();
    assert_eq!(
        path,
        vec![
            (None, Rapid, -8.0, -6.0, None),
            (None, Lin, -5.0, -6.0, None),
            (None, Lin, -5.0, 45.0, None),
            (None, Lin, -5.0, 45.0, None),
            (None, Cw, -4.698, 46.71, Some((0.0, 45.0))),
            (None, Lin, 9.861, 86.71, None),
            (None, Cw, 14.559, 90.0, Some((14.559, 85.0))),
            (None, Lin, 50.0, 90.0, None),
            (None, Cw, 55.0, 85.0, Some((50.0, 85.0))),
            (None, Lin, 55.0, 0.0, None),
            (None, Cw, 50.0, -5.0, Some((50.0, 0.0))),
            (None, Lin, 0.0, -5.0, None),
            (None, Lin, -8.0, -6.0, None),
        ]
    );
}

/// One random contour element: a line to (x, y), or an arc about the start + (i, j) sweeping `turn`
/// radians (positive counter-clockwise), or a Z move.
#[derive(Debug, Clone)]
enum Seg {
    Line(f64, f64),
    Arc(f64, f64, f64),
    Z(f64),
}

fn seg() -> impl proptest::strategy::Strategy<Value = Seg> {
    use proptest::prelude::*;
    prop_oneof![
        4 => (-50.0..50.0f64, -50.0..50.0f64).prop_map(|(x, y)| Seg::Line(x, y)),
        3 => (-20.0..20.0f64, -20.0..20.0f64, -6.0..6.0f64).prop_map(|(i, j, t)| Seg::Arc(i, j, t)),
        1 => (-10.0..0.0f64).prop_map(Seg::Z),
    ]
}

/// `blocks` with their modal records reset (to compare geometry, feeds and functions only).
fn without_modal(blocks: Vec<partprogram::Canon>) -> Vec<partprogram::Canon> {
    blocks
        .into_iter()
        .map(|mut c| {
            c.modal = partprogram::BlockModal::default();
            c
        })
        .collect()
}

/// The program text of a random contour with G41/G42 of radius `r`, starting and cancelling with lines.
fn contour(segs: &[Seg], left: bool, r: f64) -> String {
    let mut s = format!(
        "%1\nN1 G92 D1 R0={r:.3}\nN2 G0 X-60. Y-60.\nN3 G1 G4{} D1 X0 Y0 F100\n",
        if left { 1 } else { 2 }
    );
    let (mut x, mut y) = (0.0f64, 0.0f64);
    for (k, g) in segs.iter().enumerate() {
        let n = k + 4;
        match *g {
            Seg::Line(tx, ty) => {
                s += &format!("N{n} G1 X{tx:.3} Y{ty:.3}\n");
                (x, y) = (
                    (tx * 1000.0).round() / 1000.0,
                    (ty * 1000.0).round() / 1000.0,
                );
            }
            Seg::Arc(i, j, t) => {
                let (i, j) = ((i * 1000.0).round() / 1000.0, (j * 1000.0).round() / 1000.0);
                let (cx, cy) = (x + i, y + j);
                let a = (y - cy).datan2(x - cx) + t;
                let rr = i.dhypot(j);
                let (ex, ey) = (cx + rr * a.dcos(), cy + rr * a.dsin());
                let g = if t >= 0.0 { 3 } else { 2 };
                s += &format!("N{n} G{g} X{ex:.3} Y{ey:.3} I{i:.3} J{j:.3}\n");
                (x, y) = (
                    (ex * 1000.0).round() / 1000.0,
                    (ey * 1000.0).round() / 1000.0,
                );
            }
            Seg::Z(z) => s += &format!("N{n} Z{z:.3}\n"),
        }
    }
    let n = segs.len() + 4;
    s += &format!("N{n} G1 G40 X-60. Y60.\nN{} M30\n", n + 1);
    s
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

    #[test]
    fn random_contours_never_panic_and_radius_zero_is_the_programmed_path(
        segs in proptest::collection::vec(seg(), 1..10),
        left in proptest::bool::ANY,
        r in -15.0..15.0f64,
        arcs in proptest::bool::ANY,
    ) {
        let o = opts(if arcs { Corners::Arc } else { Corners::Intersection });
        let (prog, _) = compile(&mill(), "p", &contour(&segs, left, r));
        let prog = prog.expect("generated programs compile");
        match plan(&prog, o) {
            Ok(p) => {
                for c in &p.blocks {
                    proptest::prop_assert!(c.end.iter().all(|(_, v)| v.is_finite()), "{c:?}");
                    proptest::prop_assert!(c.center.iter().all(|(_, v)| v.is_finite()), "{c:?}");
                }
            }
            Err((_, d)) => proptest::prop_assert!(
                matches!(d.code, 2503 | 2510 | 2511 | 2512), "unexpected {d}"
            ),
        }
        // With radius 0 the compensated plan is the programmed one.
        let (zero, _) = compile(&mill(), "p", &contour(&segs, left, 0.0));
        let (off, _) = compile(&mill(), "p", &contour(&segs, left, 0.0).replace("G41 D1", "G40 D1").replace("G42 D1", "G40 D1"));
        let (zero, off) = (zero.expect("compiles"), off.expect("compiles"));
        match (plan(&zero, o), plan(&off, o)) {
            // The modal records differ (G41/G42 against G40); everything else is the same.
            (Ok(a), Ok(b)) => proptest::prop_assert_eq!(without_modal(a.blocks), without_modal(b.blocks)),
            (Err((_, a)), Err((_, b))) => proptest::prop_assert_eq!(a.code, b.code),
            (a, b) => proptest::prop_assert!(false, "differ: {:?} / {:?}", a.err().map(|e| e.1), b.err().map(|e| e.1)),
        }
    }
}

#[test]
fn fanuc_g71_cylinder_compensation_offsets_c_on_the_development() {
    // FX-17 (004:22–54) made concrete: G7.1 C40 (development 40·π/180 mm per degree), G41 with a 5 mm
    // cutter radius from C0 Z50 onto the contour at C0 Z15, one cut to Z−60, G40 back to Z50. The
    // left of −Z is +C: 5 mm = 5·180/(40·π) = 7.161972° of C.
    let mut m = MachineSpec::new(Dialect::Fanuc, &['X', 'Z', 'C']);
    m.diameter_x = true;
    let src = "O2\nG10 L12 P7 R5.\nG0 X80 Z50\nG19 W0 H0\nG1 G7.1 C40\n\
               G94 G41 C0 Z15 D07 F2000\nZ-60\nG40 Z50\nG7.1 C0\nG18\nM30\n";
    let p = run(&m, src, PlanOptions::default());
    let path: Vec<(f64, f64, f64)> = p
        .blocks
        .iter()
        .filter(|c| c.kind == Kind::Linear)
        .map(|c| (end(c, 'X'), end(c, 'Z'), end(c, 'C')))
        .collect();
    assert_eq!(
        path,
        vec![(80.0, 15.0, 7.162), (80.0, -60.0, 7.162), (80.0, 50.0, 0.0)]
    );
}
