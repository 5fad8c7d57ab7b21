//! The write connection of one Modbus device, shared by the scan thread and the device's write task.
//!
//! Handing a write to the I/O task costs a thread wake-up before the request reaches the wire, and
//! on a loaded machine that wake-up is most of the input → output latency (`BENCHMARKS.md`). So the
//! scan thread sends the request itself: when `WriteLink::push` finds the connection up and idle,
//! it frames the first output mapping whose commanded bytes the device does not hold yet
//! ([`super::frame`]) and issues **one non-blocking `send`** on the connection's socket. Everything
//! else stays with the write task (`WriteTask`): it connects and reconnects, reads and checks
//! every answer (transaction id, echo, exception), times requests out, sends whatever the scan could
//! not (a busy or contended link, the rest of a multi-mapping change, a socket that would block),
//! and reports faults as before.
//!
//! The scan side never waits: it only `try_lock`s the link (a contended lock means "let the task do
//! it"), and the socket is non-blocking. Both sides take transaction ids from the same counter under
//! that lock, with at most one request in flight, so ids stay unique and in wire order and a device
//! never sees pipelined requests. Only bytes the scan published are ever sent: the scan sends its
//! newest commanded image after publishing it, and the task reads the published frame under the
//! lock, so it never sends an older image than the scan already did.

use std::io::{ErrorKind, Write};
use std::net::{Shutdown, TcpStream as StdStream};
use std::sync::atomic::{AtomicU8, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, TryLockError};
use std::time::{Duration, Instant};

use tokio::sync::Notify;

use crate::exchange::{OutFrame, TripleReader};
use crate::health::Fault;
use crate::map::ModbusDevice;
use crate::modbus::frame::{Answer, MAX_ADU, WriteRequest};
use crate::tick_io::A_LEN;

/// The write connection's state, changed by both sides, always under the link's lock.
struct LinkState {
    /// The connection's socket for sending (non-blocking; shares the task's connection) while up.
    sock: Option<StdStream>,
    /// Bytes of the request in flight that are not on the wire yet (`unsent[sent..len]`).
    unsent: [u8; MAX_ADU],
    unsent_at: usize,
    unsent_len: usize,
    /// The next transaction id.
    next_tid: u16,
    in_flight: Option<InFlight>,
    /// What the device acknowledged, for the output mappings whose `known` flag is set.
    held: [u8; A_LEN],
    known: Vec<bool>,
    /// A send failed with an error other than "would block": the connection is broken.
    broken: bool,
}

/// The one request on the wire.
struct InFlight {
    req: WriteRequest,
    mapping: usize,
    data: [u8; A_LEN],
    sent_at: Instant,
}

/// What trying to send the next write gave.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Step {
    /// The device holds every commanded output already (nothing in flight).
    Idle,
    /// A request is in flight (or its bytes are still queued): nothing new may be sent.
    Busy,
    /// A request went out whole.
    Sent,
    /// A request was committed but part of it waits for the socket to drain.
    Queued,
    /// No connection, or it broke.
    Down,
}

/// The write connection shared by the scan side ([`WriteLink::push`]) and the [`WriteTask`].
pub(crate) struct WriteLink {
    state: Mutex<LinkState>,
    /// Requests the scan thread put on the wire itself.
    direct: AtomicU64,
}

fn lock(m: &Mutex<LinkState>) -> MutexGuard<'_, LinkState> {
    m.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

impl LinkState {
    /// Sends the write of the first output mapping whose commanded bytes in `data` the device is
    /// not known to hold, unless a request is in flight. Never blocks.
    fn send_next(&mut self, cfg: &ModbusDevice, data: &[u8; A_LEN]) -> Step {
        if self.broken || self.sock.is_none() {
            return Step::Down;
        }
        if self.in_flight.is_some() {
            return Step::Busy;
        }
        let pending = cfg.outputs.iter().enumerate().position(|(i, m)| {
            let r = m.range.start..m.range.end();
            !self.known.get(i).copied().unwrap_or(false) || self.held[r.clone()] != data[r]
        });
        let Some(i) = pending else {
            return Step::Idle;
        };
        let m = &cfg.outputs[i];
        let mut frame = [0u8; MAX_ADU];
        let bytes = &data[m.range.start..m.range.end()];
        let Ok((req, n)) = WriteRequest::encode(
            self.next_tid,
            cfg.unit,
            m.area,
            m.address,
            bytes,
            &mut frame,
        ) else {
            // ModbusIo::start keeps only mappings that frame; a hand-built one is never written.
            return Step::Down;
        };
        self.next_tid = self.next_tid.wrapping_add(1);
        // Unknown until the device acknowledges: after a failure the mapping is written again.
        if let Some(k) = self.known.get_mut(i) {
            *k = false;
        }
        let sent = match self.sock.as_ref().map(|mut s| s.write(&frame[..n])) {
            Some(Ok(k)) => k,
            Some(Err(e)) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::Interrupted) => 0,
            Some(Err(_)) | None => {
                self.broken = true;
                return Step::Down;
            }
        };
        self.in_flight = Some(InFlight {
            req,
            mapping: i,
            data: *data,
            sent_at: Instant::now(),
        });
        if sent == n {
            return Step::Sent;
        }
        self.unsent[..n - sent].copy_from_slice(&frame[sent..n]);
        self.unsent_at = 0;
        self.unsent_len = n - sent;
        Step::Queued
    }

    /// Puts queued request bytes on the wire; true when none are left. Never blocks.
    fn flush(&mut self) -> Result<bool, Fault> {
        while self.unsent_at < self.unsent_len {
            let chunk = &self.unsent[self.unsent_at..self.unsent_len];
            match self.sock.as_ref().map(|mut s| s.write(chunk)) {
                Some(Ok(0)) | None => return Err(Fault::Io),
                Some(Ok(k)) => self.unsent_at += k,
                Some(Err(e)) if e.kind() == ErrorKind::WouldBlock => return Ok(false),
                Some(Err(e)) if e.kind() == ErrorKind::Interrupted => {}
                Some(Err(_)) => return Err(Fault::Io),
            }
        }
        Ok(true)
    }

    /// Forgets the connection: nothing in flight, nothing known about the device's outputs.
    fn drop_connection(&mut self) {
        if let Some(s) = self.sock.take() {
            let _ = s.shutdown(Shutdown::Both);
        }
        self.in_flight = None;
        self.unsent_at = 0;
        self.unsent_len = 0;
        self.known.iter_mut().for_each(|k| *k = false);
        self.broken = false;
    }
}

impl WriteLink {
    /// A link for a device with `outputs` output mappings, not connected yet.
    pub(crate) fn new(outputs: usize) -> WriteLink {
        WriteLink {
            state: Mutex::new(LinkState {
                sock: None,
                unsent: [0; MAX_ADU],
                unsent_at: 0,
                unsent_len: 0,
                next_tid: 0,
                in_flight: None,
                held: [0; A_LEN],
                known: vec![false; outputs],
                broken: false,
            }),
            direct: AtomicU64::new(0),
        }
    }

    /// Scan side, right after publishing output frame `seq` (`data`): puts the write on the wire
    /// from this thread when the link is up and idle, and otherwise wakes the write task. Never
    /// blocks: a contended lock or a full socket leaves the write to the task.
    pub(crate) fn push(
        &self,
        cfg: &ModbusDevice,
        seq: u64,
        data: &[u8; A_LEN],
        wake: &Notify,
        acked: &AtomicU64,
    ) {
        if !cfg.direct_write {
            wake.notify_one();
            return;
        }
        let step = match self.state.try_lock() {
            Ok(mut st) => st.send_next(cfg, data),
            Err(TryLockError::Poisoned(p)) => p.into_inner().send_next(cfg, data),
            Err(TryLockError::WouldBlock) => Step::Busy,
        };
        match step {
            Step::Sent => {
                self.direct.fetch_add(1, Ordering::Relaxed);
            }
            Step::Idle => acked.store(seq, Ordering::Release),
            Step::Busy | Step::Queued | Step::Down => wake.notify_one(),
        }
    }

    /// How many requests the scan thread sent itself.
    pub(crate) fn direct_sends(&self) -> u64 {
        self.direct.load(Ordering::Relaxed)
    }
}

/// The write side of one device, on a connection of its own.
pub(crate) struct WriteTask {
    /// The device.
    pub cfg: ModbusDevice,
    /// The outputs the scan published.
    pub outputs: TripleReader<OutFrame>,
    /// The connection shared with the scan.
    pub link: Arc<WriteLink>,
    /// Woken by the scan when it left a write to this task.
    pub wake: Arc<Notify>,
    /// The newest output frame the device holds completely.
    pub acked: Arc<AtomicU64>,
    /// This connection's fault ([`Fault::code`]).
    pub fault: Arc<AtomicU8>,
}

/// What one look at the link under its lock found.
enum Look {
    /// Nothing to do until an answer, a wake-up or the timeout check; `true`: wait until the
    /// socket takes the queued bytes.
    Wait(bool),
    /// The device holds every commanded output (or the logic has not published yet).
    Settled,
}

impl WriteTask {
    /// Connects, serves, and reconnects with exponential backoff, forever.
    pub(crate) async fn run(mut self) {
        let mut backoff = self.cfg.reconnect_min;
        let mut retry_now = false;
        loop {
            let fault = match self.connect().await {
                Ok(stream) => {
                    let fault = self.serve(&stream, &mut backoff, &mut retry_now).await;
                    lock(&self.link.state).drop_connection();
                    fault
                }
                Err(f) => f,
            };
            // An idle connection may have been closed by a device that restarted meanwhile: the
            // first write on it fails at once. Reconnect at once (once) before calling it a fault.
            if fault == Fault::Io && std::mem::take(&mut retry_now) {
                continue;
            }
            retry_now = false;
            self.fault.store(fault.code(), Ordering::Release);
            tokio::time::sleep(backoff).await;
            backoff = (backoff * 2).min(self.cfg.reconnect_max);
        }
    }

    /// Opens the connection and shares its socket with the scan side.
    async fn connect(&self) -> Result<tokio::net::TcpStream, Fault> {
        let connect = tokio::net::TcpStream::connect(self.cfg.address);
        let stream = match tokio::time::timeout(self.cfg.timeout, connect).await {
            Ok(Ok(s)) => s,
            Ok(Err(_)) | Err(_) => return Err(Fault::Connect),
        };
        let _ = stream.set_nodelay(true);
        // The std socket stays non-blocking: the scan's sends return instead of waiting.
        let std = stream.into_std().map_err(|_| Fault::Connect)?;
        let send = std.try_clone().map_err(|_| Fault::Connect)?;
        let stream = tokio::net::TcpStream::from_std(std).map_err(|_| Fault::Connect)?;
        let mut st = lock(&self.link.state);
        st.drop_connection();
        st.sock = Some(send);
        Ok(stream)
    }

    /// Writes what the scan left, reads and checks every answer, until something fails.
    async fn serve(
        &mut self,
        stream: &tokio::net::TcpStream,
        backoff: &mut Duration,
        retry_now: &mut bool,
    ) -> Fault {
        let mut rx = [0u8; 2 * MAX_ADU];
        let mut rx_len = 0;
        // Requests the scan sent are timed out by this periodic check (no wake-up per write).
        let check = (self.cfg.timeout / 4).max(Duration::from_millis(1));
        loop {
            let want_write = match self.look() {
                Ok(Look::Wait(w)) => w,
                Ok(Look::Settled) => {
                    self.fault.store(Fault::None.code(), Ordering::Release);
                    *backoff = self.cfg.reconnect_min;
                    *retry_now = true;
                    false
                }
                Err(f) => return f,
            };
            tokio::select! {
                r = stream.readable() => {
                    if r.is_err() {
                        return Fault::Io;
                    }
                    match stream.try_read(&mut rx[rx_len..]) {
                        Ok(0) => return Fault::Io,
                        Ok(n) => {
                            rx_len += n;
                            if let Err(f) = self.answer(&rx, &mut rx_len) {
                                return f;
                            }
                        }
                        Err(e) if e.kind() == ErrorKind::WouldBlock => {}
                        Err(_) => return Fault::Io,
                    }
                }
                r = stream.writable(), if want_write => {
                    if r.is_err() {
                        return Fault::Io;
                    }
                }
                () = self.wake.notified() => {}
                () = tokio::time::sleep(check) => {}
            }
        }
    }

    /// Under the lock: times out the request in flight, flushes its queued bytes, or sends the
    /// next write the published outputs need.
    fn look(&mut self) -> Result<Look, Fault> {
        let mut st = lock(&self.link.state);
        if st.broken {
            return Err(Fault::Io);
        }
        if let Some(f) = &st.in_flight {
            if f.sent_at.elapsed() >= self.cfg.timeout {
                return Err(Fault::Timeout);
            }
            return Ok(Look::Wait(!st.flush()?));
        }
        let (out, _) = self.outputs.read();
        if out.seq == 0 {
            // Never write before the logic publishes.
            return Ok(Look::Settled);
        }
        match st.send_next(&self.cfg, &out.data) {
            Step::Idle => {
                self.acked.store(out.seq, Ordering::Release);
                Ok(Look::Settled)
            }
            Step::Sent | Step::Busy => Ok(Look::Wait(false)),
            Step::Queued => Ok(Look::Wait(true)),
            Step::Down => Err(Fault::Io),
        }
    }

    /// Under the lock: checks the bytes received against the request in flight.
    fn answer(&mut self, rx: &[u8], rx_len: &mut usize) -> Result<(), Fault> {
        let mut st = lock(&self.link.state);
        // Bytes nobody asked for: the stream is out of step.
        let Some(f) = &st.in_flight else {
            return Err(Fault::Protocol);
        };
        match f.req.parse_answer(&rx[..*rx_len]) {
            Ok(None) => Ok(()),
            Ok(Some((n, Answer::Done))) if n == *rx_len => {
                *rx_len = 0;
                if let Some(f) = st.in_flight.take()
                    && let Some(m) = self.cfg.outputs.get(f.mapping)
                {
                    let r = m.range.start..m.range.end();
                    st.held[r.clone()].copy_from_slice(&f.data[r]);
                    if let Some(k) = st.known.get_mut(f.mapping) {
                        *k = true;
                    }
                }
                Ok(())
            }
            Ok(Some((_, Answer::Done))) => Err(Fault::Protocol),
            Ok(Some((_, Answer::Exception(_)))) => Err(Fault::Exception),
            Err(_) => Err(Fault::Protocol),
        }
    }
}

#[cfg(test)]
mod tests {
    use std::io::Read;
    use std::net::TcpListener;

    use super::*;
    use crate::map::{ByteRange, ModbusArea, ModbusMapping};

    fn cfg() -> ModbusDevice {
        ModbusDevice {
            name: "rio1".into(),
            address: "127.0.0.1:502".parse().expect("addr"),
            unit: 1,
            timeout: Duration::from_millis(50),
            poll: Duration::ZERO,
            write_connection: true,
            direct_write: true,
            alarm_ticks: 5,
            reconnect_min: Duration::from_millis(10),
            reconnect_max: Duration::from_millis(100),
            healthy: None,
            inputs: Vec::new(),
            outputs: vec![ModbusMapping {
                range: ByteRange { start: 16, len: 1 },
                area: ModbusArea::Coils,
                address: 100,
                fail: 0,
            }],
        }
    }

    /// A connected pair: the link's non-blocking sending side and the peer's receiving side.
    fn pair() -> (StdStream, StdStream) {
        let l = TcpListener::bind("127.0.0.1:0").expect("bind");
        let tx = StdStream::connect(l.local_addr().expect("addr")).expect("connect");
        let (rx, _) = l.accept().expect("accept");
        tx.set_nonblocking(true).expect("nonblocking");
        (tx, rx)
    }

    #[test]
    fn a_full_socket_queues_the_request_instead_of_blocking_and_flush_completes_it() {
        let (tx, mut rx) = pair();
        // Fill the socket until it would block (the peer reads nothing yet).
        let mut junk_len = 0usize;
        let chunk = [0xEEu8; 65536];
        loop {
            match (&tx).write(&chunk) {
                Ok(n) => junk_len += n,
                Err(e) if e.kind() == ErrorKind::WouldBlock => break,
                Err(e) => panic!("fill: {e}"),
            }
        }
        let link = WriteLink::new(1);
        let cfg = cfg();
        let mut data = [0u8; A_LEN];
        data[16] = 0b101;
        let mut st = lock(&link.state);
        st.sock = Some(tx);
        let started = Instant::now();
        assert_eq!(st.send_next(&cfg, &data), Step::Queued);
        assert!(
            started.elapsed() < Duration::from_millis(50),
            "did not block"
        );
        assert_eq!(
            st.send_next(&cfg, &data),
            Step::Busy,
            "one request in flight"
        );
        // The peer drains everything; the queued request then goes out whole.
        let want = [0, 0, 0, 0, 0, 8, 1, 15, 0, 100, 0, 8, 1, 0b101];
        let mut got = Vec::new();
        let mut buf = vec![0u8; 1 << 16];
        let deadline = Instant::now() + Duration::from_secs(5);
        while got.len() < junk_len + want.len() && Instant::now() < deadline {
            let n = rx.read(&mut buf).expect("read");
            got.extend_from_slice(&buf[..n]);
            if st.unsent_at < st.unsent_len {
                let _ = st.flush().expect("flush");
            }
        }
        assert_eq!(st.flush(), Ok(true));
        assert_eq!(got.len(), junk_len + want.len());
        assert_eq!(&got[junk_len..], &want);
        assert_eq!(st.in_flight.as_ref().map(|f| f.req.tid), Some(0));
        assert_eq!(st.next_tid, 1);
    }

    #[test]
    fn nothing_is_sent_while_down_and_an_acknowledged_image_is_idle() {
        let link = WriteLink::new(1);
        let cfg = cfg();
        let data = [0u8; A_LEN];
        let mut st = lock(&link.state);
        assert_eq!(st.send_next(&cfg, &data), Step::Down);
        assert_eq!(st.next_tid, 0, "no id used");
        let (tx, _rx) = pair();
        st.sock = Some(tx);
        st.known[0] = true; // the device holds 0 already
        assert_eq!(st.send_next(&cfg, &data), Step::Idle);
        assert!(st.in_flight.is_none());
    }
}
