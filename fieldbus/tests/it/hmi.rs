//! The HMI/SCADA server read and written by a Modbus TCP client on 127.0.0.1, and `open` /
//! `start_hmi` driven from an `io.toml` in a temporary machine directory.

use std::net::SocketAddr;
use std::time::{Duration, Instant};

use fieldbus::map::{HmiConfig, HmiLimits, HmiWindow};
use fieldbus::modbus::server::HmiIo;
use fieldbus::modbus::sim::RemoteIoSim;
use fieldbus::{DeclaredConnectors, IoKind};
use packets::{PACKETS_LEN, Packet, PacketIo};
use tokio_modbus::client::{Reader, Writer};
use tokio_modbus::{ExceptionCode, Slave};

/// A stand-in for the simulated I/O: remembers the last outputs, sets input W0A0 = 0x81.
struct Fixed;

impl PacketIo for Fixed {
    fn name(&self) -> &str {
        "fixed"
    }
    fn latch_inputs(&mut self, _tick: u64, packets: &mut [u8]) {
        packets[0] = 0x81;
    }
    fn publish_outputs(&mut self, _tick: u64, _packets: &[u8]) {}
}

fn runtime() -> tokio::runtime::Runtime {
    tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()
        .expect("runtime")
}

async fn client(addr: SocketAddr) -> tokio_modbus::client::Context {
    tokio::time::timeout(
        Duration::from_secs(2),
        tokio_modbus::client::tcp::connect_slave(addr, Slave(1)),
    )
    .await
    .expect("in time")
    .expect("connect")
}

#[test]
fn hmi_reads_the_image_writes_only_its_window_and_gets_exceptions_elsewhere() {
    let window = HmiWindow {
        start: Packet::K.offset() + 800,
        len: 4,
    }; // W200K0..W200K3
    let cfg = HmiConfig {
        bind: "127.0.0.1:0".parse().expect("addr"),
        holding: vec![window],
        limits: HmiLimits::default(),
    };
    let mut hmi = HmiIo::start(Box::new(Fixed), &cfg).expect("server");
    let addr = hmi.local_addr();
    let mut image = vec![0u8; PACKETS_LEN];
    hmi.latch_inputs(1, &mut image);
    image[16] = 0b0000_0100; // U4A2: coil 4*32+2 = 130
    image[Packet::K.offset() + 21] = 0xBE; // W5K1: high byte of input register 10
    image[Packet::N.offset()] = 0x07; // W0N0: low byte of input register 512
    hmi.publish_outputs(1, &image);

    let rt = runtime();
    rt.block_on(async {
        let mut c = client(addr).await;
        assert_eq!(
            c.read_discrete_inputs(0, 8).await.expect("io"),
            Ok(vec![true, false, false, false, false, false, false, true])
        );
        assert_eq!(
            c.read_coils(128, 4).await.expect("io"),
            Ok(vec![false, false, true, false])
        );
        assert_eq!(
            c.read_input_registers(10, 1).await.expect("io"),
            Ok(vec![0xBE00])
        );
        assert_eq!(
            c.read_input_registers(512, 1).await.expect("io"),
            Ok(vec![0x0007])
        );
        // Wrong direction, out of range, read-only tables, outside the window.
        assert_eq!(
            c.read_discrete_inputs(120, 16).await.expect("io"),
            Err(ExceptionCode::IllegalDataAddress),
            "crosses into output connector 4"
        );
        assert_eq!(
            c.read_coils(0, 1).await.expect("io"),
            Err(ExceptionCode::IllegalDataAddress)
        );
        assert_eq!(
            c.read_input_registers(1020, 8).await.expect("io"),
            Err(ExceptionCode::IllegalDataAddress)
        );
        assert_eq!(
            c.read_input_registers(0, 126).await.expect("io"),
            Err(ExceptionCode::IllegalDataValue)
        );
        assert_eq!(
            c.write_single_coil(130, false).await.expect("io"),
            Err(ExceptionCode::IllegalFunction)
        );
        assert_eq!(
            c.write_single_register(399, 1).await.expect("io"),
            Err(ExceptionCode::IllegalDataAddress)
        );
        assert_eq!(
            c.write_multiple_registers(400, &[1, 2, 3])
                .await
                .expect("io"),
            Err(ExceptionCode::IllegalDataAddress),
            "spills past the window"
        );
        assert_eq!(
            c.read_holding_registers(0, 1).await.expect("io"),
            Err(ExceptionCode::IllegalDataAddress)
        );
        // The window: K bytes 800..803 = registers 400, 401.
        assert_eq!(
            c.write_multiple_registers(400, &[0x0201, 0x0403])
                .await
                .expect("io"),
            Ok(())
        );
        assert_eq!(
            c.read_holding_registers(400, 2).await.expect("io"),
            Ok(vec![0x0201, 0x0403])
        );
    });
    // The next latch brings the HMI's bytes into the image, and they stay on later ticks.
    for tick in 2..4 {
        image[Packet::K.offset() + 800] = 0;
        hmi.latch_inputs(tick, &mut image);
        assert_eq!(
            &image[Packet::K.offset() + 800..Packet::K.offset() + 804],
            &[1, 2, 3, 4]
        );
        assert_eq!(image[Packet::K.offset() + 804], 0);
        assert_eq!(image[0], 0x81, "the inner driver's inputs are kept");
    }
}

fn write_map(dir: &std::path::Path, device: SocketAddr, hmi_port: u16) {
    let text = format!(
        "[hmi]\nbind = \"127.0.0.1:{hmi_port}\"\nholding = [{{ byte = \"W200K0\", len = 2 }}]\n\
         [[modbus.device]]\nname = \"rio1\"\naddress = \"{device}\"\ntimeout_ms = 50\npoll_us = 200\nhealthy = \"I100K0\"\n\
         [[input]]\ndevice = \"rio1\"\nconnector = 0\narea = \"discrete_inputs\"\naddress = 0\n\
         [[output]]\ndevice = \"rio1\"\nconnector = 4\narea = \"coils\"\naddress = 0\n"
    );
    std::fs::write(dir.join("io.toml"), text).expect("write io.toml");
}

#[test]
fn open_modbus_and_start_hmi_from_io_toml() {
    let rt = runtime();
    let sim = rt
        .block_on(RemoteIoSim::start("127.0.0.1:0".parse().expect("addr")))
        .expect("sim");
    sim.state().discrete[3] = true;
    let dir = tempfile::tempdir().expect("tempdir");
    let free = std::net::TcpListener::bind("127.0.0.1:0")
        .expect("probe")
        .local_addr()
        .expect("addr")
        .port();
    write_map(dir.path(), sim.addr(), free);
    let declared = DeclaredConnectors {
        inputs: vec![0],
        outputs: vec![4],
    };
    let io = fieldbus::open(IoKind::Modbus, dir.path(), &declared)
        .map_err(|d| format!("{d:?}"))
        .expect("driver");
    let mut io = fieldbus::start_hmi(dir.path(), &declared, io)
        .map_err(|d| format!("{d:?}"))
        .expect("hmi");
    assert_eq!(io.name(), "modbus");
    let mut image = vec![0u8; PACKETS_LEN];
    let start = Instant::now();
    image[16] = 0x01;
    while start.elapsed() < Duration::from_secs(5) && !(image[0] == 0x08 && sim.state().coils[0]) {
        io.latch_inputs(0, &mut image);
        io.publish_outputs(0, &image);
        std::thread::sleep(Duration::from_millis(1));
    }
    assert_eq!(image[0], 0x08);
    assert!(sim.state().coils[0]);
    rt.block_on(async {
        let mut c = client(SocketAddr::from(([127, 0, 0, 1], free))).await;
        assert_eq!(
            c.read_discrete_inputs(0, 4).await.expect("io"),
            Ok(vec![false, false, false, true])
        );
        assert_eq!(c.read_coils(128, 1).await.expect("io"), Ok(vec![true]));
    });
    // open canopen on a map without [canopen] is a located refusal, not a panic.
    let err = fieldbus::open(IoKind::Canopen, dir.path(), &declared)
        .err()
        .expect("no canopen");
    assert_eq!(err[0].code, fieldbus::codes::NO_DEVICES);
}

#[test]
fn open_canopen_virtual_runs_the_simulated_nodes() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text = "[canopen]\ntransport = \"virtual\"\n[[canopen.node]]\nname = \"dio1\"\nnode_id = 4\nheartbeat_ms = 100\nhealthy = \"I100K1\"\n\
                sdo = [{ index = 0x1017, value = 20, size = 2 }]\n\
                [[output]]\ndevice = \"dio1\"\nconnector = 4\npdo = 1\n";
    std::fs::write(dir.path().join("io.toml"), text).expect("write");
    let declared = DeclaredConnectors {
        inputs: vec![],
        outputs: vec![4],
    };
    let mut io = fieldbus::open(IoKind::Canopen, dir.path(), &declared)
        .map_err(|d| format!("{d:?}"))
        .expect("driver");
    let mut image = vec![0u8; PACKETS_LEN];
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(5) && image[128 + 400] & 0b10 == 0 {
        io.latch_inputs(0, &mut image);
        io.publish_outputs(0, &image);
        std::thread::sleep(Duration::from_millis(1));
    }
    assert_eq!(
        image[128 + 400] & 0b10,
        0b10,
        "the simulated node is healthy"
    );
    assert!(io.take_alarms().is_empty());
}

#[test]
fn drivers_start_from_inside_another_tokio_runtime() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text = "[hmi]\nbind = \"127.0.0.1:0\"\n[canopen]\n[[canopen.node]]\nname = \"dio1\"\nnode_id = 4\n\
                [[output]]\ndevice = \"dio1\"\nconnector = 4\npdo = 1\n";
    std::fs::write(dir.path().join("io.toml"), text).expect("write");
    let declared = DeclaredConnectors {
        inputs: vec![],
        outputs: vec![4],
    };
    let rt = runtime();
    let names = rt.block_on(async {
        let io = fieldbus::open(IoKind::Canopen, dir.path(), &declared)
            .map_err(|d| format!("{d:?}"))
            .expect("driver");
        let io = fieldbus::start_hmi(dir.path(), &declared, io)
            .map_err(|d| format!("{d:?}"))
            .expect("hmi");
        let name = io.name().to_string();
        // Dropping the drivers inside the runtime must not panic either.
        drop(io);
        name
    });
    assert_eq!(names, "canopen");
}

/// Request counts outside the protocol's ranges (found by the `modbus_server` fuzz target: they
/// panicked tokio-modbus's decoder inside the server's thread) close the connection without an
/// answer and without a panic; the server goes on serving, and a valid write in split reads is
/// still served.
#[test]
fn requests_with_counts_outside_the_protocol_close_their_connection_and_nothing_else() {
    use std::io::{Read, Write};
    use std::sync::atomic::{AtomicUsize, Ordering};
    // Panics on the server's threads (tokio would contain them in the connection's task).
    static SERVER_PANICS: AtomicUsize = AtomicUsize::new(0);
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if std::thread::current().name() == Some("ncplc-hmi") {
            SERVER_PANICS.fetch_add(1, Ordering::SeqCst);
        }
        previous(info);
    }));
    let cfg = HmiConfig {
        bind: "127.0.0.1:0".parse().expect("addr"),
        holding: vec![HmiWindow {
            start: Packet::K.offset() + 800,
            len: 4,
        }],
        limits: HmiLimits::default(),
    };
    let hmi = HmiIo::start(Box::new(Fixed), &cfg).expect("server");
    let addr = hmi.local_addr();
    let exchange = |chunks: &[&[u8]]| {
        let mut s = std::net::TcpStream::connect(addr).expect("connect");
        s.set_read_timeout(Some(Duration::from_secs(5)))
            .expect("timeout");
        for c in chunks {
            s.write_all(c).expect("write");
            std::thread::sleep(Duration::from_millis(20));
        }
        let _ = s.shutdown(std::net::Shutdown::Write);
        let mut got = Vec::new();
        let _ = s.read_to_end(&mut got);
        got
    };
    // 0x10 with quantity 0xC013 (× 2 overflows), 0x0F with 100 coils in one byte.
    let overflow = [0x31, 0, 0, 0, 0, 7, 1, 0x10, 0xFF, 0x2F, 0xC0, 0x13, 0];
    let coils = [0, 2, 0, 0, 0, 8, 1, 0x0F, 0, 0, 0, 100, 1, 0xFF];
    assert_eq!(exchange(&[&overflow]), Vec::<u8>::new());
    assert_eq!(exchange(&[&coils]), Vec::<u8>::new());
    // Write W200K0..W200K3 (holding registers 400, 401), the frame in two reads: answered.
    let write = [
        0, 3, 0, 0, 0, 11, 1, 0x10, 1, 0x90, 0, 2, 4, 0xAB, 0xCD, 0x12, 0x34,
    ];
    assert_eq!(
        exchange(&[&write[..9], &write[9..]]),
        [0, 3, 0, 0, 0, 6, 1, 0x10, 1, 0x90, 0, 2]
    );
    assert_eq!(SERVER_PANICS.load(Ordering::SeqCst), 0);
}
