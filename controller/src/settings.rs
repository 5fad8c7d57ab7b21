//! The typed choices a [`crate::Builder`] collects, one type per step: engine, I/O, CNC part,
//! recording, servers and clock. Plain data: nothing here opens, compiles or validates.

use std::net::SocketAddr;
use std::path::PathBuf;

pub use crate::io::IoKind;
pub use crate::part_run::{PartSpec, VarsSource};
pub use runtime::compiled::EngineKind;

/// The engine step: which back end runs the PLC program, and power flow.
#[derive(Debug, Clone)]
pub struct Engine {
    /// JIT (cranelift) or the reference interpreter.
    pub kind: EngineKind,
    /// Start with power flow instrumented (`--hmi-flow`; switchable at run time).
    pub flow: bool,
}

/// The I/O step: what is behind packet A.
#[derive(Debug, Clone)]
pub struct Io {
    /// The built-in simulation, Modbus TCP or CANopen (drives on the fieldbus: a further kind of
    /// [`IoKind`] opened in [`crate::io::open_io_with`]).
    pub kind: IoKind,
}

/// The CNC step: a partprogram (and MDI) run on the CNC kernel behind the simulated I/O.
#[derive(Debug, Clone, Default)]
pub struct Part {
    /// Program, process, dialect, MDI blocks, kor-change, macro-variable source.
    pub spec: PartSpec,
    /// Write the set points of every interpolation tick here (JSON Lines).
    pub trajectory: Option<PathBuf>,
    /// Stop when every selected program has ended (or a stopping alarm).
    pub until_end: bool,
}

/// The recording step: a trace of the run.
#[derive(Debug, Clone)]
pub struct Recording {
    /// The trace file (text; `.ptrace` or `.bin`: binary).
    pub path: PathBuf,
    /// Sync to disk at least this often (ms).
    pub flush_ms: u64,
}

/// The web HMI's settings.
#[derive(Debug, Clone)]
pub struct Hmi {
    /// Where it listens.
    pub addr: SocketAddr,
    /// Everyone is a viewer: writes, forces, commands and the power-flow switch refused.
    pub readonly: bool,
    /// Read the tokens and their roles from this file (else one integrator token is generated
    /// and printed in the start URL; docs/hmi-security.md).
    pub token_file: Option<PathBuf>,
    /// More names the `Host` header may give (`--hmi-allow-host`).
    pub allow_hosts: Vec<String>,
    /// More origins a state-changing request or WebSocket may come from (`--hmi-allow-origin`).
    pub allow_origins: Vec<String>,
    /// Serve HTTPS with these PEM files (`--hmi-tls-cert`, `--hmi-tls-key`).
    pub tls: Option<hmi::security::tls::TlsFiles>,
    /// Request body, client and WebSocket limits.
    pub limits: hmi::security::limits::Limits,
}

/// The clock step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Clock {
    /// Real time with absolute deadlines; busy-wait the last `spin_us` µs before each tick.
    Real {
        /// Busy-wait time before each tick (µs).
        spin_us: u64,
    },
    /// Unthrottled virtual time.
    Virtual,
}

/// How the scan runs: ticks, tick length, overruns, online change, retain, CPU.
#[derive(Debug, Clone)]
pub struct Scan {
    /// Stop after this many ticks.
    pub ticks: Option<u64>,
    /// Override the machine's logic tick (ms).
    pub tick_ms: Option<u32>,
    /// Consecutive overruns that trip the safe state (0: never).
    pub overrun_limit: u32,
    /// Watch the PLC source for online change.
    pub watch: bool,
    /// Keep retained data in this file instead of the machine's.
    pub retain_file: Option<PathBuf>,
    /// Pin the scan thread to this CPU.
    pub scan_cpu: Option<usize>,
}

impl Default for Scan {
    fn default() -> Scan {
        Scan {
            ticks: None,
            tick_ms: None,
            overrun_limit: 3,
            watch: true,
            retain_file: None,
            scan_cpu: None,
        }
    }
}
