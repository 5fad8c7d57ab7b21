//! Choosing the I/O behind packet A: the built-in simulation, Modbus TCP or CANopen.
//!
//! [`open_io`] is the one dispatch point; the lead wires the fieldbus crate's `PacketIo`
//! implementations into its `Modbus` and `Canopen` arms.

use std::path::Path;

use packets::PacketIo;

use crate::sim::{CncSignals, Script, Sim};

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

/// Opens the I/O of `kind` for the machine in `machine_dir`.
pub fn open_io(
    kind: IoKind,
    machine_dir: &Path,
    script: Script,
    signals: CncSignals,
    tick_ms: u32,
) -> Result<Box<dyn PacketIo>, String> {
    match kind {
        IoKind::Sim => Ok(Box::new(
            Sim::new(script, signals, tick_ms).map_err(|e| e.to_string())?,
        )),
        IoKind::Modbus | IoKind::Canopen => Err(format!(
            "--io {kind:?}: the fieldbus drivers are not wired into the runtime yet (map file {})",
            machine_dir.join("io.toml").display()
        )
        .to_lowercase()),
    }
}
