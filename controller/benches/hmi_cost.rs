//! What the web HMI costs the scan (issue 13 target: ≤ 5 %): 2,000 logic ticks of the lathe part
//! (PART1 through kernel + logic + plant, virtual time) without the HMI, and with the HMI serving
//! and a WebSocket client pulling the live image at 20 Hz. With the HMI, every tick services the
//! request channel and samples the tool path, and every second tick publishes a snapshot (the
//! 40 Hz publish rate of a real-time run at the lathe's 10 ms tick is one every 2.5 ticks: this is
//! the dearer bound). The client runs on its own thread, as a browser's server task would. Every
//! controller is built as `ncplc run plc-programs/lathe --program PART1 --virtual-time [--hmi]`.

mod common;

use std::io::{Read, Write};
use std::net::TcpStream;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use controller::{Controller, Quiet};
use criterion::{BatchSize, Criterion, criterion_group, criterion_main};

const TICKS: u64 = 2_000;

/// A WebSocket client that reads whatever arrived every 50 ms (20 Hz) until `stop`.
fn client(addr: std::net::SocketAddr, stop: Arc<AtomicBool>) -> std::thread::JoinHandle<u64> {
    std::thread::spawn(move || {
        let mut s = TcpStream::connect(addr).unwrap_or_else(|e| panic!("{e}"));
        let _ = write!(
            s,
            "GET /ws HTTP/1.1\r\nHost: {addr}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n\
             Authorization: Bearer {}\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n",
            common::BENCH_TOKEN
        );
        let _ = s.set_read_timeout(Some(Duration::from_millis(5)));
        let mut buf = vec![0u8; 1 << 16];
        let mut got = 0u64;
        while !stop.load(Ordering::Relaxed) {
            std::thread::sleep(Duration::from_millis(50));
            while let Ok(n) = s.read(&mut buf) {
                if n == 0 {
                    break;
                }
                got += n as u64;
            }
        }
        got
    })
}

/// `n` ticks of `c`, publishing the HMI's frame every `publish_every` ticks (0: at its own rate).
fn ticks(c: &mut Controller, n: u64, publish_every: u64) {
    for _ in 0..n {
        c.step(&mut Quiet);
        if publish_every > 0 && c.scheduler().tick_count().is_multiple_of(publish_every) {
            c.publish_hmi();
        }
    }
}

fn bench(c: &mut Criterion) {
    let tmp = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let lathe = common::machine_dir("lathe");
    let with_hmi =
        || common::part_controller(&lathe, "PART1", Some(common::bench_hmi(tmp.path())), None);
    let mut g = c.benchmark_group("hmi_cost");
    g.sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(8));
    g.bench_function("lathe_part1_2000_ticks_without_hmi", |b| {
        b.iter_batched(
            || common::part_controller(&lathe, "PART1", None, None),
            |mut c| {
                ticks(&mut c, TICKS, 0);
                c.scheduler().tick_count()
            },
            BatchSize::PerIteration,
        )
    });
    // Each iteration builds a controller with its own HMI server (the old ones stop with it).
    for (name, publish_every) in [
        ("lathe_part1_2000_ticks_with_hmi_and_a_20hz_client", 2),
        (
            "lathe_part1_2000_ticks_hmi_service_only_publish_at_25ms_wall",
            0,
        ),
    ] {
        g.bench_function(name, |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    let mut c = with_hmi();
                    let addr = c.hmi_addr().unwrap_or_else(|| panic!("no HMI"));
                    let stop = Arc::new(AtomicBool::new(false));
                    let reader = client(addr, Arc::clone(&stop));
                    std::thread::sleep(Duration::from_millis(100));
                    let t = Instant::now();
                    ticks(&mut c, TICKS, publish_every);
                    total += t.elapsed();
                    stop.store(true, Ordering::Relaxed);
                    let got = reader.join().unwrap_or(0);
                    assert!(got > 0, "the client received nothing");
                }
                total
            })
        });
    }
    // The scan thread's part of one published snapshot alone, on the lathe 1,000 ticks into
    // PART1 (the kernel moving, a tool path sampled).
    g.bench_function("publish_one_snapshot_scan_thread_part", |b| {
        let mut c = with_hmi();
        ticks(&mut c, 1_000, 0);
        b.iter(|| c.publish_hmi())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
