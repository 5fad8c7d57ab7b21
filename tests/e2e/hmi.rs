//! End-to-end tests of the web HMI's JSON API over real HTTP against `ncplc run --hmi`: reads,
//! writes, forces (and that a recorded session with forces replays exactly), refusals as JSON
//! 4xx, read-only mode, and the access token of a non-loopback bind (the security checks
//! themselves: `hmi_security.rs`).

use crate::hmi_common;

use std::process::Command;

use hmi_common::{Hmi, Ws, http, replay, root};

fn json(body: &str) -> serde_json::Value {
    serde_json::from_str(body).unwrap_or_else(|e| panic!("not JSON ({e}): {body}"))
}

#[test]
fn the_api_forces_and_writes_and_a_recorded_session_replays_exactly() {
    let dir = tempfile::tempdir().expect("tempdir");
    let trace = dir.path().join("session.jsonl");
    let machine = root().join("plc-programs/lathe");
    let hmi = Hmi::start(
        &machine,
        &["--record", trace.to_str().expect("utf8"), "--hmi-flow"],
    );
    hmi.wait_tick(20);
    // The sim closes the e-stop chain at tick 0.
    let (code, body) = hmi.http("GET", "/api/signal/I0A0", None);
    assert_eq!(code, 200);
    let v = json(&body);
    assert_eq!(
        (
            v["signal"].as_str(),
            v["value"].as_u64(),
            v["forced"].as_bool()
        ),
        (Some("I0A0"), Some(1), Some(false))
    );
    // LUBE_LAMP (U5A2) is off while the lube level is fine: force it on by its program name.
    let (code, body) = hmi.http(
        "POST",
        "/api/force",
        Some(r#"{"signal":"LUBE_LAMP","value":1}"#),
    );
    assert_eq!(code, 200, "{body}");
    let applied = json(&body)["tick"].as_u64().expect("tick");
    hmi.wait_tick(applied + 3);
    let v = json(&hmi.http("GET", "/api/signal/U5A2", None).1);
    assert_eq!(
        (v["value"].as_u64(), v["forced"].as_bool()),
        (Some(1), Some(true))
    );
    let v = json(&hmi.http("GET", "/api/force", None).1);
    assert_eq!(
        v["forced"],
        serde_json::json!([{"signal": "U5A2", "value": 1}])
    );
    // Power flow from the scan (PLCPRG): the e-stop chain is closed (lines 62–64 compute 1), and
    // the LUBE_LAMP rung (line 133) shows what the logic computed — 0, lube level fine — while
    // the force holds the output at 1.
    let v = json(&hmi.http("GET", "/api/flow", None).1);
    let flow: Vec<(u64, f64)> = v["flow"]
        .as_array()
        .expect("flow")
        .iter()
        .map(|p| {
            (
                p[0].as_u64().unwrap_or(0),
                p[1].as_f64().unwrap_or(f64::NAN),
            )
        })
        .collect();
    let at = |line: u64| -> Vec<f64> {
        flow.iter()
            .filter(|(l, _)| *l == line)
            .map(|(_, v)| *v)
            .collect()
    };
    assert_eq!(
        (at(62), at(63), at(64), at(133)),
        (vec![1.0], vec![1.0], vec![1.0], vec![0.0]),
        "{v}"
    );
    // Lines 113/114: SET/RES LUBE_ALARM conditions, both 0 with a full tank and no RESET.
    assert_eq!((at(113), at(114)), (vec![0.0], vec![0.0]));
    // A write once: CYCLE START pressed for one scan (the sim releases it again at its next latch).
    let (code, _) = hmi.http("POST", "/api/write", Some(r#"{"signal":"I0A3","value":1}"#));
    assert_eq!(code, 200);
    // Refusals: JSON with a 4xx and the reason.
    for (method, path, body, want_code, want) in [
        (
            "POST",
            "/api/force",
            r#"{"signal":"U5A2","value":2}"#,
            400,
            "U5A2: value 2 is out of range (0..1)",
        ),
        (
            "POST",
            "/api/write",
            r#"{"signal":"W0T2","value":1}"#,
            400,
            "W0T2: packet T holds the machine's constants (IOCFIL section 4); it is not written from the HMI",
        ),
        (
            "POST",
            "/api/write",
            r#"{"signal":"NOPE","value":1}"#,
            404,
            "`NOPE` is neither a signal address (I0A3, U4A0, W3K0) nor a name of this machine",
        ),
        (
            "POST",
            "/api/write",
            r#"{"signal":"I0A3","value":1,"extra":0}"#,
            400,
            "request body: unknown field `extra`, expected `signal` or `value` at line 1 column 34",
        ),
        (
            "POST",
            "/api/command",
            r#"{"process":1,"command":"jump"}"#,
            400,
            "unknown command \"jump\" (expected start, hold, reset, mode, mdi, ack)",
        ),
        (
            "POST",
            "/api/command",
            r#"{"process":9,"command":"start"}"#,
            400,
            "process 9 does not exist (processes are 1..5)",
        ),
        (
            "POST",
            "/api/command",
            r#"{"process":1,"command":"start"}"#,
            409,
            "start for process 1: no CNC kernel runs (the scripted sim plays the CNC); start with --program or --mdi for operator commands",
        ),
        ("DELETE", "/api/force/U4A0", "", 409, "U4A0 is not forced"),
        (
            "GET",
            "/api/nothing",
            "",
            404,
            "no such page or API route: /api/nothing",
        ),
    ] {
        let (code, got) = hmi.http(method, path, (!body.is_empty()).then_some(body));
        assert_eq!(
            (code, json(&got)["error"].as_str()),
            (want_code, Some(want)),
            "{method} {path} {body}"
        );
    }
    let (code, _) = hmi.http("DELETE", "/api/force/U5A2", None);
    assert_eq!(code, 200);
    hmi.wait_tick(applied + 10);
    hmi.stop();
    let text = std::fs::read_to_string(&trace).expect("trace");
    assert!(
        text.lines().any(|l| l.contains(r#""forced":{"U5A2":1}"#)),
        "the force is in the trace:\n{text}"
    );
    assert!(
        text.lines().any(|l| l.contains(r#""I0A3":1"#)),
        "the write is in the trace"
    );
    let (ok, text) = replay(&machine, &trace, &[]);
    assert!(ok, "replay diverges:\n{text}");
}

#[test]
fn a_readonly_hmi_refuses_writes_forces_and_commands() {
    let hmi = Hmi::start(&root().join("plc-programs/lathe"), &["--hmi-readonly"]);
    for (method, path, body) in [
        ("POST", "/api/write", Some(r#"{"signal":"I0A3","value":1}"#)),
        ("POST", "/api/force", Some(r#"{"signal":"I0A3","value":1}"#)),
        ("DELETE", "/api/force", None),
        (
            "POST",
            "/api/command",
            Some(r#"{"process":1,"command":"hold"}"#),
        ),
    ] {
        let (code, got) = hmi.http(method, path, body);
        assert_eq!(code, 403, "{method} {path}");
        let v = json(&got);
        let error = v["error"].as_str().unwrap_or_default();
        assert!(
            error.ends_with(
                "; the HMI is read-only (--hmi-readonly): writes, forces and commands are disabled"
            ),
            "{got}"
        );
        // The start URL's token is an integrator's; read-only makes it a viewer.
        assert_eq!(v["role"], "viewer", "{got}");
    }
    assert_eq!(hmi.http("GET", "/api/status", None).0, 200);
    hmi.stop();
}

#[test]
fn a_non_loopback_bind_needs_the_printed_token() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .args([
            "run".as_ref(),
            root().join("plc-programs/lathe").as_os_str(),
        ])
        .args([
            "--hmi",
            "0.0.0.0:0",
            "--no-watch",
            "--ticks",
            "3000",
            "--overrun-limit",
            "0",
        ])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("ncplc");
    let err = child.stderr.take().expect("stderr");
    let mut lines = std::io::BufRead::lines(std::io::BufReader::new(err)).map_while(Result::ok);
    let line = lines
        .find(|l| l.starts_with("hmi: http://"))
        .expect("the HMI line");
    // hmi: http://0.0.0.0:PORT/?token=T
    let (bound, token) = hmi_common::start_line(&line).expect("start line");
    let token = token.expect("the start URL carries the token");
    let token = token.as_str();
    let port = bound.rsplit(':').next().expect("port");
    assert_eq!(token.len(), 32, "{line}");
    // The plain-HTTP risk of a non-loopback bind is named.
    let warning = lines.next().expect("a warning after the start line");
    assert!(
        warning.starts_with(&format!("hmi: warning: 0.0.0.0:{port} is reachable from the network and the HMI speaks plain HTTP: anyone on the network path can read the session token")),
        "{warning}"
    );
    let addr = format!("127.0.0.1:{port}");
    let (code, body) = http(&addr, "GET", "/api/status", None, None);
    assert_eq!(code, 401, "{body}");
    assert_eq!(
        http(&addr, "GET", "/api/status", None, Some("wrong")).0,
        401
    );
    assert_eq!(http(&addr, "GET", "/api/status", None, Some(token)).0, 200);
    // The start URL sets the session cookie and sends the browser to `/`.
    assert_eq!(
        http(&addr, "GET", &format!("/?token={token}"), None, None).0,
        303
    );
    // The scripts are public (they hold no data).
    assert_eq!(http(&addr, "GET", "/static/app.js", None, None).0, 200);
    // A missing asset is refused like every other request: a JSON error.
    let (code, body) = http(&addr, "GET", "/static/nothing.js", None, None);
    assert_eq!(code, 404);
    assert_eq!(body, r#"{"error":"no such file: nothing.js"}"#);
    // A path parameter that is not UTF-8 once decoded: a JSON 400, not axum's plain text.
    for (path, param) in [("/static/%FF", "path"), ("/api/signal/%FF", "addr")] {
        let (code, body) = http(&addr, "GET", path, None, Some(token));
        assert_eq!(code, 400, "{path}");
        assert_eq!(
            body,
            format!(r#"{{"error":"the request's path: Invalid UTF-8 in `{param}`"}}"#),
            "{path}"
        );
    }
    let _ = child.kill();
    let _ = child.wait();
}

/// `/ws?ack=1` sends nothing more until the client acknowledges, and then the newest snapshot, not
/// the next in a queue; `/ws` pushes without being asked.
#[test]
fn a_paced_websocket_client_gets_the_latest_snapshot_after_each_acknowledgement() {
    let hmi = Hmi::start(&root().join("plc-programs/lathe"), &["--ticks", "3000"]);
    let mut paced = hmi.ws("/ws?ack=1");
    let wait = std::time::Duration::from_secs(10);
    let first = paced.next_tick(wait).expect("the first frame");
    // Not acknowledged: nothing comes, however many snapshots the scan publishes (every 25 ms).
    assert_eq!(paced.next_tick(std::time::Duration::from_millis(600)), None);
    hmi.wait_tick(first + 60);
    paced.send("ack");
    let second = paced.next_tick(wait).expect("a frame after the ack");
    assert!(
        second >= first + 60,
        "after the ack the newest snapshot (tick ≥ {}), not a queued one: {second}",
        first + 60
    );
    // A pacing the server does not know is refused, not taken for the unpaced stream.
    for bad in ["/ws?ack=2", "/ws?ack=yes"] {
        let auth = format!(
            "Authorization: Bearer {}\r\n",
            hmi.token.as_deref().unwrap_or("")
        );
        let Err(answer) = Ws::try_connect_with(&hmi.addr, bad, &auth) else {
            panic!("{bad} was upgraded");
        };
        assert!(answer.starts_with("HTTP/1.1 400"), "{bad}: {answer}");
        assert!(answer.contains("\"error\":"), "{bad}: {answer}");
    }
    // Unpaced: frames keep coming with nothing sent.
    let mut pushed = hmi.ws("/ws");
    let ticks: Vec<u64> = (0..3).filter_map(|_| pushed.next_tick(wait)).collect();
    assert_eq!(ticks.len(), 3, "{ticks:?}");
    hmi.stop();
}
