//! Recordings survive `kill -9`: `ncplc run --record` is killed at pseudo-random moments, and what
//! it left in `FILE.partial` must recover (`ncplc trace recover`) into a prefix of the golden trace
//! and replay (`ncplc replay FILE.partial`) with identical outputs.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::e2e_common::Ncplc;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn ncplc(args: &[&std::ffi::OsStr]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .args(args)
        .output()
        .expect("ncplc runs")
}

/// Starts an endless recording run of the lathe.
fn start_recording(record: &Path, virtual_time: bool, flush_ms: &str) -> Child {
    let machine = root().join("plc-programs/lathe");
    let run = Ncplc::run(&machine)
        .args(["--record-flush-ms", flush_ms])
        .record(record);
    let run = if virtual_time {
        run.virtual_time()
    } else {
        run
    };
    run.command()
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("ncplc run starts")
}

/// Waits until the run has written the trace header into `partial`.
fn wait_for_header(partial: &Path) {
    let deadline = Instant::now() + Duration::from_secs(60);
    while std::fs::metadata(partial).map_or(true, |m| m.len() == 0) {
        assert!(Instant::now() < deadline, "no recording started");
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// The golden records of the lathe without the end marker (`{"t":1999}`).
fn golden_lines() -> Vec<String> {
    let golden = std::fs::read_to_string(root().join("plc-programs/lathe/traces/basic.jsonl"))
        .expect("golden");
    let mut lines: Vec<String> = golden.lines().map(str::to_string).collect();
    assert_eq!(lines.pop().as_deref(), Some("{\"t\":1999}"));
    lines
}

/// Recovers `partial` as text and checks it against the golden trace; returns the records kept.
fn recover_and_replay(partial: &Path, round: usize) -> Vec<String> {
    let out = ncplc(&["trace".as_ref(), "recover".as_ref(), partial.as_os_str()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "round {round}: recover: {stderr}");
    assert!(stderr.contains(": recovered "), "round {round}: {stderr}");
    let text = String::from_utf8(out.stdout).expect("utf8");
    let got: Vec<String> = text.lines().map(str::to_string).collect();
    // Every recovered record is the golden one (the run is deterministic), in order.
    let golden = golden_lines();
    let upto = got.len().min(golden.len());
    assert_eq!(got[..upto], golden[..upto], "round {round}");
    let machine = root().join("plc-programs/lathe");
    let out = ncplc(&["replay".as_ref(), machine.as_os_str(), partial.as_os_str()]);
    assert!(
        out.status.success(),
        "round {round}: replay of what survived: {}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    got
}

#[test]
fn sigkill_during_recording_leaves_a_recoverable_replayable_prefix() {
    let dir = tempfile::tempdir().expect("tempdir");
    // A fixed pseudo-random sequence (reproducible failures), kill moments 0..600 ms.
    let mut seed: u64 = 0x9e37_79b9_7f4a_7c15;
    for round in 0..6 {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let delay = Duration::from_millis((seed >> 33) % 600);
        let ext = if round % 2 == 0 { "ptrace" } else { "jsonl" };
        let record = dir.path().join(format!("r{round}.{ext}"));
        let partial = dir.path().join(format!("r{round}.{ext}.partial"));
        let mut child = start_recording(&record, true, "20");
        wait_for_header(&partial);
        std::thread::sleep(delay);
        child.kill().expect("SIGKILL");
        child.wait().expect("reaped");
        assert!(!record.exists(), "round {round}: a killed run finished");
        recover_and_replay(&partial, round);
    }
}

#[test]
fn a_real_time_recording_killed_after_3_s_keeps_all_but_the_last_flush_period() {
    let dir = tempfile::tempdir().expect("tempdir");
    let record = dir.path().join("live.ptrace");
    let partial = dir.path().join("live.ptrace.partial");
    let mut child = start_recording(&record, false, "200");
    wait_for_header(&partial);
    std::thread::sleep(Duration::from_secs(3));
    child.kill().expect("SIGKILL");
    child.wait().expect("reaped");
    let got = recover_and_replay(&partial, 0);
    // 3 s at the lathe's 10 ms tick is 300 ticks; with 200 ms unsynced and up to ~1.5 s of start-up
    // on a loaded machine, at least the golden records up to tick 120 (1.2 s) survive.
    let golden = golden_lines();
    let upto_120 = golden
        .iter()
        .position(|l| l.starts_with("{\"t\":120,"))
        .expect("tick 120 in the golden trace");
    assert!(
        got.len() > upto_120,
        "only {} records survived: {got:?}",
        got.len()
    );
}
