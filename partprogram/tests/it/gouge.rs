//! Interference (gouge) check of tool radius compensation (error 2512), with hand-computed coordinates:
//! a step lower than the tool radius between two inside/outside corners, a slot narrower than the tool
//! diameter, an arc eaten by its two inside corners, the same slot in the Fanuc dialect, near misses
//! (a slot 2 µm wider than the tool, a shallower arc) that plan unchanged, and a property: a slot gouges
//! exactly when it is not wider than the tool.

use crate::common;

use common::*;
use partprogram::radius::{Corners, RadiusOptions};
use partprogram::{Dialect, Kind, MachineSpec, Plan, PlanOptions, compile, plan};

use Kind::{ArcCcw as Ccw, ArcCw as Cw, Linear as Lin, Rapid};

/// (N, kind, X, Y, arc centre) of every motion block, µm-rounded.
type Step = (Option<u32>, Kind, f64, f64, Option<(f64, f64)>);

fn steps(p: &Plan) -> Vec<Step> {
    p.blocks
        .iter()
        .filter(|c| matches!(c.kind, Rapid | Lin | Cw | Ccw))
        .map(|c| {
            let centre = (!c.center.is_empty()).then(|| {
                let get = |a: char| {
                    c.center
                        .iter()
                        .find(|x| x.0 == a)
                        .map_or(f64::NAN, |x| um(x.1))
                };
                (get('X'), get('Y'))
            });
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

/// Plans and returns the located error (code, line, message).
fn fails(m: &MachineSpec, src: &str, o: PlanOptions) -> (u32, u32, String) {
    let (prog, diags) = compile(m, "test", src);
    let Some(prog) = prog else {
        panic!("compile failed: {diags:#?}")
    };
    match plan(&prog, o) {
        Ok(p) => panic!("planned without error: {:?}", steps(&p)),
        Err((_, d)) => {
            // `nc check` runs the program without keeping the plan: the same error.
            assert_eq!(partprogram::check_plan(&prog, o), Err(d.clone()));
            (d.code, d.line, d.message)
        }
    }
}

/// G41 (tool on the left, above) along Y0, up a 2 mm step at X10 (N50), on along Y2; tool radius 5.
const STEP: &str = "%1\nN10 G92 D1 R0=5.\nN20 G0 X-20 Y10\nN30 G1 G41 D1 X0 Y0 F100\nN40 X10\n\
N50 Y2\nN60 X30\nN70 G40 X40 Y20\nN80 M30\n";

#[test]
fn step_lower_than_the_radius_gouges_with_inserted_arcs() {
    // N40→N50 turns left (inside): equidistants Y5 and X5 meet at (5, 5). N50→N60 turns right
    // (outside): with an inserted arc N50 ends on its perpendicular (5, 2), 3 mm back down the wall —
    // the tool would cut 3 mm below the floor Y0.
    assert_eq!(
        fails(&mill(), STEP, opts(Corners::Arc)),
        (
            2512,
            6,
            "radius compensation: interference (gouge) at N50: the compensated line from X5.0000 \
             Y5.0000 to X5.0000 Y2.0000 runs against its programmed direction before N60; the tool \
             radius 5.0000 does not fit"
                .to_string()
        )
    );
}

#[test]
fn step_lower_than_the_radius_rides_over_it_in_intersection_mode() {
    // The outside corner N50→N60 is the intersection of X5 and Y7: N50 runs (5, 5)→(5, 7), forward.
    let p = run(&mill(), STEP, opts(Corners::Intersection));
    assert_eq!(
        steps(&p),
        vec![
            (Some(20), Rapid, -20.0, 10.0, None),
            (Some(30), Lin, 0.0, 5.0, None),
            (Some(40), Lin, 5.0, 5.0, None),
            (Some(50), Lin, 5.0, 7.0, None),
            (Some(60), Lin, 30.0, 7.0, None),
            (Some(70), Lin, 40.0, 20.0, None),
        ]
    );
}

/// A slot of width `w` from X10 down to Y−20 with the tool (radius 5, G41) inside it.
fn slot(w: &str) -> String {
    format!(
        "%1\nN10 G92 D1 R0=5.\nN20 G0 X-10 Y10\nN30 G1 G41 D1 X0 Y0 F100\nN40 X10\nN50 Y-20\n\
         N60 X{w}\nN70 Y0\nN80 X30\nN90 G40 X40 Y10\nN100 M30\n"
    )
}

#[test]
fn slot_narrower_than_the_tool_gouges_at_its_bottom_in_both_modes() {
    // Bottom N60 (X10→X14, width 4 < diameter 10): its corners are the intersections (15, −15) and
    // (14 − 5, −15) = (9, −15), so the compensated bottom runs 6 mm in −X.
    for mode in [Corners::Arc, Corners::Intersection] {
        let (code, line, msg) = fails(&mill(), &slot("14"), opts(mode));
        assert_eq!((code, line), (2512, 7), "{mode:?}");
        assert!(
            msg.contains("N60: the compensated line from X15.0000 Y-15.0000 to X9.0000 Y-15.0000 runs against"),
            "{msg}"
        );
    }
}

#[test]
fn slot_as_wide_as_the_tool_collapses_the_bottom() {
    // Width 10 = diameter: the bottom shrinks to the point (15, −15).
    let (code, line, msg) = fails(&mill(), &slot("20"), PlanOptions::default());
    assert_eq!((code, line), (2512, 7));
    assert!(
        msg.contains("from X15.0000 Y-15.0000 to X15.0000 Y-15.0000 has no length left"),
        "{msg}"
    );
}

#[test]
fn slot_two_microns_wider_than_the_tool_is_not_flagged() {
    // Near miss: width 10.002, the bottom keeps 2 µm; outside corners get arcs about (10, 0) and
    // (20.002, 0).
    let p = run(&mill(), &slot("20.002"), PlanOptions::default());
    assert_eq!(
        steps(&p),
        vec![
            (Some(20), Rapid, -10.0, 10.0, None),
            (Some(30), Lin, 0.0, 5.0, None),
            (Some(40), Lin, 10.0, 5.0, None),
            (Some(50), Cw, 15.0, 0.0, Some((10.0, 0.0))),
            (Some(50), Lin, 15.0, -15.0, None),
            (Some(60), Lin, 15.002, -15.0, None),
            (Some(70), Lin, 15.002, 0.0, None),
            (Some(80), Cw, 20.002, 5.0, Some((20.002, 0.0))),
            (Some(80), Lin, 30.0, 5.0, None),
            (Some(90), Lin, 40.0, 10.0, None),
        ]
    );
}

/// A quarter circle G03 of radius 10 about the origin (N50) between a line along Y0 and a line down
/// X0, both joining it at inside corners for G41 with tool radius `r`.
fn eaten_arc(r: &str) -> String {
    format!(
        "%1\nN10 G92 D1 R0={r}\nN20 G0 X-20 Y-10\nN30 G1 G41 D1 X-10 Y0 F100\nN40 X10\n\
         N50 G3 X0 Y10 I-10 J0\nN60 G1 Y2\nN70 G40 X-10 Y-10\nN80 M30\n"
    )
}

#[test]
fn arc_eaten_by_its_inside_corners_gouges() {
    // r = 4.8: the equidistant circle has radius 5.2; Y4.8 meets it at (2, 4.8), X4.8 at (4.8, 2).
    // The compensated G03 would run from 67.380° back to 22.620°: −44.760° instead of 90°.
    let (code, line, msg) = fails(&mill(), &eaten_arc("4.8"), PlanOptions::default());
    assert_eq!((code, line), (2512, 6));
    assert_eq!(
        msg,
        "radius compensation: interference (gouge) at N50: the compensated arc from X2.0000 Y4.8000 \
         to X4.8000 Y2.0000 sweeps -44.760° instead of the programmed 90.000° before N60; the tool \
         radius 4.8000 does not fit"
    );
}

#[test]
fn arc_with_a_smaller_tool_keeps_its_sweep() {
    // r = 3.2: circle radius 6.8 meets Y3.2 at (6, 3.2) and X3.2 at (3.2, 6); feed 100·6.8/10.
    let p = run(&mill(), &eaten_arc("3.2"), PlanOptions::default());
    assert_eq!(
        steps(&p),
        vec![
            (Some(20), Rapid, -20.0, -10.0, None),
            (Some(30), Lin, -10.0, 3.2, None),
            (Some(40), Lin, 6.0, 3.2, None),
            (Some(50), Ccw, 3.2, 6.0, Some((0.0, 0.0))),
            (Some(60), Lin, 3.2, 2.0, None),
            (Some(70), Lin, -10.0, -10.0, None),
        ]
    );
    assert_eq!(p.blocks[3].feed.map(um), Some(68.0));
}

#[test]
fn gouge_at_program_end_without_g40() {
    // Without G40 the last element N60 ends on its perpendicular (14, −15), from (15, −15): reversed.
    let src = "%1\nN10 G92 D1 R0=5.\nN20 G0 X-10 Y10\nN30 G1 G41 D1 X0 Y0 F100\nN40 X10\nN50 Y-20\n\
               N60 X14\nN70 M30\n";
    let (code, line, msg) = fails(&mill(), src, PlanOptions::default());
    assert_eq!((code, line), (2512, 7));
    assert!(
        msg.ends_with("to X14.0000 Y-15.0000 runs against its programmed direction at the end of the program; the tool radius 5.0000 does not fit"),
        "{msg}"
    );
}

fn haas() -> MachineSpec {
    MachineSpec::new(Dialect::Fanuc, &['X', 'Y', 'Z'])
}

#[test]
fn fanuc_slot_narrower_than_the_tool_gouges() {
    // The slot of the MEFI test with D1 = 5 set by G10 L12: the bottom X14 (line 7) runs backwards.
    let src = "O1\nG10 L12 P1 R5.\nG0 X-10 Y10\nG1 G41 D1 X0 Y0 F100\nX10\nY-20\nX14\nY0\nX30\n\
               G40 X40 Y10\nM30\n";
    let (code, line, msg) = fails(&haas(), src, PlanOptions::default());
    assert_eq!((code, line), (2512, 7));
    assert!(
        msg.contains("the compensated line from X15.0000 Y-15.0000 to X9.0000 Y-15.0000"),
        "{msg}"
    );
    // 2 µm wider: planned, bottom from (15, −15) to (15.002, −15).
    let wide = src.replace("X14\n", "X20.002\n");
    let p = run(&haas(), &wide, PlanOptions::default());
    let bottom: Vec<(f64, f64)> = p
        .blocks
        .iter()
        .filter(|c| c.kind == Lin)
        .map(|c| (end(c, 'X'), end(c, 'Y')))
        .collect();
    assert_eq!(
        bottom,
        vec![
            (0.0, 5.0),
            (10.0, 5.0),
            (15.0, -15.0),
            (15.002, -15.0),
            (15.002, 0.0),
            (30.0, 5.0),
            (40.0, 10.0)
        ]
    );
}

#[test]
fn fanuc_step_gouges_and_a_step_two_microns_higher_than_the_radius_does_not() {
    // The MEFI step in the Fanuc dialect: the wall (line 6) runs back from (5, 5) to (5, 2).
    let src =
        "O1\nG10 L12 P1 R5.\nG0 X-20 Y10\nG1 G41 D1 X0 Y0 F100\nX10\nY2\nX30\nG40 X40 Y20\nM30\n";
    let (code, line, _) = fails(&haas(), src, PlanOptions::default());
    assert_eq!((code, line), (2512, 6));
    // Step 5.002: the wall keeps 2 µm, (5, 5)→(5, 5.002), then the arc about (10, 5.002).
    let high = src.replace("Y2\n", "Y5.002\n");
    let p = run(&haas(), &high, PlanOptions::default());
    let path: Vec<(Kind, f64, f64)> = p
        .blocks
        .iter()
        .filter(|c| matches!(c.kind, Lin | Cw | Ccw))
        .map(|c| (c.kind, end(c, 'X'), end(c, 'Y')))
        .collect();
    assert_eq!(
        path,
        vec![
            (Lin, 0.0, 5.0),
            (Lin, 5.0, 5.0),
            (Lin, 5.0, 5.002),
            (Cw, 10.0, 10.002),
            (Lin, 30.0, 10.002),
            (Lin, 40.0, 20.0)
        ]
    );
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

    /// The slot of width w (0.5..19.9 mm) and a tool of radius r (0.5..9.9 mm), both in µm: the bottom
    /// keeps w − 2r, so the plan fails with 2512 at N60 exactly when w ≤ 2r, in both corner modes.
    #[test]
    fn slot_gouges_exactly_when_it_is_not_wider_than_the_tool(
        w_um in 500u32..19_900,
        r_um in 500u32..9_900,
        arcs in proptest::bool::ANY,
    ) {
        let (w, r) = (f64::from(w_um) / 1000.0, f64::from(r_um) / 1000.0);
        let src = slot(&format!("{:.3}", 10.0 + w)).replace("R0=5.", &format!("R0={r:.3}"));
        let (prog, d) = compile(&mill(), "p", &src);
        let prog = prog.ok_or_else(|| proptest::test_runner::TestCaseError::fail(format!("{d:?}")))?;
        let mode = if arcs { Corners::Arc } else { Corners::Intersection };
        match plan(&prog, opts(mode)) {
            Ok(p) => {
                proptest::prop_assert!(w_um > 2 * r_um, "w {w} r {r} planned");
                // The bottom runs from X10 + r to X10 + w − r at Y−20 + r.
                let bottom = p.blocks.iter().find(|c| c.n == Some(60)).map(|c| (end(c, 'X'), end(c, 'Y')));
                proptest::prop_assert_eq!(bottom, Some((um(10.0 + w - r), um(-20.0 + r))));
            }
            Err((_, e)) => {
                proptest::prop_assert!(w_um <= 2 * r_um, "w {w} r {r}: {e}");
                proptest::prop_assert_eq!((e.code, e.line), (2512, 7));
            }
        }
    }
}
