//! `nc check` and `nc plan` with the machine's tables: the correction table `TAB0.KOR`, the zero
//! offsets `TAB0.POS` and the machine constants `nc/CONSTANTS`, valid and broken.

use super::*;

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
