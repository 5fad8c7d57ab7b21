//! CiA 402 drives on the virtual bus and over cannelloni UDP: the master's start-up, the state
//! machine, the set point of each tick in the RPDO before its SYNC, faults, heartbeat loss and
//! fault reset, against the simulated drive node.

use std::time::Duration;

use fieldbus::canopen::drive::{
    AxisId, DriveCommand, DriveFault, DriveStartError, Drives, FaultCause, State,
};
use fieldbus::canopen::drive_sim::Cia402Node;
use fieldbus::canopen::transport::CanBus;
use fieldbus::canopen::virtual_bus::{VirtualBus, VirtualPort};
use fieldbus::canopen::{CanMsg, nmt};
use fieldbus::map::{CanDrive, DriveMode, SdoWrite};

const TICK: Duration = Duration::from_millis(4);
const X: AxisId = AxisId {
    process: 1,
    name: 'X',
};

fn drive(axis: char, node_id: u8, mode: DriveMode, cpu: f64) -> CanDrive {
    CanDrive {
        process: 1,
        axis,
        node_id,
        counts_per_unit: cpu,
        mode,
        // Long enough that a loaded test machine never loses a heartbeat by accident.
        heartbeat: Duration::from_millis(200),
        sdo: Vec::new(),
        simulate: Default::default(),
        span: 0..0,
        homing: true,
    }
}

/// Starts the drives; every simulated drive answers each SYNC, so the wait for the answers may be
/// long (a loaded test machine must not make a tick's answer late).
async fn start(
    bus: &VirtualBus,
    drives: &[CanDrive],
) -> Result<Drives<VirtualPort>, DriveStartError> {
    let mut d = Drives::start(bus.port(), drives, TICK, Duration::from_millis(500)).await?;
    d.set_answer_timeout(Duration::from_secs(1));
    Ok(d)
}

fn enable(set_point: f64) -> DriveCommand {
    DriveCommand {
        set_point,
        enable: true,
        ..DriveCommand::default()
    }
}

/// One tick: command X, SYNC, then let the tick's time pass (heartbeats flow meanwhile).
async fn tick(d: &mut Drives<VirtualPort>, cmd: DriveCommand) {
    assert!(d.command(X, cmd));
    d.sync().await.expect("sync");
    d.idle(TICK).await.expect("idle");
}

async fn drain(port: &mut VirtualPort) -> Vec<CanMsg> {
    let mut out = Vec::new();
    while let Ok(Ok(m)) = tokio::time::timeout(Duration::from_millis(20), port.recv()).await {
        out.push(m);
    }
    out
}

#[tokio::test]
async fn the_set_point_of_tick_n_is_in_the_rpdo_before_the_sync_of_tick_n() {
    let bus = VirtualBus::new();
    let node = Cia402Node::spawn(bus.port(), 3);
    let mut d = start(&bus, &[drive('X', 3, DriveMode::Csp, 1000.0)])
        .await
        .expect("start");
    let mut spy = bus.port();
    let mut seen = Vec::new();
    for n in 1..=8u32 {
        tick(&mut d, enable(0.25 * f64::from(n))).await;
        let f = d.feedback(X).expect("X");
        seen.push((f.state, f.position, f.velocity, f.healthy));
    }
    // The walk: Shutdown, Switch on, Enable operation; then the drive follows with no lag.
    assert_eq!(seen[0], (State::ReadyToSwitchOn, 0.0, 0.0, true));
    assert_eq!(seen[1], (State::SwitchedOn, 0.0, 0.0, true));
    assert_eq!(seen[2], (State::OperationEnabled, 0.75, 187.5, true));
    for (i, s) in seen.iter().enumerate().skip(3) {
        let n = i as f64 + 1.0;
        assert_eq!(
            *s,
            (State::OperationEnabled, 0.25 * n, 62.5, true),
            "tick {n}"
        );
    }
    // On the wire: before SYNC n, RPDO1 of node 3 = controlword + 250·n counts.
    let frames = drain(&mut spy).await;
    let mut last_rpdo = None;
    let mut per_sync = Vec::new();
    for m in &frames {
        match m.id {
            0x203 => last_rpdo = Some(m.payload().to_vec()),
            0x080 => per_sync.push(last_rpdo.take().expect("an RPDO before every SYNC")),
            _ => {}
        }
    }
    assert_eq!(per_sync.len(), 8);
    for (i, p) in per_sync.iter().enumerate() {
        let n = i as i32 + 1;
        let cw = u16::from_le_bytes([p[0], p[1]]);
        let target = i32::from_le_bytes([p[2], p[3], p[4], p[5]]);
        let want_cw = [0x06, 0x07][..].get(i).copied().unwrap_or(0x0F);
        assert_eq!((cw, target), (want_cw, 250 * n), "SYNC {n}");
    }
    // The drive applied target n at its SYNC n.
    let applied = node.state().applied.clone();
    let want: Vec<(u64, u16, i32)> = (1..=8)
        .map(|n| {
            (
                n as u64,
                [0x06, 0x07][..].get(n - 1).copied().unwrap_or(0x0F),
                250 * n as i32,
            )
        })
        .collect();
    assert_eq!(applied, want);
}

async fn enabled(bus: &VirtualBus, heartbeat_ms: u64) -> Drives<VirtualPort> {
    let mut x = drive('X', 3, DriveMode::Csp, 1000.0);
    x.heartbeat = Duration::from_millis(heartbeat_ms);
    let mut d = start(bus, &[x]).await.expect("start");
    for _ in 0..3 {
        tick(&mut d, enable(1.0)).await;
    }
    assert_eq!(d.feedback(X).expect("X").state, State::OperationEnabled);
    d
}

#[tokio::test]
async fn a_fault_in_the_statusword_is_in_the_feedback_within_two_ticks_with_its_code() {
    let bus = VirtualBus::new();
    let node = Cia402Node::spawn(bus.port(), 3);
    let mut d = enabled(&bus, 200).await;
    tick(&mut d, enable(1.5)).await;
    node.state().inject_fault(0x2310);
    tick(&mut d, enable(2.0)).await;
    let f = d.feedback(X).expect("X");
    assert_eq!(f.state, State::Fault);
    assert_eq!(
        f.fault,
        Some(DriveFault {
            node: 3,
            code: 0x2310,
            cause: FaultCause::Drive
        })
    );
    assert!(!f.healthy);
    // Nothing from the faulted drive is a position: the last healthy one stays.
    assert_eq!(f.position, 1.5);
    tick(&mut d, enable(2.5)).await;
    assert_eq!(d.feedback(X).expect("X").position, 1.5);
    // The master sends Disable voltage to the faulted drive until a reset.
    assert_eq!(node.state().controlword, 0x00);
}

#[tokio::test]
async fn fault_reset_walks_back_to_operation_enabled() {
    let bus = VirtualBus::new();
    let node = Cia402Node::spawn(bus.port(), 3);
    let mut d = enabled(&bus, 200).await;
    node.state().inject_fault(0x7500);
    tick(&mut d, enable(1.0)).await;
    tick(&mut d, enable(1.0)).await;
    assert_eq!(d.feedback(X).expect("X").state, State::Fault);
    let before = node.state().applied.len();
    let reset = DriveCommand {
        fault_reset: true,
        ..enable(1.0)
    };
    let mut states = Vec::new();
    for _ in 0..4 {
        tick(&mut d, reset).await;
        let f = d.feedback(X).expect("X");
        states.push((f.state, f.fault.is_none(), f.healthy));
    }
    assert_eq!(
        states,
        [
            (State::SwitchOnDisabled, true, true),
            (State::ReadyToSwitchOn, true, true),
            (State::SwitchedOn, true, true),
            (State::OperationEnabled, true, true),
        ]
    );
    let words: Vec<u16> = node.state().applied[before..].iter().map(|a| a.1).collect();
    assert_eq!(words, [0x80, 0x06, 0x07, 0x0F]);
    assert_eq!(node.state().error_code, 0);
}

#[tokio::test]
async fn an_sdo_abort_at_start_up_names_the_node_the_object_and_the_code_and_starts_no_drive() {
    let bus = VirtualBus::new();
    let good = Cia402Node::spawn(bus.port(), 3);
    let bad = Cia402Node::spawn(bus.port(), 4);
    bad.state().sdo_abort = Some((0x60C2, 1, 0x0609_0030));
    let drives = [
        drive('X', 3, DriveMode::Csp, 1000.0),
        drive('Z', 4, DriveMode::Csp, 1000.0),
    ];
    let err = start(&bus, &drives).await.err().expect("refused");
    assert_eq!(
        err,
        DriveStartError::Sdo {
            axis: 'Z',
            node: 4,
            what: "write",
            index: 0x60C2,
            subindex: 1,
            code: Some(0x0609_0030)
        }
    );
    assert_eq!(
        err.to_string(),
        "drive of axis Z (node 4): SDO write 60C2h/1 was aborted with code 06090030h (value range of parameter exceeded)"
    );
    assert_eq!(err.diagnostic(0..0).code, fieldbus::codes::DRIVE_START);
    // Neither drive was started: both stay pre-operational, so none can be enabled.
    assert_eq!(good.state().nmt, nmt::PRE_OPERATIONAL);
    assert_eq!(bad.state().nmt, nmt::PRE_OPERATIONAL);
}

#[tokio::test]
async fn a_silent_node_at_start_up_is_a_timeout_naming_it() {
    let bus = VirtualBus::new();
    let err = Drives::start(
        bus.port(),
        &[drive('X', 9, DriveMode::Csp, 1.0)],
        TICK,
        Duration::from_millis(30),
    )
    .await
    .err()
    .expect("refused");
    assert_eq!(
        err.to_string(),
        "drive of axis X (node 9): SDO read 1000h/0 got no answer (timeout)"
    );
}

#[tokio::test]
async fn the_configuration_reaches_the_drives_dictionary() {
    let bus = VirtualBus::new();
    let node = Cia402Node::spawn(bus.port(), 5);
    let mut s = drive('S', 5, DriveMode::Csv, 4096.0);
    s.sdo = vec![SdoWrite {
        index: 0x1800,
        subindex: 2,
        value: 1,
        size: 1,
    }];
    let _d = start(&bus, &[s]).await.expect("start");
    // Let the node take the NMT start the master sent last.
    tokio::time::sleep(Duration::from_millis(10)).await;
    let st = node.state();
    assert_eq!(st.mode, 9);
    assert_eq!(st.interpolation, (40, -4));
    assert_eq!(
        (st.rpdo.cob_id, st.rpdo.transmission, st.rpdo.count),
        (0x205, 1, 2)
    );
    assert_eq!(&st.rpdo.map[..2], &[0x6040_0010, 0x60FF_0020]);
    assert_eq!(
        (st.tpdo.cob_id, st.tpdo.transmission, st.tpdo.count),
        (0x185, 1, 2)
    );
    assert_eq!(&st.tpdo.map[..2], &[0x6041_0010, 0x606C_0020]);
    assert_eq!(st.heartbeat_ms, 200);
    assert_eq!(st.nmt, nmt::OPERATIONAL);
}

#[tokio::test]
async fn a_csv_spindle_follows_its_speed() {
    let bus = VirtualBus::new();
    let _node = Cia402Node::spawn(bus.port(), 5);
    let s = AxisId::new('S');
    let mut d = start(&bus, &[drive('S', 5, DriveMode::Csv, 4096.0)])
        .await
        .expect("start");
    let mut speeds = Vec::new();
    for _ in 0..4 {
        assert!(d.command(s, enable(10.0)));
        d.sync().await.expect("sync");
        speeds.push(d.feedback(s).expect("S").velocity);
    }
    assert_eq!(speeds, [0.0, 0.0, 10.0, 10.0]);
}

#[tokio::test]
async fn a_lost_heartbeat_is_a_fault_and_the_drive_is_quick_stopped() {
    let bus = VirtualBus::new();
    let node = Cia402Node::spawn(bus.port(), 3);
    let mut d = enabled(&bus, 50).await;
    node.state().heartbeat_stopped = true;
    let stopped = std::time::Instant::now();
    let mut ticks = 0;
    while d.feedback(X).expect("X").fault.is_none() && ticks < 100 {
        tick(&mut d, enable(1.0)).await;
        ticks += 1;
    }
    let f = d.feedback(X).expect("X");
    assert_eq!(
        f.fault,
        Some(DriveFault {
            node: 3,
            code: 0x8130,
            cause: FaultCause::HeartbeatLost
        })
    );
    assert!(!f.healthy);
    // Consumer time 2 × 50 ms from the last heartbeat, which came at most 50 ms before the hook.
    let silent = stopped.elapsed();
    assert!(silent >= Duration::from_millis(50), "{silent:?}");
    assert!(ticks < 100);
    tick(&mut d, enable(1.0)).await;
    assert_eq!(node.state().controlword, 0x02, "quick stop");
    assert_eq!(node.state().state, State::QuickStopActive);
    // A reset without the heartbeat back keeps the fault.
    let reset = DriveCommand {
        fault_reset: true,
        ..enable(1.0)
    };
    tick(&mut d, reset).await;
    assert_eq!(
        d.feedback(X).expect("X").fault.map(|f| f.cause),
        Some(FaultCause::HeartbeatLost)
    );
    // Heartbeat back, reset: Disable voltage, then the walk up.
    node.state().heartbeat_stopped = false;
    d.idle(Duration::from_millis(60)).await.expect("idle");
    let mut states = Vec::new();
    for _ in 0..5 {
        tick(&mut d, reset).await;
        states.push(d.feedback(X).expect("X").state);
    }
    assert_eq!(
        states,
        [
            State::SwitchOnDisabled,
            State::ReadyToSwitchOn,
            State::SwitchedOn,
            State::OperationEnabled,
            State::OperationEnabled
        ]
    );
    assert!(d.feedback(X).expect("X").healthy);
}

#[tokio::test]
async fn a_drive_that_refuses_to_enable_is_a_fault_after_twenty_ticks() {
    let bus = VirtualBus::new();
    let node = Cia402Node::spawn(bus.port(), 3);
    node.state().refuse_enable = true;
    let mut d = start(&bus, &[drive('X', 3, DriveMode::Csp, 1000.0)])
        .await
        .expect("start");
    let mut faults = Vec::new();
    for _ in 0..22 {
        assert!(d.command(X, enable(0.0)));
        d.sync().await.expect("sync");
        faults.push(d.feedback(X).expect("X").fault);
    }
    assert!(faults[..20].iter().all(Option::is_none));
    let refused = Some(DriveFault {
        node: 3,
        code: 0xFF01,
        cause: FaultCause::EnableRefused,
    });
    assert_eq!(faults[20], refused);
    // The fault is the safe state: Disable voltage.
    assert_eq!(d.feedback(X).expect("X").state, State::SwitchOnDisabled);
}

#[tokio::test]
async fn drives_run_over_cannelloni_udp_on_loopback() {
    use fieldbus::canopen::cannelloni::UdpBus;
    let free = || std::net::UdpSocket::bind("127.0.0.1:0").expect("port");
    // Both held at once, so the two ports differ.
    let (sa, sb) = (free(), free());
    let (a, b) = (sa.local_addr().expect("a"), sb.local_addr().expect("b"));
    drop((sa, sb));
    let node_bus = UdpBus::bind(b, a).await.expect("bind node");
    let node = Cia402Node::spawn(node_bus, 3);
    let master_bus = UdpBus::bind(a, b).await.expect("bind master");
    let mut d = Drives::start(
        master_bus,
        &[drive('X', 3, DriveMode::Csp, 1000.0)],
        TICK,
        Duration::from_millis(200),
    )
    .await
    .expect("start");
    d.set_answer_timeout(Duration::from_secs(1));
    let mut positions = Vec::new();
    for n in 1..=5 {
        assert!(d.command(X, enable(0.5 * f64::from(n))));
        d.sync().await.expect("sync");
        positions.push(d.feedback(X).expect("X").position);
    }
    assert_eq!(positions, [0.0, 0.0, 1.5, 2.0, 2.5]);
    assert_eq!(node.state().applied.last().copied(), Some((5, 0x0F, 2500)));
}
