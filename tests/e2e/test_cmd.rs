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

/// `ncplc test … --jobs 1` in the workspace root; (exit code, stdout, stderr).
fn ncplc_test(args: &[&str]) -> (Option<i32>, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .current_dir(root())
        .arg("test")
        .args(args)
        .args(["--jobs", "1"])
        .output()
        .expect("ncplc");
    let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
    (o.status.code(), text(&o.stdout), text(&o.stderr))
}

/// The lines of `stdout` up to the summary, and the summary without its time.
fn shard_lines(stdout: &str) -> (Vec<&str>, &str) {
    let mut lines: Vec<&str> = stdout.lines().collect();
    let summary = lines.pop().unwrap_or_default();
    (lines, summary.split(" (").next().unwrap_or_default())
}

#[test]
fn shards_split_the_sorted_traces_round_robin_and_together_replay_them_all() {
    let ok = |name: &str, ticks: u32| {
        format!("ok       plc-programs/lathe/traces/{name}  ({ticks} ticks)")
    };
    // Sorted: basic (0), estop-handwritten (1), part1 (2); trace i goes to shard i mod N.
    let (code, out, err) = ncplc_test(&["plc-programs/lathe", "--shard", "1/2"]);
    assert_eq!(code, Some(0), "{out}{err}");
    let (lines, summary) = shard_lines(&out);
    assert_eq!(lines, [ok("basic.jsonl", 2000), ok("part1.jsonl", 4252)]);
    assert_eq!(
        summary,
        "shard 1/2: 2 of 3 traces on 1 threads: 2 identical, 0 diverging, 0 errors"
    );
    let (code, out, _) = ncplc_test(&["plc-programs/lathe", "--shard", "2/2"]);
    assert_eq!(code, Some(0), "{out}");
    let (lines, summary) = shard_lines(&out);
    assert_eq!(lines, [ok("estop-handwritten.jsonl", 31)]);
    assert_eq!(
        summary,
        "shard 2/2: 1 of 3 traces on 1 threads: 1 identical, 0 diverging, 0 errors"
    );
    // Traces given out of order are sorted first: every machine of a CI matrix splits alike.
    let (code, out, _) = ncplc_test(&[
        "plc-programs/lathe",
        "plc-programs/lathe/traces/part1.jsonl",
        "plc-programs/lathe/traces/estop-handwritten.jsonl",
        "plc-programs/lathe/traces/basic.jsonl",
        "--shard",
        "3/3",
    ]);
    assert_eq!(code, Some(0), "{out}");
    let (lines, summary) = shard_lines(&out);
    assert_eq!(lines, [ok("part1.jsonl", 4252)]);
    assert_eq!(
        summary,
        "shard 3/3: 1 of 3 traces on 1 threads: 1 identical, 0 diverging, 0 errors"
    );
}

#[test]
fn an_empty_shard_passes_with_an_empty_junit_suite() {
    // The mill has two traces: with four shards the last two have none, which is not a failure
    // (a CI matrix may be wider than a machine's fleet).
    let dir = tempfile::tempdir().expect("tempdir");
    let junit = dir.path().join("junit.xml");
    let junit_arg = junit.to_str().expect("utf-8");
    let (code, out, err) =
        ncplc_test(&["plc-programs/mill", "--shard", "4/4", "--junit", junit_arg]);
    assert_eq!(code, Some(0), "{out}{err}");
    let (lines, summary) = shard_lines(&out);
    assert!(lines.is_empty(), "{out}");
    assert_eq!(
        summary,
        "shard 4/4: 0 of 2 traces on 1 threads: 0 identical, 0 diverging, 0 errors"
    );
    assert_eq!(
        std::fs::read_to_string(&junit).expect("junit"),
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites>\n  <testsuite name=\"ncplc test mill\" tests=\"0\" failures=\"0\" errors=\"0\" time=\"0.000\">\n  </testsuite>\n</testsuites>\n"
    );
    // Shard 2/4 has the second trace, in the same JUnit format as without --shard.
    let (code, out, _) = ncplc_test(&["plc-programs/mill", "--shard", "2/4", "--junit", junit_arg]);
    assert_eq!(code, Some(0), "{out}");
    let xml = std::fs::read_to_string(&junit).expect("junit");
    assert!(
        xml.contains(
            "<testsuite name=\"ncplc test mill\" tests=\"1\" failures=\"0\" errors=\"0\" time=\""
        ),
        "{xml}"
    );
    assert!(
        xml.contains(
            "    <testcase classname=\"mill\" name=\"plc-programs/mill/traces/part1.jsonl\" time=\""
        ),
        "{xml}"
    );
    assert_eq!(xml.matches("<testcase ").count(), 1, "{xml}");
}

#[test]
fn a_shard_outside_one_to_n_is_a_usage_error() {
    for (shard, why) in [
        (
            "0/2",
            "`0/2`: K must be between 1 and N (shards are numbered from 1)",
        ),
        (
            "3/2",
            "`3/2`: K must be between 1 and N (shards are numbered from 1)",
        ),
        (
            "1/0",
            "`1/0`: K must be between 1 and N (shards are numbered from 1)",
        ),
        (
            "2",
            "`2` is not K/N (for example 2/4: the second of four shards)",
        ),
        (
            "a/b",
            "`a/b` is not K/N (for example 2/4: the second of four shards)",
        ),
    ] {
        let (code, out, err) = ncplc_test(&["plc-programs/lathe", "--shard", shard]);
        assert_eq!(code, Some(2), "{shard}: {out}{err}");
        assert!(out.is_empty(), "{shard}: nothing replayed: {out}");
        assert!(
            err.starts_with(&format!(
                "error: invalid value '{shard}' for '--shard <K/N>': {why}\n"
            )),
            "{shard}: {err}"
        );
    }
}
