//! Benchmarks of the Modbus TCP path on loopback.
//!
//! 1. **Input → output latency** (printed before the criterion groups): a simulated remote-I/O device,
//!    the client driver, and a 1 ms scan whose "logic" copies input byte W0A0 to output byte W4A0.
//!    Each of 10,000 events flips a device input at a pseudo-random phase of the tick and measures
//!    the time until the device applied the dependent coil write. The client polls back to back
//!    (`poll_us = 0`). The p99 is compared with
//!    1 tick + 2 round trips, the round trip being the median of 1,000 plain read requests.
//! 2. **Scan overhead** (criterion): one tick = latch + a fixed scan workload + publish, with the
//!    simulated I/O and with the Modbus client (default 1 ms poll) and the HMI server active, an
//!    HMI client reading 100 registers every millisecond.
//!
//! `FIELDBUS_BENCH_EVENTS` overrides the number of latency events (default 10,000);
//! `FIELDBUS_BENCH_FIFO=1` runs the scan thread as SCHED_FIFO 80 (as `ncplc run` does when it may).

use std::hint::black_box;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group};
use fieldbus::map::{ByteRange, HmiConfig, HmiWindow, ModbusArea, ModbusDevice, ModbusMapping};
use fieldbus::modbus::client::ModbusIo;
use fieldbus::modbus::server::HmiIo;
use fieldbus::modbus::sim::RemoteIoSim;
use packets::{PACKETS_LEN, Packet, PacketIo};
use tokio_modbus::client::Reader;

const TICK: Duration = Duration::from_millis(1);

fn device(addr: std::net::SocketAddr, poll: Duration) -> ModbusDevice {
    ModbusDevice {
        name: "rio1".into(),
        address: addr,
        unit: 1,
        timeout: Duration::from_millis(50),
        poll,
        write_connection: true,
        alarm_ticks: 50,
        reconnect_min: Duration::from_millis(10),
        reconnect_max: Duration::from_millis(100),
        healthy: Some("I100K0".parse().expect("signal")),
        inputs: vec![ModbusMapping {
            range: ByteRange { start: 0, len: 4 },
            area: ModbusArea::DiscreteInputs,
            address: 0,
            fail: 0,
        }],
        outputs: vec![ModbusMapping {
            range: ByteRange { start: 16, len: 4 },
            area: ModbusArea::Coils,
            address: 0,
            fail: 0,
        }],
    }
}

fn percentile(sorted: &[Duration], p: f64) -> Duration {
    sorted[((sorted.len() as f64 - 1.0) * p).round() as usize]
}

fn latency_report() {
    let events: usize = std::env::var("FIELDBUS_BENCH_EVENTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(10_000);
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()
        .expect("runtime");
    let sim = rt
        .block_on(RemoteIoSim::start("127.0.0.1:0".parse().expect("addr")))
        .expect("sim");
    let addr = sim.addr();

    // Round trip of one plain read.
    let mut rtts: Vec<Duration> = rt.block_on(async {
        let mut c = tokio_modbus::client::tcp::connect_slave(addr, tokio_modbus::Slave(1))
            .await
            .expect("connect");
        let mut v = Vec::new();
        for _ in 0..1000 {
            let t = Instant::now();
            let _ = c.read_discrete_inputs(0, 32).await;
            v.push(t.elapsed());
        }
        v
    });
    rtts.sort();
    let rtt = percentile(&rtts, 0.5);

    // The scan thread: latch, copy W0A0 → W4A0, publish, every 1 ms on an absolute schedule.
    let stop = Arc::new(AtomicBool::new(false));
    let scan = {
        let stop = stop.clone();
        std::thread::spawn(move || {
            if std::env::var("FIELDBUS_BENCH_FIFO").is_ok_and(|v| v == "1") {
                let param = libc::sched_param { sched_priority: 80 };
                // SAFETY: plain syscall on the calling thread with a valid parameter block.
                let rc = unsafe { libc::sched_setscheduler(0, libc::SCHED_FIFO, &param) };
                println!(
                    "scan thread SCHED_FIFO 80: {}",
                    if rc == 0 { "on" } else { "refused" }
                );
            }
            let mut io = ModbusIo::start(&[device(addr, Duration::ZERO)]).expect("driver");
            let mut image = vec![0u8; PACKETS_LEN];
            let mut next = Instant::now();
            let mut tick = 0;
            while !stop.load(Ordering::Relaxed) {
                tick += 1;
                io.latch_inputs(tick, &mut image);
                image[16] = image[0];
                io.publish_outputs(tick, &image);
                next += TICK;
                let now = Instant::now();
                if next > now {
                    std::thread::sleep(next - now);
                } else {
                    next = now;
                }
            }
        })
    };
    // Wait until the loop runs (first write of the initial outputs).
    let start = Instant::now();
    while sim.state().last_write.is_none() && start.elapsed() < Duration::from_secs(5) {
        std::thread::sleep(Duration::from_millis(1));
    }
    let mut seed = 0x2545_F491u32;
    let mut lat = Vec::with_capacity(events);
    let mut lost = 0;
    for i in 0..events {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        std::thread::sleep(Duration::from_micros(u64::from(seed % 1000)));
        let want = i % 2 == 0;
        let t0 = {
            let mut s = sim.state();
            s.discrete[0] = want;
            Instant::now()
        };
        let deadline = t0 + Duration::from_millis(200);
        loop {
            let (coil, at) = {
                let s = sim.state();
                (s.coils[0], s.last_write)
            };
            if coil == want {
                if let Some(at) = at {
                    lat.push(at.saturating_duration_since(t0));
                }
                break;
            }
            if Instant::now() > deadline {
                lost += 1;
                break;
            }
            std::thread::sleep(Duration::from_micros(50));
        }
    }
    stop.store(true, Ordering::Relaxed);
    let _ = scan.join();
    lat.sort();
    let target = TICK + 2 * rtt;
    println!(
        "modbus input→output latency over {} events (tick 1 ms, loopback, {} lost):",
        lat.len(),
        lost
    );
    println!(
        "  round trip median {:?} (p99 {:?}); target 1 tick + 2 RT = {:?}",
        rtt,
        percentile(&rtts, 0.99),
        target
    );
    if !lat.is_empty() {
        let p99 = percentile(&lat, 0.99);
        println!(
            "  p50 {:?}  p90 {:?}  p99 {:?}  max {:?}  → p99 {} target",
            percentile(&lat, 0.5),
            percentile(&lat, 0.9),
            p99,
            lat[lat.len() - 1],
            if p99 <= target { "meets" } else { "MISSES" }
        );
    }
}

/// The simulated-I/O stand-in: copies 8 input bytes in and nothing out, like the runtime's sim.
struct SimIo {
    inputs: [u8; 8],
}

impl PacketIo for SimIo {
    fn name(&self) -> &str {
        "sim"
    }
    fn latch_inputs(&mut self, _tick: u64, packets: &mut [u8]) {
        packets[0..8].copy_from_slice(&self.inputs);
    }
    fn publish_outputs(&mut self, _tick: u64, packets: &[u8]) {
        black_box(&packets[16..24]);
    }
}

/// A fixed scan workload: 2,000 bit operations over K, like a mid-sized PLC program.
fn scan(image: &mut [u8]) {
    let k = Packet::K.offset();
    for i in 0..2000usize {
        let a = image[k + (i * 7) % 1024];
        let b = image[(i * 13) % 128];
        image[k + (i * 11) % 1024] = a ^ (b & 1);
    }
}

fn scan_overhead(c: &mut Criterion) {
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()
        .expect("runtime");
    let sim_dev = rt
        .block_on(RemoteIoSim::start("127.0.0.1:0".parse().expect("addr")))
        .expect("sim");
    let mut g = c.benchmark_group("tick");
    let mut image = vec![0u8; PACKETS_LEN];

    let mut sim = SimIo {
        inputs: [1, 2, 3, 4, 5, 6, 7, 8],
    };
    let mut tick = 0u64;
    g.bench_function("latch_publish/sim", |b| {
        b.iter(|| {
            tick += 1;
            sim.latch_inputs(tick, &mut image);
            sim.publish_outputs(tick, &image);
        })
    });
    g.bench_function("latch_scan_publish/sim", |b| {
        b.iter(|| {
            tick += 1;
            sim.latch_inputs(tick, &mut image);
            scan(&mut image);
            sim.publish_outputs(tick, &image);
        })
    });

    let client =
        ModbusIo::start(&[device(sim_dev.addr(), Duration::from_millis(1))]).expect("driver");
    let hmi_cfg = HmiConfig {
        bind: "127.0.0.1:0".parse().expect("addr"),
        holding: vec![HmiWindow {
            start: Packet::K.offset() + 800,
            len: 16,
        }],
    };
    let mut io = HmiIo::start(Box::new(client), &hmi_cfg).expect("hmi");
    // Keep an HMI client polling the server while measuring.
    let hmi_addr = io.local_addr();
    let polling = Arc::new(AtomicBool::new(true));
    let p = polling.clone();
    rt.spawn(async move {
        if let Ok(mut c) =
            tokio_modbus::client::tcp::connect_slave(hmi_addr, tokio_modbus::Slave(1)).await
        {
            while p.load(Ordering::Relaxed) {
                let _ = c.read_input_registers(0, 100).await;
                tokio::time::sleep(Duration::from_millis(1)).await;
            }
        }
    });
    g.bench_function("latch_publish/modbus+hmi", |b| {
        b.iter(|| {
            tick += 1;
            io.latch_inputs(tick, &mut image);
            image[16] = image[0];
            io.publish_outputs(tick, &image);
        })
    });
    g.bench_function("latch_scan_publish/modbus+hmi", |b| {
        b.iter(|| {
            tick += 1;
            io.latch_inputs(tick, &mut image);
            scan(&mut image);
            image[16] = image[0];
            io.publish_outputs(tick, &image);
        })
    });
    g.finish();
    polling.store(false, Ordering::Relaxed);
}

criterion_group!(benches, scan_overhead);

fn main() {
    latency_report();
    benches();
    Criterion::default().configure_from_args().final_summary();
}
