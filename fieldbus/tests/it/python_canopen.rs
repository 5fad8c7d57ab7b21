//! ncplc's CiA 402 code against an independent CANopen stack, python-canopen (PyPI `canopen`, with
//! `python-can`), over cannelloni UDP on loopback (`tests/peers/canopen_peer.py` carries a small
//! python-can bus for the format):
//!
//! (a) python-canopen's `BaseNode402` is the master: it reads the PDO mapping of ncplc's simulated
//!     drive by SDO, walks its power state machine to *Operation enabled* and sends CSP targets;
//! (b) ncplc's master drives a drive built on python-canopen's `LocalNode` (its SDO server and PDO
//!     handling, the script's own state machine): start-up configuration, the walk, and the target
//!     of every SYNC, which the script reports.
//!
//! Without `python3` and those packages the tests are skipped with a loud message, except under
//! `CI=true`, where they fail (`.ci/run` installs them with pip).

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::Duration;

use fieldbus::canopen::cannelloni::UdpBus;
use fieldbus::canopen::drive::{AxisId, DriveCommand, Drives, State};
use fieldbus::canopen::drive_sim::Cia402Node;
use fieldbus::map::{CanDrive, DriveMode};

const SCRIPT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/peers/canopen_peer.py");

/// Whether python-canopen is there; without it, skip loudly (fail under CI).
fn have_peer() -> bool {
    let ok = Command::new("python3")
        .args(["-c", "import canopen, can"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        assert!(
            std::env::var("CI").as_deref() != Ok("true"),
            "python-canopen is missing under CI (python3 -m pip install canopen python-can)"
        );
        eprintln!(
            "SKIPPED: no python-canopen for python3; python3 -m pip install canopen python-can"
        );
    }
    ok
}

/// Two distinct free UDP ports on loopback.
fn two_ports() -> (u16, u16) {
    let free = || std::net::UdpSocket::bind("127.0.0.1:0").expect("port");
    let (a, b) = (free(), free());
    let ports = (
        a.local_addr().expect("a").port(),
        b.local_addr().expect("b").port(),
    );
    drop((a, b));
    ports
}

fn addr(port: u16) -> std::net::SocketAddr {
    std::net::SocketAddr::from(([127, 0, 0, 1], port))
}

fn json(line: &str) -> serde_json::Value {
    serde_json::from_str(line).unwrap_or_else(|e| panic!("peer output `{line}`: {e}"))
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn python_canopen_base_node_402_drives_the_simulated_drive() {
    if !have_peer() {
        return;
    }
    let (ours, theirs) = two_ports();
    let bus = UdpBus::bind(addr(ours), addr(theirs)).await.expect("bind");
    let node = Cia402Node::spawn(bus, 6);
    let out = tokio::task::spawn_blocking(move || {
        Command::new("python3")
            .args([
                SCRIPT,
                "master",
                &theirs.to_string(),
                &ours.to_string(),
                "6",
            ])
            .output()
            .expect("python3 runs")
    })
    .await
    .expect("join");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "peer failed: {stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v = json(stdout.lines().last().unwrap_or(""));
    assert_eq!(v["start"], "SWITCH ON DISABLED");
    assert_eq!(v["enabled"], "OPERATION ENABLED");
    assert_eq!(v["positions"], serde_json::json!([1000, 2500, -4000]));
    assert_eq!(v["disabled"], "SWITCHED ON");
    assert_eq!(v["mode"], 8);
    let st = node.state();
    assert_eq!(st.state, State::SwitchedOn);
    assert_eq!((st.mode, st.heartbeat_ms), (8, 50));
    // The targets the drive applied while enabled, each once in the order sent.
    let mut targets: Vec<i32> = st
        .applied
        .iter()
        .filter(|a| a.1 == 0x0F)
        .map(|a| a.2)
        .collect();
    targets.dedup();
    assert_eq!(targets, [0, 1000, 2500, -4000]);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn ncplc_drives_a_python_canopen_local_node() {
    if !have_peer() {
        return;
    }
    let (ours, theirs) = two_ports();
    let mut child = Command::new("python3")
        .args([
            SCRIPT,
            "node",
            &theirs.to_string(),
            &ours.to_string(),
            "7",
            "8",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("python3 runs");
    let mut lines = BufReader::new(child.stdout.take().expect("stdout")).lines();
    let ready = tokio::task::block_in_place(|| lines.next());
    assert_eq!(
        ready.and_then(Result::ok).as_deref(),
        Some("ready"),
        "the peer did not start"
    );
    let bus = UdpBus::bind(addr(ours), addr(theirs)).await.expect("bind");
    let x = AxisId::new('X');
    let drive = CanDrive {
        process: 1,
        axis: 'X',
        node_id: 7,
        counts_per_unit: 1000.0,
        mode: DriveMode::Csp,
        heartbeat: Duration::from_millis(100),
        sdo: Vec::new(),
        simulate: Default::default(),
        span: 0..0,
        homing: true,
    };
    let tick = Duration::from_millis(10);
    let mut d = Drives::start(bus, &[drive], tick, Duration::from_secs(2))
        .await
        .expect("the LocalNode drive starts");
    d.set_answer_timeout(Duration::from_secs(1));
    let mut seen = Vec::new();
    let mut probe_status = Vec::new();
    for n in 1..=8 {
        let cmd = DriveCommand {
            set_point: 0.25 * f64::from(n),
            enable: true,
            // The touch probe armed from the 6th SYNC on (as homing's stage 3 arms it).
            probe: n >= 6,
            ..DriveCommand::default()
        };
        assert!(d.command(x, cmd));
        d.sync().await.expect("sync");
        let f = d.feedback(x).expect("X");
        seen.push((f.state, f.position, f.healthy));
        probe_status.push(f.probe_status);
        d.idle(tick).await.expect("idle");
    }
    let report = tokio::task::block_in_place(|| lines.next());
    let status = tokio::task::block_in_place(|| child.wait()).expect("peer exits");
    let line = report.and_then(Result::ok).unwrap_or_default();
    assert!(status.success(), "peer failed: {line}");
    let v = json(&line);
    // The target of each SYNC is the set point of that tick: 250 counts per tick.
    let want: Vec<serde_json::Value> = (1..=8)
        .map(|n: i32| {
            let cw = match n {
                1 => 0x06,
                2 => 0x07,
                _ => 0x0F,
            };
            serde_json::json!([cw, 250 * n])
        })
        .collect();
    assert_eq!(
        v["seen"],
        serde_json::Value::Array(want),
        "per SYNC (controlword, target)"
    );
    assert_eq!(v["state"], "OE");
    assert_eq!(v["mode"], 8);
    assert_eq!(v["period"], serde_json::json!([100, -4]));
    assert_eq!(v["heartbeat"], 100);
    assert_eq!(v["rpdo"], serde_json::json!([2, 0x6040_0010, 0x607A_0020]));
    assert_eq!(v["tpdo"], serde_json::json!([2, 0x6041_0010, 0x6064_0020]));
    // The homing PDOs: RPDO2 (touch probe function), TPDO2 (probe status and latched position),
    // TPDO3 (digital inputs), every SYNC, enabled; the probe function of every SYNC.
    assert_eq!(
        v["pdo2"],
        serde_json::json!([[0x307, 1], [0x287, 1], [0x387, 1]])
    );
    assert_eq!(v["rpdo2"], serde_json::json!([1, 0x60B8_0010]));
    assert_eq!(v["tpdo2"], serde_json::json!([2, 0x60B9_0010, 0x60BA_0020]));
    assert_eq!(v["tpdo3"], serde_json::json!([1, 0x60FD_0020]));
    assert_eq!(
        v["probes"],
        serde_json::json!([0, 0, 0, 0, 0, 0x15, 0x15, 0x15])
    );
    assert_eq!(probe_status, [0, 0, 0, 0, 0, 1, 1, 1]);
    assert_eq!(seen[0], (State::ReadyToSwitchOn, 0.0, true));
    assert_eq!(seen[1], (State::SwitchedOn, 0.0, true));
    for (i, s) in seen.iter().enumerate().skip(2) {
        assert_eq!(*s, (State::OperationEnabled, 0.25 * (i as f64 + 1.0), true));
    }
}
