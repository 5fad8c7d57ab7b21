//! The geometry `nc plan` computes and `nc check` checks: threads and their run-out, radius
//! compensation (corners, equidistants, gouges), planes, arcs.

use super::*;

#[test]
fn plan_cuts_the_lathe_thread_with_the_run_out_of_machine_constant_8() {
    // plc-programs/lathe/nc/CONSTANTS: R8 = 04000.000, the run-out slope is in R04 (= 120.0: X, +20°).
    let out = ncplc(&["nc", "plan", "plc-programs/lathe", "THREAD"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let threads: Vec<(f64, f64)> = json_lines(&out.stdout)
        .iter()
        .filter(|v| v["thread"] == true)
        .map(|v| {
            let x = v["end"]["X"].as_f64().unwrap_or(f64::NAN) - LATHE_G54[0];
            let z = v["end"]["Z"].as_f64().unwrap_or(f64::NAN) - LATHE_G54[1];
            (um(x), z)
        })
        .collect();
    // 64 + 2·12·tan 20° = 72.735 at the end of the 12 mm run-out.
    assert_eq!(threads, vec![(64.0, -88.0), (72.735, -100.0)]);
}

/// (N, kind, X, Y, feed) of the motion blocks of a JSON plan of the mill, X and Y in the G54 frame.
fn xy_path(lines: &[serde_json::Value]) -> Vec<(u64, String, f64, f64, f64)> {
    lines
        .iter()
        .filter(|v| v["kind"] != "aux" && v["kind"] != "dwell")
        .map(|v| {
            (
                v["n"].as_u64().unwrap_or(0),
                v["kind"].as_str().unwrap_or("").to_string(),
                v["end"]["X"].as_f64().unwrap_or(f64::NAN) - MILL_G54[0],
                v["end"]["Y"].as_f64().unwrap_or(f64::NAN) - MILL_G54[1],
                v["feed"].as_f64().unwrap_or(0.0),
            )
        })
        .collect()
}

#[test]
fn plan_applies_radius_compensation_in_both_corner_modes() {
    // nc/CONTOUR: a 40 × 40 square with the corner (40, 40) rounded R10, G41 with D1 = 5 mm.
    let out = ncplc(&["nc", "plan", "plc-programs/mill", "CONTOUR"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines = json_lines(&out.stdout);
    let s = |n: u64, k: &str, x: f64, y: f64, f: f64| (n, k.to_string(), x, y, f);
    let head = vec![
        s(20, "rapid", -20.0, -20.0, 0.0),
        s(30, "rapid", -20.0, -20.0, 0.0),
        s(40, "linear", -5.0, 0.0, 200.0),
    ];
    let mut arcs = head.clone();
    arcs.extend([
        s(50, "linear", -5.0, 40.0, 200.0),
        s(60, "arc_cw", 0.0, 45.0, 200.0),
        s(60, "linear", 30.0, 45.0, 200.0),
        // G2 with G41: the tool centre runs on R 15 at F·15/10.
        s(70, "arc_cw", 45.0, 30.0, 300.0),
        s(80, "linear", 45.0, 0.0, 200.0),
        s(90, "arc_cw", 40.0, -5.0, 200.0),
        s(90, "linear", 0.0, -5.0, 200.0),
        s(100, "linear", -20.0, -20.0, 200.0),
        s(110, "rapid", -20.0, -20.0, 0.0),
    ]);
    assert_eq!(xy_path(&lines), arcs);
    let centre = &lines[4]["center"];
    assert_eq!(
        (centre["X"].as_f64(), centre["Y"].as_f64()),
        (Some(MILL_G54[0]), Some(40.0 + MILL_G54[1]))
    );
    let out = ncplc(&[
        "nc",
        "plan",
        "plc-programs/mill",
        "CONTOUR",
        "--corners",
        "intersection",
    ]);
    assert!(out.status.success());
    let mut meet = head;
    meet.extend([
        s(50, "linear", -5.0, 45.0, 200.0),
        s(60, "linear", 30.0, 45.0, 200.0),
        s(70, "arc_cw", 45.0, 30.0, 300.0),
        s(80, "linear", 45.0, -5.0, 200.0),
        s(90, "linear", 0.0, -5.0, 200.0),
        s(100, "linear", -20.0, -20.0, 200.0),
        s(110, "rapid", -20.0, -20.0, 0.0),
    ]);
    assert_eq!(xy_path(&json_lines(&out.stdout)), meet);
}

#[test]
fn plan_reports_equidistants_not_found_with_code_2510() {
    let dir = tempfile::tempdir().expect("tempdir");
    let p = dir.path().join("inside");
    std::fs::write(
        &p,
        "%1\nN10 G92 D1 R0=5.\nN20 G0 X-10 Y0\nN30 G1 G41 D1 X0 Y0 F100\nN40 X10\n\
         N50 G3 X2 Y8 I-8 J0\nN60 G1 G40 X-10 Y8\nN70 M30\n",
    )
    .expect("program");
    let out = ncplc(&[
        "nc",
        "plan",
        "plc-programs/mill",
        p.to_str().unwrap_or_default(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let diags = json_lines(&out.stderr);
    assert_eq!(diags.len(), 1);
    assert_eq!(
        (diags[0]["code"].as_u64(), diags[0]["line"].as_u64()),
        (Some(2510), Some(5))
    );
    assert_eq!(
        diags[0]["message"],
        "radius compensation: intersection of equidistants not found between N40 and N50"
    );
}

#[test]
fn plan_reports_a_gouge_with_code_2512() {
    // A slot 4 mm wide with a 10 mm tool (G41, radius 5): the bottom N60 would run from (15, −15) back
    // to (9, −15).
    let dir = tempfile::tempdir().expect("tempdir");
    let p = dir.path().join("slot");
    std::fs::write(
        &p,
        "%1\nN10 G92 D1 R0=5.\nN20 G0 X-10 Y10\nN30 G1 G41 D1 X0 Y0 F100\nN40 X10\nN50 Y-20\n\
         N60 X14\nN70 Y0\nN80 X30\nN90 G40 X40 Y10\nN100 M30\n",
    )
    .expect("program");
    let out = ncplc(&[
        "nc",
        "plan",
        "plc-programs/mill",
        p.to_str().unwrap_or_default(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let diags = json_lines(&out.stderr);
    assert_eq!(diags.len(), 1);
    assert_eq!(
        (diags[0]["code"].as_u64(), diags[0]["line"].as_u64()),
        (Some(2512), Some(7))
    );
    assert_eq!(
        diags[0]["message"],
        "radius compensation: interference (gouge) at N60: the compensated line from X15.0000 \
         Y-15.0000 to X9.0000 Y-15.0000 runs against its programmed direction before N70; the tool \
         radius 5.0000 does not fit"
    );
}

#[test]
fn check_and_plan_reject_g14_on_the_three_axis_mill_with_code_2036() {
    // The example mill has X, Y, Z: G14 (MC 341 pair 1 = axes 3 and 4) has no 4th axis.
    let dir = tempfile::tempdir().expect("tempdir");
    let p = dir.path().join("g14");
    std::fs::write(&p, "%1\nN10 G0 X0\nN20 G14\nN30 M30\n").expect("program");
    for cmd in ["check", "plan"] {
        let out = ncplc(&[
            "nc",
            cmd,
            "plc-programs/mill",
            p.to_str().unwrap_or_default(),
            "--format",
            "json",
        ]);
        assert_eq!(out.status.code(), Some(1), "{cmd}");
        assert!(out.stdout.is_empty(), "{cmd}: nothing planned");
        let diags = json_lines(&out.stderr);
        assert_eq!(diags.len(), 1, "{cmd}");
        assert_eq!(
            (
                diags[0]["code"].as_u64(),
                diags[0]["line"].as_u64(),
                diags[0]["column"].as_u64()
            ),
            (Some(2036), Some(3), Some(5)),
            "{cmd}"
        );
        assert_eq!(
            diags[0]["message"],
            "G14 selects the correction plane of axes 3 and 4 (machine constant 341 pair 1), but the \
             process has 3 axes (XYZ)"
        );
    }
}

#[test]
fn plan_runs_the_lathe_thread_cycle_g84_from_pevnecy5() {
    let out = ncplc(&[
        "nc",
        "plan",
        "plc-programs/lathe",
        "G84THREAD",
        "--format",
        "json",
    ]);
    assert!(
        out.status.success() && out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines = json_lines(&out.stdout);
    let threads: Vec<(u64, f64, f64, f64)> = lines
        .iter()
        .filter(|v| v["unit"] == "L84" && v["thread"] == true)
        .map(|v| {
            (
                v["n"].as_u64().unwrap_or(0),
                um(v["end"]["X"].as_f64().unwrap_or(f64::NAN) - LATHE_G54[0]),
                um(v["end"]["Z"].as_f64().unwrap_or(f64::NAN) - LATHE_G54[1]),
                v["feed"].as_f64().unwrap_or(f64::NAN),
            )
        })
        .collect();
    // Chips 0.623, 0.498, 0.398 on the diameter from Ø20 (first chip 1.840/2.952 truncated), then
    // R23 + 1 = 2 passes at Ø18.16; lead R26 = 1.5 mm at S500 = 750 mm/min.
    assert_eq!(
        threads,
        vec![
            (6, 19.377, -30.0, 750.0),
            (6, 18.879, -30.0, 750.0),
            (6, 18.481, -30.0, 750.0),
            (10, 18.16, -30.0, 750.0),
            (10, 18.16, -30.0, 750.0),
        ]
    );
    assert_eq!(lines.iter().filter(|v| v["unit"] == "L84").count(), 20);
    // The alternating variant plans the same with the interpreter.
    let a = ncplc(&["nc", "plan", "plc-programs/lathe", "G84ALTERN"]);
    let b = ncplc(&[
        "nc",
        "plan",
        "plc-programs/lathe",
        "G84ALTERN",
        "--interpreter",
    ]);
    assert!(a.status.success() && b.status.success());
    assert_eq!(a.stdout, b.stdout);
}

/// `nc check` runs the geometric checks of `nc plan`: an arc whose end point is not on its circle
/// is refused by both, as E2503 with a hint (issue 12, item 5).
#[test]
fn check_refuses_an_arc_whose_end_point_is_off_its_circle() {
    let dir = tempfile::tempdir().expect("temp dir");
    copy_machine("mill", dir.path());
    // Start (0,0), centre (3,0): radius 3 at the start, 7 at the end point (10,0).
    std::fs::write(
        dir.path().join("nc/ARC"),
        "%1\nN1 G0 X0 Y0\nN2 G2 X10 Y0 I3 J0 F100\nN3 M30\n",
    )
    .expect("write");
    let d = dir.path().display().to_string();
    for cmd in ["check", "plan"] {
        let out = ncplc(&["nc", cmd, &d, "ARC", "--format", "json"]);
        assert_eq!(out.status.code(), Some(1), "{cmd}");
        let lines = json_lines(&out.stderr);
        assert_eq!(lines.len(), 1, "{cmd}: {lines:?}");
        let e = &lines[0];
        assert_eq!(
            (
                e["code"].as_u64(),
                e["file"].as_str(),
                e["line"].as_u64(),
                e["column"].as_u64(),
                e["message"].as_str(),
                e["hint"].as_str(),
            ),
            (
                Some(2503),
                Some(format!("{d}/nc/ARC").as_str()),
                Some(3),
                Some(1),
                Some(
                    "end point is not on the circle (error 7.56): start radius 3.0000, end radius 7.0000"
                ),
                Some(
                    "the end point must be as far from the centre (I, J, K, relative to the start \
                     point) as the start point is, within 0.002 mm; correct the end point or the centre"
                ),
            ),
            "{cmd}"
        );
    }
}
