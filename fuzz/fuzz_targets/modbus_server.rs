#![no_main]
//! The Modbus HMI server's frame decoding and request handling on arbitrary bytes, sent over a
//! real loopback connection to one server started once (`HmiIo`, unit 1, a holding window): the
//! server never panics (libFuzzer's hook aborts on a panic in any thread), every answer is a
//! well-formed MBAP frame, and after each input the server still
//! answers a valid request on a fresh connection.

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::sync::{Mutex, OnceLock};
use std::time::Duration;

use fieldbus::map::{HmiConfig, HmiLimits, HmiWindow};
use fieldbus::modbus::server::HmiIo;
use packets::{IoAlarm, Packet, PacketIo};

struct Still;

impl PacketIo for Still {
    fn name(&self) -> &str {
        "still"
    }
    fn latch_inputs(&mut self, _tick: u64, _packets: &mut [u8]) {}
    fn publish_outputs(&mut self, _tick: u64, _packets: &[u8]) {}
    fn take_alarms(&mut self) -> Vec<IoAlarm> {
        Vec::new()
    }
    fn safe_state(&mut self) {}
}

fn server() -> SocketAddr {
    static SERVER: OnceLock<Mutex<HmiIo>> = OnceLock::new();
    let s = SERVER.get_or_init(|| {
        let cfg = HmiConfig {
            bind: "127.0.0.1:0".parse().expect("addr"),
            holding: vec![HmiWindow {
                start: Packet::K.offset() + 800,
                len: 16,
            }],
            limits: HmiLimits {
                max_requests_per_s: 100_000,
                // Every exchange shuts its side down, so no connection idles: a short timeout only
                // raced the server's first read when the machine was busy ("stopped answering").
                idle_timeout: Duration::from_secs(10),
                ..HmiLimits::default()
            },
        };
        Mutex::new(HmiIo::start(Box::new(Still), &cfg).expect("server"))
    });
    s.lock().map(|h| h.local_addr()).expect("server")
}

/// The complete frames of `buf`: (transaction id, function code).
fn answers(buf: &[u8]) -> Vec<(u16, u8)> {
    let mut out = Vec::new();
    let mut at = 0;
    while buf.len() >= at + 8 {
        let len = usize::from(u16::from_be_bytes([buf[at + 4], buf[at + 5]]));
        assert_eq!(&buf[at + 2..at + 4], &[0, 0], "protocol id of an answer");
        assert!((2..=254).contains(&len), "length field {len}");
        assert!(buf.len() >= at + 6 + len, "a truncated answer");
        out.push((u16::from_be_bytes([buf[at], buf[at + 1]]), buf[at + 7]));
        at += 6 + len;
    }
    assert_eq!(at, buf.len(), "bytes after the last answer");
    out
}

fn exchange(addr: SocketAddr, data: &[u8]) -> Vec<u8> {
    let mut s = TcpStream::connect(addr).expect("connect");
    s.set_read_timeout(Some(Duration::from_secs(10)))
        .expect("timeout");
    let _ = s.write_all(data);
    let _ = s.shutdown(std::net::Shutdown::Write);
    let mut got = Vec::new();
    let _ = s.read_to_end(&mut got);
    got
}

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if data.len() > 4096 {
        return;
    }
    let addr = server();
    let got = exchange(addr, data);
    // Function code 0 is no function: a request for it is answered with the exception 0x80
    // (code + 0x80, Modbus application protocol §7), never with a plain 0.
    for (_, fc) in answers(&got) {
        assert_ne!(fc, 0, "a plain answer with function code 0");
    }
    // Still serving: read input register 0 of unit 1.
    let ok = exchange(addr, &[0, 9, 0, 0, 0, 6, 1, 4, 0, 0, 0, 1]);
    assert_eq!(answers(&ok), [(9, 4)], "the server stopped answering");
});
