//! End-to-end tests of `ncplc nc check` and `ncplc nc plan` on the bundled machines.

use std::path::PathBuf;
use std::process::Command;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn ncplc(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .current_dir(repo())
        .args(args)
        .output()
        .expect("ncplc runs")
}

/// Copies the bundled machine `name` into `to` (characterization files, macros, partprograms).
fn copy_machine(name: &str, to: &std::path::Path) {
    fn copy_dir(from: &std::path::Path, to: &std::path::Path) {
        std::fs::create_dir_all(to).expect("mkdir");
        for entry in std::fs::read_dir(from).expect("read dir") {
            let entry = entry.expect("entry");
            let target = to.join(entry.file_name());
            if entry.file_type().expect("type").is_dir() {
                copy_dir(&entry.path(), &target);
            } else {
                std::fs::copy(entry.path(), &target).expect("copy");
            }
        }
    }
    copy_dir(&repo().join("plc-programs").join(name), to);
}

fn json_lines(out: &[u8]) -> Vec<serde_json::Value> {
    String::from_utf8_lossy(out)
        .lines()
        .map(|l| serde_json::from_str(l).expect("one JSON object per line"))
        .collect()
}

/// G54 of the mill's `MP0/TAB0.POS` (X, Y, Z): machine = programmed + offset. The expected
/// values below are the programs' part coordinates; the plan's machine coordinates less this.
const MILL_G54: [f64; 3] = [-400.0, -250.0, -200.0];
/// G54 of the lathe's `MP0/TAB0.POS` (X in diameter, Z).
const LATHE_G54: [f64; 2] = [-150.0, -300.0];

/// Rounds to the µm of a MEFI coordinate (undoes the rounding of adding an offset).
fn um(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

#[test]
fn plan_grid_macro_writes_twelve_drilling_feeds_in_json() {
    let out = ncplc(&[
        "nc",
        "plan",
        "plc-programs/mill",
        "GRID",
        "--format",
        "json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines = json_lines(&out.stdout);
    let holes: Vec<(f64, f64)> = lines
        .iter()
        .filter(|v| v["unit"] == "L81" && v["kind"] == "linear")
        .map(|v| {
            (
                v["end"]["X"].as_f64().unwrap_or(f64::NAN) - MILL_G54[0],
                v["end"]["Y"].as_f64().unwrap_or(f64::NAN) - MILL_G54[1],
            )
        })
        .collect();
    assert_eq!(holes.len(), 12);
    assert_eq!(holes[4], (300.0, 75.0));
    assert_eq!(holes[11], (300.0, 150.0));
    let first = &lines[0];
    assert_eq!(first["n"], 10);
    assert_eq!(first["kind"], "rapid");
    assert_eq!(first["plane"], "XY");
    assert_eq!(first["m"], serde_json::json!([3]));
    assert_eq!(first["s"], 800.0);
    let drill = lines
        .iter()
        .find(|v| v["kind"] == "linear")
        .expect("a feed move");
    assert_eq!(drill["feed"], 150.0);
    assert_eq!(drill["end"]["Z"], -10.0 + MILL_G54[2]);
}

#[test]
fn native_and_interpreter_plans_are_identical() {
    let a = ncplc(&["nc", "plan", "plc-programs/lathe", "G81ROUGH"]);
    let b = ncplc(&[
        "nc",
        "plan",
        "plc-programs/lathe",
        "G81ROUGH",
        "--interpreter",
    ]);
    assert!(a.status.success() && b.status.success());
    assert_eq!(a.stdout, b.stdout);
    let lines = json_lines(&a.stdout);
    assert_eq!(lines.iter().filter(|v| v["unit"] == "L81").count(), 78);
    assert!(lines.iter().all(|v| v["plane"] == "ZX"));
}

#[test]
fn check_reports_located_json_diagnostics_and_fails() {
    let dir = tempfile::tempdir().expect("tempdir");
    let m = dir.path().join("testmill");
    copy_machine("mill", &m);
    // The mill's IOCFIL declares M03 and M30 but not M07.
    std::fs::write(
        m.join("nc/P1"),
        "%1\nN10 G0 X10 M03\nN20 M07\nN30 G73 L99\nN40 M30\n",
    )
    .expect("program");
    let out = ncplc(&[
        "nc",
        "check",
        m.to_str().unwrap_or_default(),
        "P1",
        "--format",
        "json",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let diags = json_lines(&out.stderr);
    let got: Vec<(u64, u64, u64)> = diags
        .iter()
        .map(|d| {
            (
                d["code"].as_u64().unwrap_or(0),
                d["line"].as_u64().unwrap_or(0),
                d["column"].as_u64().unwrap_or(0),
            )
        })
        .collect();
    assert_eq!(got, vec![(2016, 3, 5), (2018, 4, 1)]);
    let ok = ncplc(&["nc", "check", "plc-programs/mill", "GRID"]);
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
}

#[test]
fn plan_reports_run_time_errors_with_exit_code_1() {
    let dir = tempfile::tempdir().expect("tempdir");
    let p = dir.path().join("bad");
    std::fs::write(&p, "%1\nN10 G0 X1\nN20 R10=123 N30 GR10\nN40 M30\n").expect("program");
    let out = ncplc(&[
        "nc",
        "plan",
        "plc-programs/mill",
        p.to_str().unwrap_or_default(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        json_lines(&out.stdout).len(),
        1,
        "the block before the error is planned"
    );
    assert!(String::from_utf8_lossy(&out.stderr).contains("\"code\":2502"));
}

#[test]
fn fanuc_programs_are_detected_and_planned() {
    // The NC-110 lathe's IOCFIL does not declare M21 (C axis on), so the spec's cylinder
    // interpolation program (FX20, a partprogram test fixture) fails the check there...
    let cylinder = "partprogram/tests/fixtures/O1000-cylinder.nc";
    let out = ncplc(&[
        "nc",
        "check",
        "plc-programs/lathe",
        cylinder,
        "--format",
        "json",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let diags = json_lines(&out.stderr);
    assert_eq!(diags[0]["code"], 2016);
    assert_eq!(
        (diags[0]["line"].as_u64(), diags[0]["column"].as_u64()),
        (Some(3), Some(5))
    );
    // ... and plans on a lathe whose IOCFIL declares M21.
    let dir = tempfile::tempdir().expect("tempdir");
    let m = dir.path().join("fanuclathe");
    copy_machine("lathe", &m);
    let iocfil = std::fs::read_to_string(m.join("MP0/IOCFIL")).expect("IOCFIL");
    let iocfil = iocfil.replacen("M30=", "M21=45,00,44\nM30=", 1);
    assert!(iocfil.contains("M21="), "the lathe's IOCFIL declares M30");
    std::fs::write(m.join("MP0/IOCFIL"), iocfil).expect("IOCFIL");
    let out = ncplc(&["nc", "plan", m.to_str().unwrap_or_default(), cylinder]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines = json_lines(&out.stdout);
    let n120 = lines.iter().find(|v| v["n"] == 120).expect("N120");
    assert_eq!(n120["kind"], "arc_cw");
    assert_eq!(n120["plane"], "YZ");
    // Z-25 in the part frame, G54 (the Fanuc power-up system) Z -300 of the lathe's TAB0.POS.
    assert_eq!(n120["center"]["Z"], -25.0 + LATHE_G54[1]);
    let out = ncplc(&[
        "nc",
        "check",
        "plc-programs/mill",
        "O00023.nc",
        "--dialect",
        "fanuc",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = ncplc(&[
        "nc",
        "check",
        "plc-programs/mill",
        "O00023.nc",
        "--dialect",
        "mefi",
    ]);
    assert_eq!(out.status.code(), Some(1));
}

#[test]
fn plan_uses_the_machines_tab0_kor_for_g43_and_length_correction() {
    // The mill's MP0/TAB0.KOR: H01 has Z length -150, so `G43 H01 Z2.` is machine Z -148.
    let out = ncplc(&["nc", "plan", "plc-programs/mill", "O00050.nc"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines = json_lines(&out.stdout);
    let z = |n: u64| {
        lines
            .iter()
            .filter(|v| v["n"] == n)
            .map(|v| v["end"]["Z"].as_f64().unwrap_or(f64::NAN))
            .collect::<Vec<_>>()
    };
    // Under G54 (TAB0.POS Z -200): -148 - 200.
    assert_eq!(z(15), vec![-148.0 + MILL_G54[2]]);
    assert_eq!(
        z(17),
        vec![-125.0 + MILL_G54[2]],
        "G00 Z25. keeps the length"
    );
    assert_eq!(z(18), vec![0.0], "G53 G49 Z0. is machine zero");
    // MEFI on a copy of the mill: method A by default, method B from nc/CONSTANTS.
    let dir = tempfile::tempdir().expect("tempdir");
    let m = dir.path().join("mill");
    copy_machine("mill", &m);
    std::fs::write(m.join("nc/LEN"), "%1\nN10 G0 X0 Y0 Z0 &1120 D10\nN20 M30\n").expect("program");
    let xyz = |out: &std::process::Output| {
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v = &json_lines(&out.stdout)[0];
        ["X", "Y", "Z"].map(|a| v["end"][a].as_f64().unwrap_or(f64::NAN))
    };
    let machine = m.to_str().unwrap_or_default();
    let a = ncplc(&["nc", "plan", machine, "LEN"]);
    assert_eq!(xyz(&a), [1.5, -2.0, -40.0]);
    // Machine constant 329 decade 7 = 1: method B.
    std::fs::write(m.join("nc/CONSTANTS"), "R329: 01000.000\n").expect("option");
    let b = ncplc(&["nc", "plan", machine, "LEN"]);
    assert_eq!(xyz(&b), [1.5, -2.0, 40.0]);
    // --kor replaces the machine's table.
    let kor = dir.path().join("other.KOR");
    std::fs::write(&kor, "$KOR\n10: Z=7.5\n").expect("kor");
    let k = ncplc(&[
        "nc",
        "plan",
        machine,
        "LEN",
        "--kor",
        kor.to_str().unwrap_or_default(),
    ]);
    assert_eq!(xyz(&k), [0.0, 0.0, 7.5]);
}

/// A bad zero-offset table is a located error of `nc check`, `nc plan` and `nc run` (no motion).
#[test]
fn errors_in_the_zero_offset_table_fail_check_plan_and_run() {
    let dir = tempfile::tempdir().expect("tempdir");
    let m = dir.path().join("lathe");
    copy_machine("lathe", &m);
    // The lathe has no axis Y.
    std::fs::write(
        m.join("MP0/TAB0.POS"),
        "comment\n$POS\nG54: X=-150 Y=-300\n",
    )
    .expect("pos");
    let machine = m.to_str().unwrap_or_default();
    for cmd in ["check", "plan"] {
        let out = ncplc(&["nc", cmd, machine, "G84THREAD", "--format", "json"]);
        assert_eq!(out.status.code(), Some(1), "{cmd}");
        assert!(
            out.stdout.is_empty() || cmd == "check",
            "nothing is planned"
        );
        let diags = json_lines(&out.stderr);
        assert_eq!(
            (
                &diags[0]["code"],
                &diags[0]["file"],
                &diags[0]["line"],
                &diags[0]["column"]
            ),
            (
                &serde_json::json!(2072),
                &serde_json::json!(format!("{machine}/MP0/TAB0.POS")),
                &serde_json::json!(3),
                &serde_json::json!(13)
            ),
            "{cmd}"
        );
    }
    let out = ncplc(&["nc", "run", machine, "G84THREAD"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty(), "nothing runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("error[E2072]: `Y` is not an axis of the machine\n")
            && err.contains("/MP0/TAB0.POS:3:13\n"),
        "{err}"
    );
}

#[test]
fn errors_in_the_correction_table_fail_check_and_plan() {
    let dir = tempfile::tempdir().expect("tempdir");
    let m = dir.path().join("lathe");
    copy_machine("lathe", &m);
    // The lathe's axis 2 is Z: its length must be written `2=`.
    std::fs::write(
        m.join("MP0/TAB0.KOR"),
        "comment\n$KOR\n01: R=0.8 X=0.0 2=0.0\n02: X=1.0 Z=2.0\n",
    )
    .expect("kor");
    let machine = m.to_str().unwrap_or_default();
    for cmd in ["check", "plan"] {
        let out = ncplc(&["nc", cmd, machine, "G81ROUGH", "--format", "json"]);
        assert_eq!(out.status.code(), Some(1), "{cmd}");
        assert!(
            out.stdout.is_empty() || cmd == "check",
            "nothing is planned"
        );
        let diags = json_lines(&out.stderr);
        assert_eq!(diags.len(), 1, "{cmd}");
        assert_eq!(
            (
                &diags[0]["code"],
                &diags[0]["file"],
                &diags[0]["line"],
                &diags[0]["column"]
            ),
            (
                &serde_json::json!(2044),
                // Named as the user can open it from the current directory (here: absolute).
                &serde_json::json!(format!("{machine}/MP0/TAB0.KOR")),
                &serde_json::json!(4),
                &serde_json::json!(11)
            )
        );
    }
    // Without TAB0.KOR the lathe name TAB2.KOR of the manual is read.
    std::fs::rename(m.join("MP0/TAB0.KOR"), m.join("MP0/TAB2.KOR")).expect("rename");
    let out = ncplc(&["nc", "check", machine, "G81ROUGH", "--format", "json"]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        json_lines(&out.stderr)[0]["file"],
        format!("{machine}/MP0/TAB2.KOR")
    );
    // The shipped lathe table is valid and keeps the roughing example's entry 01 without lengths.
    let ok = ncplc(&["nc", "check", "plc-programs/lathe", "G81ROUGH"]);
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
}

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
fn o00023_takes_h03_length_and_d03_radius_from_the_mills_table() {
    // TAB0.KOR entry 03: R=6.0 (the program's "DIA. OFFSET D03 AN 12."), Z=-135.5.
    let out = ncplc(&["nc", "plan", "plc-programs/mill", "O00023.nc"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines = json_lines(&out.stdout);
    let end = |v: &serde_json::Value| {
        // Part coordinates: less G54 of the mill's TAB0.POS.
        let e = |a: &str, i: usize| v["end"][a].as_f64().unwrap_or(f64::NAN) - MILL_G54[i];
        (e("X", 0), e("Y", 1), e("Z", 2))
    };
    // G01 Z-16. F500. after G43 H03: Z -16 - 135.5.
    let plunge = lines
        .iter()
        .position(|v| v["kind"] == "linear" && v["feed"] == 500.0)
        .expect("the end mill plunge");
    assert_eq!(end(&lines[plunge]), (-58.0, 58.0, -151.5));
    // The contour Y50 → X50 → Y-50 … with the tool 6 mm to its left (an arc at the outside corner).
    let contour: Vec<(String, (f64, f64, f64))> = lines[plunge + 1..plunge + 4]
        .iter()
        .map(|v| (v["kind"].as_str().unwrap_or("").to_string(), end(v)))
        .collect();
    assert_eq!(
        contour,
        vec![
            ("linear".to_string(), (-58.0, 56.0, -151.5)),
            ("linear".to_string(), (50.0, 56.0, -151.5)),
            ("arc_cw".to_string(), (56.0, 50.0, -151.5)),
        ]
    );
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

#[test]
fn a_bad_or_unreadable_constants_file_is_an_error_not_ignored() {
    let dir = tempfile::tempdir().expect("tempdir");
    let m = dir.path().join("mill");
    copy_machine("mill", &m);
    let machine = m.to_str().unwrap_or_default();
    let cases: [(&[u8], &str); 3] = [
        (
            b"R8: 0\nR329 01000.000\n",
            "nc/CONSTANTS: line 2: expected `R<n>: <value>`, found `R329 01000.000`",
        ),
        (
            b"R329: 03000.000\n",
            "nc/CONSTANTS: R329: unknown length correction method `3`",
        ),
        // Not UTF-8: once silently skipped, now refused.
        (
            b"R329: 01000.000 \xff\n",
            "nc/CONSTANTS: stream did not contain valid UTF-8",
        ),
    ];
    for (text, want) in cases {
        std::fs::write(m.join("nc/CONSTANTS"), text).expect("constants");
        let out = ncplc(&["nc", "plan", machine, "GRID"]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.contains(want), "{err}");
        assert!(out.stdout.is_empty());
    }
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

/// A one-block program with 20,000 errors: `--max-errors 2` prints two diagnostics of the file
/// (the long-line warning sorts first, then one error, its line as an excerpt), then one note.
#[test]
fn check_caps_the_errors_of_a_one_block_program() {
    let dir = tempfile::tempdir().expect("temp dir");
    copy_machine("mill", dir.path());
    let text = format!("%1\nN1{}\nN2 M30\n", " U1".repeat(20_000));
    std::fs::write(dir.path().join("nc/ONE"), text).expect("write");
    let d = dir.path().display().to_string();
    let out = ncplc(&[
        "nc",
        "check",
        &d,
        "ONE",
        "--max-errors",
        "2",
        "--color",
        "never",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        err.matches("error[E2008]: the machine has no axis U")
            .count(),
        1,
        "{err}"
    );
    assert!(
        err.contains(&format!(
            "= in {d}/nc/ONE:2:4 (a long line): `N1 U1 U1 U1 U1 U1 U1 U1 U1 U1 U1 …`"
        )),
        "{err}"
    );
    assert!(
        err.ends_with(&format!(
            "note: 19999 more errors in {d}/nc/ONE (--max-errors 0 shows all)\n20000 errors, 1 warning\n"
        )),
        "{err}"
    );
}

/// An empty partprogram is one error saying so, without the "no M02/M30" warning.
#[test]
fn check_of_an_empty_partprogram_is_one_error() {
    let dir = tempfile::tempdir().expect("temp dir");
    copy_machine("mill", dir.path());
    std::fs::write(dir.path().join("nc/EMPTY"), "\n").expect("write");
    let d = dir.path().display().to_string();
    let out = ncplc(&["nc", "check", &d, "EMPTY", "--format", "json"]);
    assert_eq!(out.status.code(), Some(1));
    let lines = json_lines(&out.stderr);
    let got: Vec<_> = lines
        .iter()
        .map(|e| {
            (
                e["code"].as_u64(),
                e["line"].as_u64(),
                e["column"].as_u64(),
                e["message"].as_str().map(str::to_string),
            )
        })
        .collect();
    assert_eq!(
        got,
        [(
            Some(2003),
            Some(1),
            Some(1),
            Some("the partprogram is empty".to_string())
        )]
    );
}

#[test]
fn fanuc_issue_14_classes_plan_end_to_end_and_an_unexecuted_word_is_refused() {
    let dir = tempfile::tempdir().expect("tempdir");
    let prog = dir.path().join("O1234.nc");
    std::fs::write(
        &prog,
        "O1234\nG21 G90 G17 G54\nG10 L2 P2 X100. Y50. Z0\nG55 G00 X10. Y0 Z5.\nG01 Z-1. F200.\n\
         G02 I-10.\nG61 G01 X20.\nG64 P0.02 X25.\nG00 Z10.\nG91 G98 G81 X10. Y0 Z-6. R-4. L3 F100.\n\
         G80 G90\nM98 P2001 L2\nG28\nM30\nO2001\nG91 G01 Y1.2345 F300.\nG90\nM99\n",
    )
    .expect("program");
    let out = ncplc(&[
        "nc",
        "plan",
        "plc-programs/mill",
        prog.to_str().unwrap_or_default(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let l = json_lines(&out.stdout);
    // G10 L2 P2 + G55: X10 Y0 is machine X110 Y50; the full circle G02 I-10 ends where it starts.
    assert_eq!(
        (l[0]["end"]["X"].as_f64(), l[0]["end"]["Y"].as_f64()),
        (Some(110.0), Some(50.0))
    );
    assert_eq!(l[2]["kind"], "arc_cw");
    assert_eq!(l[2]["end"]["X"], 110.0);
    assert_eq!(l[2]["center"]["X"], 100.0);
    assert_eq!(l[3]["exact_stop"], true);
    assert_eq!(l[4]["tolerance"], 0.02);
    // L3 in G91: three holes at X120, 130, 140 (machine 135, 145, 155), bottom Z0.
    let holes: Vec<f64> = l
        .iter()
        .filter(|v| v["kind"] == "linear" && v["end"]["Z"] == 0.0)
        .filter_map(|v| v["end"]["X"].as_f64())
        .collect();
    assert_eq!(holes, vec![135.0, 145.0, 155.0]);
    // O2001 after M30 runs twice: Y1.2345 rounds to 1.235.
    let sub: Vec<f64> = l
        .iter()
        .filter(|v| v["unit"] == "O2001")
        .filter_map(|v| v["end"]["Y"].as_f64())
        .collect();
    assert_eq!(sub, vec![51.235, 52.47]);
    // G28 without axes: every axis to machine zero.
    let home = &l[l.len() - 2];
    assert_eq!(
        (
            home["kind"].as_str(),
            home["end"]["X"].as_f64(),
            home["end"]["Y"].as_f64(),
            home["end"]["Z"].as_f64()
        ),
        (Some("rapid"), Some(0.0), Some(0.0), Some(0.0))
    );
    std::fs::write(&prog, "O1\nG01 X1. R5. F100.\nM30\n").expect("program");
    let out = ncplc(&[
        "nc",
        "plan",
        "plc-programs/mill",
        prog.to_str().unwrap_or_default(),
        "--format",
        "json",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let d = json_lines(&out.stderr);
    assert_eq!(
        (
            d[0]["code"].as_u64(),
            d[0]["line"].as_u64(),
            d[0]["column"].as_u64()
        ),
        (Some(2530), Some(2), Some(9))
    );
}
