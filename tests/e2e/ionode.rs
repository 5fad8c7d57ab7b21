//! End to end: the simulated CiA 401 I/O node of the `virtual` transport in part runs on drives
//! (issue 21): the node carries `sim.toml`'s panel script and the plant's contacts (an input set
//! at tick t reaches the scan over the bus at tick t + 1, the trace records it so, the replay is
//! exact), its heartbeat runs on the SYNCs in virtual time (a stalled process logs no false
//! loss), and drive start-up errors come under their own code.

use std::path::Path;

use crate::e2e_common;
use e2e_common::{Killed, Ncplc, copy_dir, ncplc, root};

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// The ticks at which a text trace's inputs set `signal`, with the value.
fn input_changes(trace: &str, signal: &str) -> Vec<(u64, u64)> {
    trace
        .lines()
        .skip(1)
        .filter_map(|l| {
            let rec: serde_json::Value = serde_json::from_str(l).expect("json");
            let v = rec.get("in")?.get(signal)?.as_u64()?;
            Some((rec["t"].as_u64().expect("t"), v))
        })
        .collect()
}

/// Records PART1 of `machine` on `io` in virtual time until its end: (output, trace text).
fn record(machine: &Path, io: &str, trace: &Path) -> (String, String) {
    let out = Ncplc::run(machine)
        .args(["--io", io])
        .virtual_time()
        .program("PART1")
        .until_end()
        .record(trace)
        .output();
    let r = text(&out);
    assert!(out.status.success(), "{r}");
    (r, std::fs::read_to_string(trace).expect("trace"))
}

/// stdout and stderr of a run.
fn text(out: &std::process::Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

/// A copy of the lathe whose io.toml has `edit` applied (`from` replaced by `to`, once).
fn lathe_edited(from: &str, to: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("tempdir");
    copy_dir(&root().join("plc-programs/lathe"), dir.path());
    let path = dir.path().join("io.toml");
    let text = std::fs::read_to_string(&path).expect("io.toml");
    assert!(text.contains(from), "{from}");
    std::fs::write(&path, text.replacen(from, to, 1)).expect("write");
    dir
}

fn run_part(machine: &Path, extra: &[&str]) -> std::process::Output {
    Ncplc::run(machine)
        .args(["--io", "canopen"])
        .virtual_time()
        .program("PART1")
        .args(extra)
        .output()
}

/// A drive that aborts an SDO write of its start-up: error 3077 naming the drive's axis and node,
/// the object and the abort code; exit code 2 (the environment: the drive) and nothing runs.
#[test]
fn a_drive_that_refuses_an_sdo_write_is_error_3077_with_node_object_and_abort_code() {
    let m = lathe_edited(
        "[[canopen.drive]]\naxis = \"Z\"\n",
        "[[canopen.drive]]\naxis = \"Z\"\nsimulate = { sdo_abort = { index = 0x60C2, subindex = 1, code = 0x06090030 } }\n",
    );
    let out = run_part(m.path(), &["--until-end"]);
    let r = text(&out);
    assert_eq!(out.status.code(), Some(2), "{r}");
    assert!(r.contains("error[E3077]"), "{r}");
    assert!(
        r.contains(
            "drive of axis Z (node 4): SDO write 60C2h/1 was aborted with code 06090030h (value range of parameter exceeded)"
        ),
        "{r}"
    );
    assert!(!r.contains("E3060"), "{r}");
    // Located at the drive's entry: its `node_id` in io.toml.
    let io = std::fs::read_to_string(m.path().join("io.toml")).expect("io.toml");
    let entry = io.find("axis = \"Z\"\nsimulate").expect("the Z entry");
    let at = entry + io[entry..].find("node_id = ").expect("node_id") + "node_id = ".len();
    let line = io[..at].matches('\n').count() + 1;
    let column = at - io[..at].rfind('\n').map_or(0, |i| i + 1) + 1;
    assert!(r.contains(&format!("io.toml:{line}:{column}\n")), "{r}");
}

/// The lathe's panel script over the bus: CYCLE START (`I0A3`, IN0 on node dio1) set at tick 10
/// and released at 15 reaches the scan at 11 and 16 (at 10 and 15 on the simulated I/O); the
/// power-on inputs of tick 0 and the node's healthy bit (`I100K1`) at tick 1; the plant's
/// at-speed contact (`I0A5`, wired to the node too) three ticks after the plant's. Two runs give the
/// same trace byte for byte, and the replay without the bus is exact.
#[test]
fn the_panel_script_reaches_the_scan_over_the_bus_one_tick_later_and_replays_exactly() {
    let _serial = e2e_common::serial();
    let m = root().join("plc-programs/lathe");
    let dir = tempfile::tempdir().expect("tempdir");
    let (_, plant) = record(&m, "sim", &dir.path().join("sim.jsonl"));
    let bus_path = dir.path().join("bus.jsonl");
    let (out, bus) = record(&m, "canopen", &bus_path);
    assert!(
        out.contains("cycle time 42.44 s (ticks 13..4257), ended"),
        "{out}"
    );
    assert!(!out.contains("lost"), "{out}");
    assert_eq!(
        input_changes(&plant, "I0A3"),
        [(10, 1), (15, 0), (500, 1), (505, 0)]
    );
    assert_eq!(
        input_changes(&bus, "I0A3"),
        [(11, 1), (16, 0), (501, 1), (506, 0)]
    );
    assert_eq!(input_changes(&plant, "I0A0"), [(0, 1)]);
    assert_eq!(input_changes(&bus, "I0A0"), [(1, 1)]);
    assert_eq!(input_changes(&bus, "I100K1"), [(1, 1)]);
    let at_speed = |t: &str| input_changes(t, "I0A5").first().copied();
    let (p, b) = (
        at_speed(&plant).expect("plant"),
        at_speed(&bus).expect("bus"),
    );
    assert_eq!(p.1, 1);
    assert_eq!(b.1, 1);
    // M03 reaches the spindle one tick later too (CYCLE START came a tick later), the spindle
    // drive's answer says "at speed" one tick after the model would (drives.rs), and the contact
    // travels one more tick.
    assert_eq!(b.0, p.0 + 3, "plant {p:?} bus {b:?}");
    // The header names the bytes that came over the bus: IN0 and IN1 (TPDO1 of dio1).
    let header = bus.lines().next().expect("header");
    assert!(
        header.contains(r#""bus_inputs":[0,1,2,3,4,5,6,7]"#),
        "{header}"
    );
    // Deterministic in virtual time: a second run is the same trace.
    let again = dir.path().join("again.jsonl");
    let (_, bus2) = record(&m, "canopen", &again);
    assert!(bus == bus2, "two runs on the bus differ");
    let out = ncplc(&["replay", s(&m), s(&bus_path)]);
    let r = text(&out);
    assert!(out.status.success(), "{r}");
    assert!(
        r.contains("outputs identical, kernel signals and axis positions identical"),
        "{r}"
    );
}

/// In virtual time the I/O node's heartbeat and the master's consumer count SYNCs: a run whose
/// process is stopped (SIGSTOP) three times for 400 ms — far beyond the node's 100 ms consumer
/// time on the wall clock — logs no heartbeat loss and runs its part as undisturbed.
#[test]
fn a_stalled_virtual_time_run_logs_no_heartbeat_loss() {
    let _serial = e2e_common::serial();
    let m = root().join("plc-programs/lathe");
    let mut c = Ncplc::run(&m)
        .args(["--io", "canopen"])
        .virtual_time()
        .program("PART1")
        .until_end()
        .command();
    c.stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped());
    let mut child = Killed(c.spawn().expect("ncplc runs"));
    let pid = child.0.id().to_string();
    let read = |r: Option<Box<dyn std::io::Read + Send>>| {
        std::thread::spawn(move || {
            let mut s = String::new();
            if let Some(mut r) = r {
                let _ = std::io::Read::read_to_string(&mut r, &mut s);
            }
            s
        })
    };
    let stdout = read(child.0.stdout.take().map(|r| Box::new(r) as _));
    let stderr = read(child.0.stderr.take().map(|r| Box::new(r) as _));
    for _ in 0..3 {
        std::thread::sleep(std::time::Duration::from_millis(700));
        let stop = std::process::Command::new("kill")
            .args(["-STOP", &pid])
            .status();
        std::thread::sleep(std::time::Duration::from_millis(400));
        let cont = std::process::Command::new("kill")
            .args(["-CONT", &pid])
            .status();
        assert!(stop.is_ok_and(|s| s.success()) && cont.is_ok_and(|s| s.success()));
    }
    let status = child.0.wait().expect("wait");
    let r = format!(
        "{}{}",
        stdout.join().expect("stdout"),
        stderr.join().expect("stderr")
    );
    assert!(status.success(), "{r}");
    assert!(!r.contains("heartbeat lost"), "{r}");
    assert!(!r.contains("lost"), "{r}");
    assert!(
        r.contains("cycle time 42.44 s (ticks 13..4257), ended"),
        "{r}"
    );
}

/// A silent I/O node (io.toml `simulate = { silent_at_sync = 1000 }`): its heartbeat comes every
/// 20 SYNCs (40 ms of 2 ms periods) from SYNC 1, so the last one is SYNC 981 (tick 196, taken with
/// its tick's five SYNCs: the clock reads SYNC 985); the consumer's 100 ms are 50 SYNCs, passed at
/// the end of tick 207 (SYNC 1040). The scan takes the loss at tick 208: the node's inputs read
/// their fail values (0), its healthy bit `I100K1` falls, and the stopping alarm naming the node
/// switches the machine off (CONP `I0K2` 0, ALARM `I1K4` 1, CYCLE `I1K5` 0) in that tick. The
/// trace records the loss at that tick (`nodes_lost`), so the replay without the bus raises the
/// same alarm there and is exact.
#[test]
fn a_silent_io_node_is_a_stopping_alarm_naming_it_at_its_exact_tick() {
    let _serial = e2e_common::serial();
    let m = lathe_edited(
        "[[canopen.node]]\nname = \"dio1\"\n",
        "[[canopen.node]]\nname = \"dio1\"\nsimulate = { silent_at_sync = 1000 }\n",
    );
    let trace_path = m.path().join("run.jsonl");
    let out = run_part(m.path(), &["--until-end", "--record", s(&trace_path)]);
    let r = text(&out);
    assert_ne!(out.status.code(), Some(0), "{r}");
    assert!(
        r.contains("alarm: process 1: I/O node dio1 (node 2) lost (heartbeat lost): its inputs read their fail values and its outputs are safe; machine off"),
        "{r}"
    );
    assert!(r.contains("did not end"), "{r}");
    let trace = std::fs::read_to_string(&trace_path).expect("trace");
    assert_eq!(input_changes(&trace, "I100K1"), [(1, 1), (208, 0)]);
    assert_eq!(input_changes(&trace, "I0A0"), [(1, 1), (208, 0)]);
    assert_eq!(input_changes(&trace, "I0K2").last(), Some(&(208, 0)));
    assert_eq!(input_changes(&trace, "I1K4").last(), Some(&(208, 1)));
    assert_eq!(input_changes(&trace, "I1K5").last(), Some(&(208, 0)));
    let lost: Vec<(u64, serde_json::Value)> = trace
        .lines()
        .skip(1)
        .filter_map(|l| {
            let rec: serde_json::Value = serde_json::from_str(l).expect("json");
            Some((rec["t"].as_u64()?, rec.get("nodes_lost")?.clone()))
        })
        .collect();
    assert_eq!(
        lost,
        [(
            208,
            serde_json::json!([{"name": "dio1", "node": 2, "why": "heartbeat lost"}])
        )]
    );
    let out = ncplc(&["replay", s(m.path()), s(&trace_path)]);
    let r = text(&out);
    assert!(out.status.success(), "{r}");
    assert!(
        r.contains("outputs identical, kernel signals and axis positions identical"),
        "{r}"
    );
}

/// `simulate` on an I/O node rehearses faults on the virtual bus only: error 3078 elsewhere.
#[test]
fn node_simulate_hooks_need_the_virtual_bus() {
    let m = lathe_edited(
        "transport = \"virtual\"\n",
        "transport = \"socketcan\"\ninterface = \"can0\"\n",
    );
    let io = m.path().join("io.toml");
    let text0 = std::fs::read_to_string(&io).expect("io.toml");
    let text0 = text0.replacen(
        "[[canopen.node]]\nname = \"dio1\"\n",
        "[[canopen.node]]\nname = \"dio1\"\nsimulate = { silent_at_sync = 10 }\n",
        1,
    );
    std::fs::write(&io, text0).expect("write");
    let out = ncplc(&["check", s(m.path())]);
    let r = text(&out);
    assert!(!out.status.success(), "{r}");
    assert!(r.contains("error[E3078]"), "{r}");
    assert!(
        r.contains(
            "`simulate` rehearses faults on simulated nodes: it needs transport = \"virtual\""
        ),
        "{r}"
    );
}

/// A handwheel whose counter (`W1A3`) is on the node's terminals: the counter is the CNC's own
/// encoder input, so it stays out of the bus path (the header's `bus_inputs` lacks byte 7) and the
/// kernel reads it in the tick it turns: −250 pulses × 10 µm move Z by −2.5 mm as on the plant
/// (`manual_limits::`), and the run replays exactly.
#[test]
fn a_handwheel_counter_on_the_node_stays_the_kernels_and_replays_exactly() {
    let _serial = e2e_common::serial();
    let m = lathe_edited("transport = \"virtual\"\n", "transport = \"virtual\"\n");
    let edit = |file: &str, f: &dyn Fn(String) -> String| {
        let p = m.path().join(file);
        let text = std::fs::read_to_string(&p).expect("read");
        std::fs::write(&p, f(text)).expect("write");
    };
    edit("MP0/IOCFIL", &|t| t.replace("ASM=S\n", "ASM=S\nADV=0,0\n"));
    edit("MP0/PLCPRG", &|t| {
        let end = t.rfind('$').expect("the closing $");
        format!(
            "{}COMU = I1A1\nHW_ON1 = I1A1\nHW_AXIS1 = 2\nHW_SCALE = 1\n{}",
            &t[..end],
            &t[end..]
        )
    });
    edit("sim.toml", &|t| {
        t + "\n[[handwheel]]\nchannel = 1\ncounter = \"W1A3\"\n\n\
             [[part.at]]\ntick = 300\nset = { I1A1 = 1 }\n\
             [[part.at]]\ntick = 310\nturn = { 1 = -250 }\n"
    });
    let traj = m.path().join("hw.traj");
    let rec = m.path().join("hw.jsonl");
    let out = Ncplc::run(m.path())
        .args(["--io", "canopen"])
        .virtual_time()
        .mdi("N1 G00 X-10 Z-20")
        .ticks(450)
        .trajectory(&traj)
        .record(&rec)
        .output();
    let r = text(&out);
    assert!(out.status.success(), "{r}");
    let last = std::fs::read_to_string(&traj).expect("trajectory");
    let v: serde_json::Value =
        serde_json::from_str(last.lines().last().expect("a line")).expect("json");
    assert_eq!(v["p"].to_string(), "[-10,-22.5]");
    let trace = std::fs::read_to_string(&rec).expect("trace");
    let header = trace.lines().next().expect("header");
    assert!(
        header.contains(r#""bus_inputs":[0,1,2,3,4,5,6]}"#),
        "{header}"
    );
    let out = ncplc(&["replay", s(m.path()), s(&rec)]);
    let r = text(&out);
    assert!(out.status.success(), "{r}");
    assert!(
        r.contains("outputs identical, kernel signals and axis positions identical"),
        "{r}"
    );
}
