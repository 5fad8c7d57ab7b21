//! The channel's methods of ncplc's OPC UA server (issue 25): an asyncua client
//! (`tests/peers/opcua_peer.py methods`) starts, holds, resumes and resets a part run of the
//! operator lathe (nothing in its script presses CYCLE START) through `Channel1`'s `Start`, `Hold`
//! and `Reset`. Each accepted call is applied at a tick boundary on the scan thread, recorded in
//! the trace with the caller's role at the tick the call answered, and the recorded session
//! replays exactly; a viewer is refused with `BadUserAccessDenied`, a command the kernel refuses
//! answers `BadInvalidState`. The part run's spindle and blocks executed reach the client too.

use serde_json::{Value, json};

use crate::e2e_common::{Ncplc, serial};
use crate::hmi_common::operator_lathe;
use crate::opcua::{have_asyncua, image_at, images, peer, spawn_opcua};

/// A short part: the spindle to 600 rpm, 2 s of feed along X, back, spindle off, end.
const SHORT: &str = "%1 \"Short part for the OPC UA method test\n\
N10 G53 S600 M03\n\
N20 G01 X-20 F600\n\
N30 G00 X0\n\
N40 M05\n\
N50 M30\n";

/// The operator commands of a trace's text: (tick, commands).
fn recorded_commands(text: &str) -> Vec<(u64, Value)> {
    text.lines()
        .filter_map(|l| serde_json::from_str::<Value>(l).ok())
        .filter(|r| r.get("cmd").is_some())
        .map(|r| (r["t"].as_u64().unwrap_or(0), r["cmd"].clone()))
        .collect()
}

#[test]
fn an_operator_starts_holds_and_resets_a_part_run_through_the_channel_s_methods() {
    if !have_asyncua() {
        return;
    }
    let _serial = serial();
    let machine = operator_lathe();
    std::fs::write(machine.path().join("nc/SHORT"), SHORT).expect("nc/SHORT");
    let users = machine.path().join("opcua-users");
    std::fs::write(&users, "viewer mes mes-secret-1\noperator op op-secret-1\n").expect("users");
    let trace = machine.path().join("session.jsonl");
    let mut c = Ncplc::run(machine.path())
        .args(["--overrun-limit", "0", "--opcua", "127.0.0.1:0"])
        .args(["--program", "SHORT", "--ticks", "2500", "--record"])
        .args([trace.as_os_str()])
        .args([std::ffi::OsStr::new("--opcua-users"), users.as_os_str()])
        .command();
    let (mut run, url) = spawn_opcua(&mut c);
    let name = machine
        .path()
        .file_name()
        .expect("name")
        .to_string_lossy()
        .into_owned();
    let got = peer(&["methods", &url, &name, "op", "op-secret-1"]);
    assert!(run.0.wait().expect("ncplc ends").success());

    // An anonymous session is a viewer when there is a users file: no methods, no writes.
    assert_eq!(got["viewer_start"], "BadUserAccessDenied", "{got}");
    assert_eq!(got["viewer_write_window"], "BadUserAccessDenied");
    assert_eq!(got["viewer_write_outside"], "BadNotWritable");
    assert_eq!(got["methods"], json!(["Hold", "Reset", "Start"]));
    // Nothing runs yet: the kernel refuses HOLD.
    assert_eq!(got["hold_idle"], "BadInvalidState", "{got}");
    let tick = |k: &str| -> u64 {
        assert_eq!(got[k][0], "Good", "{k}: {got}");
        got[k][1]
            .as_u64()
            .expect("the tick the command was applied at")
    };
    let (started, held, resumed, reset) =
        (tick("start"), tick("hold"), tick("resume"), tick("reset"));
    assert!(started < held && held < resumed && resumed < reset, "{got}");
    for k in ["running", "interrupted", "ended"] {
        assert_eq!(got[k], true, "{k}: {got}");
    }

    // Each command is in the record of the tick the call named, with the operator's role.
    let text = std::fs::read_to_string(&trace).expect("trace");
    let cmd = |c: &str| json!([{"process": 1, "command": c, "role": "operator"}]);
    assert_eq!(
        recorded_commands(&text),
        vec![
            (started, cmd("start")),
            (held, cmd("hold")),
            (resumed, cmd("start")),
            (reset, cmd("reset"))
        ]
    );
    // CYCLE (I1K5) rises in the tick START went in.
    let images = images(&text);
    let cycle: packets::Signal = "I1K5".parse().expect("signal");
    let hold: packets::Signal = "I1K6".parse().expect("signal");
    assert_eq!(cycle.read(image_at(&images, started - 1)), 0);
    assert_eq!(cycle.read(image_at(&images, started)), 1);

    // Every program and channel state the client was notified of is the recorded image's at the
    // tick its timestamp names.
    let t0 = got["tick"][0].as_i64().expect("tick");
    let origin = got["tick"][1].as_i64().expect("ts") - t0 * 10_000;
    let (scode, sov): (packets::Signal, packets::Signal) = (
        "W4K0".parse().expect("signal"),
        "W14K1".parse().expect("signal"),
    );
    let mut states = Vec::new();
    let mut blocks = Vec::new();
    let mut speeds: Vec<(u64, f64)> = Vec::new();
    let mut rotating = std::collections::BTreeMap::new();
    for n in got["notifications"].as_array().expect("notifications") {
        let us = n[2].as_i64().expect("ts") - origin;
        assert_eq!(us % 10_000, 0, "{n}");
        let t = u64::try_from(us / 10_000).expect("after the origin");
        let img = image_at(&images, t);
        let (c, h) = (cycle.read(img) != 0, hold.read(img) != 0);
        let id = n[0].as_str().expect("id");
        let want = match id.rsplit('/').next().unwrap_or_default() {
            "ChannelState" => json!(if h {
                1
            } else if c {
                0
            } else {
                2
            }),
            "CurrentState" => {
                let ran = images.range(..=t).any(|(_, i)| cycle.read(i) != 0);
                states.push(n[1].clone());
                json!(match (h, c, ran) {
                    (true, _, _) => "Interrupted",
                    (false, true, _) => "Running",
                    (false, false, true) => "Ended",
                    (false, false, false) => "Initializing",
                })
            }
            // The programmed speed is SCODE, a binary dword (W4K0..W4K3, little-endian).
            "CommandedSpeed" => {
                let at = scode.image_byte();
                let b = &img[at..at + 4];
                json!(f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])))
            }
            "Override" => json!(f64::from(sov.read(img))),
            // The kernel's values: checked below as a whole.
            "BlocksExecuted" => {
                blocks.push(n[1].as_u64().expect("blocks"));
                continue;
            }
            "ActualSpeed" => {
                speeds.push((t, n[1].as_f64().expect("rpm")));
                continue;
            }
            "IsRotating" => {
                rotating.insert(t, n[1].as_i64().expect("bool") != 0);
                continue;
            }
            other => panic!("a notification of {other}"),
        };
        assert_eq!(n[1], want, "{id} at tick {t}");
    }
    assert_eq!(
        states,
        json!(["Initializing", "Running", "Interrupted", "Running", "Ended"])
            .as_array()
            .cloned()
            .unwrap_or_default()
    );
    // SHORT's five blocks, counted one by one by the kernel.
    assert_eq!(blocks, [0, 1, 2, 3, 4, 5]);
    // The spindle (AXCFIL GM1 3000 rev/min, TSM 4 s: 2 × 3000 / 4 = 1500 rev/min per s) changes
    // by 15 rev/min every 10 ms tick, up to S600 and back to 0 after M05; every tick reaches the
    // client, and IsRotating says whether the speed is not 0 at each change.
    assert_eq!(speeds.first().map(|s| s.1), Some(0.0));
    assert_eq!(speeds.last().map(|s| s.1), Some(0.0));
    let top = speeds.iter().map(|s| s.1).fold(0.0, f64::max);
    assert_eq!(top, 600.0);
    for w in speeds.windows(2).skip(1) {
        let plateau = w[0].1 == 0.0 || w[0].1 == top;
        assert!(
            plateau || w[1].0 == w[0].0 + 1,
            "a tick of the ramp is missing: {w:?}"
        );
        assert_eq!((w[1].1 - w[0].1).abs(), 15.0, "{w:?}");
    }
    let mut turning = false;
    for (t, rpm) in &speeds {
        if let Some(r) = rotating.get(t) {
            turning = *r;
        }
        assert_eq!(
            turning,
            *rpm != 0.0,
            "IsRotating at tick {t} ({rpm} rev/min)"
        );
    }

    // The session replays exactly: the commands go to the replay's kernel at their ticks.
    let replay = crate::e2e_common::ncplc(&[
        "replay".as_ref(),
        machine.path().as_os_str(),
        trace.as_os_str(),
    ]);
    let err = String::from_utf8_lossy(&replay.stderr);
    assert!(replay.status.success(), "{err}");
    assert!(
        err.contains("kernel signals and axis positions identical"),
        "{err}"
    );
}

/// The brief's run: `ncplc run <operator lathe> --program PART1 --virtual-time --opcua`; nothing
/// presses CYCLE START until the client calls `Start` (an anonymous integrator on loopback), then
/// PART1 runs to its end at the speed of the machine and the client sees Running, then Ended.
#[test]
fn start_through_opc_ua_runs_part1_in_virtual_time_to_its_end() {
    if !have_asyncua() {
        return;
    }
    let _serial = serial();
    let machine = operator_lathe();
    let trace = machine.path().join("session.jsonl");
    // Virtual time runs as fast as the machine allows: enough ticks for the client to connect
    // (idle ticks) and for PART1's 4,240 ticks; the run then ends by itself.
    let mut c = Ncplc::run(machine.path())
        .args([
            "--overrun-limit",
            "0",
            "--opcua",
            "127.0.0.1:0",
            "--virtual-time",
        ])
        .args(["--program", "PART1", "--ticks", "150000", "--record"])
        .args([trace.as_os_str()])
        .command();
    let (mut run, url) = spawn_opcua(&mut c);
    let name = machine
        .path()
        .file_name()
        .expect("name")
        .to_string_lossy()
        .into_owned();
    let got = peer(&["start_part", &url, &name]);
    assert!(run.0.wait().expect("ncplc ends").success());
    assert_eq!(got["program"], "PART1");
    assert_eq!(got["start"][0], "Good", "{got}");
    assert_eq!(got["ended"], true, "{got}");
    let states: Vec<&str> = got["states"]
        .as_array()
        .expect("states")
        .iter()
        .filter_map(Value::as_str)
        .collect();
    assert_eq!(states.first(), Some(&"Initializing"), "{got}");
    assert_eq!(states.last(), Some(&"Ended"), "{got}");
    assert!(states.contains(&"Running"), "{got}");
    let started = got["start"][1].as_u64().expect("tick");
    let text = std::fs::read_to_string(&trace).expect("trace");
    let cmd = json!([{"process": 1, "command": "start", "role": "integrator"}]);
    assert_eq!(recorded_commands(&text), vec![(started, cmd)]);
}
