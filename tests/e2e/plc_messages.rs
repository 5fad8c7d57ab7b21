//! The PLC's messages end to end (docs/plc-messages.md): the lathe raises message 1 (lubrication
//! level low) from U21K0 and message 2 (chuck guard open) from U21K1; `ncplc run` prints them at
//! the tick the bit rose with the text of MP0/MESSAG; CWD 0004H switches them off; the web HMI
//! lists them, its `ack` (HTTP POST) gives the logic the acknowledge bit for exactly one scan,
//! recorded as the trace's input, the logic reacts in that scan (its lamp U5A3 goes out), and the
//! recording replays exactly.

use crate::e2e_common;
use crate::hmi_common;

use e2e_common::{Ncplc, copy_dir, root};
use hmi_common::{Hmi, replay, status, wait_status};
use serde_json::{Value, json};

const LUBE: &str = "Lubrication level low: refill the tank, then RESET";

/// The lathe's scripted 2000 ticks (sim.toml: level low at 1000, the 2 s filter, RESET at 1450;
/// guard open 1600..1700): the lines by hand from the script and the PLC program.
#[test]
fn run_prints_the_lathes_messages_at_the_ticks_their_bits_rose_and_fell() {
    let out = Ncplc::run(root().join("plc-programs/lathe"))
        .virtual_time()
        .ticks(2000)
        .output();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let lines: Vec<&str> = err.lines().filter(|l| l.starts_with("message")).collect();
    assert_eq!(
        lines,
        vec![
            format!("message: P1 #1 at tick 1200: {LUBE}"),
            format!("message cleared: P1 #1 at tick 1450: {LUBE}"),
            "message: P1 #2 at tick 1600: Chuck guard open".to_string(),
            "message cleared: P1 #2 at tick 1700: Chuck guard open".to_string(),
        ],
        "{err}"
    );
}

/// IOCFIL CWD bit 0004H: the messages are not serviced (the bits are still written).
#[test]
fn cwd_0004_switches_the_messages_off() {
    let dir = tempfile::tempdir().expect("tempdir");
    copy_dir(&root().join("plc-programs/lathe"), dir.path());
    let io = dir.path().join("MP0/IOCFIL");
    let text = std::fs::read(&io).expect("IOCFIL");
    let text = String::from_utf8_lossy(&text).replacen("CWD=0040", "CWD=0044", 1);
    std::fs::write(&io, text.as_bytes()).expect("write");
    let out = Ncplc::run(dir.path()).virtual_time().ticks(2000).output();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(!err.contains("message"), "{err}");
}

/// The trace's records as JSON.
fn records(trace: &std::path::Path) -> Vec<Value> {
    std::fs::read_to_string(trace)
        .expect("trace")
        .lines()
        .skip(1)
        .map(|l| serde_json::from_str(l).expect("record"))
        .collect()
}

#[test]
fn http_ack_reaches_the_logic_for_one_scan_and_the_run_replays_exactly() {
    let dir = tempfile::tempdir().expect("tempdir");
    let lathe = dir.path().join("lathe");
    std::fs::create_dir_all(&lathe).expect("mkdir");
    copy_dir(&root().join("plc-programs/lathe"), &lathe);
    let trace = dir.path().join("messages.jsonl");
    let hmi = Hmi::start(&lathe, &["--record", trace.to_str().expect("utf-8")]);
    // The lubrication level goes low now (forced), so message 1 comes 2 s later and stays.
    let (code, _) = hmi.http("POST", "/api/force", Some(r#"{"signal":"I0A7","value":0}"#));
    assert_eq!(code, 200);
    let s = wait_status(&hmi, "message 1", 20, |s| {
        s["messages"].as_array().is_some_and(|m| !m.is_empty())
    });
    let m = &s["messages"][0];
    assert_eq!(
        (&m["process"], &m["number"], &m["text"], &m["severity"]),
        (&json!(1), &json!(1), &json!(LUBE), &json!(500))
    );
    assert_eq!(
        (&m["active"], &m["acknowledged"]),
        (&json!(true), &json!(false))
    );
    let raised_at = m["tick"].as_u64().expect("tick");
    let (code, body) = hmi.http("POST", "/api/command", Some(r#"{"command":"ack"}"#));
    assert_eq!(code, 200, "{body}");
    let applied: Value = serde_json::from_str(&body).expect("JSON");
    let s = wait_status(&hmi, "message 1 acknowledged", 5, |s| {
        s["messages"][0]["acknowledged"] == true
    });
    assert_eq!(s["messages"][0]["active"], true);
    hmi.wait_tick(status(&hmi)["tick"].as_u64().unwrap_or(0) + 20);
    hmi.stop();
    let recs = records(&trace);
    // The request bit rose in the record of the tick the message names.
    let rose: Vec<u64> = recs
        .iter()
        .filter(|r| r["out"]["U21K0"] == 1)
        .map(|r| r["t"].as_u64().unwrap_or(0))
        .collect();
    assert_eq!(rose, vec![raised_at]);
    // The acknowledge bit I0N0 is 1 in exactly one scan: set in one record, cleared in the next.
    let ack: Vec<(u64, Value)> = recs
        .iter()
        .filter(|r| r["in"].get("I0N0").is_some())
        .map(|r| (r["t"].as_u64().unwrap_or(0), r["in"]["I0N0"].clone()))
        .collect();
    assert_eq!(ack.len(), 2, "{ack:?}");
    let at = ack[0].0;
    assert_eq!(ack, vec![(at, json!(1)), (at + 1, json!(0))]);
    // The tick the POST's answer names is the scan whose latch took the acknowledge.
    assert_eq!(Some(at), applied["tick"].as_u64(), "{applied}");
    assert!(at > raised_at);
    // The logic saw it in that scan: its lamp "not acknowledged yet" (U5A3, lit with the
    // message) went out in the same record.
    let lamp: Vec<(u64, Value)> = recs
        .iter()
        .filter(|r| r["out"].get("U5A3").is_some())
        .map(|r| (r["t"].as_u64().unwrap_or(0), r["out"]["U5A3"].clone()))
        .collect();
    assert_eq!(lamp, vec![(raised_at, json!(1)), (at, json!(0))]);
    let (ok, text) = replay(&lathe, &trace, &[]);
    assert!(ok, "{text}");
}

/// `ncplc check` reads the message file and locates every line it cannot use; `run` refuses the
/// machine with the same errors.
#[test]
fn check_locates_the_bad_lines_of_the_message_file_and_run_refuses_it() {
    let dir = tempfile::tempdir().expect("tempdir");
    copy_dir(&root().join("plc-programs/lathe"), dir.path());
    std::fs::write(
        dir.path().join("MP0/MESSAG"),
        "; texts\n1 one\n1 again\n65 high\nno number\n2\n",
    )
    .expect("write");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .current_dir(dir.path())
        .args(["check", ".", "--format", "json"])
        .output()
        .expect("ncplc runs");
    assert_eq!(out.status.code(), Some(1));
    let got: Vec<(u64, String, u64, u64)> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .chain(String::from_utf8_lossy(&out.stderr).lines())
        .filter_map(|l| serde_json::from_str::<Value>(l).ok())
        .map(|d| {
            (
                d["code"].as_u64().unwrap_or(0),
                d["file"].as_str().unwrap_or("").to_string(),
                d["line"].as_u64().unwrap_or(0),
                d["column"].as_u64().unwrap_or(0),
            )
        })
        .collect();
    let f = "MP0/MESSAG".to_string();
    assert_eq!(
        got,
        vec![
            (948, f.clone(), 3, 1),
            (947, f.clone(), 4, 1),
            (946, f.clone(), 5, 1),
            (946, f, 6, 1)
        ]
    );
    // Refused before anything runs, as for any characterization error (exit 2).
    let run = Ncplc::run(dir.path()).virtual_time().ticks(5).output();
    assert_eq!(run.status.code(), Some(2));
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(
        err.contains("error[E0947]: message number 65 is outside 1..64"),
        "{err}"
    );
}
