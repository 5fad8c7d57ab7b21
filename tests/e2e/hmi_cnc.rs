//! The web HMI driving the CNC kernel (`ncplc run --program PART1 --hmi`) over real HTTP: the
//! status comes from the kernel (mode, state, block with its source line, DRO, path speed, the
//! tool path), START / FEED HOLD / RESET / mode / MDI go through the kernel's operator channel and
//! take effect at the next tick, refusals carry the kernel's reason, and alarms are acknowledged.
//! The lathe copy has no scripted CYCLE START: the HMI is the operator.

use crate::hmi_common;

use hmi_common::{Hmi, operator_lathe, replay, status, wait_status};
use serde_json::{Value, json};

fn json_of(body: &str) -> Value {
    serde_json::from_str(body).unwrap_or_else(|e| panic!("not JSON ({e}): {body}"))
}

fn p1(s: &Value) -> &Value {
    &s["machine"]["processes"][0]
}

fn post(hmi: &Hmi, body: &str) -> (u16, Value) {
    let (code, text) = hmi.http("POST", "/api/command", Some(body));
    (code, json_of(&text))
}

fn axis(s: &Value, name: &str) -> (f64, f64) {
    let a = p1(s)["axes"]
        .as_array()
        .and_then(|v| v.iter().find(|a| a["name"] == name))
        .unwrap_or_else(|| panic!("axis {name} in {s}"));
    (
        a["command"].as_f64().unwrap_or(f64::NAN),
        a["actual"].as_f64().unwrap_or(f64::NAN),
    )
}

/// The modal codes in effect at block `n` of the lathe's PART1 (N30 onwards, up to N140), by hand
/// from its text: N10 G53 S1200 M03, N20 M08, then G00/G01 and F300 until N120 sets F150 (F stays
/// in effect across rapids); the lathe interpolates in the ZX plane (G18); MEFI's G90, G94 and
/// G40 hold from the start, no D is programmed.
fn part1_modal(n: u64) -> Vec<&'static str> {
    let (g, f) = match n {
        30 => ("G00", None),
        40 | 50 | 80 | 90 => ("G01", Some("F300")),
        60 | 70 | 100 | 110 => ("G00", Some("F300")),
        120 | 130 => ("G01", Some("F150")),
        140 => ("G00", Some("F150")),
        _ => panic!("PART1 has no motion block N{n}"),
    };
    let mut v = vec![g, "G18", "G90", "G94", "G53", "G40"];
    v.extend(f);
    v.extend(["S1200", "M03", "M08"]);
    v
}

#[test]
fn start_hold_reset_mode_and_mdi_go_to_the_kernel_and_refusals_carry_its_reason() {
    let lathe = operator_lathe();
    let dir = tempfile::tempdir().expect("tempdir");
    let trace = dir.path().join("session.jsonl");
    // Selected in AUTO by the part run; nothing starts it.
    let (hmi, s) = part1_session(lathe.path(), &trace);
    let p = p1(&s);
    assert_eq!(
        (
            &p["state"],
            &p["on"],
            &p["block"],
            &p["block_index"],
            &p["block_source"]
        ),
        (
            &json!("idle"),
            &json!(true),
            &json!(10),
            &json!(1),
            &json!("N10 G53 S1200 M03                \" Machine frame; spindle on, waits at speed")
        )
    );
    assert_eq!(axis(&s, "X").0, 0.0);
    assert_eq!(p["active_codes"], json!(["S1200", "M03"]));
    assert_eq!(
        p["modal_codes"],
        json!(["G90", "G94", "G53", "G40", "S1200", "M03"])
    );
    // MDI in AUTO: the kernel's reason.
    let (code, v) = post(
        &hmi,
        r#"{"process":1,"command":"mdi","line":"N1 G00 X-10"}"#,
    );
    assert_eq!(
        (code, &v["error"]),
        (409, &json!("process 1: not allowed in this mode"))
    );
    let (code, v) = post(&hmi, r#"{"process":1,"command":"mode","mode":"FAST"}"#);
    assert_eq!(
        (code, &v["error"]),
        (
            409,
            &json!("unknown mode \"FAST\" (expected AUTO, STEP, MDI, MANU, MANJ, HOME or IDLE)")
        )
    );
    // START: the cycle runs from the next tick on.
    let (code, v) = post(&hmi, r#"{"process":1,"command":"start"}"#);
    assert_eq!(code, 200, "{v}");
    let started = v["tick"].as_u64().expect("tick");
    let s = wait_status(&hmi, "the axes moving in block N30 or later", 30, |s| {
        p1(s)["block"].as_u64().unwrap_or(0) >= 30 && p1(s)["path_speed"].as_f64() > Some(0.0)
    });
    assert_eq!(p1(&s)["state"], "running");
    // A mode change now: refused with the kernel's reason.
    let (code, v) = post(&hmi, r#"{"process":1,"command":"mode","mode":"MANU"}"#);
    assert_eq!(code, 409, "{v}");
    let why = v["error"].as_str().unwrap_or_default();
    assert!(
        why == "process 1: can't switch mode while axes move"
            || why == "process 1: can't do that while a program is active (reset first)",
        "{why}"
    );
    // FEED HOLD: the path speed reaches 0 and the set points stop.
    let (code, _) = post(&hmi, r#"{"process":1,"command":"hold"}"#);
    assert_eq!(code, 200);
    let held = wait_status(&hmi, "the path held", 10, |s| {
        p1(s)["state"] == "held" && p1(s)["path_speed"] == 0.0
    });
    assert_eq!(
        p1(&held)["modal_codes"],
        json!(part1_modal(p1(&held)["block"].as_u64().unwrap_or(0))),
        "{held}"
    );
    std::thread::sleep(std::time::Duration::from_millis(300));
    let later = status(&hmi);
    assert!(later["tick"].as_u64() >= Some(held["tick"].as_u64().unwrap_or(0) + 10));
    assert_eq!(
        (axis(&later, "X").0, axis(&later, "Z").0),
        (axis(&held, "X").0, axis(&held, "Z").0)
    );
    // START resumes; RESET returns to the program start.
    let (code, _) = post(&hmi, r#"{"process":1,"command":"start"}"#);
    assert_eq!(code, 200);
    wait_status(&hmi, "the path resumed", 10, |s| {
        p1(s)["state"] == "running" && p1(s)["path_speed"].as_f64() > Some(0.0)
    });
    let (code, _) = post(&hmi, r#"{"process":1,"command":"reset"}"#);
    assert_eq!(code, 200);
    let s = wait_status(&hmi, "the reset", 10, |s| {
        p1(s)["state"] == "idle" && p1(s)["block_index"] == 1 && p1(s)["path_speed"] == 0.0
    });
    // Back at the first block: the modal codes are folded again from the start.
    assert_eq!(
        p1(&s)["modal_codes"],
        json!(["G90", "G94", "G53", "G40", "S1200", "M03"])
    );
    let (x, z) = (axis(&s, "X").0, axis(&s, "Z").0);
    assert!(
        x < 0.0 && z < 0.0,
        "the axes stay where the reset stopped them: X {x} Z {z}"
    );
    // MDI: mode MDI, one block; the set point reaches its end point.
    let (code, v) = post(&hmi, r#"{"process":1,"command":"mode","mode":"mdi"}"#);
    assert_eq!(code, 200, "{v}");
    wait_status(&hmi, "mode MDI", 5, |s| p1(s)["mode"] == "MDI");
    let (code, v) = post(
        &hmi,
        r#"{"process":1,"command":"mdi","line":"N5 G00 X-30 Z-20"}"#,
    );
    assert_eq!(code, 200, "{v}");
    let s = wait_status(&hmi, "the MDI block's end point", 30, |s| {
        axis(s, "X").0 == -30.0 && axis(s, "Z").0 == -20.0 && p1(s)["state"] == "idle"
    });
    assert_eq!(p1(&s)["program"], "MDI");
    // The tool path: the MDI program's (one block: nothing to draw before its end point) and the
    // sampled set points ending at X-30 Z-20 (drawn Z right, X up).
    let (code, body) = hmi.http("GET", "/api/toolpath/1", None);
    assert_eq!(code, 200);
    let tp = json_of(&body);
    assert_eq!(
        (&tp["axes"], &tp["program"], &tp["programmed"]),
        (&json!(["Z", "X"]), &json!("MDI"), &json!([]))
    );
    let actual = tp["actual"].as_array().expect("actual");
    assert_eq!(actual.last(), Some(&json!([-20.0, -30.0])));
    // Sampled once per published frame (≥ 20 Hz) along the move (about half a second since X
    // moves in diameter): more than the two ends.
    assert!(actual.len() > 4, "{} sampled points", actual.len());
    let (code, v) = json_pair(hmi.http("GET", "/api/toolpath/2", None));
    assert_eq!(
        (code, &v["error"]),
        (
            404,
            &json!(
                "process 2 has no tool path (no CNC kernel runs, or the process has no interpolated axes)"
            )
        )
    );
    hmi.stop();
    // START took effect at the tick the reply named (or the next): CYCLE (I1K5) rises in that
    // tick's inputs.
    let text = std::fs::read_to_string(&trace).expect("trace");
    let cycle_on = text
        .lines()
        .filter_map(|l| serde_json::from_str::<Value>(l).ok())
        .find(|r| r["in"]["I1K5"] == 1)
        .and_then(|r| r["t"].as_u64());
    assert!(
        cycle_on.is_some_and(|t| t >= started && t <= started + 1),
        "CYCLE rose at {cycle_on:?}, START applied at {started}"
    );
}

/// `ncplc run` of the operator lathe `lathe` with PART1 under the HMI, recording to `trace`,
/// once the part run has selected PART1 in AUTO (nothing starts it): the HMI and that status.
fn part1_session(lathe: &std::path::Path, trace: &std::path::Path) -> (Hmi, Value) {
    let trace = trace.to_str().expect("utf8");
    let hmi = Hmi::start(lathe, &["--program", "PART1", "--record", trace]);
    let s = wait_status(&hmi, "PART1 selected in AUTO", 30, |s| {
        p1(s)["mode"] == "AUTO" && p1(s)["program"] == "PART1"
    });
    (hmi, s)
}

/// The operator commands of a recorded trace's text with the ticks they are recorded at.
fn recorded_commands(text: &str) -> Vec<(u64, Value)> {
    text.lines()
        .filter_map(|l| serde_json::from_str::<Value>(l).ok())
        .filter(|r| r.get("cmd").is_some())
        .map(|r| (r["t"].as_u64().unwrap_or(0), r["cmd"].clone()))
        .collect()
}

fn json_pair((code, body): (u16, String)) -> (u16, Value) {
    (code, json_of(&body))
}

#[test]
fn acknowledge_clears_gone_alarms_and_a_persisting_one_comes_back() {
    let lathe = operator_lathe();
    let hmi = Hmi::start(lathe.path(), &["--program", "PART1"]);
    wait_status(&hmi, "PART1 selected", 30, |s| p1(s)["program"] == "PART1");
    // Open the e-stop chain (I0A0): the kernel raises its stopping alarm.
    let (code, _) = hmi.http("POST", "/api/force", Some(r#"{"signal":"I0A0","value":0}"#));
    assert_eq!(code, 200);
    let estop = "process 1: emergency stop";
    let s = wait_status(&hmi, "the e-stop alarm", 10, |s| {
        p1(s)["alarms"].as_array().is_some_and(|a| !a.is_empty())
    });
    let entry = &p1(&s)["alarms"][0];
    assert_eq!(
        (&entry["text"], &entry["active"], &entry["acknowledged"]),
        (&json!(estop), &json!(true), &json!(false))
    );
    assert_eq!(p1(&s)["on"], false);
    // The kernel keeps it until RESET: after acknowledge it is back at once, acknowledged.
    let (code, v) = post(&hmi, r#"{"process":1,"command":"ack"}"#);
    assert_eq!(code, 200, "{v}");
    let s = wait_status(&hmi, "the acknowledged alarm", 5, |s| {
        p1(s)["alarms"][0]["acknowledged"] == true
    });
    assert_eq!(p1(&s)["alarms"].as_array().map(Vec::len), Some(1));
    assert_eq!(p1(&s)["alarms"][0]["active"], true);
    // Chain closed, RESET: the cause has gone, and an acknowledged entry leaves with it.
    let (code, _) = hmi.http("DELETE", "/api/force/I0A0", None);
    assert_eq!(code, 200);
    let (code, _) = post(&hmi, r#"{"process":1,"command":"reset"}"#);
    assert_eq!(code, 200);
    wait_status(&hmi, "the list empty after RESET", 5, |s| {
        p1(s)["alarms"] == json!([]) && p1(s)["on"] == true
    });
    // Once more without acknowledging first: after RESET it stays listed, gone, until `ack`
    // (without a process: every list).
    hmi.http("POST", "/api/force", Some(r#"{"signal":"I0A0","value":0}"#));
    wait_status(&hmi, "the second e-stop alarm", 10, |s| {
        p1(s)["alarms"][0]["active"] == true
    });
    hmi.http("DELETE", "/api/force/I0A0", None);
    post(&hmi, r#"{"process":1,"command":"reset"}"#);
    let s = wait_status(&hmi, "the gone alarm still listed", 5, |s| {
        p1(s)["alarms"][0]["active"] == false
    });
    assert_eq!(p1(&s)["alarms"][0]["acknowledged"], false);
    let (code, v) = post(&hmi, r#"{"command":"ack"}"#);
    assert_eq!((code, &v["process"]), (200, &Value::Null));
    wait_status(&hmi, "the list empty after ack", 5, |s| {
        p1(s)["alarms"] == json!([])
    });
    hmi.stop();
}

#[test]
fn a_part_run_with_start_and_hold_from_the_api_replays_exactly() {
    let lathe = operator_lathe();
    let dir = tempfile::tempdir().expect("tempdir");
    let trace = dir.path().join("session.jsonl");
    let (hmi, _) = part1_session(lathe.path(), &trace);
    let (code, v) = post(&hmi, r#"{"process":1,"command":"start"}"#);
    assert_eq!(code, 200, "{v}");
    let started = v["tick"].as_u64().expect("tick");
    wait_status(&hmi, "the axes moving", 30, |s| {
        p1(s)["path_speed"].as_f64() > Some(0.0)
    });
    let (code, v) = post(&hmi, r#"{"process":1,"command":"hold"}"#);
    assert_eq!(code, 200, "{v}");
    let held = v["tick"].as_u64().expect("tick");
    wait_status(&hmi, "the path held", 10, |s| {
        p1(s)["state"] == "held" && p1(s)["path_speed"] == 0.0
    });
    let (code, v) = post(&hmi, r#"{"process":1,"command":"start"}"#);
    assert_eq!(code, 200, "{v}");
    let resumed = v["tick"].as_u64().expect("tick");
    let s = wait_status(&hmi, "the path resumed", 10, |s| {
        p1(s)["state"] == "running" && p1(s)["path_speed"].as_f64() > Some(0.0)
    });
    hmi.wait_tick(s["tick"].as_u64().unwrap_or(0) + 20);
    hmi.stop();
    // Each command is in the record of the tick whose latch first saw it: the tick its reply
    // named.
    let text = std::fs::read_to_string(&trace).expect("trace");
    let cmds = recorded_commands(&text);
    // Each with the role of the session that sent it (the start URL's token: integrator).
    let start = json!([{"process": 1, "command": "start", "role": "integrator"}]);
    let hold = json!([{"process": 1, "command": "hold", "role": "integrator"}]);
    assert_eq!(
        cmds,
        vec![(started, start.clone()), (held, hold), (resumed, start)]
    );
    let (ok, err) = replay(lathe.path(), &trace, &[]);
    assert!(ok, "the recorded session replays:\n{err}");
    assert!(
        err.contains("kernel signals and axis positions identical"),
        "{err}"
    );
    // Without the recorded HOLD the replay runs through it: the positions diverge.
    let without: String = text
        .lines()
        .map(|l| {
            l.replace(
                r#","cmd":[{"process":1,"command":"hold","role":"integrator"}]"#,
                "",
            )
        })
        .collect::<Vec<_>>()
        .join("\n");
    assert_ne!(without.len(), text.trim_end().len(), "the HOLD was removed");
    let edited = dir.path().join("without-hold.jsonl");
    std::fs::write(&edited, without + "\n").expect("write");
    let (ok, err) = replay(lathe.path(), &edited, &[]);
    assert!(!ok, "a replay without the HOLD diverges:\n{err}");
}

#[test]
fn an_mdi_line_from_the_api_is_planned_beside_the_scan_and_replays_exactly() {
    let lathe = operator_lathe();
    let dir = tempfile::tempdir().expect("tempdir");
    let trace = dir.path().join("session.jsonl");
    let (hmi, s) = part1_session(lathe.path(), &trace);
    assert_eq!(s["mdi_compiles"], json!({"requests": 0, "scan": 0}));
    let (code, v) = post(&hmi, r#"{"process":1,"command":"mode","mode":"mdi"}"#);
    assert_eq!(code, 200, "{v}");
    wait_status(&hmi, "mode MDI", 5, |s| p1(s)["mode"] == "MDI");
    // A line that does not compile is answered by the request thread: the scan never sees it.
    let (code, v) = post(&hmi, r#"{"process":1,"command":"mdi","line":"N5 G00 X-"}"#);
    assert_eq!(code, 409, "{v}");
    let err = v["error"].as_str().unwrap_or_default();
    assert!(err.starts_with("MDI: "), "{err}");
    let (code, v) = post(
        &hmi,
        r#"{"process":1,"command":"mdi","line":"N5 G00 X-30 Z-20"}"#,
    );
    assert_eq!(code, 200, "{v}");
    let applied = v["tick"].as_u64().expect("tick");
    let s = wait_status(&hmi, "the MDI block's end point", 30, |s| {
        axis(s, "X").0 == -30.0 && axis(s, "Z").0 == -20.0 && p1(s)["state"] == "idle"
    });
    // Both lines were compiled on the request thread, none on the scan's.
    assert_eq!(s["mdi_compiles"], json!({"requests": 2, "scan": 0}));
    hmi.wait_tick(s["tick"].as_u64().unwrap_or(0) + 10);
    hmi.stop();
    // The accepted line is in the record of the tick that applied it; the refused one is not.
    let text = std::fs::read_to_string(&trace).expect("trace");
    let cmds = recorded_commands(&text);
    let mdi =
        json!([{"process": 1, "command": "mdi", "line": "N5 G00 X-30 Z-20", "role": "integrator"}]);
    assert_eq!(cmds.last(), Some(&(applied, mdi)), "{cmds:?}");
    let (ok, err) = replay(lathe.path(), &trace, &[]);
    assert!(ok, "the recorded session replays:\n{err}");
    assert!(
        err.contains("kernel signals and axis positions identical"),
        "{err}"
    );
}
