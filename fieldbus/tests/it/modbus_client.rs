//! End-to-end tests of the Modbus TCP client driver against the simulated remote I/O on 127.0.0.1,
//! with fault injection: the device killed and restarted, slow answers, a mute device, garbage
//! frames, and a disconnect during a write. Every wait is bounded.

use std::net::SocketAddr;
use std::time::{Duration, Instant};

use fieldbus::map::{ByteRange, ModbusArea, ModbusDevice, ModbusMapping};
use fieldbus::modbus::client::ModbusIo;
use fieldbus::modbus::sim::RemoteIoSim;
use packets::{PACKETS_LEN, PacketIo, Signal};

fn device(addr: SocketAddr) -> ModbusDevice {
    ModbusDevice {
        name: "rio1".into(),
        address: addr,
        unit: 1,
        timeout: Duration::from_millis(80),
        poll: Duration::from_micros(500),
        write_connection: true,
        direct_write: true,
        alarm_ticks: 50,
        reconnect_min: Duration::from_millis(10),
        reconnect_max: Duration::from_millis(40),
        healthy: Some("I100K0".parse().expect("signal")),
        inputs: vec![
            // IN0 from discrete inputs 0..31, W1A0..W1A1 from input registers 10..
            ModbusMapping {
                range: ByteRange { start: 0, len: 4 },
                area: ModbusArea::DiscreteInputs,
                address: 0,
                fail: 0,
            },
            ModbusMapping {
                range: ByteRange { start: 4, len: 2 },
                area: ModbusArea::InputRegisters,
                address: 10,
                fail: 0xAA,
            },
        ],
        outputs: vec![
            ModbusMapping {
                range: ByteRange { start: 16, len: 4 },
                area: ModbusArea::Coils,
                address: 100,
                fail: 0,
            },
            ModbusMapping {
                range: ByteRange { start: 20, len: 2 },
                area: ModbusArea::HoldingRegisters,
                address: 7,
                fail: 0x55,
            },
        ],
    }
}

/// Runs scan ticks (1 ms apart) until `done` holds or `limit` passes; returns the ticks used.
fn tick_until(
    io: &mut ModbusIo,
    image: &mut [u8],
    limit: Duration,
    mut done: impl FnMut(&[u8], &mut ModbusIo) -> bool,
) -> Option<u64> {
    let start = Instant::now();
    let mut tick = 0;
    while start.elapsed() < limit {
        tick += 1;
        io.latch_inputs(tick, image);
        io.publish_outputs(tick, image);
        if done(image, io) {
            return Some(tick);
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    None
}

fn sim_runtime() -> tokio::runtime::Runtime {
    tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()
        .expect("runtime")
}

#[test]
fn inputs_are_latched_and_changed_outputs_written() {
    latch_and_write(true);
}

#[test]
fn inputs_are_latched_and_changed_outputs_written_on_one_connection() {
    latch_and_write(false);
}

fn latch_and_write(write_connection: bool) {
    let rt = sim_runtime();
    let sim = rt
        .block_on(RemoteIoSim::start("127.0.0.1:0".parse().expect("addr")))
        .expect("sim");
    {
        let mut s = sim.state();
        s.discrete[0] = true;
        s.discrete[9] = true;
        s.discrete[31] = true;
        s.input_regs[10] = 0x1234;
    }
    let mut cfg = device(sim.addr());
    cfg.write_connection = write_connection;
    let mut io = ModbusIo::start(&[cfg]).expect("driver");
    let mut image = vec![0u8; PACKETS_LEN];
    let healthy: Signal = "I100K0".parse().expect("signal");
    tick_until(&mut io, &mut image, Duration::from_secs(5), |img, _| {
        healthy.read(img) == 1 && img[4] == 0x34
    })
    .expect("inputs arrive");
    assert_eq!(&image[0..6], &[0x01, 0x02, 0x00, 0x80, 0x34, 0x12]);
    assert_eq!(image[6], 0, "bytes outside the mappings stay untouched");

    // The logic sets U4A3 (coil 103) and W5A0..1 (holding register 7).
    image[16] = 0b1000;
    image[20] = 0xCD;
    image[21] = 0xAB;
    tick_until(&mut io, &mut image, Duration::from_secs(5), |_, _| {
        sim.state().holding[7] == 0xABCD && sim.state().coils[103]
    })
    .expect("outputs written");
    let s = sim.state();
    assert_eq!(s.coils[100..132].iter().filter(|b| **b).count(), 1);
    assert!(s.coils[103]);
    // The first publish writes both mappings once; nothing is written while nothing changes.
    let writes_before = s.writes.len();
    drop(s);
    tick_until(&mut io, &mut image, Duration::from_millis(30), |_, _| false);
    assert_eq!(sim.state().writes.len(), writes_before);
    assert!(io.take_alarms().is_empty());
}

#[test]
fn killed_device_raises_alarm_takes_fail_state_and_recovers() {
    let rt = sim_runtime();
    let mut sim = rt
        .block_on(RemoteIoSim::start("127.0.0.1:0".parse().expect("addr")))
        .expect("sim");
    sim.state().discrete[1] = true;
    sim.state().input_regs[10] = 0x0101;
    let mut io = ModbusIo::start(&[device(sim.addr())]).expect("driver");
    let mut image = vec![0u8; PACKETS_LEN];
    tick_until(&mut io, &mut image, Duration::from_secs(5), |img, _| {
        img[0] == 2
    })
    .expect("healthy first");
    assert!(io.take_alarms().is_empty());

    sim.kill();
    let mut alarms = Vec::new();
    let ticks = tick_until(&mut io, &mut image, Duration::from_secs(5), |_, io| {
        alarms.extend(io.take_alarms());
        !alarms.is_empty()
    })
    .expect("alarm raised");
    assert!(
        ticks <= 51,
        "alarm within alarm_ticks (50) + 1, took {ticks}"
    );
    assert_eq!(alarms[0].device, "rio1");
    assert!(!alarms[0].cleared);
    assert_eq!(&image[0..6], &[0, 0, 0, 0, 0xAA, 0xAA], "fail state");
    assert_eq!(image[100 * 4 + 128] & 1, 0, "healthy bit cleared");

    rt.block_on(sim.restart()).expect("restart");
    let mut cleared = Vec::new();
    tick_until(&mut io, &mut image, Duration::from_secs(5), |_, io| {
        cleared.extend(io.take_alarms());
        cleared.iter().any(|a| a.cleared)
    })
    .expect("alarm cleared after reconnect");
    tick_until(&mut io, &mut image, Duration::from_secs(2), |img, _| {
        img[0] == 2
    })
    .expect("inputs again");
    assert_eq!(image[100 * 4 + 128] & 1, 1);
}

#[test]
fn slow_and_mute_devices_time_out_into_the_alarm() {
    let rt = sim_runtime();
    let sim = rt
        .block_on(RemoteIoSim::start("127.0.0.1:0".parse().expect("addr")))
        .expect("sim");
    sim.state().discrete[0] = true;
    let mut io = ModbusIo::start(&[device(sim.addr())]).expect("driver");
    let mut image = vec![0u8; PACKETS_LEN];
    tick_until(&mut io, &mut image, Duration::from_secs(5), |img, _| {
        img[0] == 1
    })
    .expect("healthy first");

    sim.set_delay(Duration::from_millis(250)); // timeout is 80 ms
    let mut alarms = Vec::new();
    tick_until(&mut io, &mut image, Duration::from_secs(5), |_, io| {
        alarms.extend(io.take_alarms());
        !alarms.is_empty()
    })
    .expect("slow answers raise the alarm");
    assert_eq!(image[0], 0);
    sim.set_delay(Duration::ZERO);
    tick_until(&mut io, &mut image, Duration::from_secs(5), |img, _| {
        img[0] == 1
    })
    .expect("recovers");

    sim.set_mute(true);
    alarms.clear();
    tick_until(&mut io, &mut image, Duration::from_secs(5), |_, io| {
        alarms.extend(io.take_alarms());
        alarms.iter().any(|a| !a.cleared)
    })
    .expect("a mute device raises the alarm");
    assert_eq!(image[0], 0);
}

#[test]
fn garbage_frames_never_panic_and_raise_the_alarm() {
    let rt = sim_runtime();
    let listener = rt
        .block_on(tokio::net::TcpListener::bind("127.0.0.1:0"))
        .expect("bind");
    let addr = listener.local_addr().expect("addr");
    rt.spawn(async move {
        use tokio::io::{AsyncReadExt, AsyncWriteExt};
        let mut seed = 0x1234_5678u32;
        while let Ok((mut s, _)) = listener.accept().await {
            let mut buf = [0u8; 260];
            while let Ok(n) = s.read(&mut buf).await {
                if n == 0 {
                    break;
                }
                // An MBAP-looking header with the right transaction id, then random noise.
                let mut reply = vec![buf[0], buf[1], 0, 0, 0, 9, 1];
                for _ in 0..8 {
                    seed = seed.wrapping_mul(1_103_515_245).wrapping_add(12345);
                    reply.push((seed >> 16) as u8);
                }
                if s.write_all(&reply).await.is_err() {
                    break;
                }
            }
        }
    });
    let mut io = ModbusIo::start(&[device(addr)]).expect("driver");
    let mut image = vec![0u8; PACKETS_LEN];
    image[16] = 0xFF;
    let mut alarms = Vec::new();
    tick_until(&mut io, &mut image, Duration::from_secs(5), |_, io| {
        alarms.extend(io.take_alarms());
        !alarms.is_empty()
    })
    .expect("garbage raises the alarm");
    assert_eq!(&image[0..6], &[0, 0, 0, 0, 0xAA, 0xAA]);
    assert!(!io.is_healthy("rio1"));
}

#[test]
fn disconnect_during_a_write_rewrites_only_commanded_values() {
    disconnect_during_a_write(true);
}

#[test]
fn disconnect_during_a_write_on_one_connection_rewrites_only_commanded_values() {
    disconnect_during_a_write(false);
}

fn disconnect_during_a_write(write_connection: bool) {
    let rt = sim_runtime();
    let mut sim = rt
        .block_on(RemoteIoSim::start("127.0.0.1:0".parse().expect("addr")))
        .expect("sim");
    let mut cfg = device(sim.addr());
    cfg.write_connection = write_connection;
    let mut io = ModbusIo::start(&[cfg]).expect("driver");
    let mut image = vec![0u8; PACKETS_LEN];
    tick_until(&mut io, &mut image, Duration::from_secs(5), |_, io| {
        io.is_healthy("rio1")
    })
    .expect("healthy");
    // Slow writes, then kill the device while a write is in flight.
    sim.set_delay(Duration::from_millis(30));
    image[16] = 0b0001;
    io.publish_outputs(1, &image);
    std::thread::sleep(Duration::from_millis(10));
    sim.kill();
    sim.set_delay(Duration::ZERO);
    {
        let mut s = sim.state();
        s.writes.clear();
        s.coils.iter_mut().for_each(|c| *c = false);
        s.holding.iter_mut().for_each(|h| *h = 0);
    }
    // The logic changes its mind while the device is away.
    image[16] = 0b0110;
    tick_until(&mut io, &mut image, Duration::from_millis(50), |_, _| false);
    rt.block_on(sim.restart()).expect("restart");
    tick_until(&mut io, &mut image, Duration::from_secs(5), |_, _| {
        sim.state().coils[101]
    })
    .expect("rewritten after reconnect");
    let s = sim.state();
    let on: Vec<usize> = (100..132).filter(|&i| s.coils[i]).collect();
    assert_eq!(on, [101, 102], "exactly the commanded bits");
    assert_eq!(
        s.holding[7], 0,
        "the register holds what the logic commanded (0)"
    );
    assert!(
        s.writes
            .iter()
            .all(|&(f, a, _)| (f == 15 && a == 100) || (f == 16 && a == 7)),
        "{:?}",
        s.writes
    );
}

#[test]
fn a_write_does_not_wait_behind_a_read_on_the_wire() {
    assert_eq!(reads_pending_when_written(true), 1);
}

#[test]
fn on_one_connection_a_write_waits_for_the_read_on_the_wire() {
    assert_eq!(reads_pending_when_written(false), 0);
}

/// Publishes an output change while a slow read is on the wire; returns how many reads the device
/// still had pending when it applied the write.
fn reads_pending_when_written(write_connection: bool) -> usize {
    let rt = sim_runtime();
    let sim = rt
        .block_on(RemoteIoSim::start("127.0.0.1:0".parse().expect("addr")))
        .expect("sim");
    let mut cfg = device(sim.addr());
    cfg.write_connection = write_connection;
    cfg.timeout = Duration::from_millis(2000);
    let mut io = ModbusIo::start(&[cfg]).expect("driver");
    let mut image = vec![0u8; PACKETS_LEN];
    tick_until(&mut io, &mut image, Duration::from_secs(5), |_, io| {
        io.is_healthy("rio1")
    })
    .expect("healthy");
    // Every read now takes 300 ms; wait until one is on the wire, then command an output.
    sim.set_read_delay(Duration::from_millis(300));
    let start = Instant::now();
    while sim.state().reads_pending == 0 && start.elapsed() < Duration::from_secs(2) {
        std::thread::sleep(Duration::from_millis(1));
    }
    assert_eq!(sim.state().reads_pending, 1, "a read is on the wire");
    image[16] = 0b0100;
    io.publish_outputs(1, &image);
    let start = Instant::now();
    while !sim.state().coils[102] && start.elapsed() < Duration::from_secs(3) {
        std::thread::sleep(Duration::from_millis(1));
    }
    let s = sim.state();
    assert!(s.coils[102], "written");
    s.reads_pending_at_last_write
}

#[test]
fn no_write_happens_before_the_logic_publishes() {
    let rt = sim_runtime();
    let sim = rt
        .block_on(RemoteIoSim::start("127.0.0.1:0".parse().expect("addr")))
        .expect("sim");
    let mut io = ModbusIo::start(&[device(sim.addr())]).expect("driver");
    let mut image = vec![0u8; PACKETS_LEN];
    let start = Instant::now();
    while start.elapsed() < Duration::from_millis(100) && !io.is_healthy("rio1") {
        io.latch_inputs(0, &mut image);
        std::thread::sleep(Duration::from_millis(1));
    }
    assert!(io.is_healthy("rio1"));
    assert!(sim.state().writes.is_empty());
}

#[test]
fn safe_state_writes_the_safe_values() {
    let rt = sim_runtime();
    let sim = rt
        .block_on(RemoteIoSim::start("127.0.0.1:0".parse().expect("addr")))
        .expect("sim");
    let mut io = ModbusIo::start(&[device(sim.addr())]).expect("driver");
    let mut image = vec![0u8; PACKETS_LEN];
    image[16] = 0xFF;
    tick_until(&mut io, &mut image, Duration::from_secs(5), |_, _| {
        sim.state().coils[100]
    })
    .expect("written");
    io.safe_state();
    let s = sim.state();
    assert!(s.coils[100..132].iter().all(|c| !c));
    assert_eq!(s.holding[7], 0x5555);
}

#[test]
fn a_dead_device_does_not_hold_up_a_live_one() {
    let rt = sim_runtime();
    let mut a = rt
        .block_on(RemoteIoSim::start("127.0.0.1:0".parse().expect("addr")))
        .expect("sim a");
    let b = rt
        .block_on(RemoteIoSim::start("127.0.0.1:0".parse().expect("addr")))
        .expect("sim b");
    let mut second = device(b.addr());
    second.name = "rio2".into();
    second.healthy = Some("I100K1".parse().expect("signal"));
    second.inputs = vec![ModbusMapping {
        range: ByteRange { start: 32, len: 4 },
        area: ModbusArea::DiscreteInputs,
        address: 0,
        fail: 0,
    }];
    second.outputs = vec![ModbusMapping {
        range: ByteRange { start: 48, len: 4 },
        area: ModbusArea::Coils,
        address: 0,
        fail: 0,
    }];
    let mut io = ModbusIo::start(&[device(a.addr()), second]).expect("driver");
    let mut image = vec![0u8; PACKETS_LEN];
    tick_until(&mut io, &mut image, Duration::from_secs(5), |_, io| {
        io.is_healthy("rio1") && io.is_healthy("rio2")
    })
    .expect("both healthy");
    a.kill();
    let mut alarms = Vec::new();
    tick_until(&mut io, &mut image, Duration::from_secs(5), |_, io| {
        alarms.extend(io.take_alarms());
        !alarms.is_empty()
    })
    .expect("rio1 lost");
    assert_eq!(
        alarms.iter().map(|a| a.device.as_str()).collect::<Vec<_>>(),
        ["rio1"]
    );
    // rio2 keeps exchanging: an input change arrives and an output change is written.
    b.state().discrete[5] = true;
    image[48] = 0x80;
    tick_until(&mut io, &mut image, Duration::from_secs(5), |img, _| {
        img[32] == 0x20 && b.state().coils[7]
    })
    .expect("rio2 still runs");
    assert!(io.is_healthy("rio2"));
    assert!(!io.is_healthy("rio1"));
    assert_eq!(
        image[128 + 400] & 0b11,
        0b10,
        "healthy bits: rio1 0, rio2 1"
    );
}
