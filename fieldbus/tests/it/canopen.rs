//! End-to-end tests of the CANopen master against simulated CiA 401 nodes on the in-process virtual
//! bus and over cannelloni UDP on 127.0.0.1: SDO configuration, NMT start, SYNC-driven PDO exchange,
//! the heartbeat consumer (lost node → alarm and fail state), SDO failures. Every wait is bounded.

use std::time::{Duration, Instant};

use fieldbus::canopen::cannelloni::UdpBus;
use fieldbus::canopen::master::CanopenIo;
use fieldbus::canopen::nmt;
use fieldbus::canopen::node_sim::Cia401Node;
use fieldbus::canopen::sdo;
use fieldbus::canopen::virtual_bus::VirtualBus;
use fieldbus::map::{ByteRange, CanNode, CanopenConfig, PdoMapping, SdoWrite, TransportConfig};
use packets::{IoAlarm, PACKETS_LEN, PacketIo};

fn node_cfg(heartbeat_ms: u64, sdo: Vec<SdoWrite>) -> CanopenConfig {
    CanopenConfig {
        transport: TransportConfig::Virtual,
        sdo_timeout: Duration::from_millis(100),
        drives: Vec::new(),
        nodes: vec![CanNode {
            name: "dio1".into(),
            node_id: 2,
            heartbeat: Duration::from_millis(heartbeat_ms),
            healthy: Some("I100K1".parse().expect("signal")),
            sdo,
            // TPDO1 bytes 0..3 → IN0 (W0A0..W0A3); TPDO2 byte 0 → W1A0.
            inputs: vec![
                PdoMapping {
                    range: ByteRange { start: 0, len: 4 },
                    pdo: 1,
                    offset: 0,
                    fail: 0,
                },
                PdoMapping {
                    range: ByteRange { start: 4, len: 1 },
                    pdo: 2,
                    offset: 0,
                    fail: 0xEE,
                },
            ],
            // OU4 (W4A0..W4A3) → RPDO1 bytes 0..3.
            outputs: vec![PdoMapping {
                range: ByteRange { start: 16, len: 4 },
                pdo: 1,
                offset: 0,
                fail: 0,
            }],
            simulate: Default::default(),
        }],
    }
}

fn heartbeat_20ms() -> Vec<SdoWrite> {
    vec![SdoWrite {
        index: 0x1017,
        subindex: 0,
        value: 20,
        size: 2,
    }]
}

fn runtime() -> tokio::runtime::Runtime {
    tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()
        .expect("runtime")
}

fn tick_until(
    io: &mut CanopenIo,
    image: &mut [u8],
    limit: Duration,
    alarms: &mut Vec<IoAlarm>,
    mut done: impl FnMut(&[u8], &CanopenIo, &[IoAlarm]) -> bool,
) -> Option<u64> {
    let start = Instant::now();
    let mut tick = 0;
    while start.elapsed() < limit {
        tick += 1;
        io.latch_inputs(tick, image);
        alarms.extend(io.take_alarms());
        io.publish_outputs(tick, image);
        if done(image, io, alarms) {
            return Some(tick);
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    None
}

#[test]
fn configured_node_is_started_and_exchanges_pdos_every_sync() {
    let rt = runtime();
    let bus = VirtualBus::new();
    let node = rt.block_on(async { Cia401Node::spawn(bus.port(), 2) });
    node.state().inputs[..4].copy_from_slice(&[0x11, 0x22, 0x33, 0x44]);
    node.state().inputs[8] = 0x55;
    let port = bus.port();
    let mut io =
        CanopenIo::start(&node_cfg(300, heartbeat_20ms()), || async { Ok(port) }).expect("master");
    let mut image = vec![0u8; PACKETS_LEN];
    let mut alarms = Vec::new();
    tick_until(
        &mut io,
        &mut image,
        Duration::from_secs(5),
        &mut alarms,
        |img, _, _| img[4] == 0x55 && img[0] == 0x11,
    )
    .expect("inputs arrive");
    assert_eq!(&image[0..5], &[0x11, 0x22, 0x33, 0x44, 0x55]);
    assert_eq!(
        node.state().heartbeat_ms,
        20,
        "SDO configuration reached the node"
    );
    assert_eq!(node.state().nmt, nmt::OPERATIONAL);
    image[16..20].copy_from_slice(&[1, 2, 4, 8]);
    tick_until(
        &mut io,
        &mut image,
        Duration::from_secs(5),
        &mut alarms,
        |_, _, _| node.state().outputs[..4] == [1, 2, 4, 8],
    )
    .expect("outputs arrive");
    assert_eq!(
        &node.state().outputs[4..],
        &[0u8; 12],
        "unmapped output bytes stay 0"
    );
    tick_until(
        &mut io,
        &mut image,
        Duration::from_secs(5),
        &mut alarms,
        |_, io, _| io.is_healthy("dio1"),
    )
    .expect("healthy");
    assert_eq!(image[128 + 400] & 0b10, 0b10, "healthy bit I100K1");
    assert!(alarms.is_empty(), "{alarms:?}");
}

#[test]
fn lost_node_raises_alarm_within_its_heartbeat_time_and_takes_fail_state() {
    let rt = runtime();
    let bus = VirtualBus::new();
    let node = rt.block_on(async { Cia401Node::spawn(bus.port(), 2) });
    node.state().inputs[..4].copy_from_slice(&[9, 9, 9, 9]);
    let port = bus.port();
    let mut io =
        CanopenIo::start(&node_cfg(60, heartbeat_20ms()), || async { Ok(port) }).expect("master");
    let mut image = vec![0u8; PACKETS_LEN];
    let mut alarms = Vec::new();
    tick_until(
        &mut io,
        &mut image,
        Duration::from_secs(5),
        &mut alarms,
        |img, io, _| img[0] == 9 && io.is_healthy("dio1"),
    )
    .expect("running");

    node.state().silent = true;
    let lost_at = Instant::now();
    tick_until(
        &mut io,
        &mut image,
        Duration::from_secs(5),
        &mut alarms,
        |_, _, a| !a.is_empty(),
    )
    .expect("alarm");
    let took = lost_at.elapsed();
    let seen = std::mem::take(&mut alarms);
    // Heartbeat time 60 ms after the last heartbeat (≤ 20 ms before the silence), checked every
    // 15 ms; 100 ms more for the scan's 1 ms ticks on a loaded 2-core CI machine.
    assert!(
        took < Duration::from_millis(60 + 20 + 15 + 100),
        "lost after {took:?}, heartbeat time 60 ms"
    );
    assert!(
        seen.iter()
            .any(|a| a.device == "dio1" && a.message == "heartbeat lost" && !a.cleared),
        "{seen:?}"
    );
    assert_eq!(&image[0..5], &[0, 0, 0, 0, 0xEE], "fail state");
    assert_eq!(image[128 + 400] & 0b10, 0, "healthy bit cleared");

    node.state().silent = false;
    tick_until(
        &mut io,
        &mut image,
        Duration::from_secs(5),
        &mut alarms,
        |_, io, _| io.is_healthy("dio1"),
    )
    .expect("back");
    assert!(alarms.iter().any(|a| a.cleared), "{alarms:?}");
    assert_eq!(image[0], 9);
}

/// A node whose heartbeat stops while it still listens: once lost, the master sends its outputs'
/// safe values instead of the scan's (as the safe state does); when its heartbeat is back, the
/// scan's outputs again.
#[test]
fn a_lost_node_gets_its_safe_outputs_until_it_answers_again() {
    let rt = runtime();
    let bus = VirtualBus::new();
    let node = rt.block_on(async { Cia401Node::spawn(bus.port(), 2) });
    let port = bus.port();
    let mut cfg = node_cfg(60, heartbeat_20ms());
    cfg.nodes[0].outputs[0].fail = 0xA5;
    let mut io = CanopenIo::start(&cfg, || async { Ok(port) }).expect("master");
    let mut image = vec![0u8; PACKETS_LEN];
    image[16..20].copy_from_slice(&[1, 2, 4, 8]);
    let mut alarms = Vec::new();
    tick_until(
        &mut io,
        &mut image,
        Duration::from_secs(5),
        &mut alarms,
        |_, io, _| io.is_healthy("dio1") && node.state().outputs[..4] == [1, 2, 4, 8],
    )
    .expect("running");
    node.state().heartbeat_ms = 0;
    tick_until(
        &mut io,
        &mut image,
        Duration::from_secs(5),
        &mut alarms,
        // The scan's view of the node's health comes with the next tick after the master's own
        // (which already sends the safe values): wait for both, or a loaded machine sees the
        // outputs before the tick that reports the loss.
        |_, io, _| node.state().outputs[..4] == [0xA5; 4] && io.lost_nodes().next().is_some(),
    )
    .expect("safe outputs");
    let lost: Vec<_> = io
        .lost_nodes()
        .map(|(n, id, f)| (n.to_string(), id, f))
        .collect();
    assert_eq!(
        lost,
        [(
            "dio1".to_string(),
            2,
            fieldbus::health::Fault::HeartbeatLost
        )]
    );
    assert!(
        alarms
            .iter()
            .any(|a| a.device == "dio1" && a.message == "heartbeat lost"),
        "{alarms:?}"
    );
    node.state().heartbeat_ms = 20;
    tick_until(
        &mut io,
        &mut image,
        Duration::from_secs(5),
        &mut alarms,
        |_, io, _| io.is_healthy("dio1") && node.state().outputs[..4] == [1, 2, 4, 8],
    )
    .expect("back");
    assert_eq!(io.lost_nodes().count(), 0);
}

#[test]
fn failed_sdo_configuration_keeps_the_node_stopped_and_alarms() {
    let rt = runtime();
    let bus = VirtualBus::new();
    let node = rt.block_on(async { Cia401Node::spawn(bus.port(), 2) });
    let port = bus.port();
    let bad = vec![SdoWrite {
        index: 0x2000,
        subindex: 0,
        value: 1,
        size: 1,
    }];
    let mut io = CanopenIo::start(&node_cfg(60, bad), || async { Ok(port) }).expect("master");
    let mut image = vec![0u8; PACKETS_LEN];
    image[16] = 0xFF;
    let mut alarms = Vec::new();
    tick_until(
        &mut io,
        &mut image,
        Duration::from_secs(5),
        &mut alarms,
        |_, _, a| !a.is_empty(),
    )
    .expect("alarm");
    assert_eq!(&image[0..5], &[0, 0, 0, 0, 0xEE], "fail state");
    assert!(
        alarms
            .iter()
            .any(|a| a.message == "SDO configuration failed"),
        "{alarms:?}"
    );
    let s = node.state();
    assert_eq!(s.nmt, nmt::PRE_OPERATIONAL);
    assert_eq!(s.rpdos, 0);
    assert_eq!(s.outputs, [0u8; 16]);
}

#[test]
fn no_pdo_or_sync_before_the_scan_publishes() {
    let rt = runtime();
    let bus = VirtualBus::new();
    let node = rt.block_on(async { Cia401Node::spawn(bus.port(), 2) });
    let port = bus.port();
    let mut io =
        CanopenIo::start(&node_cfg(60, heartbeat_20ms()), || async { Ok(port) }).expect("master");
    let mut image = vec![0u8; PACKETS_LEN];
    let start = Instant::now();
    while start.elapsed() < Duration::from_millis(80) {
        io.latch_inputs(0, &mut image);
        std::thread::sleep(Duration::from_millis(1));
    }
    let s = node.state();
    assert_eq!(s.nmt, nmt::OPERATIONAL);
    assert_eq!((s.rpdos, s.syncs), (0, 0));
}

#[test]
fn master_and_node_talk_over_cannelloni_udp() {
    let rt = runtime();
    let (node_bus, node_addr) = rt.block_on(async {
        let b = UdpBus::bind(
            "127.0.0.1:0".parse().expect("addr"),
            "127.0.0.1:1".parse().expect("addr"),
        )
        .await
        .expect("bind");
        let a = b.local_addr().expect("addr");
        (b, a)
    });
    // The master binds first so that the node can be told its address.
    let master_sock = std::net::UdpSocket::bind("127.0.0.1:0").expect("probe");
    let master_addr = master_sock.local_addr().expect("addr");
    drop(master_sock);
    let node_bus = rt.block_on(async {
        drop(node_bus);
        UdpBus::bind(node_addr, master_addr).await.expect("rebind")
    });
    let node = rt.block_on(async { Cia401Node::spawn(node_bus, 2) });
    node.state().inputs[0] = 0x5A;
    let mut io = CanopenIo::start(&node_cfg(60, heartbeat_20ms()), move || {
        UdpBus::bind(master_addr, node_addr)
    })
    .expect("master");
    let mut image = vec![0u8; PACKETS_LEN];
    let mut alarms = Vec::new();
    tick_until(
        &mut io,
        &mut image,
        Duration::from_secs(5),
        &mut alarms,
        |img, _, _| img[0] == 0x5A,
    )
    .expect("TPDO over UDP");
    image[16] = 0x81;
    tick_until(
        &mut io,
        &mut image,
        Duration::from_secs(5),
        &mut alarms,
        |_, _, _| node.state().outputs[0] == 0x81,
    )
    .expect("RPDO over UDP");
}

#[test]
fn sdo_upload_reads_the_object_dictionary() {
    let rt = runtime();
    rt.block_on(async {
        let bus = VirtualBus::new();
        let node = Cia401Node::spawn(bus.port(), 5);
        node.state().inputs[2] = 0x42;
        let mut port = bus.port();
        let t = Duration::from_millis(200);
        let mut ignore = |_: &fieldbus::canopen::CanMsg| {};
        assert_eq!(
            sdo::upload(&mut port, 5, 0x1000, 0, t, &mut ignore).await,
            Ok((0x000F_0191, 4))
        );
        assert_eq!(
            sdo::upload(&mut port, 5, 0x6000, 3, t, &mut ignore).await,
            Ok((0x42, 1))
        );
        assert_eq!(
            sdo::download(
                &mut port,
                5,
                &SdoWrite {
                    index: 0x6000,
                    subindex: 1,
                    value: 1,
                    size: 1
                },
                t,
                &mut ignore
            )
            .await,
            Err(sdo::SdoError::Abort {
                index: 0x6000,
                subindex: 1,
                code: sdo::ABORT_READ_ONLY
            })
        );
        assert_eq!(
            sdo::upload(
                &mut port,
                9,
                0x1000,
                0,
                Duration::from_millis(20),
                &mut ignore
            )
            .await,
            Err(sdo::SdoError::Timeout {
                index: 0x1000,
                subindex: 0
            })
        );
    });
}

#[test]
fn a_missing_node_fails_its_sdo_check_and_raises_the_alarm() {
    let bus = VirtualBus::new();
    let port = bus.port();
    let mut cfg = node_cfg(60, Vec::new());
    cfg.nodes[0].node_id = 7; // nobody answers as node 7
    let mut io = CanopenIo::start(&cfg, || async { Ok(port) }).expect("master");
    let mut image = vec![0u8; PACKETS_LEN];
    let mut alarms = Vec::new();
    tick_until(
        &mut io,
        &mut image,
        Duration::from_secs(5),
        &mut alarms,
        |_, _, a| !a.is_empty(),
    )
    .expect("alarm");
    assert_eq!(alarms[0].message, "SDO configuration failed");
    assert_eq!(&image[0..5], &[0, 0, 0, 0, 0xEE]);
}
