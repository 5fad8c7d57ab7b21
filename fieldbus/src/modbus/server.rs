//! The Modbus TCP server for an HMI or SCADA, wrapped around any packet-A driver.
//!
//! The data tables (addresses are 0-based):
//!
//! | table | address `a` | content | access |
//! |---|---|---|---|
//! | discrete inputs | `32c + n` (0..1023) | contact `n` of packet-A **input** connector `c` | read |
//! | coils | `32c + n` (0..1023) | contact `n` of packet-A **output** connector `c` | read |
//! | input registers | `r` (0..1023) | K bytes `2r`, `2r+1` for `r < 512`; N bytes for `r ≥ 512` (low byte first) | read |
//! | holding registers | same numbering as input registers | the windows `[hmi] holding` declares | read + write |
//!
//! A bit request touching a connector of the other direction, a register outside the tables or a
//! holding register outside the windows gets exception 02 (illegal data address); a coil write gets
//! 01 (illegal function: no coil is writable, the logic owns the outputs); an empty or oversized
//! quantity gets 03 (illegal data value); any other function gets 01.
//!
//! Requests go to the unit `[hmi] unit` names (default 1); another unit id gets exception 0B
//! (gateway target device failed to respond). What one client may cost is bounded (`guard`): at
//! most `max_connections` open connections (default 8; one more is closed at once), at most
//! `max_requests_per_s` requests per second per connection (default 100; more are answered with
//! exception 06, server device busy, and not served), and a connection with no request byte for
//! `idle_timeout_ms` (default 60 000) is closed. A malformed MBAP header (protocol id other than 0,
//! length 0) closes its connection; other clients go on.
//!
//! The scan never waits for a client: [`HmiIo::publish_outputs`] copies the packets into a triple
//! buffer the server reads, and HMI writes reach the scan through an `rtrb` ring that
//! [`HmiIo::latch_inputs`] drains. The window keeps its last written value and overrides the image
//! bytes at every latch, like a holding register.

use std::future::Ready;
use std::net::SocketAddr;
use std::sync::{Arc, Mutex};

use packets::{IoAlarm, Packet, PacketIo, is_a_input_connector};
use tokio_modbus::{ExceptionCode, Request, Response, SlaveRequest};

use super::guard::{Guarded, Places, Rate};
use crate::exchange::{TripleReader, TripleWriter, triple};
use crate::map::{HmiConfig, HmiLimits, HmiWindow};

const IMAGE: usize = packets::PACKETS_LEN;
/// Registers in the input/holding register tables (K and N, 2 bytes each).
const REGISTERS: usize = (Packet::K.len() + Packet::N.len()) / 2;
/// Bits in the discrete-input/coil tables (all of packet A).
const BITS: usize = Packet::A.len() * 8;

struct Shared {
    snapshot: Mutex<TripleReader<Vec<u8>>>,
    /// The window values as the HMI last wrote them, indexed by image byte.
    shadow: Mutex<Vec<u8>>,
    writes: Mutex<rtrb::Producer<(u16, u8)>>,
    windows: Vec<HmiWindow>,
}

/// A [`PacketIo`] that serves the packets to HMI/SCADA clients around an inner driver.
pub struct HmiIo {
    inner: Box<dyn PacketIo>,
    runtime: Option<tokio::runtime::Runtime>,
    snapshot: TripleWriter<Vec<u8>>,
    writes: rtrb::Consumer<(u16, u8)>,
    window: Vec<u8>,
    windows: Vec<HmiWindow>,
    local: SocketAddr,
}

impl HmiIo {
    /// Binds the server to `cfg.bind` and starts it on a private runtime.
    pub fn start(inner: Box<dyn PacketIo>, cfg: &HmiConfig) -> std::io::Result<HmiIo> {
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .thread_name("ncplc-hmi")
            .enable_all()
            .build()?;
        // A std bind, not `block_on`, which panics when the caller is inside a tokio runtime.
        let std_listener = std::net::TcpListener::bind(cfg.bind)?;
        std_listener.set_nonblocking(true)?;
        let listener = {
            let _guard = runtime.enter();
            tokio::net::TcpListener::from_std(std_listener)?
        };
        let local = listener.local_addr()?;
        let (snap_tx, snap_rx) = triple(vec![0u8; IMAGE]);
        let (w_tx, w_rx) = rtrb::RingBuffer::new(4096);
        let shared = Arc::new(Shared {
            snapshot: Mutex::new(snap_rx),
            shadow: Mutex::new(vec![0u8; IMAGE]),
            writes: Mutex::new(w_tx),
            windows: cfg.holding.clone(),
        });
        let limits = cfg.limits;
        runtime.spawn(async move {
            let server = tokio_modbus::server::tcp::Server::new(listener);
            let places = Places::new(limits.max_connections);
            let on_connected = move |stream: tokio::net::TcpStream, _addr: SocketAddr| {
                let shared = shared.clone();
                let _ = stream.set_nodelay(true);
                // Over the cap the connection is dropped (closed) at once.
                let conn = places.take().map(|place| {
                    let service = HmiService {
                        shared,
                        limits,
                        rate: Mutex::new(Rate::new(
                            limits.max_requests_per_s,
                            std::time::Instant::now(),
                        )),
                    };
                    (service, Guarded::new(stream, limits.idle_timeout, place))
                });
                std::future::ready(Ok::<_, std::io::Error>(conn))
            };
            // A failing connection only ends that connection; `serve` ends when accept fails.
            let _ = server.serve(&on_connected, |_err| {}).await;
        });
        Ok(HmiIo {
            inner,
            runtime: Some(runtime),
            snapshot: snap_tx,
            writes: w_rx,
            window: vec![0u8; IMAGE],
            windows: cfg.holding.clone(),
            local,
        })
    }

    /// The address the server listens on (useful after binding port 0).
    pub fn local_addr(&self) -> SocketAddr {
        self.local
    }
}

impl Drop for HmiIo {
    fn drop(&mut self) {
        if let Some(rt) = self.runtime.take() {
            rt.shutdown_background();
        }
    }
}

impl PacketIo for HmiIo {
    fn name(&self) -> &str {
        self.inner.name()
    }

    fn latch_inputs(&mut self, tick: u64, packets: &mut [u8]) {
        self.inner.latch_inputs(tick, packets);
        while let Ok((at, v)) = self.writes.pop() {
            if let Some(b) = self.window.get_mut(usize::from(at)) {
                *b = v;
            }
        }
        for w in &self.windows {
            if let (Some(dst), Some(src)) = (
                packets.get_mut(w.start..w.start + w.len),
                self.window.get(w.start..w.start + w.len),
            ) {
                dst.copy_from_slice(src);
            }
        }
    }

    fn publish_outputs(&mut self, tick: u64, packets: &[u8]) {
        self.inner.publish_outputs(tick, packets);
        let n = packets.len().min(IMAGE);
        self.snapshot.buf()[..n].copy_from_slice(&packets[..n]);
        self.snapshot.publish();
    }

    fn take_alarms(&mut self) -> Vec<IoAlarm> {
        self.inner.take_alarms()
    }

    fn safe_state(&mut self) {
        self.inner.safe_state();
    }
}

struct HmiService {
    shared: Arc<Shared>,
    limits: HmiLimits,
    /// This connection's requests in the current second.
    rate: Mutex<Rate>,
}

impl HmiService {
    fn bits(&self, a: u16, n: u16, want_input: bool) -> Result<Vec<bool>, ExceptionCode> {
        let (a, n) = (usize::from(a), usize::from(n));
        if n == 0 || n > 2000 {
            return Err(ExceptionCode::IllegalDataValue);
        }
        if a + n > BITS
            || (a..a + n).any(|bit| is_a_input_connector((bit / 32) as u16) != want_input)
        {
            return Err(ExceptionCode::IllegalDataAddress);
        }
        let mut reader = self
            .shared
            .snapshot
            .lock()
            .map_err(|_| ExceptionCode::ServerDeviceFailure)?;
        let (img, _) = reader.read();
        Ok((a..a + n)
            .map(|bit| img[bit / 8] >> (bit % 8) & 1 == 1)
            .collect())
    }

    fn registers(&self, a: u16, n: u16, holding: bool) -> Result<Vec<u16>, ExceptionCode> {
        let (a, n) = (usize::from(a), usize::from(n));
        if n == 0 || n > 125 {
            return Err(ExceptionCode::IllegalDataValue);
        }
        if a + n > REGISTERS {
            return Err(ExceptionCode::IllegalDataAddress);
        }
        let base = Packet::K.offset();
        if holding {
            if !(a..a + n).all(|r| self.writable(base + 2 * r)) {
                return Err(ExceptionCode::IllegalDataAddress);
            }
            let shadow = self
                .shared
                .shadow
                .lock()
                .map_err(|_| ExceptionCode::ServerDeviceFailure)?;
            return Ok((a..a + n)
                .map(|r| u16::from(shadow[base + 2 * r]) | u16::from(shadow[base + 2 * r + 1]) << 8)
                .collect());
        }
        let mut reader = self
            .shared
            .snapshot
            .lock()
            .map_err(|_| ExceptionCode::ServerDeviceFailure)?;
        let (img, _) = reader.read();
        Ok((a..a + n)
            .map(|r| u16::from(img[base + 2 * r]) | u16::from(img[base + 2 * r + 1]) << 8)
            .collect())
    }

    /// True when both bytes of the register starting at image byte `at` are in a window.
    fn writable(&self, at: usize) -> bool {
        self.shared
            .windows
            .iter()
            .any(|w| w.start <= at && at + 2 <= w.start + w.len)
    }

    fn write_registers(&self, a: u16, words: &[u16]) -> Result<(), ExceptionCode> {
        let (start, n) = (usize::from(a), words.len());
        if n == 0 || n > 123 {
            return Err(ExceptionCode::IllegalDataValue);
        }
        let base = Packet::K.offset();
        if start + n > REGISTERS || !(start..start + n).all(|r| self.writable(base + 2 * r)) {
            return Err(ExceptionCode::IllegalDataAddress);
        }
        let mut ring = self
            .shared
            .writes
            .lock()
            .map_err(|_| ExceptionCode::ServerDeviceFailure)?;
        if ring.slots() < 2 * n {
            return Err(ExceptionCode::ServerDeviceBusy);
        }
        let mut shadow = self
            .shared
            .shadow
            .lock()
            .map_err(|_| ExceptionCode::ServerDeviceFailure)?;
        for (k, w) in words.iter().enumerate() {
            let at = base + 2 * (start + k);
            for (i, v) in [(*w & 0xFF) as u8, (*w >> 8) as u8].into_iter().enumerate() {
                shadow[at + i] = v;
                // `slots()` was checked above, so the push cannot fail.
                let _ = ring.push(((at + i) as u16, v));
            }
        }
        Ok(())
    }
}

impl tokio_modbus::server::Service for HmiService {
    type Request = SlaveRequest<'static>;
    type Response = Response;
    type Exception = ExceptionCode;
    type Future = Ready<Result<Response, ExceptionCode>>;

    fn call(&self, req: Self::Request) -> Self::Future {
        if req.slave != self.limits.unit {
            return std::future::ready(Err(ExceptionCode::GatewayTargetDevice));
        }
        let within = self
            .rate
            .lock()
            .map(|mut r| r.hit(std::time::Instant::now()))
            .unwrap_or(false);
        if !within {
            return std::future::ready(Err(ExceptionCode::ServerDeviceBusy));
        }
        let r = match req.request {
            Request::ReadDiscreteInputs(a, n) => {
                self.bits(a, n, true).map(Response::ReadDiscreteInputs)
            }
            Request::ReadCoils(a, n) => self.bits(a, n, false).map(Response::ReadCoils),
            Request::ReadInputRegisters(a, n) => self
                .registers(a, n, false)
                .map(Response::ReadInputRegisters),
            Request::ReadHoldingRegisters(a, n) => self
                .registers(a, n, true)
                .map(Response::ReadHoldingRegisters),
            Request::WriteSingleRegister(a, w) => self
                .write_registers(a, &[w])
                .map(|()| Response::WriteSingleRegister(a, w)),
            Request::WriteMultipleRegisters(a, words) => {
                let n = words.len() as u16;
                self.write_registers(a, &words)
                    .map(|()| Response::WriteMultipleRegisters(a, n))
            }
            _ => Err(ExceptionCode::IllegalFunction),
        };
        std::future::ready(r)
    }
}
