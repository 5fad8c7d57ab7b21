//! End-to-end tests of `ncplc replay`: every golden trace replays identically with both engines;
//! a deliberately changed program fails with a readable divergence report; `--update` rewrites.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn ncplc(args: &[&std::ffi::OsStr]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .args(args)
        .output()
        .expect("ncplc runs")
}

fn goldens(machine: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(machine.join("traces"))
        .expect("traces folder")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "jsonl" || e == "ptrace"))
        .collect();
    v.sort();
    v
}

#[test]
fn every_golden_trace_replays_identically_with_both_engines() {
    let mut count = 0;
    for name in ["lathe", "mill"] {
        let machine = root().join("plc-programs").join(name);
        for trace in goldens(&machine) {
            for engine in ["jit", "interp"] {
                let out = ncplc(&[
                    "replay".as_ref(),
                    machine.as_os_str(),
                    trace.as_os_str(),
                    "--engine".as_ref(),
                    engine.as_ref(),
                ]);
                assert!(
                    out.status.success(),
                    "{} with {engine}:\n{}{}",
                    trace.display(),
                    String::from_utf8_lossy(&out.stdout),
                    String::from_utf8_lossy(&out.stderr)
                );
                count += 1;
            }
        }
    }
    assert!(count >= 4, "only {count} replays");
}

/// The lathe's program with the spindle override changed from 100 % to 90 %.
fn changed_lathe(dir: &Path) -> PathBuf {
    let src = std::fs::read_to_string(root().join("plc-programs/lathe/MP0/PLCPRG"))
        .expect("lathe PLCPRG");
    assert!(src.contains("SOV = 100"));
    let path = dir.join("PLCPRG");
    std::fs::write(&path, src.replace("SOV = 100", "SOV = 90")).expect("write");
    path
}

#[test]
fn a_changed_program_fails_with_a_divergence_report() {
    let dir = tempfile::tempdir().expect("tempdir");
    let plc = changed_lathe(dir.path());
    let machine = root().join("plc-programs/lathe");
    let trace = machine.join("traces/basic.jsonl");
    for engine in ["jit", "interp"] {
        let out = ncplc(&[
            "replay".as_ref(),
            machine.as_os_str(),
            trace.as_os_str(),
            "--plc".as_ref(),
            plc.as_os_str(),
            "--engine".as_ref(),
            engine.as_ref(),
        ]);
        assert_eq!(
            out.status.code(),
            Some(1),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let report = String::from_utf8_lossy(&out.stderr);
        let lines: Vec<&str> = report.lines().collect();
        assert_eq!(
            lines[0],
            "replay diverges from the trace (1 divergence(s)); first ones:"
        );
        assert_eq!(lines[1], "      tick  signal    expected    actual");
        assert_eq!(lines[2], "         0  W14K1          100        90");
        assert_eq!(lines[3], "context, ticks 0..=3:");
        assert!(
            report.contains("  replay (actual):\n    {\"t\":0,"),
            "{report}"
        );
    }
}

#[test]
fn update_rewrites_the_expectations() {
    let dir = tempfile::tempdir().expect("tempdir");
    let plc = changed_lathe(dir.path());
    let machine = root().join("plc-programs/lathe");
    let trace = dir.path().join("t.jsonl");
    std::fs::copy(machine.join("traces/basic.jsonl"), &trace).expect("copy");
    let replay = |extra: &[&std::ffi::OsStr]| {
        let mut args: Vec<&std::ffi::OsStr> =
            vec!["replay".as_ref(), machine.as_os_str(), trace.as_os_str()];
        args.extend_from_slice(extra);
        ncplc(&args).status.code()
    };
    assert_eq!(
        replay(&["--plc".as_ref(), plc.as_os_str(), "--update".as_ref()]),
        Some(0)
    );
    assert_eq!(replay(&["--plc".as_ref(), plc.as_os_str()]), Some(0));
    assert_eq!(replay(&[]), Some(1));
    let text = std::fs::read_to_string(&trace).expect("read");
    assert!(
        text.lines()
            .nth(1)
            .is_some_and(|l| l.contains("\"W14K1\":90")),
        "{text}"
    );
}

/// The names in `dir` (sorted).
fn names_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .expect("dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn a_damaged_record_after_good_ones_is_a_located_error_and_update_leaves_the_trace() {
    // The trace is read record by record while the replay runs: a bad line far into it ends the
    // replay with the error the whole-file reader gave (exit 2), and `--update` replaces nothing.
    let dir = tempfile::tempdir().expect("tempdir");
    let machine = root().join("plc-programs/lathe");
    let good = std::fs::read_to_string(machine.join("traces/basic.jsonl")).expect("basic");
    let lines = good.lines().count();
    let trace = dir.path().join("t.jsonl");
    let damaged = format!("{good}{{\"t\":999999,\"in\":{{\"I0A5\":2}}}}\n");
    std::fs::write(&trace, &damaged).expect("write");
    for update in [false, true] {
        let mut args: Vec<&std::ffi::OsStr> =
            vec!["replay".as_ref(), machine.as_os_str(), trace.as_os_str()];
        if update {
            args.push("--update".as_ref());
        }
        let out = ncplc(&args);
        assert_eq!(
            String::from_utf8_lossy(&out.stderr),
            format!(
                "{}: line {}: I0A5: value 2 is out of range (0..1)\n",
                trace.display(),
                lines + 1
            )
        );
        assert_eq!(out.status.code(), Some(2));
        assert_eq!(std::fs::read_to_string(&trace).expect("read"), damaged);
        assert_eq!(names_in(dir.path()), ["t.jsonl"]);
    }
}

#[test]
fn update_of_a_binary_trace_writes_a_binary_trace() {
    let dir = tempfile::tempdir().expect("tempdir");
    let plc = changed_lathe(dir.path());
    let machine = root().join("plc-programs/lathe");
    let packed = dir.path().join("t.ptrace");
    let out = ncplc(&[
        "trace".as_ref(),
        "pack".as_ref(),
        machine.join("traces/basic.jsonl").as_os_str(),
        packed.as_os_str(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let replay = |extra: &[&std::ffi::OsStr]| {
        let mut args: Vec<&std::ffi::OsStr> =
            vec!["replay".as_ref(), machine.as_os_str(), packed.as_os_str()];
        args.extend_from_slice(extra);
        ncplc(&args).status.code()
    };
    assert_eq!(replay(&[]), Some(0));
    assert_eq!(
        replay(&["--plc".as_ref(), plc.as_os_str(), "--update".as_ref()]),
        Some(0)
    );
    let bytes = std::fs::read(&packed).expect("read");
    assert_ne!(bytes.first(), Some(&b'{'), "still binary");
    assert_eq!(replay(&["--plc".as_ref(), plc.as_os_str()]), Some(0));
    assert_eq!(replay(&[]), Some(1));
    let out = ncplc(&["trace".as_ref(), "dump".as_ref(), packed.as_os_str()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.lines()
            .nth(1)
            .is_some_and(|l| l.contains("\"W14K1\":90")),
        "{text}"
    );
    assert_eq!(names_in(dir.path()), ["PLCPRG", "t.ptrace"]);
}
