//! Tests of the scan thread's direct writes on the write connection (`fieldbus::modbus::writer`):
//! an idle link takes the write from the scan itself, a busy one leaves it to the I/O task in
//! order, transaction ids stay consecutive across both senders, and a refused write raises the
//! alarm. Everything runs on 127.0.0.1 with bounded waits.

use std::net::SocketAddr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use fieldbus::map::{ByteRange, ModbusArea, ModbusDevice, ModbusMapping};
use fieldbus::modbus::client::ModbusIo;
use fieldbus::modbus::sim::RemoteIoSim;
use packets::{PACKETS_LEN, PacketIo};
use tokio::io::{AsyncReadExt, AsyncWriteExt};

fn device(addr: SocketAddr) -> ModbusDevice {
    ModbusDevice {
        name: "rio1".into(),
        address: addr,
        unit: 1,
        timeout: Duration::from_millis(500),
        poll: Duration::from_micros(500),
        write_connection: true,
        direct_write: true,
        alarm_ticks: 200,
        reconnect_min: Duration::from_millis(10),
        reconnect_max: Duration::from_millis(40),
        healthy: None,
        inputs: vec![ModbusMapping {
            range: ByteRange { start: 0, len: 2 },
            area: ModbusArea::DiscreteInputs,
            address: 0,
            fail: 0,
        }],
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
                fail: 0,
            },
        ],
    }
}

fn runtime() -> tokio::runtime::Runtime {
    tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()
        .expect("runtime")
}

/// Runs 1 ms ticks until `done` holds; false after `limit`.
fn tick_until(
    io: &mut ModbusIo,
    image: &mut [u8],
    limit: Duration,
    mut done: impl FnMut(&mut ModbusIo) -> bool,
) -> bool {
    let start = Instant::now();
    let mut tick = 0;
    while start.elapsed() < limit {
        tick += 1;
        io.latch_inputs(tick, image);
        io.publish_outputs(tick, image);
        if done(io) {
            return true;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    false
}

#[test]
fn an_idle_link_sends_from_the_scan_and_a_busy_one_leaves_the_write_to_the_task() {
    let rt = runtime();
    let sim = rt
        .block_on(RemoteIoSim::start("127.0.0.1:0".parse().expect("addr")))
        .expect("sim");
    let mut cfg = device(sim.addr());
    cfg.outputs.truncate(1);
    let mut io = ModbusIo::start(&[cfg]).expect("driver");
    let mut image = vec![0u8; PACKETS_LEN];
    assert!(tick_until(
        &mut io,
        &mut image,
        Duration::from_secs(5),
        |io| { io.is_healthy("rio1") && io.outputs_acknowledged() }
    ));
    let before = io.direct_writes("rio1");

    // Idle link: publish_outputs itself puts the write on the wire.
    image[16] = 0b0001;
    io.publish_outputs(1, &image);
    assert_eq!(io.direct_writes("rio1"), before + 1);
    assert!(tick_until(
        &mut io,
        &mut image,
        Duration::from_secs(5),
        |io| { io.outputs_acknowledged() }
    ));
    assert!(sim.state().coils[100]);

    // A slow write in flight: the next change waits for its answer and goes from the task.
    sim.set_delay(Duration::from_millis(30));
    let writes = sim.state().writes.len();
    image[16] = 0b0010;
    io.publish_outputs(2, &image);
    image[16] = 0b0100;
    io.publish_outputs(3, &image);
    assert_eq!(io.direct_writes("rio1"), before + 2);
    assert!(tick_until(
        &mut io,
        &mut image,
        Duration::from_secs(5),
        |io| { io.outputs_acknowledged() }
    ));
    let s = sim.state();
    assert_eq!(&s.writes[writes..], &[(15, 100, 32), (15, 100, 32)]);
    let on: Vec<usize> = (100..132).filter(|&i| s.coils[i]).collect();
    assert_eq!(on, [102], "the newest commanded value, applied last");
    assert!(io.take_alarms().is_empty());
}

#[test]
fn with_direct_write_off_every_write_goes_from_the_task() {
    let rt = runtime();
    let sim = rt
        .block_on(RemoteIoSim::start("127.0.0.1:0".parse().expect("addr")))
        .expect("sim");
    let mut cfg = device(sim.addr());
    cfg.direct_write = false;
    let mut io = ModbusIo::start(&[cfg]).expect("driver");
    let mut image = vec![0u8; PACKETS_LEN];
    for k in 1..=3u8 {
        image[16] = k;
        assert!(tick_until(
            &mut io,
            &mut image,
            Duration::from_secs(5),
            |io| { io.outputs_acknowledged() }
        ));
        assert_eq!(sim.state().coils[100..102], [k & 1 == 1, k & 2 == 2]);
    }
    assert_eq!(io.direct_writes("rio1"), 0);
}

/// One write request as a fake device saw it: (transaction id, function, address, data bytes).
type Seen = (u16, u8, u16, Vec<u8>);

/// A device that answers every write (and nothing else) on any connection, logging each request;
/// with `refuse` set it answers with exception 4 instead.
fn fake_device(
    rt: &tokio::runtime::Runtime,
) -> (SocketAddr, Arc<Mutex<Vec<Seen>>>, Arc<AtomicBool>) {
    let listener = rt
        .block_on(tokio::net::TcpListener::bind("127.0.0.1:0"))
        .expect("bind");
    let addr = listener.local_addr().expect("addr");
    let log = Arc::new(Mutex::new(Vec::new()));
    let refuse = Arc::new(AtomicBool::new(false));
    let (l, r) = (log.clone(), refuse.clone());
    rt.spawn(async move {
        while let Ok((mut s, _)) = listener.accept().await {
            let (log, refuse) = (l.clone(), r.clone());
            tokio::spawn(async move {
                let mut buf = Vec::new();
                let mut chunk = [0u8; 512];
                while let Ok(n) = s.read(&mut chunk).await {
                    if n == 0 {
                        break;
                    }
                    buf.extend_from_slice(&chunk[..n]);
                    while buf.len() >= 7 {
                        let total = 6 + usize::from(u16::from_be_bytes([buf[4], buf[5]]));
                        if buf.len() < total {
                            break;
                        }
                        let f: Vec<u8> = buf.drain(..total).collect();
                        let tid = u16::from_be_bytes([f[0], f[1]]);
                        log.lock().expect("log").push((
                            tid,
                            f[7],
                            u16::from_be_bytes([f[8], f[9]]),
                            f.get(13..).unwrap_or_default().to_vec(),
                        ));
                        let reply = if refuse.load(Ordering::SeqCst) {
                            vec![f[0], f[1], 0, 0, 0, 3, f[6], f[7] | 0x80, 4]
                        } else {
                            let mut r = vec![f[0], f[1], 0, 0, 0, 6];
                            r.extend_from_slice(&f[6..12]);
                            r
                        };
                        if s.write_all(&reply).await.is_err() {
                            return;
                        }
                    }
                }
            });
        }
    });
    (addr, log, refuse)
}

#[test]
fn transaction_ids_stay_consecutive_across_scan_and_task_sends() {
    let rt = runtime();
    let (addr, log, _) = fake_device(&rt);
    let mut cfg = device(addr);
    cfg.inputs.clear(); // the fake device answers writes only
    let mut io = ModbusIo::start(&[cfg]).expect("driver");
    let mut image = vec![0u8; PACKETS_LEN];
    for k in 1..=6u8 {
        image[16] = k;
        image[20] = k;
        let want = 2 * usize::from(k);
        assert!(
            tick_until(&mut io, &mut image, Duration::from_secs(5), |io| {
                io.outputs_acknowledged() && log.lock().expect("log").len() >= want
            }),
            "change {k} written"
        );
    }
    let seen = log.lock().expect("log").clone();
    let expected: Vec<Seen> = (1..=6u8)
        .flat_map(|k| {
            let t = 2 * u16::from(k - 1);
            [(t, 15, 100, vec![k, 0, 0, 0]), (t + 1, 16, 7, vec![0, k])]
        })
        .collect();
    assert_eq!(seen, expected);
    assert!(io.direct_writes("rio1") >= 1, "the scan sent some itself");
}

#[test]
fn a_refused_write_raises_the_alarm() {
    let rt = runtime();
    let (addr, _, refuse) = fake_device(&rt);
    refuse.store(true, Ordering::SeqCst);
    let mut cfg = device(addr);
    cfg.inputs.clear();
    let mut io = ModbusIo::start(&[cfg]).expect("driver");
    let mut image = vec![0u8; PACKETS_LEN];
    image[16] = 1;
    let mut alarms = Vec::new();
    assert!(tick_until(
        &mut io,
        &mut image,
        Duration::from_secs(5),
        |io| {
            alarms.extend(io.take_alarms());
            !alarms.is_empty()
        }
    ));
    assert_eq!(alarms[0].message, "answered with a Modbus exception");
    assert!(!alarms[0].cleared);
}
