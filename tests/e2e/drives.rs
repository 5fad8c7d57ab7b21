//! End to end: part runs on CiA 402 drives (issue 21). `ncplc run … --io canopen --program PART1
//! --virtual-time` runs the bundled parts with their axes and spindle on simulated drives on the
//! virtual bus (io.toml `[[canopen.drive]]`), in lock-step with the scan; the drives' feedback is
//! recorded and `ncplc replay` re-runs the kernel from it without a bus. Faults are rehearsed with
//! the simulated drive's `simulate` hooks in a copy of the machine.

use std::path::Path;

use crate::e2e_common;
use e2e_common::{Ncplc, copy_dir, ncplc, root};

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// stdout and stderr of a run.
pub(crate) fn text(out: &std::process::Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

/// The last value of every axis in a text trace's `pos` records.
pub(crate) fn final_positions(trace: &str) -> Vec<(String, f64)> {
    let mut pos: Vec<(String, f64)> = Vec::new();
    for line in trace.lines().skip(1) {
        let rec: serde_json::Value = serde_json::from_str(line).expect("json");
        let Some(obj) = rec.get("pos").and_then(|p| p.as_object()) else {
            continue;
        };
        for (axis, bits) in obj {
            let bits = u64::from_str_radix(bits.as_str().expect("hex"), 16).expect("hex");
            let v = f64::from_bits(bits);
            match pos.iter_mut().find(|(a, _)| a == axis) {
                Some(p) => p.1 = v,
                None => pos.push((axis.clone(), v)),
            }
        }
    }
    pos.sort_by(|a, b| a.0.cmp(&b.0));
    pos
}

/// Runs PART1 of `machine` to its end on `io`, recording a text trace; (output, trace text).
fn part1(machine: &Path, io: &str, dir: &Path) -> (String, String, bool) {
    run_to_end(machine, "PART1", io, dir)
}

/// Runs `part` of `machine` to its end on `io` in virtual time, recording `<dir>/<io>.jsonl`;
/// (output, trace text, success).
pub(crate) fn run_to_end(
    machine: &Path,
    part: &str,
    io: &str,
    dir: &Path,
) -> (String, String, bool) {
    let trace = dir.join(format!("{io}.jsonl"));
    let out = Ncplc::run(machine)
        .args(["--io", io])
        .virtual_time()
        .program(part)
        .until_end()
        .record(&trace)
        .output();
    let t = std::fs::read_to_string(&trace).expect("trace");
    (text(&out), t, out.status.success())
}

#[test]
fn the_bundled_parts_run_on_drives_as_on_the_plant_and_replay_exactly() {
    let _serial = e2e_common::serial();
    // On the bus the panel and the machine's contacts reach the logic one tick later (the
    // simulated I/O node carries them: tests/e2e/ionode.rs), so the cycle starts a tick later
    // and its handshakes take a little longer; and each wait for the spindle at speed ends a
    // logic tick later (the at-speed contact comes from the drive's 606Ch, whose answer to a
    // tick's SYNCs reaches the kernel at the next tick).
    for (machine, (cycle, bus_cycle), end, header) in [
        (
            "lathe",
            (
                "cycle time 42.40 s (ticks 12..4252), ended",
                "cycle time 42.44 s (ticks 13..4257), ended",
            ),
            vec![("1X", -20.0), ("1Z", -50.0)],
            r#""drives":[{"axis":{"process":1,"axis":"X"},"node":3},{"axis":{"process":1,"axis":"Z"},"node":4},{"axis":{"process":1,"axis":"S"},"node":5}]"#,
        ),
        (
            "mill",
            (
                "cycle time 34.26 s (ticks 12..3438), ended",
                "cycle time 34.33 s (ticks 13..3446), ended",
            ),
            vec![("1X", -100.0), ("1Y", -100.0), ("1Z", -50.0)],
            r#""drives":[{"axis":{"process":1,"axis":"X"},"node":4},{"axis":{"process":1,"axis":"Y"},"node":5},{"axis":{"process":1,"axis":"Z"},"node":6},{"axis":{"process":1,"axis":"S"},"node":7}]"#,
        ),
    ] {
        let m = root().join("plc-programs").join(machine);
        let dir = tempfile::tempdir().expect("tempdir");
        let (plant, plant_trace, ok) = part1(&m, "sim", dir.path());
        assert!(ok, "{plant}");
        let (bus, bus_trace, ok) = part1(&m, "canopen", dir.path());
        assert!(ok, "{bus}");
        // The cycles, tick for tick, and the same end positions.
        assert!(plant.contains(cycle), "{plant}");
        assert!(bus.contains(bus_cycle), "{bus}");
        let want: Vec<(String, f64)> = end.iter().map(|(a, v)| (a.to_string(), *v)).collect();
        assert_eq!(final_positions(&bus_trace), want, "{machine}");
        assert_eq!(final_positions(&plant_trace), want, "{machine}");
        assert!(!bus.contains("alarm: process"), "{bus}");
        // The header names the drives; the feedback is in the records.
        let first = bus_trace.lines().next().expect("header");
        assert!(first.contains(header), "{first}");
        assert!(bus_trace.contains(r#""drives":[{"axis":{"process":1,"axis":"X"},"values":["#));
        // The replay re-runs the kernel from the recorded feedback, with no bus.
        let trace = dir.path().join("canopen.jsonl");
        let out = ncplc(&["replay", s(&m), s(&trace)]);
        let r = text(&out);
        assert!(out.status.success(), "{r}");
        assert!(
            r.contains("outputs identical, kernel signals and axis positions identical"),
            "{r}"
        );
    }
}

/// The ticks where a text trace records the input `name` changing, with its value.
pub(crate) fn input_changes(trace: &str, name: &str) -> Vec<(u64, u64)> {
    trace
        .lines()
        .skip(1)
        .filter_map(|l| {
            let rec: serde_json::Value = serde_json::from_str(l).expect("json");
            let v = rec.get("in")?.get(name)?.as_u64()?;
            Some((rec["t"].as_u64()?, v))
        })
        .collect()
}

/// The spindle's last answer (rev/min) the kernel had at tick `t`: from the last record at or
/// before `t` with drive feedback (a trace records it when it changes).
fn spindle_rpm_at(trace: &str, t: u64) -> Option<f64> {
    let mut rpm = None;
    for l in trace.lines().skip(1) {
        let rec: serde_json::Value = serde_json::from_str(l).expect("json");
        if rec["t"].as_u64().is_none_or(|r| r > t) {
            break;
        }
        let s = rec
            .get("drives")
            .and_then(|d| d.as_array()?.iter().find(|d| d["axis"]["axis"] == "S"));
        if let Some(bits) = s.and_then(|s| s["values"].as_array()?.last()?.as_u64()) {
            rpm = Some(f64::from_bits(bits) * 60.0);
        }
    }
    rpm
}

/// The lathe's `csv` spindle: its at-speed contact (I0A5, POM max deviation 0.1) comes from the
/// drive's 606Ch. S1200 M03: on the plant the model is at speed at tick 87. On the bus the cycle
/// starts a tick later (CYCLE START comes over the I/O node), the drive's answer reaches
/// 1080.0 rev/min = 1200 − 10 % at tick 89 (one logic tick after the model, whose ramp the drive
/// follows), and the contact the kernel then closes reaches the logic over the I/O node at tick
/// 90; the summary shows the drive's top speed.
#[test]
fn the_spindle_is_at_speed_when_its_drive_says_so() {
    let _serial = e2e_common::serial();
    let m = root().join("plc-programs/lathe");
    let dir = tempfile::tempdir().expect("tempdir");
    let (plant, plant_trace, ok) = part1(&m, "sim", dir.path());
    assert!(ok, "{plant}");
    let (bus, bus_trace, ok) = part1(&m, "canopen", dir.path());
    assert!(ok, "{bus}");
    assert_eq!(input_changes(&plant_trace, "I0A5").first(), Some(&(87, 1)));
    assert_eq!(input_changes(&bus_trace, "I0A5").first(), Some(&(90, 1)));
    assert_eq!(spindle_rpm_at(&bus_trace, 89), Some(1080.0));
    assert!(spindle_rpm_at(&bus_trace, 88).is_some_and(|r| r < 1080.0));
    assert!(
        bus.contains("process 1 spindle on its drive: top speed 1200.0 rev/min (606Ch)\n"),
        "{bus}"
    );
    assert!(!plant.contains("spindle on its drive"), "{plant}");
}

/// A spindle drive that never reaches its speed keeps the feed waiting: its speed is limited to
/// 40960 units/s = 10 rev/s = 600 rev/min (io.toml `simulate = { max_speed = 40960 }`, 4096
/// units per revolution), below 1080 (S1200 − 10 %): M03 of N10 never gets FIN, no axis moves,
/// and after the 5 s strobe timeout the process stops with its alarm.
#[test]
fn a_spindle_drive_that_never_reaches_speed_keeps_the_feed_waiting() {
    let _serial = e2e_common::serial();
    let m = lathe_with_hooks("S", "{ max_speed = 40960 }");
    let (out, trace, _) = run_part(m.path(), &["--ticks", "1000"]);
    assert!(
        out.contains("process 1: 0 blocks; handshakes M 0 S 1 T 0; FIN wait M 5.01 s"),
        "{out}"
    );
    assert!(
        out.contains("process 1 spindle on its drive: top speed 600.0 rev/min (606Ch)\n"),
        "{out}"
    );
    assert!(
        out.contains("M03 not acknowledged (FIN) within the strobe timeout (block 1 (N10))"),
        "{out}"
    );
    assert_eq!(input_changes(&trace, "I0A5"), []);
    assert_eq!(spindle_rpm_at(&trace, 300), Some(600.0));
    // No axis moved: the positions are recorded once, at 0.
    assert_eq!(trace.matches(r#""pos":"#).count(), 1, "{trace}");
    assert!(
        trace.contains(r#""pos":{"1X":"0000000000000000","1Z":"0000000000000000"}"#),
        "{trace}"
    );
}

/// A replay takes the axes' positions from the recorded feedback: a changed value shows.
#[test]
fn a_replay_takes_the_positions_from_the_recorded_feedback() {
    let _serial = e2e_common::serial();
    let m = root().join("plc-programs/lathe");
    let dir = tempfile::tempdir().expect("tempdir");
    let (out, trace, ok) = part1(&m, "canopen", dir.path());
    assert!(ok, "{out}");
    // The first record where X moves: its last answer 1 mm further.
    let mut lines: Vec<String> = trace.lines().map(String::from).collect();
    let (i, t) = lines
        .iter()
        .enumerate()
        .skip(1)
        .find_map(|(i, l)| {
            let rec: serde_json::Value = serde_json::from_str(l).expect("json");
            let x = rec
                .get("drives")?
                .get(0)?
                .get("values")?
                .as_array()?
                .clone();
            let first = x.first()?.as_u64()?;
            let last = x.last()?.as_u64()?;
            (first != last).then(|| (i, rec["t"].as_u64().expect("t")))
        })
        .expect("X moves");
    let mut rec: serde_json::Value = serde_json::from_str(&lines[i]).expect("json");
    let values = rec["drives"][0]["values"].as_array_mut().expect("values");
    let last = values.last_mut().expect("value");
    let x = f64::from_bits(last.as_u64().expect("bits"));
    *last = serde_json::json!((x + 1.0).to_bits());
    lines[i] = rec.to_string();
    let changed = dir.path().join("changed.jsonl");
    std::fs::write(&changed, lines.join("\n") + "\n").expect("write");
    let out = ncplc(&["replay", s(&m), s(&changed)]);
    let r = text(&out);
    assert!(!out.status.success(), "{r}");
    assert!(r.contains("axis positions diverge from the trace"), "{r}");
    // The divergence table: tick, axis, expected, actual — 1 mm apart at the changed tick.
    let row = r
        .lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>())
        .find(|w| w.len() == 4 && w[1] == "1X")
        .unwrap_or_else(|| panic!("a 1X row: {r}"));
    assert_eq!(row[0], t.to_string(), "{r}");
    let (want, got): (f64, f64) = (row[2].parse().expect("num"), row[3].parse().expect("num"));
    assert!((got - want - 1.0).abs() < 1e-9, "{r}");
}

/// A copy of the lathe whose drive `axis` has the simulated drive's `hooks` (io.toml `simulate`).
fn lathe_with_hooks(axis: &str, hooks: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("tempdir");
    copy_dir(&root().join("plc-programs/lathe"), dir.path());
    let path = dir.path().join("io.toml");
    let text = std::fs::read_to_string(&path).expect("io.toml");
    let entry = format!("[[canopen.drive]]\naxis = \"{axis}\"\n");
    assert!(text.contains(&entry), "{entry}");
    let text = text.replacen(&entry, &format!("{entry}simulate = {hooks}\n"), 1);
    std::fs::write(&path, text).expect("write");
    dir
}

/// Runs PART1 on the drives of `machine` until its end (or a stopping alarm).
fn run_part(machine: &Path, extra: &[&str]) -> (String, String, Option<i32>) {
    let trace = machine.join("run.jsonl");
    let out = Ncplc::run(machine)
        .args(["--io", "canopen"])
        .virtual_time()
        .program("PART1")
        .record(&trace)
        .args(extra)
        .output();
    let t = std::fs::read_to_string(&trace).unwrap_or_default();
    (text(&out), t, out.status.code())
}

/// The tick of the first record whose drive sample of `axis` carries a fault, with the record.
fn first_fault(trace: &str, axis: char) -> Option<(u64, serde_json::Value)> {
    trace.lines().skip(1).find_map(|l| {
        let rec: serde_json::Value = serde_json::from_str(l).expect("json");
        let hit = rec.get("drives")?.as_array()?.iter().any(|d| {
            d["axis"]["axis"].as_str() == Some(&axis.to_string()) && d.get("fault").is_some()
        });
        hit.then(|| (rec["t"].as_u64().expect("t"), rec))
    })
}

#[test]
fn a_drive_fault_stops_the_process_with_its_603f_code_within_two_ticks() {
    let _serial = e2e_common::serial();
    // SYNC 1000 is the last of the five SYNCs of tick 199's set points (SYNCs 996..1000).
    let m = lathe_with_hooks("X", "{ fault_at_sync = 1000, fault_code = 0x5530 }");
    let (out, trace, code) = run_part(m.path(), &["--until-end"]);
    assert!(
        out.contains("alarm: process 1: drive fault on axis X (node 3): error code 5530h (603Fh)"),
        "{out}"
    );
    assert!(out.contains("did not end"), "{out}");
    assert_ne!(code, Some(0), "{out}");
    // The scan takes the answers to tick 199's SYNCs at tick 200's latch: the alarm (ALARM,
    // I1K4), the process's CYCLE (I1K5) down and the machine off (CONP, I0K2) in that tick.
    let (t, rec) = first_fault(&trace, 'X').expect("a fault in the trace");
    assert_eq!(t, 200, "{rec}");
    let x = &rec["drives"][0];
    assert_eq!(x["fault"]["code"], 0x5530, "{rec}");
    assert_eq!(x["fault"]["cause"], "drive", "{rec}");
    assert_eq!(
        x["statusword"].as_u64().map(|w| w & 0x4F),
        Some(0x08),
        "{rec}"
    );
    assert_eq!(rec["in"]["I1K5"], 0, "{rec}");
    assert_eq!(rec["in"]["I0K2"], 0, "{rec}");
    assert_eq!(rec["in"]["I1K4"], 1, "{rec}");
    // Nothing from the faulted drive is a position: the answers to SYNCs 996..999 are healthy,
    // the answer to SYNC 1000 (with the fault) is null.
    let nulls: Vec<bool> = x["values"]
        .as_array()
        .expect("values")
        .iter()
        .map(|v| v.is_null())
        .collect();
    assert_eq!(nulls, [false, false, false, false, true], "{rec}");
    // And the run replays exactly, alarm included.
    let replay = ncplc(&["replay", s(m.path()), s(&m.path().join("run.jsonl"))]);
    assert!(replay.status.success(), "{}", text(&replay));
}

#[test]
fn a_lost_heartbeat_is_an_alarm_and_quick_stops_the_drive() {
    let _serial = e2e_common::serial();
    // Heartbeats every 50 SYNCs (100 ms of 2 ms periods): the last at SYNC 950; the consumer
    // (2 × 100 ms = 100 SYNCs) gives up after SYNC 1050, i.e. at SYNC 1051 of tick 210's
    // set points, which the scan takes at tick 211.
    let m = lathe_with_hooks("Z", "{ heartbeat_stop_at_sync = 1000 }");
    let (out, trace, code) = run_part(m.path(), &["--until-end"]);
    assert!(
        out.contains("alarm: process 1: drive of axis Z (node 4) lost: no heartbeat within the consumer time (8130h); quick stop, machine off"),
        "{out}"
    );
    assert_ne!(code, Some(0), "{out}");
    let (t, rec) = first_fault(&trace, 'Z').expect("a fault in the trace");
    assert_eq!(t, 211, "{rec}");
    assert_eq!(rec["drives"][1]["fault"]["cause"], "heartbeat", "{rec}");
    assert_eq!(rec["drives"][1]["fault"]["code"], 0x8130, "{rec}");
    assert_eq!(rec["in"]["I0K2"], 0, "{rec}");
    assert_eq!(rec["in"]["I1K5"], 0, "{rec}");
}

#[test]
fn a_drive_that_refuses_to_enable_keeps_the_machine_off_with_a_clear_message() {
    let _serial = e2e_common::serial();
    let m = lathe_with_hooks("X", "{ refuse_enable = true }");
    let (out, _, code) = run_part(m.path(), &["--until-end"]);
    assert!(
        out.contains("alarm: process 1: drive of axis X (node 3) did not reach Operation enabled within 20 SYNCs (FF01h): the machine does not enable"),
        "{out}"
    );
    assert!(out.contains("the cycle never started"), "{out}");
    assert_ne!(code, Some(0), "{out}");
}

#[test]
fn simulate_hooks_need_the_virtual_bus_and_a_whole_fault() {
    let m = lathe_with_hooks("X", "{ fault_at_sync = 10 }");
    let out = ncplc(&["check", s(m.path())]);
    let r = text(&out);
    assert!(!out.status.success(), "{r}");
    assert!(r.contains("error[E3078]"), "{r}");
    assert!(
        r.contains("a simulated fault needs both fault_at_sync (≥ 1) and fault_code (not 0)"),
        "{r}"
    );
}

/// RESET (the PLC's ERS) after a drive fault: the kernel resets, the drive gets a fault reset
/// (the rising edge of controlword bit 7) and, with the machine on again, walks back to
/// *Operation enabled*.
#[test]
fn reset_clears_a_drive_fault_and_the_drive_enables_again() {
    let _serial = e2e_common::serial();
    let m = lathe_with_hooks("X", "{ fault_at_sync = 1000, fault_code = 0x5530 }");
    // A panel RESET button on I1A1 drives ERS; the operator presses it at tick 300 (the scan
    // reads it over the bus at tick 301).
    let prg = m.path().join("MP0/PLCPRG");
    let source = std::fs::read_to_string(&prg).expect("PLCPRG");
    let source = source.replacen(
        "\n$\n",
        "\nERS = I1A1                ; panel RESET button\n$\n",
        1,
    );
    std::fs::write(&prg, source).expect("write");
    let sim = m.path().join("sim.toml");
    let mut script = std::fs::read_to_string(&sim).expect("sim.toml");
    script += "\n[[part.at]]\ntick = 300\nset = { I1A1 = 1 }\n[[part.at]]\ntick = 303\nset = { I1A1 = 0 }\n";
    std::fs::write(&sim, script).expect("write");
    let (out, trace, _) = run_part(m.path(), &["--ticks", "400"]);
    assert!(out.contains("drive fault on axis X (node 3)"), "{out}");
    // ERS rises in scan 301; the kernel resets at tick 302 and orders the fault reset with tick
    // 302's SYNCs; their answers (no fault, the drive enabled again) come at tick 303.
    let cleared = trace.lines().skip(1).find_map(|l| {
        let rec: serde_json::Value = serde_json::from_str(l).expect("json");
        let t = rec["t"].as_u64().expect("t");
        let x = rec.get("drives")?.get(0)?.clone();
        (t > 200 && x.get("fault").is_none()).then_some((t, x, rec))
    });
    let (t, x, rec) = cleared.expect("the fault clears");
    assert_eq!(t, 303, "{rec}");
    assert!(
        x["values"]
            .as_array()
            .expect("values")
            .iter()
            .all(|v| !v.is_null()),
        "{rec}"
    );
    // Out of Fault into Ready to switch on (the machine was still off in tick 302)...
    assert_eq!(
        x["statusword"].as_u64().map(|w| w & 0x6F),
        Some(0x21),
        "{rec}"
    );
    // ...then, the machine on again, Operation enabled with tick 303's SYNCs.
    let enabled = trace.lines().skip(1).find_map(|l| {
        let rec: serde_json::Value = serde_json::from_str(l).expect("json");
        (rec["t"].as_u64() == Some(304)).then(|| rec["drives"][0]["statusword"].as_u64())
    });
    assert_eq!(enabled.flatten().map(|w| w & 0x6F), Some(0x27), "{trace}");
    // The alarm is gone (ALARM, I1K4) and the machine is on again (CONP, I0K2).
    let alarm_off = trace.lines().skip(1).any(|l| {
        let rec: serde_json::Value = serde_json::from_str(l).expect("json");
        rec["t"].as_u64() == Some(302) && rec["in"]["I1K4"] == 0
    });
    assert!(alarm_off, "{trace}");
    let replay = ncplc(&["replay", s(m.path()), s(&m.path().join("run.jsonl"))]);
    assert!(replay.status.success(), "{}", text(&replay));
}
