//! End-to-end tests of replaying part-run traces (`ncplc replay` of a trace recorded by
//! `ncplc run --program … --record`): the header names the programs, the replay re-runs the CNC
//! kernel and its plant beside the logic and compares the kernel's signals and the axis positions.

use std::path::{Path, PathBuf};

use crate::e2e_common;
use e2e_common::{Ncplc, copy_dir, ncplc, root};

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// A copy of the lathe whose PART1 has `from` replaced by `to`; returns the new text's CRC-32.
fn lathe_with_part(from: &str, to: &str) -> (tempfile::TempDir, String) {
    let dir = tempfile::tempdir().expect("tempdir");
    copy_dir(&root().join("plc-programs/lathe"), dir.path());
    let path = dir.path().join("nc/PART1");
    let text = std::fs::read_to_string(&path).expect("PART1");
    assert!(text.contains(from), "{from}");
    let text = text.replacen(from, to, 1);
    std::fs::write(&path, &text).expect("write");
    (dir, format!("{:08x}", crc32fast::hash(text.as_bytes())))
}

fn golden(machine: &str) -> PathBuf {
    root()
        .join("plc-programs")
        .join(machine)
        .join("traces/part1.jsonl")
}

/// Each tick's value of axis `axis` in a text trace (the running value from the `pos` records).
fn axis_track(trace: &str, axis: &str) -> Vec<(u64, u64)> {
    let mut v = Vec::new();
    for line in trace.lines().skip(1) {
        let rec: serde_json::Value = serde_json::from_str(line).expect("json");
        let Some(bits) = rec
            .pointer(&format!("/pos/{axis}"))
            .and_then(|b| b.as_str())
        else {
            continue;
        };
        let t = rec["t"].as_u64().expect("t");
        v.push((t, u64::from_str_radix(bits, 16).expect("hex")));
    }
    v
}

#[test]
fn part_traces_rerun_the_kernel_with_both_engines() {
    for (machine, ticks) in [("lathe", 4252), ("mill", 3438)] {
        let m = root().join("plc-programs").join(machine);
        let trace = golden(machine);
        let text = std::fs::read_to_string(&trace).expect("golden");
        assert!(text.starts_with(
            "{\"format\":\"ncplc-trace\",\"version\":1,\"tick_ms\":10,\"part\":{\"kernel\":\"cnc 0.1.0\",\"process\":1,\"program\":\"PART1\",\"crc32\":"
        ));
        for engine in ["jit", "interp"] {
            let out = ncplc(&["replay", s(&m), s(&trace), "--engine", engine]);
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(0), "{machine} {engine}: {err}");
            assert!(
                err.contains(&format!(
                    "{ticks} ticks replayed (0 skipped as idle), outputs identical, kernel signals and axis positions identical"
                )),
                "{err}"
            );
        }
    }
}

#[test]
fn the_mill_header_names_the_magazine_program_of_process_2() {
    let text = std::fs::read_to_string(golden("mill")).expect("golden");
    let header: serde_json::Value =
        serde_json::from_str(text.lines().next().expect("header")).expect("json");
    let others = &header["part"]["others"];
    assert_eq!(others[0]["process"], 2);
    assert_eq!(others[0]["program"], "MAGAZINE");
    let magazine = std::fs::read(root().join("plc-programs/mill/nc/MAGAZINE")).expect("MAGAZINE");
    assert_eq!(
        others[0]["crc32"],
        format!("{:08x}", crc32fast::hash(&magazine))
    );
}

#[test]
fn an_edited_program_is_an_error_naming_the_file() {
    let (m, crc) = lathe_with_part("N50 X-48", "N50 X-47");
    let out = ncplc(&["replay", s(m.path()), s(&golden("lathe"))]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        format!(
            "error: {}: the partprogram changed since the trace was recorded (crc32 6d2bbce4 in the trace, {crc} now)\n",
            m.path().join("nc/PART1").display()
        )
    );
}

/// With the header's CRC made to match the edited program, the kernel really re-runs it: the
/// replay reports the first position divergence at the tick and with the values that a live run
/// of the edited program records.
#[test]
fn an_edited_program_with_its_hash_diverges_in_position_as_a_live_run_does() {
    let (m, crc) = lathe_with_part("N50 X-48", "N50 X-47");
    let dir = tempfile::tempdir().expect("tempdir");
    let original = std::fs::read_to_string(golden("lathe")).expect("golden");
    let forged = dir.path().join("forged.jsonl");
    std::fs::write(&forged, original.replacen("6d2bbce4", &crc, 1)).expect("write");
    let live = dir.path().join("live.jsonl");
    let out = Ncplc::run(m.path())
        .virtual_time()
        .program("PART1")
        .ticks(20000)
        .until_end()
        .record(&live)
        .output();
    assert_eq!(out.status.code(), Some(0));
    let live = std::fs::read_to_string(&live).expect("live");
    // The first tick where the running X positions of the two recordings differ.
    let (a, b) = (axis_track(&original, "1X"), axis_track(&live, "1X"));
    let at = |track: &[(u64, u64)], t: u64| {
        track
            .iter()
            .take_while(|(u, _)| *u <= t)
            .last()
            .map(|x| x.1)
    };
    let mut ticks: Vec<u64> = a.iter().chain(&b).map(|x| x.0).collect();
    ticks.sort_unstable();
    let t = ticks
        .into_iter()
        .find(|&t| at(&a, t) != at(&b, t))
        .expect("the edit moves X");
    let (exp, got) = ((t, at(&a, t).expect("X")), (t, at(&b, t).expect("X")));
    let out = ncplc(&["replay", s(m.path()), s(&forged)]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    let line = format!(
        "  {:>8}  {:<4}  {:>24}  {:>24}\n",
        t,
        "1X",
        format!("{:?}", f64::from_bits(exp.1)),
        format!("{:?}", f64::from_bits(got.1))
    );
    assert!(
        err.contains("axis positions diverge from the trace"),
        "{err}"
    );
    let table = err
        .split("axis positions diverge from the trace")
        .nth(1)
        .expect("position report");
    let first_x = table
        .lines()
        .find(|l| l.contains("  1X  "))
        .expect("an X divergence");
    assert_eq!(format!("{first_x}\n"), line, "{err}");
}

#[test]
fn a_changed_position_or_kernel_signal_in_the_trace_is_reported_exactly() {
    let m = root().join("plc-programs/lathe");
    let original = std::fs::read_to_string(golden("lathe")).expect("golden");
    let dir = tempfile::tempdir().expect("tempdir");
    // The S code the kernel writes at tick 11 (S1200: W4K0 = 0xB0, W4K1 = 4) made 177.
    let path = dir.path().join("scode.jsonl");
    let edited = original.replacen("\"W4K0\":176", "\"W4K0\":177", 1);
    assert_ne!(edited, original);
    std::fs::write(&path, edited).expect("write");
    let out = ncplc(&["replay", s(&m), s(&path)]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.starts_with(
            "replay diverges from the trace (1 divergence(s)); first ones:\n\
             \x20     tick  signal    expected    actual\n\
             \x20       11  W4K0           177       176\n"
        ),
        "{err}"
    );
    // The Z position of tick 403 (the feed hold) one unit in the last place off.
    let key = "{\"t\":403,\"in\":{\"I1K6\":1},\"pos\":{\"1Z\":\"";
    let at = original.find(key).expect("tick 403") + key.len();
    let bits = u64::from_str_radix(&original[at..at + 16], 16).expect("hex");
    let edited = format!(
        "{}{:016x}{}",
        &original[..at],
        bits + 1,
        &original[at + 16..]
    );
    let path = dir.path().join("pos.jsonl");
    std::fs::write(&path, edited).expect("write");
    let out = ncplc(&["replay", s(&m), s(&path)]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        format!(
            "axis positions diverge from the trace (1 divergence(s)); first ones:\n\
             \x20     tick  axis                  expected                    actual\n\
             \x20      403  1Z    {:>24}  {:>24}\n",
            format!("{:?}", f64::from_bits(bits + 1)),
            format!("{:?}", f64::from_bits(bits))
        )
    );
}

/// The header lists every file the run's compile read with its CRC-32; a replay after one of them
/// changed (a macro file, the correction table) or vanished (nc/CONSTANTS) names it and fails.
#[test]
fn a_changed_macro_correction_table_or_constants_file_is_named_by_the_replay() {
    let dir = tempfile::tempdir().expect("tempdir");
    let m = dir.path().join("lathe");
    std::fs::create_dir(&m).expect("mkdir");
    copy_dir(&root().join("plc-programs/lathe"), &m);
    let rec = dir.path().join("mdi.jsonl");
    let out = Ncplc::run(&m)
        .virtual_time()
        .mdi("N1 G00 X-10 Z-20")
        .ticks(30)
        .record(&rec)
        .output();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let header = std::fs::read_to_string(&rec).expect("trace");
    let crc = |f: &str| {
        format!(
            "{:08x}",
            crc32fast::hash(&std::fs::read(m.join(f)).expect(f))
        )
    };
    assert!(
        header.starts_with(&format!(
            "{{\"format\":\"ncplc-trace\",\"version\":1,\"tick_ms\":10,\"part\":{{\"kernel\":\"cnc 0.1.0\",\"process\":1,\"mdi\":[\"N1 G00 X-10 Z-20\"],\"files\":[{{\"file\":\"MP0/TAB0.KOR\",\"crc32\":\"{}\"}},{{\"file\":\"MP0/TAB0.POS\",\"crc32\":\"{}\"}},{{\"file\":\"macros/PEVNECY5.NCP\",\"crc32\":\"{}\"}},{{\"file\":\"nc/CONSTANTS\",\"crc32\":\"{}\"}}]}}}}\n",
            crc("MP0/TAB0.KOR"),
            crc("MP0/TAB0.POS"),
            crc("macros/PEVNECY5.NCP"),
            crc("nc/CONSTANTS")
        )),
        "{header}"
    );
    for (file, edit) in [
        ("macros/PEVNECY5.NCP", true),
        ("MP0/TAB0.KOR", true),
        ("MP0/TAB0.POS", true),
        ("nc/CONSTANTS", false),
    ] {
        let copy = dir.path().join("edited");
        std::fs::create_dir(&copy).expect("mkdir");
        copy_dir(&m, &copy);
        let then = crc(file);
        let path = copy.join(file);
        let expected = if edit {
            let mut text = std::fs::read(&path).expect("read");
            text.push(b'\n');
            std::fs::write(&path, &text).expect("write");
            format!(
                "error: {}: changed since the trace was recorded (crc32 {then} in the trace, {:08x} now)\n",
                path.display(),
                crc32fast::hash(&text)
            )
        } else {
            std::fs::remove_file(&path).expect("remove");
            format!(
                "error: {}: read when the trace was recorded, not now\n",
                path.display()
            )
        };
        let out = ncplc(&["replay", s(&copy), s(&rec)]);
        assert_eq!(out.status.code(), Some(1), "{file}");
        assert_eq!(String::from_utf8_lossy(&out.stderr), expected);
        std::fs::remove_dir_all(&copy).expect("clean");
    }
}
