//! The PLC program's internal variables on ncplc's OPC UA server (issue 25): every `DEF name :
//! TYPE` of the lathe's program is a read-only node of `Objects/Variables`, and every value an
//! asyncua client is notified of is what the program computes from the recorded inputs at the
//! tick its timestamp names.

use serde_json::{Value, json};

use crate::e2e_common::{Ncplc, serial};
use crate::opcua::{have_asyncua, image_at, images, peer, spawn_opcua};

#[test]
fn the_plc_program_s_variables_are_read_only_nodes_with_the_values_of_each_tick() {
    if !have_asyncua() {
        return;
    }
    let _serial = serial();
    let machine = tempfile::tempdir().expect("temp dir");
    crate::e2e_common::copy_dir(
        &crate::e2e_common::root().join("plc-programs/lathe"),
        machine.path(),
    );
    let _ = std::fs::remove_dir_all(machine.path().join("traces"));
    // The scripted feed hold (sim.toml: HOLD_PB at ticks 300..305, START at 400..405) moves to
    // ticks 750..855, so that a client slow to subscribe under load (seen: after 3 s) still
    // watches HOLD_REQ rise and fall; the run lasts 15 s.
    let sim = machine.path().join("sim.toml");
    let mut script = std::fs::read_to_string(&sim).expect("sim.toml");
    for (from, to) in [
        (
            "tick = 300\nset = { I0A4 = 1 }",
            "tick = 750\nset = { I0A4 = 1 }",
        ),
        (
            "tick = 305\nset = { I0A4 = 0,",
            "tick = 755\nset = { I0A4 = 0,",
        ),
        (
            "tick = 400\nset = { I0A3 = 1,",
            "tick = 850\nset = { I0A3 = 1,",
        ),
        (
            "tick = 405\nset = { I0A3 = 0 }",
            "tick = 855\nset = { I0A3 = 0 }",
        ),
    ] {
        assert_eq!(script.matches(from).count(), 1, "sim.toml: {from}");
        script = script.replace(from, to);
    }
    std::fs::write(&sim, script).expect("sim.toml");
    let trace = machine.path().join("session.jsonl");
    let mut c = Ncplc::run(machine.path())
        .args(["--overrun-limit", "0", "--opcua", "127.0.0.1:0"])
        .args(["--ticks", "1500", "--record"])
        .args([trace.as_os_str()])
        .command();
    let (mut run, url) = spawn_opcua(&mut c);
    let got = peer(&["variables", &url, "12"]);
    assert!(run.0.wait().expect("ncplc ends").success());

    // The lathe's DEF … : BOOL variables, its timers' Q and ET, its counter's CV and its pulses
    // (PLCPRG), by name.
    assert_eq!(
        got["names"],
        json!([
            "BLINK_OFF.ET",
            "BLINK_OFF.Q",
            "BLINK_ON.ET",
            "BLINK_ON.Q",
            "CHAIN_OK",
            "COOL_REQ",
            "HOLD_REQ",
            "LUBE_ACKED",
            "LUBE_ALARM",
            "LUBE_CLOCK.ET",
            "LUBE_CLOCK.Q",
            "LUBE_LOW.ET",
            "LUBE_LOW.Q",
            "LUBE_MINUTES.CV",
            "LUBE_RUN.ET",
            "LUBE_RUN.Q",
            "M_DONE",
            "P1",
            "P2",
            "SP_CCW_REQ",
            "SP_CW_REQ",
            "SP_READY.ET",
            "SP_READY.Q"
        ]),
        "{got}"
    );
    assert_eq!(
        got["blink_description"],
        "PLC variable BLINK_ON.ET : timer elapsed time ET, ms"
    );
    assert_eq!(got["chain_type"], "Boolean");
    assert_eq!(got["chain_description"], "PLC variable CHAIN_OK : BOOL");
    assert_eq!(got["write"], "BadNotWritable");

    let text = std::fs::read_to_string(&trace).expect("trace");
    let images = images(&text);
    let sig = |s: &str| -> packets::Signal { s.parse().expect("signal") };
    let (estop_ok, overtravel_ok, start_pb, hold_pb, reset) = (
        sig("I0A0"),
        sig("I0A1"),
        sig("I0A3"),
        sig("I0A4"),
        sig("I0K1"),
    );
    // CHAIN_OK = ESTOP_PB_OK * OVERTRAVEL_OK; HOLD_REQ is set by HOLD_PB and reset by START_PB
    // or RESET (the RES line after the SET line), from tick 0 on.
    let last = images.keys().next_back().copied().unwrap_or(0);
    let mut hold_req = vec![false; usize::try_from(last + 1).expect("ticks")];
    let mut h = false;
    for t in 0..=last {
        let img = image_at(&images, t);
        h = (h || hold_pb.read(img) != 0) && !(start_pb.read(img) != 0 || reset.read(img) != 0);
        hold_req[usize::try_from(t).expect("tick")] = h;
    }
    let t0 = got["tick"][0].as_i64().expect("tick");
    let origin = got["tick"][1].as_i64().expect("ts") - t0 * 10_000;
    let mut seen: Vec<(String, u64, i64)> = Vec::new();
    for n in got["notifications"].as_array().expect("notifications") {
        let us = n[2].as_i64().expect("ts") - origin;
        assert_eq!(us % 10_000, 0, "{n}");
        let t = u64::try_from(us / 10_000).expect("after the origin");
        let img = image_at(&images, t);
        let id = n[0].as_str().expect("id");
        let want = match id {
            "Variables/CHAIN_OK" => estop_ok.read(img) & overtravel_ok.read(img),
            "Variables/HOLD_REQ" => u8::from(hold_req[usize::try_from(t).expect("tick")]),
            // The blinker's timer: checked below against its own ET.
            "Variables/BLINK_ON.Q" | "Variables/BLINK_ON.ET" => {
                seen.push((id.to_string(), t, n[1].as_i64().unwrap_or(-1)));
                continue;
            }
            other => panic!("a notification of {other}"),
        };
        assert_eq!(n[1], Value::from(want), "{id} at tick {t}");
        seen.push((id.to_string(), t, n[1].as_i64().unwrap_or(-1)));
    }
    // The scripted lathe holds the feed at tick 750 and resumes at 850 (moved above): HOLD_REQ
    // went up and down while the client watched.
    let hold: Vec<i64> = seen
        .iter()
        .filter(|s| s.0 == "Variables/HOLD_REQ")
        .map(|s| s.2)
        .collect();
    assert!(hold.windows(2).any(|w| w == [0, 1]), "{seen:?}");
    assert!(hold.windows(2).any(|w| w == [1, 0]), "{seen:?}");
    // BLINK_ON (TON 500 ms): Q rises in the tick ET reaches 500 and falls in the tick ET goes
    // back to 0; the 1 Hz blinker rises at the same spacing every time.
    let of = |name: &str| -> Vec<(u64, i64)> {
        seen.iter()
            .filter(|s| s.0 == name)
            .map(|s| (s.1, s.2))
            .collect()
    };
    let (q, et) = (of("Variables/BLINK_ON.Q"), of("Variables/BLINK_ON.ET"));
    let et_at = |t: u64| et.iter().find(|e| e.0 == t).map(|e| e.1);
    let mut rises = Vec::new();
    for w in q.windows(2) {
        let (t, v) = w[1];
        assert_eq!(
            et_at(t),
            Some(if v == 1 { 500 } else { 0 }),
            "Q = {v} at tick {t}"
        );
        if v == 1 {
            rises.push(t);
        }
    }
    assert!(rises.len() >= 3, "{q:?}");
    let period: Vec<u64> = rises.windows(2).map(|w| w[1] - w[0]).collect();
    assert!(period.windows(2).all(|w| w[0] == w[1]), "{period:?}");
}
