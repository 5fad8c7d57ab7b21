//! End-to-end tests of `ncplc check` on the bundled machines and on broken copies of them.

use std::path::PathBuf;
use std::process::Command;

fn ncplc(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .args(args)
        .output()
        .expect("ncplc runs")
}

/// Runs ncplc with `dir` as the current directory (paths in diagnostics are relative to it).
fn ncplc_in(dir: &std::path::Path, args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("ncplc runs")
}

fn machine(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../plc-programs")
        .join(name)
        .display()
        .to_string()
}

#[test]
fn ncplc_prints_help() {
    let out = ncplc(&["--help"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("check"), "{text}");
}

#[test]
fn example_machines_check_clean() {
    // The mill's interface.toml (process 2's handshake signals) is checked and named too.
    // Run from the workspace root: the files are named as the user can open them from there.
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    for (name, extra) in [("lathe", false), ("mill", true)] {
        let out = ncplc_in(&root, &["check", &format!("plc-programs/{name}")]);
        let text = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{name}: {text}");
        assert!(
            out.stdout.is_empty(),
            "{name}: a check has no results on stdout"
        );
        let m = format!("plc-programs/{name}");
        let extra = if extra {
            format!(", {m}/interface.toml")
        } else {
            String::new()
        };
        assert_eq!(
            text,
            format!(
                "{m}/FCRSYS, {m}/MP0/AXCFIL, {m}/MP0/PGCFIL, {m}/MP0/IOCFIL{extra}: no problems found\n"
            ),
            "{name}"
        );
    }
}

/// A copy of the lathe with a broken AXCFIL: exit 1, rustc-style output and JSON lines.
#[test]
fn broken_machine_exits_1_with_located_diagnostics() {
    let dir = tempfile::tempdir().expect("temp dir");
    let lathe = PathBuf::from(machine("lathe"));
    for f in ["FCRSYS", "MP0/AXCFIL", "MP0/PGCFIL", "MP0/IOCFIL"] {
        let to = dir.path().join(f);
        std::fs::create_dir_all(to.parent().expect("parent")).expect("mkdir");
        std::fs::copy(lathe.join(f), &to).expect("copy");
    }
    let ax = dir.path().join("MP0/AXCFIL");
    let bytes = std::fs::read(&ax).expect("read");
    let text = String::from_utf8_lossy(&bytes).replacen("TIM=1,0,0,0,0", "TIM=64,0,0,0,0", 1);
    std::fs::write(&ax, text).expect("write");
    let out = ncplc_in(dir.path(), &["check", "."]);
    assert_eq!(out.status.code(), Some(1));
    let human = String::from_utf8_lossy(&out.stderr);
    assert!(
        human.contains("error[E0101]: CPU tick 64 ms is too large"),
        "{human}"
    );
    assert!(human.contains("MP0/AXCFIL:5:5"), "{human}");
    assert!(human.contains("TIM=64,0,0,0,0"), "{human}");
    assert!(human.contains("^^"), "{human}");

    let out = ncplc_in(dir.path(), &["check", ".", "--format", "json"]);
    assert_eq!(out.status.code(), Some(1));
    let lines: Vec<serde_json::Value> = String::from_utf8_lossy(&out.stderr)
        .lines()
        .map(|l| serde_json::from_str(l).expect("JSON line"))
        .collect();
    let e = lines.iter().find(|v| v["code"] == 101).expect("error 101");
    assert_eq!(
        (
            e["file"].as_str(),
            e["section"].as_u64(),
            e["line"].as_u64(),
            e["column"].as_u64()
        ),
        (Some("MP0/AXCFIL"), Some(1), Some(5), Some(5))
    );
    assert_eq!(e["severity"], "error");
    assert!(e["hint"].as_str().is_some_and(|h| h.contains("1 to 63")));
}

#[test]
fn dump_prints_the_typed_model() {
    let out = ncplc(&["check", &machine("mill"), "--dump"]);
    assert_eq!(out.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("model JSON");
    assert_eq!(v["axcfil"]["tim"], 1);
    assert_eq!(v["axcfil"]["nbp"], 2);
    assert_eq!(v["axcfil"]["processes"][1]["axes"][0]["name"], "T");
    assert_eq!(
        v["axcfil"]["processes"][1]["axes"][0]["tpa"]["axis_type"]["ptp"],
        true
    );
}

#[test]
fn missing_machine_directory_is_a_usage_error() {
    let out = ncplc(&["check", "/nonexistent/machine", "--format", "json"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "ncplc check: /nonexistent/machine: not a machine directory (no such directory)\n"
    );
}
