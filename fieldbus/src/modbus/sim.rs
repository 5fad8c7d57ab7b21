//! A Modbus TCP remote-I/O device simulator for tests and benchmarks, with fault injection.
//!
//! It serves four tables of 4096 items each, counts and logs every write, and can be told to answer
//! slowly ([`RemoteIoSim::set_delay`]), to stop answering while keeping connections open
//! ([`RemoteIoSim::set_mute`]) or to die and come back on the same port ([`RemoteIoSim::kill`],
//! [`RemoteIoSim::restart`]). It runs on whatever tokio runtime calls [`RemoteIoSim::start`].

use std::future::Future;
use std::net::SocketAddr;
use std::pin::Pin;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use tokio::sync::Notify;
use tokio_modbus::{ExceptionCode, Request, Response};

/// Items per table.
pub const TABLE: usize = 4096;

/// The simulated device's tables and fault knobs.
#[derive(Debug, Clone)]
pub struct SimState {
    /// Discrete inputs (the device's physical inputs).
    pub discrete: Vec<bool>,
    /// Coils (the device's physical outputs).
    pub coils: Vec<bool>,
    /// Input registers.
    pub input_regs: Vec<u16>,
    /// Holding registers.
    pub holding: Vec<u16>,
    /// Every write request in order: (function code, address, quantity).
    pub writes: Vec<(u8, u16, u16)>,
    /// Delay before each answer.
    pub delay: Duration,
    /// Extra delay before the answer to a read request only.
    pub read_delay: Duration,
    /// Read requests received and not answered yet (a muted request stays counted).
    pub reads_pending: usize,
    /// Read requests answered since the start.
    pub reads_done: u64,
    /// [`SimState::reads_pending`] when the last write was applied.
    pub reads_pending_at_last_write: usize,
    /// When true the device swallows requests and never answers.
    pub mute: bool,
    /// When the device applied the last write.
    pub last_write: Option<std::time::Instant>,
}

impl Default for SimState {
    fn default() -> Self {
        SimState {
            discrete: vec![false; TABLE],
            coils: vec![false; TABLE],
            input_regs: vec![0; TABLE],
            holding: vec![0; TABLE],
            writes: Vec::new(),
            delay: Duration::ZERO,
            read_delay: Duration::ZERO,
            reads_pending: 0,
            reads_done: 0,
            reads_pending_at_last_write: 0,
            mute: false,
            last_write: None,
        }
    }
}

/// A running simulated remote-I/O device.
pub struct RemoteIoSim {
    state: Arc<Mutex<SimState>>,
    addr: SocketAddr,
    task: Option<tokio::task::JoinHandle<()>>,
    /// Woken after every write the device applies.
    pub written: Arc<Notify>,
}

fn lock(state: &Mutex<SimState>) -> MutexGuard<'_, SimState> {
    state
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

impl RemoteIoSim {
    /// Starts a device on `addr` (use port 0 for a free port).
    pub async fn start(addr: SocketAddr) -> std::io::Result<RemoteIoSim> {
        let mut sim = RemoteIoSim {
            state: Arc::new(Mutex::new(SimState::default())),
            addr,
            task: None,
            written: Arc::new(Notify::new()),
        };
        sim.addr = sim.listen(addr).await?;
        Ok(sim)
    }

    async fn listen(&mut self, addr: SocketAddr) -> std::io::Result<SocketAddr> {
        let socket = tokio::net::TcpSocket::new_v4()?;
        socket.set_reuseaddr(true)?;
        socket.bind(addr)?;
        let listener = socket.listen(64)?;
        let local = listener.local_addr()?;
        let state = self.state.clone();
        let written = self.written.clone();
        self.task = Some(tokio::spawn(async move {
            let server = tokio_modbus::server::tcp::Server::new(listener);
            let on_connected = move |stream: tokio::net::TcpStream, peer| {
                let svc = SimService {
                    state: state.clone(),
                    written: written.clone(),
                };
                let _ = stream.set_nodelay(true);
                async move {
                    tokio_modbus::server::tcp::accept_tcp_connection(stream, peer, move |_| {
                        Ok(Some(SimService {
                            state: svc.state.clone(),
                            written: svc.written.clone(),
                        }))
                    })
                }
            };
            let _ = server.serve(&on_connected, |_err| {}).await;
        }));
        Ok(local)
    }

    /// The device's address.
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// Locks the device's state for reading or changing it.
    pub fn state(&self) -> MutexGuard<'_, SimState> {
        lock(&self.state)
    }

    /// Delays every answer by `d`.
    pub fn set_delay(&self, d: Duration) {
        self.state().delay = d;
    }

    /// Delays the answers to read requests (only) by `d`.
    pub fn set_read_delay(&self, d: Duration) {
        self.state().read_delay = d;
    }

    /// Stops (or resumes) answering without closing connections.
    pub fn set_mute(&self, mute: bool) {
        self.state().mute = mute;
    }

    /// Kills the device: the listener and every connection close.
    pub fn kill(&mut self) {
        if let Some(t) = self.task.take() {
            t.abort();
        }
    }

    /// Brings a killed device back on the same address, with its tables as they were.
    pub async fn restart(&mut self) -> std::io::Result<()> {
        self.kill();
        tokio::task::yield_now().await;
        self.listen(self.addr).await.map(|_| ())
    }
}

impl Drop for RemoteIoSim {
    fn drop(&mut self) {
        self.kill();
    }
}

struct SimService {
    state: Arc<Mutex<SimState>>,
    written: Arc<Notify>,
}

fn range(a: u16, n: usize) -> Result<std::ops::Range<usize>, ExceptionCode> {
    let a = usize::from(a);
    if n == 0 || a + n > TABLE {
        Err(ExceptionCode::IllegalDataAddress)
    } else {
        Ok(a..a + n)
    }
}

fn apply(state: &Mutex<SimState>, req: Request<'static>) -> Result<Response, ExceptionCode> {
    let mut s = lock(state);
    if matches!(
        req,
        Request::WriteMultipleCoils(..)
            | Request::WriteSingleCoil(..)
            | Request::WriteMultipleRegisters(..)
            | Request::WriteSingleRegister(..)
    ) {
        s.last_write = Some(std::time::Instant::now());
        s.reads_pending_at_last_write = s.reads_pending;
    }
    match req {
        Request::ReadDiscreteInputs(a, n) => Ok(Response::ReadDiscreteInputs(
            s.discrete[range(a, n.into())?].to_vec(),
        )),
        Request::ReadCoils(a, n) => Ok(Response::ReadCoils(s.coils[range(a, n.into())?].to_vec())),
        Request::ReadInputRegisters(a, n) => Ok(Response::ReadInputRegisters(
            s.input_regs[range(a, n.into())?].to_vec(),
        )),
        Request::ReadHoldingRegisters(a, n) => Ok(Response::ReadHoldingRegisters(
            s.holding[range(a, n.into())?].to_vec(),
        )),
        Request::WriteMultipleCoils(a, bits) => {
            let r = range(a, bits.len())?;
            s.coils[r].copy_from_slice(&bits);
            s.writes.push((15, a, bits.len() as u16));
            Ok(Response::WriteMultipleCoils(a, bits.len() as u16))
        }
        Request::WriteSingleCoil(a, v) => {
            let r = range(a, 1)?;
            s.coils[r.start] = v;
            s.writes.push((5, a, 1));
            Ok(Response::WriteSingleCoil(a, v))
        }
        Request::WriteMultipleRegisters(a, words) => {
            let r = range(a, words.len())?;
            s.holding[r].copy_from_slice(&words);
            s.writes.push((16, a, words.len() as u16));
            Ok(Response::WriteMultipleRegisters(a, words.len() as u16))
        }
        Request::WriteSingleRegister(a, w) => {
            let r = range(a, 1)?;
            s.holding[r.start] = w;
            s.writes.push((6, a, 1));
            Ok(Response::WriteSingleRegister(a, w))
        }
        _ => Err(ExceptionCode::IllegalFunction),
    }
}

impl tokio_modbus::server::Service for SimService {
    type Request = Request<'static>;
    type Response = Response;
    type Exception = ExceptionCode;
    type Future = Pin<Box<dyn Future<Output = Result<Response, ExceptionCode>> + Send>>;

    fn call(&self, req: Self::Request) -> Self::Future {
        let state = self.state.clone();
        let written = self.written.clone();
        Box::pin(async move {
            let is_write = matches!(
                req,
                Request::WriteMultipleCoils(..)
                    | Request::WriteSingleCoil(..)
                    | Request::WriteMultipleRegisters(..)
                    | Request::WriteSingleRegister(..)
            );
            let (delay, mute) = {
                let mut s = lock(&state);
                if is_write {
                    (s.delay, s.mute)
                } else {
                    s.reads_pending += 1;
                    (s.delay + s.read_delay, s.mute)
                }
            };
            if mute {
                std::future::pending::<()>().await;
            }
            if !delay.is_zero() {
                tokio::time::sleep(delay).await;
            }
            if !is_write {
                let mut s = lock(&state);
                s.reads_pending = s.reads_pending.saturating_sub(1);
                s.reads_done += 1;
            }
            let r = apply(&state, req);
            if is_write {
                written.notify_waiters();
                written.notify_one();
            }
            r
        })
    }
}
