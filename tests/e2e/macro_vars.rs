//! End-to-end tests of the retained Fanuc macro variables `#500`–`#999` (`<machine>/nc/MACROVARS`):
//! a part run reads them at its start and writes back what its plan changed; `nc plan` reads them
//! and never writes; a replay plans from the values its trace header recorded and never writes; a
//! corrupt file is a located error.

use std::path::Path;
use std::process::Output;

use crate::e2e_common;
use e2e_common::{Ncplc, copy_dir, ncplc, root};

/// Each run adds 10 to #500 and moves to X#500 Y[2·#500] in G54 (X −400, Y −250, Z −200 on the
/// mill's TAB0.POS).
const COUNT: &str = "O2000 (retained counter: each run goes 10 mm further)
G21 G17 G90 G54
#500 = #500 + 10.
#501 = #500 * 2
G00 Z10.
G00 X#500 Y#501
M30
";

const HEADER: &str = "(ncplc retained macro variables #500-#999; null ones are not listed)\n";

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// A copy of the mill with the program COUNT.
fn mill() -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("tempdir");
    copy_dir(&root().join("plc-programs/mill"), dir.path());
    std::fs::write(dir.path().join("nc/COUNT"), COUNT).expect("COUNT");
    dir
}

fn run(m: &Path, extra: &[&str]) -> Output {
    run_ticks(m, 20000, extra)
}

/// A part run of COUNT for at most `ticks` ticks.
fn run_ticks(m: &Path, ticks: u64, extra: &[&str]) -> Output {
    Ncplc::run(m)
        .virtual_time()
        .program("COUNT")
        .ticks(ticks)
        .args(extra)
        .output()
}

fn vars(m: &Path) -> Option<String> {
    std::fs::read_to_string(m.join("nc/MACROVARS")).ok()
}

/// The last recorded actual position of axis `axis` (`1X`) in a text trace.
fn last_pos(trace: &Path, axis: &str) -> f64 {
    let text = std::fs::read_to_string(trace).expect("trace");
    let mut last = None;
    for line in text.lines().skip(1) {
        let rec: serde_json::Value = serde_json::from_str(line).expect("json");
        if let Some(b) = rec
            .pointer(&format!("/pos/{axis}"))
            .and_then(|b| b.as_str())
        {
            last = Some(f64::from_bits(u64::from_str_radix(b, 16).expect("hex")));
        }
    }
    last.expect("positions recorded")
}

#[test]
fn retained_variables_carry_from_one_part_run_to_the_next_and_replay_is_exact() {
    let dir = mill();
    let m = dir.path();
    assert_eq!(vars(m), None);
    let t1 = m.join("run1.jsonl");
    let out = run(m, &["--until-end", "--record", s(&t1)]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    // No file: #500 null (0 in arithmetic) + 10.
    assert_eq!(
        vars(m).as_deref(),
        Some(format!("{HEADER}#500 = 10\n#501 = 20\n").as_str())
    );
    // `nc plan` reads the file (X −400 + 20, Y −250 + 40) and does not write it.
    let plan = ncplc(&["nc", "plan", s(m), "COUNT", "--format", "text"]);
    assert_eq!(plan.status.code(), Some(0), "{plan:?}");
    let text = String::from_utf8_lossy(&plan.stdout);
    assert!(text.contains("rapid X-380 Y-210 Z-190"), "{text}");
    assert_eq!(
        vars(m).as_deref(),
        Some(format!("{HEADER}#500 = 10\n#501 = 20\n").as_str())
    );
    let t2 = m.join("run2.jsonl");
    let out = run(m, &["--until-end", "--record", s(&t2)]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert_eq!(
        vars(m).as_deref(),
        Some(format!("{HEADER}#500 = 20\n#501 = 40\n").as_str())
    );
    // The path depends on the values: run 1 went to X −390, run 2 to X −380 (the drive lags
    // its set point by less than a millimetre when M30 ends the run).
    assert!((last_pos(&t1, "1X") + 390.0).abs() < 1.0);
    assert!((last_pos(&t2, "1X") + 380.0).abs() < 1.0);
    let header = std::fs::read_to_string(&t2).expect("trace");
    assert!(
        header.lines().next().expect("header").contains(
            "\"macro_vars\":\"(ncplc retained macro variables #500-#999; null ones are not listed)\\n#500 = 10\\n#501 = 20\\n\""
        ),
        "{header}"
    );
    // The file changes again; the replay of run 2 plans from its header, exactly, and writes
    // nothing.
    let changed = format!("{HEADER}#500 = 70\n#777 = -1.5\n");
    std::fs::write(m.join("nc/MACROVARS"), &changed).expect("write");
    for engine in ["jit", "interp"] {
        let out = ncplc(&["replay", s(m), s(&t2), "--engine", engine]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{err}");
        assert!(
            err.contains("outputs identical, kernel signals and axis positions identical"),
            "{err}"
        );
    }
    assert_eq!(vars(m).as_deref(), Some(changed.as_str()));
    // A run from the changed file: #500 = 80, #777 kept untouched.
    let out = run(m, &["--until-end"]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert_eq!(
        vars(m).as_deref(),
        Some(format!("{HEADER}#500 = 80\n#501 = 160\n#777 = -1.5\n").as_str())
    );
}

#[test]
fn a_run_stopped_after_the_cycle_start_persists_its_values_one_stopped_before_does_not() {
    let dir = mill();
    let m = dir.path();
    // The part script presses CYCLE START at tick 10: 5 ticks end the run before it.
    let out = run_ticks(m, 5, &[]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert_eq!(vars(m), None);
    // 100 ticks stop the run in the middle of the first rapid: the values are the plan's.
    let out = run_ticks(m, 100, &[]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    assert!(stdout.contains("did not end"), "{stdout}");
    assert_eq!(
        vars(m).as_deref(),
        Some(format!("{HEADER}#500 = 10\n#501 = 20\n").as_str())
    );
}

#[test]
fn a_corrupt_retained_file_is_a_located_error_and_is_left_alone() {
    let dir = mill();
    let m = dir.path();
    let bad = "#500 = 1\n#500 = zz\n";
    std::fs::write(m.join("nc/MACROVARS"), bad).expect("write");
    let out = run(m, &["--until-end"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("error[E2078]: #500: `zz` is not a finite number"),
        "{err}"
    );
    assert!(err.contains("nc/MACROVARS:2:1"), "{err}");
    let plan = ncplc(&["nc", "plan", s(m), "COUNT", "--format", "text"]);
    let err = String::from_utf8_lossy(&plan.stderr);
    assert_eq!(plan.status.code(), Some(1), "{err}");
    assert!(err.contains("nc/MACROVARS:2:1"), "{err}");
    assert_eq!(vars(m).as_deref(), Some(bad));
}
