//! The scan thread's cost of the OPC UA server in instructions (the companion of the web HMI's
//! `controller/examples/hmi_publish_cost`): the lathe runs PART1 (kernel + JIT logic + plant,
//! virtual time, as `ncplc run plc-programs/lathe --program PART1 --virtual-time --opcua` builds
//! it) for 1,000 ticks, then `N` more ticks without the server (`ticks`) and `N` with it
//! (`served`). The server's share is `OpcuaServer::after_tick`, the scan side of every publish:
//! `valgrind --tool=callgrind --toggle-collect='*OpcuaServer*after_tick*'
//! target/release/examples/opcua_publish_cost 200` counts it (divide by N), and
//! `--toggle-collect='*opcua_publish_cost::ticks*'` the plain ticks. Each tick is followed by a
//! 3 ms sleep outside the measured functions, so the server's publisher empties the ring and no
//! frame is dropped (a dropped frame would cost the scan less than a published one).

use std::path::PathBuf;
use std::time::Duration;

use controller::settings::{Clock, Part, PartSpec, Scan};
use controller::{Controller, Quiet};
use opcua_server::{OpcuaServer, Settings};

/// The lathe's PART1 run, with the OPC UA server on a free loopback port when `opcua`.
fn controller(opcua: bool) -> Controller {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../plc-programs/lathe");
    let part = Part {
        spec: PartSpec {
            program: Some(PathBuf::from("PART1")),
            process: 1,
            ..PartSpec::default()
        },
        trajectory: None,
        until_end: true,
    };
    let mut b = Controller::builder(&dir)
        .part(Some(part))
        .clock(Clock::Virtual)
        .scan(Scan {
            watch: false,
            ..Scan::default()
        });
    if opcua {
        let addr = "127.0.0.1:0".parse().unwrap_or_else(|e| panic!("{e}"));
        b = b.server(Box::new(OpcuaServer::new(Settings {
            addr,
            users: None,
            program: Some("PART1".into()),
        })));
    }
    b.build().unwrap_or_else(|e| panic!("{e}"))
}

/// `n` ticks, each followed by a pause for the server's publisher.
#[inline(never)]
fn warm_up(c: &mut Controller, n: u64) {
    for _ in 0..n {
        c.step(&mut Quiet);
        std::thread::sleep(Duration::from_millis(3));
    }
}

/// `n` plain ticks of a controller without a server: what a publish is compared with.
#[inline(never)]
fn ticks(c: &mut Controller, n: u64) {
    for _ in 0..n {
        c.step(&mut Quiet);
        std::thread::sleep(Duration::from_millis(3));
    }
}

/// `n` ticks with the OPC UA server (its `after_tick` after each).
#[inline(never)]
fn served(c: &mut Controller, n: u64) {
    for _ in 0..n {
        c.step(&mut Quiet);
        std::thread::sleep(Duration::from_millis(3));
    }
}

fn main() {
    let n: u64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(200);
    let mut plain = controller(false);
    let mut with = controller(true);
    warm_up(&mut plain, 1_000);
    warm_up(&mut with, 1_000);
    ticks(&mut plain, n);
    served(&mut with, n);
    println!(
        "tick {}: {n} ticks without and {n} with the OPC UA server",
        plain.scheduler().tick_count()
    );
}
