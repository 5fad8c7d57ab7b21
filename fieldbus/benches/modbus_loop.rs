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
//! The latency loop runs twice: reads and writes on one connection (`write_connection = false`),
//! then with writes on their own connection (the default). Each run also prints how late the scan
//! thread woke for its ticks (the loop's pure scheduling jitter) and how many of the events over
//! the target saw a scan tick wake later than the 2 round trips the target leaves.
//!
//! First it prints the cost of one thread hand-off (a plain thread waking a parked tokio task).
//!
//! `FIELDBUS_BENCH_EVENTS` overrides the number of latency events (default 10,000);
//! `FIELDBUS_BENCH_FIFO=1` runs the scan thread as SCHED_FIFO 80 (as `ncplc run` does when it may;
//! the driver moves its I/O thread to SCHED_FIFO 70 at the first latch, `fieldbus::rt`) and the
//! simulated device's thread as SCHED_FIFO 70;
//! `FIELDBUS_BENCH_DIRECT=0` leaves every write to the I/O task (`direct_write = false`);
//! `FIELDBUS_BENCH_IO_OTHER=1` puts the driver's I/O thread back to SCHED_OTHER after the first
//! latch (for comparison);
//! `FIELDBUS_BENCH_SLACK=1` sets the scan thread's timer slack to 1 ns (Linux default 50 µs).
//! `FIELDBUS_BENCH_PIN="scan=0,io=1,device=1"` pins the scan thread, the driver's I/O threads
//! (`ModbusIo::start_pinned`, as io.toml `[affinity] io_cpus` does) and the simulated device's
//! thread to those CPUs (any subset of the three keys).
//! `cargo bench -p fieldbus --bench modbus_loop -- latency-only` skips the criterion groups.

use std::hint::black_box;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group};
use fieldbus::map::{
    ByteRange, HmiConfig, HmiLimits, HmiWindow, ModbusArea, ModbusDevice, ModbusMapping,
};
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
        direct_write: std::env::var("FIELDBUS_BENCH_DIRECT").map_or(true, |v| v != "0"),
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

fn env_flag(name: &str) -> bool {
    std::env::var(name).is_ok_and(|v| v == "1")
}

/// The CPU `FIELDBUS_BENCH_PIN` gives for `who` (`scan`, `io` or `device`).
fn pin_for(who: &str) -> Option<usize> {
    let spec = std::env::var("FIELDBUS_BENCH_PIN").ok()?;
    spec.split(',').find_map(|kv| {
        let (k, v) = kv.split_once('=')?;
        (k.trim() == who).then(|| v.trim().parse().ok())?
    })
}

/// Every scan tick of the latency loop: when it was due, when it woke, the input bit it latched.
struct TickLog {
    /// (due, woke, latched W0A0 bit 0) of every tick, in order.
    ticks: Vec<(Instant, Instant, bool)>,
    /// Writes the scan thread put on the wire itself.
    direct: u64,
    /// Time spent in `publish_outputs` on ticks whose output changed / did not change.
    publish_changed: Vec<Duration>,
    publish_same: Vec<Duration>,
    /// The SCHED_FIFO priority the driver's I/O thread took, if any.
    io_priority: Option<i32>,
}

/// Where one event's time went, from the tick log.
struct Breakdown {
    /// Event → wake of the tick that latched the change.
    to_latch: Duration,
    /// Wake of the latching tick → the device applied the write (latch, publish, wake the I/O
    /// task, write request on the wire).
    write_path: Duration,
    /// Wake-to-wake gap before the latching tick (1 tick without scheduling noise).
    gap: Duration,
    /// A tick woke after the event but still latched the old value (the read was not back yet).
    missed_tick: bool,
    /// Event → wake of the first tick after it (whether or not that tick latched the change).
    lead: Duration,
}

impl TickLog {
    /// Splits the event at `t0` (input set to `want`) applied at `at`; None when no tick latched it.
    fn breakdown(&self, t0: Instant, at: Instant, want: bool) -> Option<Breakdown> {
        let first = self.ticks.partition_point(|(_, woke, _)| *woke < t0);
        let k = first + self.ticks[first..].iter().position(|t| t.2 == want)?;
        let woke = self.ticks[k].1;
        let prev = self.ticks.get(k.checked_sub(1)?)?.1;
        Some(Breakdown {
            to_latch: woke.saturating_duration_since(t0),
            write_path: at.saturating_duration_since(woke),
            gap: woke.saturating_duration_since(prev),
            missed_tick: k > first,
            lead: self.ticks[first].1.saturating_duration_since(t0),
        })
    }
}

/// Puts the driver's I/O threads (named `ncplc-modbus`) back to SCHED_OTHER, undoing
/// `fieldbus::rt` for the comparison `FIELDBUS_BENCH_IO_OTHER=1` asks for.
fn io_threads_to_sched_other() {
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else {
        return;
    };
    for task in tasks.flatten() {
        let comm = std::fs::read_to_string(task.path().join("comm")).unwrap_or_default();
        let tid = task
            .file_name()
            .to_str()
            .and_then(|t| t.parse::<libc::pid_t>().ok());
        if let (true, Some(tid)) = (comm.starts_with("ncplc-modbus"), tid) {
            let param = libc::sched_param { sched_priority: 0 };
            // SAFETY: plain syscall on a thread of this process with a valid parameter block.
            unsafe { libc::sched_setscheduler(tid, libc::SCHED_OTHER, &param) };
        }
    }
}

/// The scan thread of the latency loop: latch, copy W0A0 → W4A0, publish, every 1 ms on an
/// absolute schedule; returns how late each tick woke.
fn scan_loop(addr: std::net::SocketAddr, write_connection: bool, stop: Arc<AtomicBool>) -> TickLog {
    if env_flag("FIELDBUS_BENCH_FIFO") {
        let param = libc::sched_param { sched_priority: 80 };
        // SAFETY: plain syscall on the calling thread with a valid parameter block.
        let rc = unsafe { libc::sched_setscheduler(0, libc::SCHED_FIFO, &param) };
        println!(
            "  scan thread SCHED_FIFO 80: {}",
            if rc == 0 { "on" } else { "refused" }
        );
    }
    if env_flag("FIELDBUS_BENCH_SLACK") {
        // SAFETY: plain prctl on the calling thread; 1 ns timer slack instead of the default 50 µs.
        let rc = unsafe { libc::prctl(libc::PR_SET_TIMERSLACK, 1 as libc::c_ulong, 0, 0, 0) };
        println!(
            "  scan thread timer slack 1 ns: {}",
            if rc == 0 { "on" } else { "refused" }
        );
    }
    if let Some(cpu) = pin_for("scan") {
        let r = fieldbus::affinity::pin_thread(0, &[cpu]);
        println!("  scan thread pinned to CPU {cpu}: {r:?}");
    }
    let mut cfg = device(addr, Duration::ZERO);
    cfg.write_connection = write_connection;
    let io_cpus: Vec<usize> = pin_for("io").into_iter().collect();
    let mut io = ModbusIo::start_pinned(&[cfg], &io_cpus).expect("driver");
    let mut image = vec![0u8; PACKETS_LEN];
    let mut log = TickLog {
        ticks: Vec::with_capacity(100_000),
        direct: 0,
        publish_changed: Vec::new(),
        publish_same: Vec::with_capacity(100_000),
        io_priority: None,
    };
    let mut next = Instant::now();
    let mut tick = 0;
    while !stop.load(Ordering::Relaxed) {
        let woke = Instant::now();
        tick += 1;
        io.latch_inputs(tick, &mut image);
        if tick == 2 && env_flag("FIELDBUS_BENCH_IO_OTHER") {
            io_threads_to_sched_other();
        }
        log.ticks.push((next, woke, image[0] & 1 == 1));
        let changed = image[16] != image[0];
        image[16] = image[0];
        let t = Instant::now();
        io.publish_outputs(tick, &image);
        let spent = t.elapsed();
        if changed {
            log.publish_changed.push(spent);
        } else {
            log.publish_same.push(spent);
        }
        next += TICK;
        let now = Instant::now();
        if next > now {
            std::thread::sleep(next - now);
        } else {
            next = now;
        }
    }
    if !io_cpus.is_empty() {
        println!(
            "  I/O threads pinned to CPU {io_cpus:?}: {:?}",
            io.io_pinned()
        );
    }
    log.direct = io.direct_writes("rio1");
    log.io_priority = io
        .io_priority()
        .filter(|_| !env_flag("FIELDBUS_BENCH_IO_OTHER"));
    log
}

fn latency_report(write_connection: bool) {
    let events: usize = std::env::var("FIELDBUS_BENCH_EVENTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(10_000);
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .on_thread_start(|| {
            if let Some(cpu) = pin_for("device") {
                let r = fieldbus::affinity::pin_thread(0, &[cpu]);
                println!("  simulated device pinned to CPU {cpu}: {r:?}");
            }
            if env_flag("FIELDBUS_BENCH_FIFO") {
                // The simulated device stands for separate hardware: keep the build jobs sharing
                // this VM from delaying its answers (SCHED_FIFO 70, below the scan's 80).
                let param = libc::sched_param { sched_priority: 70 };
                // SAFETY: plain syscall on the calling thread with a valid parameter block.
                unsafe { libc::sched_setscheduler(0, libc::SCHED_FIFO, &param) };
            }
        })
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

    println!(
        "modbus input→output latency, {}:",
        if write_connection {
            "writes on their own connection"
        } else {
            "reads and writes on one connection"
        }
    );
    let stop = Arc::new(AtomicBool::new(false));
    let scan = {
        let stop = stop.clone();
        std::thread::spawn(move || scan_loop(addr, write_connection, stop))
    };
    // Wait until the loop runs (first write of the initial outputs).
    let start = Instant::now();
    while sim.state().last_write.is_none() && start.elapsed() < Duration::from_secs(5) {
        std::thread::sleep(Duration::from_millis(1));
    }
    let (reads_before, loop_start) = (sim.state().reads_done, Instant::now());
    let mut seed = 0x2545_F491u32;
    let mut lat = Vec::with_capacity(events);
    let mut spans = Vec::with_capacity(events);
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
                    spans.push((t0, at, want));
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
    let reads = sim.state().reads_done - reads_before;
    let read_period = loop_start.elapsed() / u32::try_from(reads.max(1)).unwrap_or(u32::MAX);
    stop.store(true, Ordering::Relaxed);
    let log = scan.join().expect("scan thread");
    let target = TICK + 2 * rtt;
    // Pure scheduling jitter of the same loop: how late each 1 ms tick woke, and wake-to-wake gaps.
    let mut late: Vec<Duration> = log
        .ticks
        .iter()
        .map(|(due, woke, _)| woke.saturating_duration_since(*due))
        .collect();
    late.sort();
    let mut gaps: Vec<Duration> = log
        .ticks
        .windows(2)
        .map(|w| w[1].1.saturating_duration_since(w[0].1))
        .collect();
    gaps.sort();
    let parts: Vec<(Duration, Breakdown)> = spans
        .iter()
        .filter_map(|&(t0, at, want)| {
            Some((
                at.saturating_duration_since(t0),
                log.breakdown(t0, at, want)?,
            ))
        })
        .collect();
    let mut write_path: Vec<Duration> = parts.iter().map(|(_, b)| b.write_path).collect();
    write_path.sort();
    let mut to_latch: Vec<Duration> = parts.iter().map(|(_, b)| b.to_latch).collect();
    to_latch.sort();
    let misses: Vec<&Breakdown> = parts
        .iter()
        .filter(|(l, _)| *l > target)
        .map(|(_, b)| b)
        .collect();
    let slack = 2 * rtt;
    let long_gap = misses.iter().filter(|b| b.gap > TICK + slack).count();
    let slow_write = misses.iter().filter(|b| b.write_path > slack).count();
    let missed_tick = misses.iter().filter(|b| b.missed_tick).count();
    let neither = misses
        .iter()
        .filter(|b| b.gap <= TICK + slack && b.write_path <= slack)
        .count();
    lat.sort();
    println!(
        "  {} events (tick 1 ms, loopback, {} lost); round trip median {:?} (p99 {:?}); target 1 tick + 2 RT = {:?}",
        lat.len(),
        lost,
        rtt,
        percentile(&rtts, 0.99),
        target
    );
    if !lat.is_empty() {
        let p99 = percentile(&lat, 0.99);
        println!(
            "  latency     p50 {:?}  p90 {:?}  p99 {:?}  max {:?}  → p99 {} target",
            percentile(&lat, 0.5),
            percentile(&lat, 0.9),
            p99,
            lat[lat.len() - 1],
            if p99 <= target { "meets" } else { "MISSES" }
        );
    }
    let show = |what: &str, v: &[Duration]| {
        if !v.is_empty() {
            println!(
                "  {what:<28} p50 {:>10.1?}  p90 {:>10.1?}  p99 {:>10.1?}  max {:>10.1?}",
                percentile(v, 0.5),
                percentile(v, 0.9),
                percentile(v, 0.99),
                v[v.len() - 1]
            );
        }
    };
    println!(
        "  {reads} reads answered during the loop (one per {read_period:.1?}); writes sent by the scan thread itself: {}; driver I/O thread: {}",
        log.direct,
        log.io_priority
            .map_or("SCHED_OTHER".to_string(), |p| format!("SCHED_FIFO {p}"))
    );
    show("event → latching tick", &to_latch);
    // Events that a tick woke after but did not latch: how close before that tick they came. With
    // back-to-back polling a change needs ≈ 0.5–1.5 RT to come back from the device.
    let mut missed_lead: Vec<Duration> = parts
        .iter()
        .filter(|(_, b)| b.missed_tick)
        .map(|(_, b)| b.lead)
        .collect();
    missed_lead.sort();
    show("event → tick that missed it", &missed_lead);
    show("latching tick → write applied", &write_path);
    let mut log = log;
    log.publish_changed.sort();
    log.publish_same.sort();
    show("publish_outputs, output changed", &log.publish_changed);
    show("publish_outputs, unchanged", &log.publish_same);
    show("scan wake-up lateness", &late);
    show("scan wake-to-wake gap", &gaps);
    println!(
        "  {} of {} events over target ({:.2} %): {} after a scan gap > 1 tick + 2 RT, {} with a write path > 2 RT, {} with neither; {} latched one tick late (read not back in time)",
        misses.len(),
        parts.len(),
        100.0 * misses.len() as f64 / parts.len().max(1) as f64,
        long_gap,
        slow_write,
        neither,
        missed_tick
    );
}

/// The cost of one thread hand-off: a plain thread wakes a task parked on a one-worker tokio
/// runtime through `Notify` (what `publish_outputs` does to the write task), at random phases.
fn wake_report() {
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()
        .expect("runtime");
    let notify = Arc::new(tokio::sync::Notify::new());
    let (tx, rx) = std::sync::mpsc::channel::<Instant>();
    let n = notify.clone();
    rt.spawn(async move {
        loop {
            n.notified().await;
            if tx.send(Instant::now()).is_err() {
                break;
            }
        }
    });
    let mut seed = 0x1234_5678u32;
    let mut v = Vec::new();
    for _ in 0..5000 {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        std::thread::sleep(Duration::from_micros(u64::from(seed % 1000)));
        let t0 = Instant::now();
        notify.notify_one();
        if let Ok(t1) = rx.recv_timeout(Duration::from_secs(1)) {
            v.push(t1.saturating_duration_since(t0));
        }
    }
    v.sort();
    if !v.is_empty() {
        println!(
            "thread → parked tokio task wake-up (Notify) over {} samples: p50 {:.1?}  p90 {:.1?}  p99 {:.1?}  max {:.1?}",
            v.len(),
            percentile(&v, 0.5),
            percentile(&v, 0.9),
            percentile(&v, 0.99),
            v[v.len() - 1]
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
        limits: HmiLimits::default(),
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
    wake_report();
    latency_report(false);
    latency_report(true);
    benches();
    Criterion::default().configure_from_args().final_summary();
}
