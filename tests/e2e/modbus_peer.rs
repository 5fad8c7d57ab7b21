//! ncplc's Modbus TCP code against an independent peer, pymodbus (Debian `python3-pymodbus`,
//! driven by `tests/peers/modbus_peer.py`):
//! - pymodbus serves a remote-I/O coupler and `ncplc run --io modbus` is its client: the lathe's
//!   logic energises coil 4 (DRIVES_ON) once discrete inputs 0 and 1 (the e-stop chain) are closed,
//!   and drops it when the peer opens input 0;
//! - pymodbus's `ModbusTcpClient` is a SCADA client of the HMI server in front of the simulated
//!   lathe (`--modbus-hmi`): what it reads is the image of a recorded tick, its write of the holding
//!   window reaches the image (and the trace, so the replay is exact), and the refusals are the
//!   documented exception codes.
//!
//! Without pymodbus for `/usr/bin/python3` the tests are skipped with a loud message, except under
//! `CI=true`, where they fail (`.ci/run` installs it).

use crate::e2e_common;

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Stdio};

use crate::e2e_common::serial;

use e2e_common::{Killed, Ncplc, copy_dir, ncplc, root, spawn_until};
use serde_json::Value;

const PYTHON: &str = "/usr/bin/python3";

/// Whether pymodbus is there; without it, skip loudly (fail under CI).
fn have_pymodbus() -> bool {
    e2e_common::python_peer(
        PYTHON,
        "import pymodbus.client, pymodbus.server",
        "pymodbus",
        "apt-get install python3-pymodbus python3-serial python3-serial-asyncio",
    )
}

fn peer(args: &[&str]) -> Command {
    let mut c = Command::new(PYTHON);
    c.arg(root().join("tests/peers/modbus_peer.py")).args(args);
    c
}

/// A copy of the lathe whose io.toml points at `device` and whose HMI server is on a free port.
fn lathe(device: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("temp dir");
    copy_dir(&root().join("plc-programs/lathe"), dir.path());
    let _ = std::fs::remove_dir_all(dir.path().join("traces"));
    let map = std::fs::read_to_string(dir.path().join("io.toml")).expect("io.toml");
    let map = map
        .replace("127.0.0.1:5020", device)
        .replace("127.0.0.1:1502", "127.0.0.1:0");
    std::fs::write(dir.path().join("io.toml"), map).expect("io.toml");
    dir
}

fn run_args(machine: &Path, extra: &[&str]) -> Command {
    let mut c = Ncplc::run(machine)
        .args(["--overrun-limit", "0"])
        .args(extra)
        .command();
    c.stdout(Stdio::null()).stderr(Stdio::piped());
    c
}

#[test]
fn ncplc_drives_a_pymodbus_remote_io_coupler() {
    if !have_pymodbus() {
        return;
    }
    let _serial = serial();
    let mut device = peer(&["device"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("python runs");
    let mut lines = BufReader::new(device.stdout.take().expect("stdout")).lines();
    let first = lines.next().and_then(Result::ok).unwrap_or_default();
    let port = first
        .strip_prefix("listening ")
        .unwrap_or_else(|| panic!("the peer did not listen: {first:?}"))
        .to_string();
    let device = Killed(device);
    let machine = lathe(&format!("127.0.0.1:{port}"));
    let run = Killed(
        run_args(machine.path(), &["--io", "modbus", "--ticks", "3000"])
            .spawn()
            .expect("ncplc runs"),
    );
    // The peer prints its verdict once coil 4 has risen and dropped again, or after 20 s.
    let verdict: Value = lines
        .next()
        .and_then(Result::ok)
        .and_then(|l| serde_json::from_str(&l).ok())
        .expect("the peer's verdict");
    drop(run);
    drop(device);
    assert_eq!(verdict["energised"], true, "{verdict}");
    assert_eq!(verdict["dropped"], true, "{verdict}");
    // Coils = OU4 contacts 0..31: DRIVES_ON (4) with the chain closed, never with input 0 open.
    let on = &verdict["coils_when_energised"];
    assert!(
        on.as_array().is_some_and(|c| c.contains(&Value::from(4))),
        "{verdict}"
    );
    let off = &verdict["coils_when_dropped"];
    assert!(
        off.as_array().is_some_and(|c| !c.contains(&Value::from(4))),
        "{verdict}"
    );
}

/// The image of every tick of a trace, as signal → value maps of inputs and outputs.
fn images(trace: &str) -> Vec<(u64, std::collections::BTreeMap<String, i64>)> {
    let mut now = std::collections::BTreeMap::new();
    let mut out = Vec::new();
    for line in trace.lines().skip(1) {
        let Ok(rec) = serde_json::from_str::<Value>(line) else {
            continue;
        };
        for part in ["in", "out"] {
            if let Some(m) = rec[part].as_object() {
                for (k, v) in m {
                    now.insert(k.clone(), v.as_i64().unwrap_or(0));
                }
            }
        }
        out.push((rec["t"].as_u64().unwrap_or(0), now.clone()));
    }
    out
}

#[test]
fn a_pymodbus_scada_client_reads_and_writes_the_simulated_lathe() {
    if !have_pymodbus() {
        return;
    }
    let _serial = serial();
    let machine = lathe("127.0.0.1:5020");
    let trace = machine.path().join("session.jsonl");
    let (run, addr) = spawn_until(
        run_args(
            machine.path(),
            &["--modbus-hmi", "127.0.0.1:0", "--ticks", "400", "--record"],
        )
        .arg(&trace),
        30,
        "HMI server address",
        listening_on,
    );
    let (host, port) = addr.rsplit_once(':').expect("ADDR:PORT");
    let out = peer(&["client", host, port]).output().expect("python runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let got: Value = serde_json::from_slice(&out.stdout).expect("the client's JSON");
    let mut run = run;
    let status = run.0.wait().expect("ncplc ends");
    assert!(status.success());
    // Exceptions, as fieldbus/src/modbus/server.rs documents them: a bit of an output connector
    // read as a discrete input and a register past the table 02, a write outside the window 02,
    // a coil write 01 (the logic owns the outputs).
    assert_eq!(got["inputs_of_an_output_connector"]["exception"], 2);
    assert_eq!(got["registers_past_the_table"]["exception"], 2);
    assert_eq!(got["write_outside_window"]["exception"], 2);
    assert_eq!(got["write_coil"]["exception"], 1);
    // 0x1234 into register 400 = K bytes 800 (low, 0x34) and 801 (high, 0x12) = W200K0.
    assert_eq!(got["write_window"]["ok"], true);
    assert_eq!(
        got["holding_read_back"]["registers"],
        serde_json::json!([0x1234])
    );
    assert_eq!(
        got["window_read_back"]["registers"],
        serde_json::json!([0x1234, 0])
    );
    // What the client read is the image of some recorded tick: discrete inputs 0..15 are
    // I0A0..I0A15, coils 128..135 are U4A0..U4A7.
    let text = std::fs::read_to_string(&trace).expect("trace");
    let ticks = images(&text);
    let bits = |prefix: &str, v: &Value| -> Vec<(String, i64)> {
        v.as_array()
            .map(|b| {
                b.iter()
                    .enumerate()
                    .map(|(i, x)| (format!("{prefix}{i}"), x.as_i64().unwrap_or(-1)))
                    .collect()
            })
            .unwrap_or_default()
    };
    for (what, prefix, read) in [
        (
            "discrete inputs",
            "I0A",
            bits("I0A", &got["inputs_0_16"]["bits"]),
        ),
        ("coils", "U4A", bits("U4A", &got["coils_128_136"]["bits"])),
    ] {
        assert!(!read.is_empty(), "{what}: {got}");
        assert!(
            ticks.iter().any(|(_, img)| read
                .iter()
                .all(|(k, v)| img.get(k).copied().unwrap_or(0) == *v)),
            "{what} {read:?} ({prefix}…) match no recorded tick"
        );
    }
    // The write is in the trace as the window's input bits (0x34: 2, 4, 5; 0x12: 9, 12) at one
    // tick, so the replay of the session is exact.
    let written = text
        .lines()
        .filter_map(|l| serde_json::from_str::<Value>(l).ok())
        .find(|r| r["in"].get("I200K2").is_some())
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
    assert_eq!(set, ["I200K12", "I200K2", "I200K4", "I200K5", "I200K9"]);
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

/// Starts `ncplc run --modbus-hmi 127.0.0.1:0` on `machine`; the run and the server's address.
fn modbus_hmi(machine: &Path, extra: &[&str]) -> (Killed, String) {
    spawn_until(
        run_args(machine, &["--modbus-hmi", "127.0.0.1:0"]).args(extra),
        30,
        "HMI server address",
        listening_on,
    )
}

/// The address in the Modbus HMI server's `… listening on ADDR` line.
fn listening_on(line: &str) -> Option<String> {
    let a = line.split("listening on ").nth(1)?;
    Some(a.split_whitespace().next().unwrap_or_default().to_string())
}

/// pymodbus as a hostile client of the HMI server (issue 23): the per-connection rate, the unit
/// id, the connection cap, the idle timeout and malformed MBAP headers, with the limits of
/// `[hmi]` in io.toml; the server keeps serving a well-behaved client throughout.
#[test]
fn the_hmi_server_holds_its_limits_against_a_hostile_pymodbus_client() {
    if !have_pymodbus() {
        return;
    }
    let _serial = serial();
    let machine = lathe("127.0.0.1:5020");
    let map_path = machine.path().join("io.toml");
    let map = std::fs::read_to_string(&map_path).expect("io.toml");
    let window = "holding = [{ byte = \"W200K0\", len = 16 }]";
    assert!(map.contains(window), "the lathe's io.toml has its window");
    let map = map.replace(
        window,
        &format!("{window}\nmax_connections = 3\nmax_requests_per_s = 20\nidle_timeout_ms = 500"),
    );
    std::fs::write(&map_path, map).expect("io.toml");
    let (run, addr) = modbus_hmi(machine.path(), &["--ticks", "100000"]);
    let (host, port) = addr.rsplit_once(':').expect("ADDR:PORT");
    let out = peer(&["hostile", host, port, "20", "3"])
        .output()
        .expect("python runs");
    drop(run);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let got: Value = serde_json::from_slice(&out.stdout).expect("the client's JSON");
    // Unit 7 is not this server (unit 1 by default): 0B, gateway target failed to respond.
    assert_eq!(got["wrong_unit"]["exception"], 11, "{got}");
    assert_eq!(got["write_outside_window"]["exception"], 2, "{got}");
    // 50 pipelined requests within a second: 20 served, 30 answered 06 (server device busy).
    assert_eq!(
        (
            &got["flood_answers"],
            &got["flood_served"],
            &got["flood_busy"]
        ),
        (&Value::from(50), &Value::from(20), &Value::from(30)),
        "{got}"
    );
    // Three connections served, a fourth closed at once, room again when one leaves.
    assert_eq!(got["held_answered"], 3, "{got}");
    assert_eq!(got["over_cap_closed"], true, "{got}");
    assert_eq!(got["after_one_left"], serde_json::json!([null]), "{got}");
    // Three bytes of a header and silence: closed by the 500 ms idle timeout.
    let half = got["half_open_closed_after_s"].as_f64().unwrap_or(-1.0);
    assert!((0.4..3.0).contains(&half), "{got}");
    assert_eq!(got["bad_protocol_closed"], true, "{got}");
    assert_eq!(got["zero_length_closed"], true, "{got}");
    assert!(got["still_serving"]["registers"].is_array(), "{got}");
}
