//! Power flow switched at run time through the API (`POST /api/flow`), on the JIT and on the
//! interpreter: the flow appears and goes, and a session recorded across both switches replays
//! exactly (the instrumented scan computes the same image as the plain one).

use crate::hmi_common;

use hmi_common::{Hmi, replay, root, status};
use serde_json::{Value, json};

fn json_of(body: &str) -> Value {
    serde_json::from_str(body).unwrap_or_else(|e| panic!("not JSON ({e}): {body}"))
}

/// Polls `GET /api/flow` (at most 30 s) until its `[line, value]` list satisfies `ok`; the tick.
fn wait_flow(hmi: &Hmi, what: &str, ok: impl Fn(&[Value]) -> bool) -> u64 {
    for _ in 0..3000 {
        let (code, body) = hmi.http("GET", "/api/flow", None);
        assert_eq!(code, 200);
        let v = json_of(&body);
        if ok(v["flow"].as_array().map_or(&[][..], Vec::as_slice)) {
            return v["tick"].as_u64().unwrap_or(0);
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    panic!("{what}: not within 30 s");
}

fn switch_flow_twice_and_replay(engine: &str) {
    let dir = tempfile::tempdir().expect("tempdir");
    let trace = dir.path().join("session.jsonl");
    let machine = root().join("plc-programs/lathe");
    let hmi = Hmi::start(
        &machine,
        &[
            "--record",
            trace.to_str().expect("utf8"),
            "--engine",
            engine,
        ],
    );
    hmi.wait_tick(20);
    assert_eq!(status(&hmi)["flow_enabled"], json!(false));
    wait_flow(&hmi, "no flow at start", <[Value]>::is_empty);
    // Bad bodies: 400.
    for body in [r#"{"enabled":1}"#, r#"{"enabled":true,"x":1}"#, "{}"] {
        let (code, _) = hmi.http("POST", "/api/flow", Some(body));
        assert_eq!(code, 400, "{body}");
    }
    let (code, body) = hmi.http("POST", "/api/flow", Some(r#"{"enabled":true}"#));
    assert_eq!(code, 200, "{body}");
    assert_eq!(json_of(&body)["enabled"], json!(true));
    // CHAIN_OK = ESTOP_PB_OK * OVERTRAVEL_OK (line 62) computes 1 while the sim closes the chain.
    let on = wait_flow(&hmi, "flow on, line 62 at 1", |flow| {
        flow.iter().any(|p| p == &json!([62, 1.0]))
    });
    assert_eq!(status(&hmi)["flow_enabled"], json!(true));
    hmi.wait_tick(on + 30);
    let (code, _) = hmi.http("POST", "/api/flow", Some(r#"{"enabled":false}"#));
    assert_eq!(code, 200);
    let off = wait_flow(&hmi, "flow off", <[Value]>::is_empty);
    assert_eq!(status(&hmi)["flow_enabled"], json!(false));
    hmi.wait_tick(off + 30);
    hmi.stop();
    let (ok, text) = replay(&machine, &trace, &["--engine", engine]);
    assert!(ok, "replay diverges:\n{text}");
}

#[test]
fn power_flow_switched_on_and_off_at_run_time_on_the_jit_replays_exactly() {
    switch_flow_twice_and_replay("jit");
}

#[test]
fn power_flow_switched_on_and_off_at_run_time_on_the_interpreter_replays_exactly() {
    switch_flow_twice_and_replay("interp");
}
