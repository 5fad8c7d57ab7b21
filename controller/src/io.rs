//! Choosing the I/O behind packet A: the built-in simulation, Modbus TCP or CANopen.
//!
//! [`open_io`] is the one dispatch point. `sim` is the built-in simulated CNC and machine
//! (`<machine>/sim.toml`); `modbus` and `canopen` are the fieldbus crate's drivers, configured by
//! `<machine>/io.toml` and checked against the connectors IOCFIL declares. With real I/O, the map's
//! `[hmi]` table also starts the Modbus TCP server for HMI and SCADA. The simulation opens no
//! socket unless asked (`--modbus-hmi ADDR:PORT` puts the same server in front of it,
//! [`with_modbus_hmi`]), so simulated runs stay deterministic and can run side by side.

use std::path::Path;

use packets::PacketIo;

use sim::{CncSignals, HandshakeCounts, Script, Sim, SimError};

/// Why the I/O could not be opened.
#[derive(Debug, thiserror::Error)]
pub enum IoOpenError {
    /// The simulated CNC refused its script.
    #[error(transparent)]
    Sim(#[from] SimError),
    /// The I/O map (`io.toml`) or a driver setting is wrong.
    #[error("{rendered}")]
    Fieldbus {
        /// The located diagnostics.
        diagnostics: Vec<diag::Diagnostic>,
        /// Their rustc-style rendering with the lines of `io.toml`.
        rendered: String,
    },
}

/// Which I/O to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum IoKind {
    /// The built-in simulated CNC and machine (`<machine>/sim.toml`).
    Sim,
    /// Modbus TCP remote I/O (`<machine>/io.toml`).
    Modbus,
    /// CANopen remote I/O (`<machine>/io.toml`).
    Canopen,
}

/// Opens the I/O of `kind` for the machine in `machine_dir`; `declared` are the packet-A
/// connectors of IOCFIL, which the I/O map must respect.
///
/// May be called before the scan thread takes `SCHED_FIFO` ([`runtime::clock::enable_realtime`]):
/// the fieldbus drivers move their I/O threads to `SCHED_FIFO` ten below the scan at the first
/// latch (`fieldbus::rt`); the HMI server's thread stays an ordinary one.
pub fn open_io(
    kind: IoKind,
    machine_dir: &Path,
    declared: &fieldbus::DeclaredConnectors,
    script: Script,
    signals: CncSignals,
    tick_ms: u32,
) -> Result<Box<dyn PacketIo>, IoOpenError> {
    open_io_counted(kind, machine_dir, declared, script, signals, tick_ms).map(|(io, _)| io)
}

/// [`open_io`], plus the simulated CNC's handshake counts per process when `kind` is `sim`.
pub fn open_io_counted(
    kind: IoKind,
    machine_dir: &Path,
    declared: &fieldbus::DeclaredConnectors,
    script: Script,
    signals: CncSignals,
    tick_ms: u32,
) -> Result<(Box<dyn PacketIo>, Option<HandshakeCounts>), IoOpenError> {
    open_io_with(kind, machine_dir, declared, script, signals, tick_ms, None)
}

/// [`open_io_counted`] with the HMI server on `hmi_bind` instead of io.toml's `[hmi] bind`
/// (`ncplc run --modbus-hmi`); with `sim` the server starts only when `hmi_bind` is given.
pub fn open_io_with(
    kind: IoKind,
    machine_dir: &Path,
    declared: &fieldbus::DeclaredConnectors,
    script: Script,
    signals: CncSignals,
    tick_ms: u32,
    hmi_bind: Option<std::net::SocketAddr>,
) -> Result<(Box<dyn PacketIo>, Option<HandshakeCounts>), IoOpenError> {
    let bus = match kind {
        IoKind::Sim => {
            let sim = Sim::new(script, signals, tick_ms)?;
            let counts = sim.counts();
            let io: Box<dyn PacketIo> = Box::new(sim);
            let io = match hmi_bind {
                Some(bind) => with_modbus_hmi(machine_dir, declared, io, bind)?,
                None => io,
            };
            return Ok((io, Some(counts)));
        }
        IoKind::Modbus => fieldbus::IoKind::Modbus,
        IoKind::Canopen => fieldbus::IoKind::Canopen,
    };
    let io = fieldbus::open(bus, machine_dir, declared).map_err(|d| map_error(machine_dir, d))?;
    Ok((modbus_hmi(machine_dir, declared, io, hmi_bind)?, None))
}

/// Puts the Modbus TCP HMI/SCADA server of io.toml's `[hmi]` table, listening on `bind`, in front
/// of `io` (the simulated machine, with or without the CNC kernel: `ncplc run --modbus-hmi`).
pub fn with_modbus_hmi(
    machine_dir: &Path,
    declared: &fieldbus::DeclaredConnectors,
    io: Box<dyn PacketIo>,
    bind: std::net::SocketAddr,
) -> Result<Box<dyn PacketIo>, IoOpenError> {
    modbus_hmi(machine_dir, declared, io, Some(bind))
}

/// Starts the Modbus HMI server of io.toml in front of `io` (if io.toml has one, or `bind` asks
/// for it) and says on stderr where it listens.
fn modbus_hmi(
    machine_dir: &Path,
    declared: &fieldbus::DeclaredConnectors,
    io: Box<dyn PacketIo>,
    bind: Option<std::net::SocketAddr>,
) -> Result<Box<dyn PacketIo>, IoOpenError> {
    let (io, addr) = fieldbus::start_hmi_listening(machine_dir, declared, io, bind)
        .map_err(|d| map_error(machine_dir, d))?;
    if let Some(addr) = addr {
        eprintln!("modbus-hmi: listening on {addr}");
    }
    Ok(io)
}

/// The located diagnostics of io.toml, rendered with its lines (as text).
pub(crate) fn render_map_error(machine_dir: &Path, diagnostics: Vec<diag::Diagnostic>) -> String {
    map_error(machine_dir, diagnostics).to_string()
}

/// The located diagnostics of io.toml, rendered with its lines.
fn map_error(machine_dir: &Path, diagnostics: Vec<diag::Diagnostic>) -> IoOpenError {
    let map = machine_dir.join("io.toml");
    let mut sources = diag::Sources::new();
    if let Ok(text) = diag::read_config(&map) {
        for d in &diagnostics {
            sources.add(d.file.clone(), text.clone());
        }
    }
    IoOpenError::Fieldbus {
        rendered: runtime::render::render_diagnostics(&diagnostics, &sources),
        diagnostics,
    }
}
