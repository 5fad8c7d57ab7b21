//! End-to-end tests of `ncplc nc check` and `ncplc nc plan` on the bundled machines.

use crate::e2e_common::{ncplc_at_root as ncplc, root as repo};

/// Copies the bundled machine `name` into `to` (characterization files, macros, partprograms).
fn copy_machine(name: &str, to: &std::path::Path) {
    std::fs::create_dir_all(to).expect("mkdir");
    crate::e2e_common::copy_dir(&repo().join("plc-programs").join(name), to);
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

mod geometry;
mod tables;
