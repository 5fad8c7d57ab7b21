//! End-to-end tests of `ncplc run --io modbus|canopen`: the binary, the example lathe's logic and a
//! remote-I/O device on loopback.
//!
//! The lathe's logic drives `DRIVES_ON` (U4A4, coil 4 of the coupler) from the emergency-stop chain
//! `ESTOP_PB_OK * OVERTRAVEL_OK` (I0A0, I0A1: discrete inputs 0 and 1). So closing both contacts at
//! the device must energise coil 4 within a few ticks, and opening one must drop it again.

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use crate::e2e_common::{copy_dir, serial};

use fieldbus::modbus::sim::RemoteIoSim;

/// A copy of the example lathe whose I/O map points at `device` and whose HMI server takes a free port.
fn lathe_with_device(device: &str) -> tempfile::TempDir {
    let lathe = Path::new(env!("CARGO_MANIFEST_DIR")).join("../plc-programs/lathe");
    let dir = tempfile::tempdir().expect("temp dir");
    copy_dir(&lathe, dir.path());
    let map = std::fs::read_to_string(lathe.join("io.toml")).expect("io.toml");
    let map = map
        .replace("127.0.0.1:5020", device)
        .replace("127.0.0.1:1502", "127.0.0.1:0");
    assert!(
        map.contains(device),
        "the example map names the coupler's address"
    );
    std::fs::write(dir.path().join("io.toml"), map).expect("write io.toml");
    dir
}

fn spawn_run(machine: &Path, io: &str, ticks: u32) -> Child {
    spawn_run_with(machine, io, ticks, &[])
}

fn spawn_run_with(machine: &Path, io: &str, ticks: u32, extra: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .args(["run"])
        .args(extra)
        .arg(machine)
        .args([
            "--io",
            io,
            "--ticks",
            &ticks.to_string(),
            "--no-watch",
            // Real time on a machine that runs other tests too: a tick may overrun, and the
            // overrun trip (tested by the scheduler's own tests) must not halt the logic under test.
            "--overrun-limit",
            "0",
            "--retain-file",
        ])
        .arg(machine.join("retain.bin"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("ncplc runs")
}

/// Polls `cond` every 10 ms for at most `limit`.
async fn wait_for(limit: Duration, mut cond: impl FnMut() -> bool) -> bool {
    let start = Instant::now();
    while start.elapsed() < limit {
        if cond() {
            return true;
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    cond()
}

#[test]
fn modbus_inputs_reach_the_logic_and_its_outputs_reach_the_device() {
    let _serial = serial();
    tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .expect("tokio runtime")
        .block_on(modbus_round_trip());
}

/// The body of the test above: closing the e-stop chain at the device energises its coil 4.
async fn modbus_round_trip() {
    let device = RemoteIoSim::start("127.0.0.1:0".parse().expect("addr"))
        .await
        .expect("device starts");
    {
        let mut s = device.state();
        s.discrete[0] = true; // ESTOP_PB_OK
        s.discrete[1] = true; // OVERTRAVEL_OK
    }
    let machine = lathe_with_device(&device.addr().to_string());
    let mut child = spawn_run(machine.path(), "modbus", 3000);

    let energised = wait_for(Duration::from_secs(10), || device.state().coils[4]).await;
    device.state().discrete[0] = false; // an emergency-stop button is pressed
    let dropped = energised && wait_for(Duration::from_secs(10), || !device.state().coils[4]).await;
    let _ = child.kill();
    let out = child.wait_with_output().expect("ncplc ends");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        energised,
        "coil 4 (DRIVES_ON) never energised; ncplc said:\n{stderr}"
    );
    assert!(
        dropped,
        "coil 4 (DRIVES_ON) stayed on after the e-stop opened; ncplc said:\n{stderr}"
    );
    let writes = device.state().writes.clone();
    assert!(
        writes.iter().all(|&(fc, _, _)| fc == 5 || fc == 15),
        "only coil writes: {writes:?}"
    );
}

#[test]
fn a_missing_modbus_device_raises_its_alarm() {
    let _serial = serial();
    // Nothing listens on this port: bind a socket to reserve a free port, then close it.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .expect("bind")
        .local_addr()
        .expect("addr")
        .port();
    let machine = lathe_with_device(&format!("127.0.0.1:{port}"));
    let out = spawn_run(machine.path(), "modbus", 100)
        .wait_with_output()
        .expect("ncplc ends");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("alarm: rio1"), "{stderr}");
    assert!(stderr.contains("100 ticks of 10 ms on modbus"), "{stderr}");
}

#[test]
fn canopen_on_the_virtual_bus_runs_without_alarms() {
    let _serial = serial();
    let machine = lathe_with_device("127.0.0.1:5020");
    // This test is about configuration and PDO exchange end to end; heartbeat loss has its own
    // tests (fieldbus/tests/it/canopen.rs). The example's 100 ms consumer time (2.5 producer periods)
    // tripped on a loaded CI machine, where the debug-built node simulation missed a period, so
    // this copy gives the consumer 1 s.
    let map = machine.path().join("io.toml");
    let text = std::fs::read_to_string(&map).expect("io.toml");
    assert!(
        text.contains("heartbeat_ms = 100 "),
        "the example's consumer time"
    );
    std::fs::write(
        &map,
        text.replace("heartbeat_ms = 100 ", "heartbeat_ms = 1000 "),
    )
    .expect("write");
    let out = spawn_run(machine.path(), "canopen", 100)
        .wait_with_output()
        .expect("ncplc ends");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains("alarm"), "{stderr}");
    assert!(stderr.contains("100 ticks of 10 ms on canopen"), "{stderr}");
}

#[test]
fn an_io_map_with_an_undeclared_connector_is_refused_with_a_located_error() {
    let _serial = serial();
    let machine = lathe_with_device("127.0.0.1:5020");
    let map = std::fs::read_to_string(machine.path().join("io.toml")).expect("io.toml");
    // OU6 is not declared in the lathe's IOCFIL (OU0=4,5).
    let map = map.replacen(
        "connector = 5\narea = \"coils\"",
        "connector = 6\narea = \"coils\"",
        1,
    );
    std::fs::write(machine.path().join("io.toml"), map).expect("write");
    let out = spawn_run(machine.path(), "modbus", 10)
        .wait_with_output()
        .expect("ncplc ends");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    assert!(stderr.contains("error[E3020]"), "{stderr}");
    assert!(stderr.contains("connector = 6"), "{stderr}");
}

#[test]
fn scan_and_io_threads_can_be_pinned_and_bad_cpus_are_refused() {
    let _serial = serial();
    let machine = lathe_with_device("127.0.0.1:5020");
    let map = std::fs::read_to_string(machine.path().join("io.toml")).expect("io.toml");
    std::fs::write(
        machine.path().join("io.toml"),
        format!("[affinity]\nio_cpus = [0]\n{map}"),
    )
    .expect("write");
    // CPU 0 exists everywhere; this test process may use it unless a cgroup says otherwise.
    let out = spawn_run_with(machine.path(), "canopen", 50, &["--scan-cpu", "0"])
        .wait_with_output()
        .expect("ncplc ends");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("50 ticks of 10 ms on canopen"), "{stderr}");

    let out = spawn_run_with(machine.path(), "canopen", 5, &["--scan-cpu", "100000"])
        .wait_with_output()
        .expect("ncplc ends");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("error: --scan-cpu: CPU 100000 does not exist"),
        "{stderr}"
    );

    std::fs::write(
        machine.path().join("io.toml"),
        format!("[affinity]\nio_cpus = [100000]\n{map}"),
    )
    .expect("write");
    let out = spawn_run(machine.path(), "canopen", 5)
        .wait_with_output()
        .expect("ncplc ends");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    assert!(stderr.contains("error[E3042]"), "{stderr}");
    assert!(stderr.contains("io_cpus = [100000]"), "{stderr}");
}
