//! End-to-end tests of `ncplc build` on temporary machine directories.

use std::path::Path;
use std::process::Command;

/// A copy of the example lathe's characterization (FCRSYS, MP0/AXCFIL, PGCFIL, IOCFIL, MESSAG) with
/// `plc` as its PLC program.
fn machine(plc: &[u8]) -> tempfile::TempDir {
    let lathe = Path::new(env!("CARGO_MANIFEST_DIR")).join("../plc-programs/lathe");
    let dir = tempfile::tempdir().expect("temp dir");
    let mp0 = dir.path().join("MP0");
    std::fs::create_dir(&mp0).expect("mkdir");
    std::fs::copy(lathe.join("FCRSYS"), dir.path().join("FCRSYS")).expect("copy FCRSYS");
    for f in ["AXCFIL", "PGCFIL", "IOCFIL", "MESSAG"] {
        std::fs::copy(lathe.join("MP0").join(f), mp0.join(f))
            .expect("copy a characterization file");
    }
    std::fs::write(mp0.join("PLCPRG"), plc).expect("write");
    dir
}

/// Runs `ncplc build . ARGS` in `dir` (so that paths in diagnostics are relative to it, as the user
/// sees them); returns the exit code, stdout and stderr.
fn ncplc(args: &[&str], dir: &Path) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .current_dir(dir)
        .arg("build")
        .arg(".")
        .args(args)
        .output()
        .expect("ncplc runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn the_example_lathe_program_builds_with_a_summary() {
    let dir = machine(include_bytes!("../../plc-programs/lathe/MP0/PLCPRG"));
    let (code, out, err) = ncplc(&[], dir.path());
    assert_eq!(code, 0, "{out}{err}");
    assert_eq!(out, "", "results only on stdout, and a build has none");
    let summary = err.lines().last().expect("summary line");
    assert!(summary.starts_with("MP0/PLCPRG: "), "{summary}");
    assert!(
        summary.contains(" statements, ") && summary.contains("image ") && summary.contains(" ms"),
        "{summary}"
    );
    // The build also produces the native code `ncplc run` loads, and says what each half cost.
    assert!(
        summary.contains("(front end ") && summary.contains(" ms, native code "),
        "{summary}"
    );
}

#[test]
fn errors_are_printed_with_the_source_line_and_exit_1() {
    let dir = machine(b"U4A0 = I0A0\nU4A1 = I2A0\n");
    let (code, _, out) = ncplc(&[], dir.path());
    assert_eq!(code, 1);
    assert!(out.contains("error[E1104]"), "{out}");
    assert!(
        out.contains("U4A1 = I2A0"),
        "the source line is shown: {out}"
    );
    assert!(out.contains("MP0/PLCPRG:2:8"), "{out}");
}

#[test]
fn json_format_has_the_check_fields() {
    let dir = machine(b"U4A0 = I0A0\nU4A1 = I2A0\n");
    let (code, out, err) = ncplc(&["--format", "json"], dir.path());
    assert_eq!(code, 1);
    assert_eq!(out, "", "diagnostics go to stderr in every format");
    let lines: Vec<serde_json::Value> = err
        .lines()
        .filter(|l| l.starts_with('{'))
        .map(|l| serde_json::from_str(l).expect("JSON line"))
        .collect();
    assert_eq!(lines.len(), 1);
    assert_eq!(lines[0]["code"], 1104);
    assert_eq!(lines[0]["line"], 2);
    assert_eq!(lines[0]["column"], 8);
    assert_eq!(lines[0]["file"], "MP0/PLCPRG");
}

#[test]
fn plc_option_and_emit_ir_and_clif() {
    let dir = machine(b"garbage that does not parse (((\n");
    let other = dir.path().join("OTHER");
    std::fs::write(&other, "U4A0 = I0A0 * /I0A1\n").expect("write");
    let plc = other.to_str().expect("utf-8 path");
    let (code, out, err) = ncplc(&["--plc", plc, "--emit", "ir"], dir.path());
    assert_eq!(code, 0, "{err}");
    let ir: serde_json::Value = serde_json::from_str(&out).expect("IR is JSON");
    assert_eq!(ir["fast"].as_array().map(Vec::len), Some(1));
    let (code, out, err) = ncplc(&["--plc", plc, "--emit", "clif"], dir.path());
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("function"), "{out}");
}

#[test]
fn a_missing_machine_is_exit_2() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (code, _, err) = ncplc(&[], dir.path());
    assert_eq!(code, 2);
    assert!(
        err.contains("the characterization files have errors"),
        "{err}"
    );
    assert!(err.contains("FCRSYS"), "{err}");
}

#[test]
fn legacy_comment_bytes_are_shown_decoded_in_the_source_line() {
    // "Привет" in CP1251 in a comment on the erroneous line.
    let dir = machine(b"U4A0 = I2A0 ; \xcf\xf0\xe8\xe2\xe5\xf2\r\n");
    let (code, _, out) = ncplc(&[], dir.path());
    assert_eq!(code, 1);
    assert!(out.contains("U4A0 = I2A0 ; Привет"), "{out}");
    assert!(out.contains("MP0/PLCPRG:1:8"), "{out}");
}

#[test]
fn machine_interface_toml_adds_predeclared_names() {
    let dir = machine(b"U4A0 = DOOR\n");
    let (code, out, _) = ncplc(&[], dir.path());
    assert_eq!(code, 1, "DOOR is not predeclared by default: {out}");
    std::fs::write(
        dir.path().join("interface.toml"),
        "[[signal]]\nname = \"DOOR\"\naddress = \"I150K0\"\nwidth = \"bit\"\ndir = \"in\"\nmeaning = \"door closed\"\n",
    )
    .expect("write");
    let (code, out, err) = ncplc(&[], dir.path());
    assert_eq!(code, 0, "{out}{err}");
}
