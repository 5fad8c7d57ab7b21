//! ncplc's OPC UA server (`ncplc run --opcua`, issue 25) against an independent peer, asyncua
//! (PyPI), driven by `tests/peers/opcua_peer.py`: the client browses the signals by browse path,
//! reads and subscribes at the logic tick, and every value it receives is checked against the
//! image the recorded trace (`--record`) has at the tick the value's source timestamp names;
//! a write inside the io.toml window reaches the trace, writes outside it or of the wrong type
//! are refused with the stack's status codes and write nothing. The channel's methods are in
//! `opcua_methods.rs`.
//!
//! Without asyncua for `python3` the tests are skipped with a loud message, except under
//! `CI=true`, where they fail (`.ci/run` installs it).

use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Stdio};

use packets::Signal;
use serde_json::Value;

use crate::e2e_common::{Killed, Ncplc, copy_dir, ncplc, root, serial, spawn_until};

const PYTHON: &str = "python3";

/// Whether asyncua is there; without it, skip loudly (fail under CI).
pub(crate) fn have_asyncua() -> bool {
    crate::e2e_common::python_peer(
        PYTHON,
        "import asyncua",
        "asyncua",
        "python3 -m pip install \"asyncua>=2.1,<2.2\"",
    )
}

/// A copy of the lathe without its traces.
fn lathe() -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("temp dir");
    copy_dir(&root().join("plc-programs/lathe"), dir.path());
    let _ = std::fs::remove_dir_all(dir.path().join("traces"));
    dir
}

/// Starts `ncplc run MACHINE --opcua 127.0.0.1:0 …`; the run and the endpoint URL it printed.
fn opcua_run(machine: &Path, extra: &[&str]) -> (Killed, String) {
    let mut c = Ncplc::run(machine)
        .args(["--overrun-limit", "0", "--opcua", "127.0.0.1:0"])
        .args(extra)
        .command();
    spawn_opcua(&mut c)
}

/// Spawns `c` (an `ncplc run … --opcua`); the run and the endpoint URL it printed.
pub(crate) fn spawn_opcua(c: &mut Command) -> (Killed, String) {
    c.stdout(Stdio::null());
    spawn_until(c, 60, "OPC UA endpoint", |line| {
        let url = line.strip_prefix("opcua: ")?;
        Some(url.split_whitespace().next().unwrap_or_default().into())
    })
}

pub(crate) fn peer(args: &[&str]) -> Value {
    let out = Command::new(PYTHON)
        .arg(root().join("tests/peers/opcua_peer.py"))
        .args(args)
        .output()
        .expect("python runs");
    assert!(
        out.status.success(),
        "the asyncua client failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("the client's JSON")
}

/// The packet image after every recorded tick: tick → bytes (the trace holds changes only).
pub(crate) fn images(trace: &str) -> BTreeMap<u64, Vec<u8>> {
    let mut now = vec![0u8; packets::PACKETS_LEN];
    let mut out = BTreeMap::new();
    for line in trace.lines().skip(1) {
        let rec: Value = serde_json::from_str(line).expect("a trace record");
        for part in ["in", "out", "forced"] {
            if let Some(m) = rec[part].as_object() {
                for (k, v) in m {
                    let s: Signal = k.parse().expect("a signal");
                    s.write(&mut now, u8::try_from(v.as_u64().unwrap_or(0)).unwrap_or(0));
                }
            }
        }
        out.insert(rec["t"].as_u64().expect("t"), now.clone());
    }
    out
}

/// The image at tick `t` (the last record at or before it).
pub(crate) fn image_at(images: &BTreeMap<u64, Vec<u8>>, t: u64) -> &[u8] {
    images
        .range(..=t)
        .next_back()
        .map(|(_, i)| i.as_slice())
        .expect("a record at or before the tick")
}

#[test]
fn an_asyncua_client_reads_subscribes_and_writes_the_signals_of_the_lathe() {
    if !have_asyncua() {
        return;
    }
    let _serial = serial();
    let machine = lathe();
    let trace = machine.path().join("session.jsonl");
    let (run, url) = opcua_run(
        machine.path(),
        &["--ticks", "900", "--record", &trace.display().to_string()],
    );
    let got = peer(&["signals", &url, "4"]);
    let mut run = run;
    let status = run.0.wait().expect("ncplc ends");
    assert!(status.success(), "{status}");
    let text = std::fs::read_to_string(&trace).expect("trace");
    let images = images(&text);

    // The address space: the packets' folders, names with the interface map's meaning, the
    // address as a property, a bit as a Boolean.
    assert_eq!(
        got["packets"],
        serde_json::json!(["A", "K", "N", "T", "Tick", "TickMs"])
    );
    assert_eq!(got["tick_ms"], 10);
    assert_eq!(got["mcode_description"], "M code in BCD (M91 -> 91H)");
    assert_eq!(got["mcode_address"], "W3K0");
    assert_eq!(got["start_description"], "PLC program alias of I0A3");
    assert_eq!(got["mfin_type"], "Boolean");

    // Every value the client read or was notified of is the recorded image at the tick its
    // source timestamp names: tick = (timestamp − origin) / 10 ms, origin from the Tick variable.
    let read = got["read"].as_array().expect("read");
    let t0 = read[0][0].as_i64().expect("tick");
    let origin = read[0][1].as_i64().expect("ts") - t0 * 10_000;
    let tick_of = |ts: &Value| -> u64 {
        let us = ts.as_i64().expect("timestamp") - origin;
        assert_eq!(us % 10_000, 0, "a timestamp off the tick grid: {ts}");
        u64::try_from(us / 10_000).expect("after the origin")
    };
    let mcode: Signal = "W3K0".parse().expect("signal");
    let mfin: Signal = "U11K0".parse().expect("signal");
    let start: Signal = "I0A3".parse().expect("signal");
    for (i, s) in [(1, mcode), (2, mfin), (3, start)] {
        let t = tick_of(&read[i][1]);
        assert_eq!(
            read[i][0].as_i64(),
            Some(i64::from(s.read(image_at(&images, t)))),
            "read of {s} at tick {t}"
        );
    }
    let notes = got["notifications"].as_array().expect("notifications");
    let mut seen: BTreeMap<&str, Vec<(u64, i64)>> = BTreeMap::new();
    for n in notes {
        let id = n[0].as_str().expect("node id");
        let t = tick_of(&n[2]);
        let v = n[1].as_i64().expect("value");
        seen.entry(id).or_default().push((t, v));
        let s = match id {
            "Signals/Tick" => {
                assert_eq!(v, i64::try_from(t).expect("tick"), "Tick's own timestamp");
                continue;
            }
            "Signals/K/3/MCODE" => mcode,
            "Signals/K/11/MFIN" => mfin,
            "Signals/A/0/START_PB" => start,
            other => panic!("a notification of {other}"),
        };
        assert_eq!(
            v,
            i64::from(s.read(image_at(&images, t))),
            "{id} notified {v} for tick {t}"
        );
    }
    // Subscribed at the logic tick: the notifications come in tick order, and the signals
    // changed while the client watched (the scripted lathe changes START_PB, MCODE or MFIN in
    // every 4 s of its first 900 ticks). A tick the publisher skipped under load (two ticks merged
    // into one frame) can hide a one-tick pulse, so not every recorded change is required.
    for (id, v) in &seen {
        assert!(v.windows(2).all(|w| w[0].0 <= w[1].0), "{id}: {v:?}");
    }
    let changes: usize = [
        "Signals/K/3/MCODE",
        "Signals/K/11/MFIN",
        "Signals/A/0/START_PB",
    ]
    .iter()
    .filter_map(|id| seen.get(id))
    .map(|v| v.windows(2).filter(|w| w[0].1 != w[1].1).count())
    .sum();
    assert!(changes >= 1, "{seen:?}");
    // Every tick reaches the client, none merged into the next (the scan's frames go through a
    // ring the publisher empties in order).
    let ticks: Vec<u64> = seen
        .get("Signals/Tick")
        .map(|v| v.iter().map(|x| x.0).collect())
        .unwrap_or_default();
    assert!(
        ticks.windows(2).all(|w| w[1] == w[0] + 1),
        "Tick notifications skip a tick: {ticks:?}"
    );
    let tick_notes = ticks.len();
    assert!(
        tick_notes >= 200,
        "{tick_notes} Tick notifications in 4 s at 10 ms"
    );

    // Writes: inside the window Good, outside refused, wrong type refused.
    assert_eq!(got["write_window"], "Good");
    // Outside the window the node itself is not writable (its AccessLevel), whatever the role.
    assert_eq!(got["write_outside"], "BadNotWritable");
    assert_eq!(got["write_wrong_type"], "BadTypeMismatch");
    assert_eq!(got["write_bit_as_byte"], "BadTypeMismatch");
    assert_eq!(got["w200k0_read_back"], 0x5A);
    assert_eq!(got["w200k1_read_back"], 0);
    // The write is in the trace as the window's input bits (0x5A: 1, 3, 4, 6) at one tick, and
    // nothing of the refused writes (W200K1 = contacts 8..15, MCODE stays the machine's).
    let written = text
        .lines()
        .filter_map(|l| serde_json::from_str::<Value>(l).ok())
        .find(|r| r["in"].get("I200K1").is_some())
        .expect("the window write is recorded");
    let mut set: Vec<&str> = written["in"]
        .as_object()
        .map(|m| {
            m.keys()
                .map(String::as_str)
                .filter(|k| k.starts_with("I200K"))
                .collect()
        })
        .unwrap_or_default();
    set.sort_unstable();
    assert_eq!(set, ["I200K1", "I200K3", "I200K4", "I200K6"]);
    assert!(!text.contains("\"I200K8\"") && !text.contains("\"W200K1\""));
    let replay = ncplc(&[
        "replay".as_ref(),
        machine.path().as_os_str(),
        trace.as_os_str(),
    ]);
    assert!(
        replay.status.success(),
        "{}",
        String::from_utf8_lossy(&replay.stderr)
    );
}

/// Off loopback: Basic256Sha256 Sign and SignAndEncrypt only, with the server certificate made on
/// first start in the machine directory; the client's certificate is refused until it is moved
/// from `rejected/` to `trusted/`; anonymous and wrong-password sessions are refused; a viewer
/// reads but may not write, an integrator writes.
#[test]
fn off_loopback_only_encrypted_sessions_of_known_users_get_in() {
    if !have_asyncua() {
        return;
    }
    let _serial = serial();
    let machine = lathe();
    let users = machine.path().join("opcua-users");
    std::fs::write(
        &users,
        "# test users\nviewer mes mes-secret-1\nintegrator int int-secret-1\n",
    )
    .expect("users file");
    let certs = tempfile::tempdir().expect("cert dir");
    let mut run = Ncplc::run(machine.path())
        .args([
            "--overrun-limit",
            "0",
            "--ticks",
            "6000",
            "--opcua",
            "0.0.0.0:0",
        ])
        .args([std::ffi::OsStr::new("--opcua-users"), users.as_os_str()])
        .command();
    let (run, url) = spawn_opcua(&mut run);
    let port = url
        .rsplit(':')
        .next()
        .unwrap_or_default()
        .trim_end_matches('/');
    let url = format!("opc.tcp://127.0.0.1:{port}/");
    let pki = machine.path().join("opcua-pki");
    assert!(
        pki.join("own/cert.der").is_file() && pki.join("private/private.pem").is_file(),
        "the server certificate is made on first start"
    );
    let certs_dir = certs.path().display().to_string();
    let first = peer(&["untrusted", &url, &certs_dir, "int", "int-secret-1"]);
    assert_eq!(first["first"], "BadCertificateUntrusted", "{first}");
    let rejected: Vec<_> = std::fs::read_dir(pki.join("rejected"))
        .expect("rejected/")
        .map(|e| e.expect("entry").path())
        .collect();
    assert_eq!(rejected.len(), 1, "{rejected:?}");
    let name = rejected[0].file_name().expect("file name");
    std::fs::rename(&rejected[0], pki.join("trusted").join(name)).expect("trust the client");
    let got = peer(&[
        "secure",
        &url,
        &certs_dir,
        "mes:mes-secret-1:viewer",
        "int:int-secret-1:integrator",
    ]);
    drop(run);
    assert_eq!(
        got["endpoints"],
        serde_json::json!(["Basic256Sha256 Sign", "Basic256Sha256 SignAndEncrypt"])
    );
    assert_eq!(got["anonymous"], "BadIdentityTokenInvalid", "{got}");
    assert_ne!(got["none_policy"], "Good", "{got}");
    assert_eq!(got["viewer_wrong_password"], "BadIdentityTokenRejected");
    assert_eq!(got["integrator_wrong_password"], "BadIdentityTokenRejected");
    assert_eq!(got["viewer"]["session"], "Good");
    assert_eq!(got["viewer"]["mcode_read"], "Good");
    assert_eq!(got["viewer"]["write"], "BadUserAccessDenied");
    assert_eq!(got["integrator"]["session"], "Good");
    assert_eq!(got["integrator"]["write"], "Good");
    assert_eq!(got["viewer_sign"], "Good");
    assert_eq!(got["integrator_sign"], "Good");
}

/// Without a users file a non-loopback bind is refused at start, a bad users file is a located
/// error, and so are a busy port and a bad `[identification]` table.
#[test]
fn bad_opcua_settings_are_refused_at_start_with_located_errors() {
    let machine = lathe();
    let busy = std::net::TcpListener::bind("127.0.0.1:0").expect("a port");
    let port = busy.local_addr().expect("addr").port();
    let out = Ncplc::run(machine.path())
        .args(["--ticks", "1", "--opcua", &format!("127.0.0.1:{port}")])
        .output();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(&format!("error: --opcua 127.0.0.1:{port}: cannot listen:")),
        "{err}"
    );
    drop(busy);
    let map_path = machine.path().join("io.toml");
    let map = std::fs::read_to_string(&map_path).expect("io.toml");
    std::fs::write(
        &map_path,
        format!("{map}\n[identification]\nmaker = \"x\"\n"),
    )
    .expect("io.toml");
    let out = Ncplc::run(machine.path())
        .args(["--ticks", "1", "--opcua", "127.0.0.1:0"])
        .output();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("error[E3400]") && err.contains("unknown field `maker`"),
        "{err}"
    );
    std::fs::write(&map_path, map).expect("io.toml");
    let out = Ncplc::run(machine.path())
        .args(["--ticks", "1", "--opcua", "0.0.0.0:0"])
        .output();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("off loopback the server refuses anonymous sessions; give --opcua-users FILE"),
        "{err}"
    );
    let users = machine.path().join("users");
    std::fs::write(&users, "viewer mes mes-secret-1\nadmin root root-secret\n").expect("users");
    let out = Ncplc::run(machine.path())
        .args(["--ticks", "1", "--opcua", "127.0.0.1:0", "--opcua-users"])
        .args([&users])
        .output();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(":2:1: unknown role `admin`: use viewer, operator or integrator"),
        "{err}"
    );
}

/// The Machine Tools instance of a part run of the lathe: its type and identification from the
/// vendored NodeSets and io.toml, and every channel, stack-light and program-state value the
/// client is notified of is what the recorded image at that tick says.
#[test]
fn an_asyncua_client_sees_the_lathe_as_an_opc_40501_machine_tool() {
    if !have_asyncua() {
        return;
    }
    let _serial = serial();
    let machine = lathe();
    let map_path = machine.path().join("io.toml");
    let map = std::fs::read_to_string(&map_path).expect("io.toml");
    std::fs::write(
        &map_path,
        format!(
            "{map}\n[identification]\nmanufacturer = \"Baltic Systems\"\nmodel = \"NC-110 lathe\"\nserial = \"L-0001\"\nyear = 2026\n\n[[stacklight]]\ncolor = \"red\"\nsignal = \"U5A1\"\n[[stacklight]]\ncolor = \"green\"\nsignal = \"U4A4\"\n"
        ),
    )
    .expect("io.toml");
    let name = machine
        .path()
        .file_name()
        .expect("name")
        .to_string_lossy()
        .into_owned();
    let trace = machine.path().join("session.jsonl");
    let (run, url) = opcua_run(
        machine.path(),
        &["--ticks", "900", "--record", &trace.display().to_string()],
    );
    let got = peer(&["model", &url, &name, "5"]);
    let mut run = run;
    assert!(run.0.wait().expect("ncplc ends").success());
    let text = std::fs::read_to_string(&trace).expect("trace");
    let images = images(&text);

    assert_eq!(got["type"], "MachineToolType", "{got}");
    assert_eq!(
        got["type_children"],
        serde_json::json!([
            "Components",
            "Equipment",
            "FileSystem",
            "Identification",
            "MachineryBuildingBlocks",
            "Monitoring",
            "Notification",
            "Production"
        ])
    );
    assert_eq!(got["identification_type"], "MachineToolIdentificationType");
    assert_eq!(got["Manufacturer"], "Baltic Systems");
    assert_eq!(got["Model"], "NC-110 lathe");
    assert_eq!(got["SerialNumber"], "L-0001");
    assert_eq!(got["YearOfConstruction"], 2026);
    assert_eq!(got["channel_state_type"], "ChannelState");
    assert_eq!(got["lamp0_color"], 1, "red");
    assert_eq!(got["program"], "");

    let t0 = got["tick"][0].as_i64().expect("tick");
    let origin = got["tick"][1].as_i64().expect("ts") - t0 * 10_000;
    let sig = |s: &str| -> Signal { s.parse().expect("signal") };
    let (cycle, hold, mode, fov, red) = (
        sig("I1K5"),
        sig("I1K6"),
        sig("W2K0"),
        sig("W14K0"),
        sig("U5A1"),
    );
    let mut kinds = std::collections::BTreeSet::new();
    for n in got["notifications"].as_array().expect("notifications") {
        let id = n[0].as_str().expect("id");
        let us = n[2].as_i64().expect("ts") - origin;
        assert_eq!(us % 10_000, 0, "{n}");
        let t = u64::try_from(us / 10_000).expect("after the origin");
        let img = image_at(&images, t);
        let (c, h) = (cycle.read(img) != 0, hold.read(img) != 0);
        let want = match id.rsplit('/').next().unwrap_or_default() {
            "ChannelState" => Value::from(if h {
                1
            } else if c {
                0
            } else {
                2
            }),
            "ChannelMode" => Value::from(match mode.read(img) {
                1 | 2 => 0,
                3 => 1,
                4 => 2,
                5 => 3,
                6 => 6,
                _ => 7,
            }),
            "FeedOverride" => Value::from(f64::from(fov.read(img))),
            "SignalOn" => Value::from(red.read(img)),
            "CurrentState" => {
                let s = if h {
                    "Interrupted"
                } else if c {
                    "Running"
                } else if images.range(..=t).any(|(_, i)| cycle.read(i) != 0) {
                    "Ended"
                } else {
                    "Initializing"
                };
                Value::from(s)
            }
            other => panic!("a notification of {other}"),
        };
        assert_eq!(n[1], want, "{id} at tick {t}");
        kinds.insert(id.rsplit('/').next().unwrap_or_default().to_string());
        if id.ends_with("ChannelState") {
            kinds.insert(format!("state {}", n[1]));
        }
    }
    // In 5 s of the scripted lathe the cycle starts (155), holds (305), resumes and ends (600).
    for k in [
        "ChannelState",
        "ChannelMode",
        "FeedOverride",
        "SignalOn",
        "CurrentState",
        "state 0",
        "state 1",
    ] {
        assert!(kinds.contains(k), "no {k} in {kinds:?}");
    }
}

/// The configured limits hold against an asyncua client that exceeds them, and the server goes on
/// serving it: the 9th session, 5001 monitored items in one call and the 5001st of a
/// subscription, a Read of 5001 nodes.
#[test]
fn the_server_holds_its_limits_against_an_asyncua_client() {
    if !have_asyncua() {
        return;
    }
    let _serial = serial();
    let machine = lathe();
    let (run, url) = opcua_run(machine.path(), &["--ticks", "100000"]);
    let got = peer(&["limits", &url]);
    drop(run);
    for i in 1..=8 {
        assert_eq!(got[format!("session{i}")], "Good", "{got}");
    }
    assert_eq!(got["session9"], "BadTooManySessions", "{got}");
    assert_eq!(
        got["items_5001_in_one_call"], "BadTooManyOperations",
        "{got}"
    );
    assert_eq!(got["items_good"], 5000, "{got}");
    assert_eq!(
        got["items_refused"],
        serde_json::json!(["BadTooManyMonitoredItems"])
    );
    assert_eq!(got["read_5001"], "BadTooManyOperations", "{got}");
    assert_eq!(got["read_after"], "Good");
}

/// The runtime's alarms are events of `Notification/Messages`: a lathe whose logic never answers
/// the M strobe (MFIN = 0) raises "not acknowledged" at the strobe timeout (6 s after the strobe
/// of tick 10, so that the client has subscribed by then): an event of severity 700 stamped with
/// its tick's time.
#[test]
fn alarms_reach_an_asyncua_client_as_events_of_the_messages_object() {
    if !have_asyncua() {
        return;
    }
    let _serial = serial();
    let machine = lathe();
    let prg = machine.path().join("MP0/PLCPRG");
    let text = std::fs::read_to_string(&prg).expect("PLCPRG");
    assert!(text.contains("MFIN = MSTB * M_DONE"));
    std::fs::write(&prg, text.replace("MFIN = MSTB * M_DONE", "MFIN = 0")).expect("PLCPRG");
    let sim = machine.path().join("sim.toml");
    let text = std::fs::read_to_string(&sim).expect("sim.toml");
    assert!(text.contains("strobe_timeout_ms = 5000"));
    std::fs::write(
        &sim,
        text.replace("strobe_timeout_ms = 5000", "strobe_timeout_ms = 6000"),
    )
    .expect("sim.toml");
    let (got, origin) = machine_events(machine.path());
    let events = got["events"].as_array().expect("events");
    let raised: Vec<&Value> = events
        .iter()
        .filter(|e| {
            e[0].as_str()
                .is_some_and(|m| m.contains("not acknowledged (FIN) within the strobe timeout"))
        })
        .collect();
    assert_eq!(raised.len(), 1, "{got}");
    for e in raised {
        assert_eq!(
            e[0],
            "cnc: M03 not acknowledged (FIN) within the strobe timeout"
        );
        assert_eq!(e[1], 700, "{e}");
        let us = e[2].as_i64().expect("time") - origin;
        assert_eq!(us % 10_000, 0, "an event off the tick grid: {e}");
    }
}

/// The PLC's messages are events of `Notification/Messages` too (docs/plc-messages.md): the
/// lathe's lubrication level goes low at tick 500 here (not 1000), so message 1 is raised at
/// tick 700 (the 2 s filter): its text from MP0/MESSAG, severity 500 (MSGPRIO 0), source
/// `process 1`, stamped with the time of tick 700.
#[test]
fn plc_messages_reach_an_asyncua_client_as_events_of_the_messages_object() {
    if !have_asyncua() {
        return;
    }
    let _serial = serial();
    let machine = lathe();
    let sim = machine.path().join("sim.toml");
    let text = std::fs::read_to_string(&sim).expect("sim.toml");
    let low = "tick = 1000\nset = { I0A7 = 0 }";
    assert!(text.contains(low));
    std::fs::write(&sim, text.replace(low, "tick = 500\nset = { I0A7 = 0 }")).expect("sim.toml");
    let (got, origin) = machine_events(machine.path());
    let events = got["events"].as_array().expect("events");
    let lube: Vec<&Value> = events
        .iter()
        .filter(|e| e[0].as_str().is_some_and(|m| m.contains("Lubrication")))
        .collect();
    assert_eq!(lube.len(), 1, "{got}");
    let e = lube[0];
    assert_eq!(
        (&e[0], &e[1], &e[3]),
        (
            &serde_json::json!("Lubrication level low: refill the tank, then RESET"),
            &serde_json::json!(500),
            &serde_json::json!("process 1")
        ),
        "{e}"
    );
    let us = e[2].as_i64().expect("time") - origin;
    assert_eq!(us, 700 * 10_000, "the event's time is tick 700's: {e}");
}

/// `ncplc check` reports the OPC UA tables' errors of io.toml with their codes and lines.
#[test]
fn check_reports_the_opcua_tables_of_io_toml() {
    let machine = lathe();
    let map_path = machine.path().join("io.toml");
    let map = std::fs::read_to_string(&map_path).expect("io.toml");
    std::fs::write(
        &map_path,
        format!("{map}\n[[stacklight]]\ncolor = \"pink\"\nsignal = \"U5A1\"\n"),
    )
    .expect("io.toml");
    let out = ncplc(&["check".as_ref(), machine.path().as_os_str()]);
    assert_eq!(out.status.code(), Some(1));
    let all = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        all.contains("E3402") && all.contains("unknown stack-light colour `pink`"),
        "{all}"
    );
}

/// Runs `machine` for 3,000 ticks with the server while the peer collects the events of
/// `Notification/Messages` for 9 s: the peer's answer and the server time (µs) of tick 0.
fn machine_events(machine: &Path) -> (Value, i64) {
    let name = machine
        .file_name()
        .expect("name")
        .to_string_lossy()
        .into_owned();
    let (run, url) = opcua_run(machine, &["--ticks", "3000"]);
    let got = peer(&["events", &url, &name, "9"]);
    drop(run);
    let t0 = got["tick"][0].as_i64().expect("tick");
    let origin = got["tick"][1].as_i64().expect("ts") - t0 * 10_000;
    (got, origin)
}
