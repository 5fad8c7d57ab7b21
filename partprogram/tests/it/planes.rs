//! MEFI correction planes G14, G15, G16 (machine constant 341, structure spec §13.7): the located
//! errors on machines without the 4th axis (2036 at compile time, 2513 for a computed `GR<n>`), and on
//! a machine with a 4th axis A the plane's axes, an arc and radius compensation in the Z/A plane with
//! hand-computed coordinates.

use crate::common;

use common::*;
use partprogram::{Dialect, Kind, MachineSpec, PlanOptions, compile, plan};

/// A MEFI mill with a 4th axis A.
fn mill4() -> MachineSpec {
    MachineSpec::new(Dialect::Mefi, &['X', 'Y', 'Z', 'A'])
}

/// (code, line, column, message) of every compile diagnostic.
fn diags(m: &MachineSpec, src: &str) -> Vec<(u32, u32, u32, String)> {
    let (_, d) = compile(m, "test", src);
    d.into_iter()
        .map(|d| (d.code, d.line, d.column, d.message))
        .collect()
}

#[test]
fn g14_to_g16_without_a_4th_axis_are_compile_errors_at_the_g_word() {
    let src = "%1\nN10 G0 X0\nN20 G14\nN30 X1 G15\nN40 G16\nN50 M30\n";
    assert_eq!(
        diags(&mill(), src),
        vec![
            (
                2036,
                3,
                5,
                "G14 selects the correction plane of axes 3 and 4 (machine constant 341 pair 1), but \
                 the process has 3 axes (XYZ)"
                    .to_string()
            ),
            (
                2036,
                4,
                8,
                "G15 selects the correction plane of axes 2 and 4 (machine constant 341 pair 2), but \
                 the process has 3 axes (XYZ)"
                    .to_string()
            ),
            (
                2036,
                5,
                5,
                "G16 selects the correction plane of axes 4 and 1 (machine constant 341 pair 3), but \
                 the process has 3 axes (XYZ)"
                    .to_string()
            ),
        ]
    );
    // G14 is no Fanuc/HAAS G function.
    let haas = MachineSpec::new(Dialect::Fanuc, &['X', 'Y', 'Z', 'A']);
    assert_eq!(codes(&haas, "O1\nG14\nM30\n"), vec![2015]);
    // The lathe has two axes: no axis 3 or 4.
    assert_eq!(codes(&lathe(), "%1\nN10 G14\nN20 M30\n"), vec![2036]);
    // G17–G19 stay valid.
    assert_eq!(
        codes(&mill(), "%1\nN10 G18\nN20 G19\nN30 G17\nN40 M30\n"),
        Vec::<u32>::new()
    );
}

#[test]
fn computed_g14_without_a_4th_axis_is_a_run_time_error_at_the_block() {
    let (prog, d) = compile(
        &mill(),
        "test",
        "%1\nN10 R10=14\nN20 G0 X5\nN30 GR10\nN40 M30\n",
    );
    assert!(d.is_empty(), "{d:?}");
    let Some(prog) = prog else { panic!("compiles") };
    match plan(&prog, PlanOptions::default()) {
        Ok(_) => panic!("planned"),
        Err((blocks, e)) => {
            assert_eq!((e.code, e.line), (2513, 4));
            // The blocks before it are kept.
            assert_eq!(blocks.len(), 1);
        }
    }
}

#[test]
fn machine_constant_341_pairs_and_defaults() {
    let mut m = mill4();
    assert_eq!(
        [14, 15, 16].map(|g| m.plane_341(g)),
        [(3, 4), (2, 4), (4, 1)]
    );
    assert_eq!(
        [14, 15, 16].map(|g| m.plane_341_axes(g)),
        [Ok(('Z', 'A')), Ok(('Y', 'A')), Ok(('A', 'X'))]
    );
    // `R341: 00412.434` is the default written out; pair 00 keeps its default.
    m.set_constant(341, 412_434).expect("341");
    assert_eq!(
        [14, 15, 16].map(|g| m.plane_341(g)),
        [(3, 4), (2, 4), (4, 1)]
    );
    m.set_constant(341, 14).expect("341");
    assert_eq!(
        [14, 15, 16].map(|g| m.plane_341(g)),
        [(1, 4), (2, 4), (4, 1)]
    );
    assert_eq!(m.plane_341_axes(14), Ok(('X', 'A')));
    // A pair naming axis 5 on a 4-axis process.
    m.set_constant(341, 5100).expect("341");
    assert!(m.plane_341_axes(15).is_err());
    assert_eq!(
        codes(&m, "%1\nN10 G15\nN20 G14\nN30 M30\n"),
        vec![2036],
        "only G15 names a missing axis"
    );
}

#[test]
fn g14_arc_in_the_z_a_plane() {
    // I runs along Z, J along A: G03 from (Z10, A0) to (Z20, A10) about (Z10, A10).
    let src = "%1\nN10 G0 Z0 A0\nN20 G14 G1 Z10 F100\nN30 G3 Z20 A10 I0 J10\nN40 M30\n";
    let p = run(&mill4(), src, PlanOptions::default());
    let arc = &p.blocks[2];
    assert_eq!((arc.n, arc.kind), (Some(30), Kind::ArcCcw));
    assert_eq!(arc.center, vec![('Z', 10.0), ('A', 10.0)]);
    assert_eq!((end(arc, 'Z'), end(arc, 'A')), (20.0, 10.0));
    assert!(
        arc.to_json_line().contains("\"plane\":\"ZA\""),
        "{}",
        arc.to_json_line()
    );
    // N10 before G14 is in the G17 plane.
    assert!(p.blocks[0].to_json_line().contains("\"plane\":\"XY\""));
}

#[test]
fn g14_radius_compensation_offsets_in_the_z_a_plane() {
    // G41, radius 2: start-up onto (Z0, A2), inside corner at the intersection (Z8, A2), cancel on
    // the perpendicular (Z8, A10). X and Y are untouched.
    let src = "%1\nN10 G92 D1 R0=2.\nN20 G14\nN30 G0 Z-10 A0\nN40 G1 G41 D1 Z0 A0 F100\nN50 Z10\n\
               N60 A10\nN70 G40 Z20 A10\nN80 M30\n";
    let p = run(&mill4(), src, PlanOptions::default());
    let path: Vec<(Option<u32>, f64, f64, f64)> = p
        .blocks
        .iter()
        .filter(|c| matches!(c.kind, Kind::Rapid | Kind::Linear))
        .map(|c| (c.n, end(c, 'Z'), end(c, 'A'), end(c, 'X')))
        .collect();
    assert_eq!(
        path,
        vec![
            (Some(30), -10.0, 0.0, 0.0),
            (Some(40), 0.0, 2.0, 0.0),
            (Some(50), 8.0, 2.0, 0.0),
            (Some(60), 8.0, 10.0, 0.0),
            (Some(70), 20.0, 10.0, 0.0),
        ]
    );
    // Switching from G17 to G14 while G41 is active breaks rule 2511.
    let (prog, _) = compile(
        &mill4(),
        "test",
        "%1\nN10 G92 D1 R0=2.\nN20 G1 G41 D1 X10 Y0 F100\nN30 X20\nN40 G14 Z5 A5\nN50 M30\n",
    );
    let Some(prog) = prog else { panic!("compiles") };
    let Err((_, e)) = plan(&prog, PlanOptions::default()) else {
        panic!("planned")
    };
    assert_eq!((e.code, e.line), (2511, 5));
}
