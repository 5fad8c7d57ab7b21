//! End-to-end tests of `ncplc test`: every golden trace of a machine replays identically, a
//! tampered trace makes it exit 1 with a one-line result and a JUnit failure.

use std::path::PathBuf;
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

#[test]
fn ncplc_test_passes_the_golden_traces_and_fails_a_tampered_one_in_junit() {
    let o = Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .current_dir(root())
        .args(["test", "plc-programs/lathe"])
        .output()
        .expect("ncplc");
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{out}");
    assert!(
        out.starts_with(
            "ok       plc-programs/lathe/traces/basic.jsonl  (2000 ticks)\n\
         ok       plc-programs/lathe/traces/estop-handwritten.jsonl  (31 ticks)\n\
         ok       plc-programs/lathe/traces/part1.jsonl  (4252 ticks)\n\
         3 traces on "
        ),
        "{out}"
    );
    // The same trace with SPINDLE_CW expected on at tick 1 instead of 11.
    let dir = tempfile::tempdir().expect("tempdir");
    let good = std::fs::read_to_string(root().join("plc-programs/lathe/traces/basic.jsonl"))
        .expect("trace");
    let bad = good.replacen(
        "{\"t\":1,\"out\":{\"U4A3\":1}}",
        "{\"t\":1,\"out\":{\"U4A0\":1,\"U4A3\":1}}",
        1,
    );
    assert_ne!(good, bad);
    let bad_path = dir.path().join("tampered.jsonl");
    std::fs::write(&bad_path, bad).expect("write");
    let junit = dir.path().join("junit.xml");
    let o = Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .current_dir(root())
        .args([
            "test",
            "plc-programs/lathe",
            "plc-programs/lathe/traces/basic.jsonl",
        ])
        .arg(&bad_path)
        .arg("--junit")
        .arg(&junit)
        .output()
        .expect("ncplc");
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{out}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(
        lines[0],
        "ok       plc-programs/lathe/traces/basic.jsonl  (2000 ticks)"
    );
    assert!(
        lines[1].starts_with(&format!("DIVERGES {}  ", bad_path.display())),
        "{out}"
    );
    assert!(
        lines[2].starts_with("2 traces on 2 threads: 1 identical, 1 diverging, 0 errors"),
        "{out}"
    );
    let xml = std::fs::read_to_string(&junit).expect("junit");
    assert!(
        xml.contains("tests=\"2\" failures=\"1\" errors=\"0\""),
        "{xml}"
    );
    assert_eq!(xml.matches("<failure message=").count(), 1);
}
