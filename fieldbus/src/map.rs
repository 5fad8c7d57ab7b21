//! The I/O map file `<machine>/io.toml`: which packet-A bytes come from or go to which device.
//!
//! The file has up to six parts, all optional:
//!
//! ```toml
//! [hmi]                                   # Modbus TCP server for an HMI or SCADA
//! bind = "127.0.0.1:1502"
//! holding = [{ byte = "W200K0", len = 4 }]   # the writable window (K/N bytes)
//! unit = 1                                # the unit id clients address (default 1)
//! max_connections = 8                     # open connections at once (default 8)
//! max_requests_per_s = 100                # per connection (default 100; more: exception 06)
//! idle_timeout_ms = 60000                 # close a connection silent this long (default 60 s)
//!
//! [[modbus.device]]                       # remote I/O reached as a Modbus TCP client
//! name = "rio1"
//! address = "127.0.0.1:5020"
//! unit = 1
//! healthy = "I100K0"                      # bit the driver sets while the device answers
//!
//! [canopen]                               # CANopen master
//! transport = "virtual"                   # virtual | socketcan | cannelloni
//! [[canopen.node]]
//! name = "dio1"
//! node_id = 2
//! heartbeat_ms = 100
//! [[canopen.drive]]                       # a CiA 402 servo drive (docs/drives.md)
//! axis = "X"                              # AXCFIL axis name (process = n when not 1)
//! node_id = 3
//! counts_per_unit = 10000                 # drive position units per mm, degree or revolution
//! mode = "csp"                            # csp (axes) | csv (spindle)
//! heartbeat_ms = 50
//!
//! [[input]]                               # device → packet A input connector bytes
//! device = "rio1"
//! connector = 0                           # or byte = "W0A1" with len = n
//! area = "discrete_inputs"                # Modbus: discrete_inputs | coils | input_registers | holding_registers
//! address = 0
//! fail = 0                                # value the bytes take while the device is lost
//!
//! [affinity]                              # optional: pin the drivers' I/O threads
//! io_cpus = [1]                           # CPU indices (0-based), e.g. the NIC interrupt's core
//!
//! [[output]]                              # packet A output connector bytes → device
//! device = "dio1"
//! connector = 4
//! pdo = 1                                 # CANopen: RPDO number (TPDO for an input), byte offset in it
//! offset = 0
//! ```
//!
//! This module holds the raw serde form (with spans) and the validated model; [`crate::validate`]
//! turns one into the other and reports located diagnostics (codes in `fieldbus/DIAGNOSTICS.md`).

use std::net::SocketAddr;
use std::time::Duration;

use packets::Signal;
use serde::Deserialize;
use toml::Spanned;

/// Packet-A connectors the machine's IOCFIL declares (`INx` inputs, `OUx` outputs).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct DeclaredConnectors {
    /// Input connector numbers (IOCFIL `INx`).
    pub inputs: Vec<u16>,
    /// Output connector numbers (IOCFIL `OUx`).
    pub outputs: Vec<u16>,
}

/// A run of consecutive bytes of packet A (offsets inside the packet, which is also the image offset).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ByteRange {
    /// First byte (0..127).
    pub start: usize,
    /// Number of bytes (≥ 1).
    pub len: usize,
}

impl ByteRange {
    /// One past the last byte.
    pub fn end(&self) -> usize {
        self.start + self.len
    }
}

/// The four Modbus data tables.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ModbusArea {
    /// Read-only bits (function 2).
    DiscreteInputs,
    /// Read-write bits (functions 1, 15).
    Coils,
    /// Read-only 16-bit registers (function 4).
    InputRegisters,
    /// Read-write 16-bit registers (functions 3, 16).
    HoldingRegisters,
}

impl ModbusArea {
    /// True for the two bit tables (8 Modbus addresses per byte; else 2 bytes per register).
    pub fn is_bits(self) -> bool {
        matches!(self, ModbusArea::DiscreteInputs | ModbusArea::Coils)
    }

    /// Number of Modbus items (bits or registers) that `len` bytes occupy.
    pub fn items(self, len: usize) -> usize {
        if self.is_bits() {
            len * 8
        } else {
            len.div_ceil(2)
        }
    }
}

/// One mapping of packet-A bytes onto a Modbus data table.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ModbusMapping {
    /// The packet-A bytes.
    pub range: ByteRange,
    /// The table on the device.
    pub area: ModbusArea,
    /// First Modbus address (bit or register number, 0-based).
    pub address: u16,
    /// Fail state of an input / safe state of an output, applied to every byte.
    pub fail: u8,
}

/// A Modbus TCP remote-I/O device.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ModbusDevice {
    /// Name used in alarms.
    pub name: String,
    /// TCP address of the device.
    pub address: SocketAddr,
    /// Modbus unit id.
    pub unit: u8,
    /// Timeout of every request.
    pub timeout: Duration,
    /// Pause between two polls of the inputs (0 = back to back).
    pub poll: Duration,
    /// Writes go over a second connection of their own, so a write never waits behind a read
    /// already on the wire (`write_connection = false` for devices that accept one connection).
    pub write_connection: bool,
    /// With a write connection: the scan thread sends a write itself when that connection is idle
    /// (one non-blocking `send`; `direct_write = false` leaves every write to the I/O task).
    pub direct_write: bool,
    /// Ticks without a fresh answer after which the device is declared lost.
    pub alarm_ticks: u32,
    /// First reconnect delay; doubles after each failed attempt up to `reconnect_max`.
    pub reconnect_min: Duration,
    /// Longest reconnect delay.
    pub reconnect_max: Duration,
    /// Bit the driver keeps at 1 while the device answers.
    pub healthy: Option<Signal>,
    /// Device → packet A.
    pub inputs: Vec<ModbusMapping>,
    /// Packet A → device.
    pub outputs: Vec<ModbusMapping>,
}

/// A packet-A byte run carried in a PDO.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PdoMapping {
    /// The packet-A bytes.
    pub range: ByteRange,
    /// PDO number 1..4 (TPDO for inputs, RPDO for outputs).
    pub pdo: u8,
    /// Byte offset inside the PDO's 8 data bytes.
    pub offset: u8,
    /// Fail state of an input / safe state of an output, applied to every byte.
    pub fail: u8,
}

/// An SDO expedited write the master performs at start.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SdoWrite {
    /// Object index.
    pub index: u16,
    /// Sub-index.
    #[serde(default)]
    pub subindex: u8,
    /// Value (little-endian on the wire).
    pub value: u32,
    /// Size in bytes: 1, 2 or 4.
    pub size: u8,
}

/// A CANopen node (CiA 401 digital I/O module).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CanNode {
    /// Name used in alarms.
    pub name: String,
    /// Node id 1..127.
    pub node_id: u8,
    /// Heartbeat consumer time: the node is lost when no heartbeat arrives within it.
    pub heartbeat: Duration,
    /// Bit the driver keeps at 1 while the node is operational.
    pub healthy: Option<Signal>,
    /// SDO writes performed before NMT start.
    pub sdo: Vec<SdoWrite>,
    /// TPDO → packet A.
    pub inputs: Vec<PdoMapping>,
    /// Packet A → RPDO.
    pub outputs: Vec<PdoMapping>,
    /// Test hooks of the simulated node (`simulate = {…}`, `transport = "virtual"` only).
    pub simulate: NodeSimHooks,
}

/// What a simulated I/O node on the virtual bus is told to do wrong (io.toml `simulate`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct NodeSimHooks {
    /// Fall silent (no answer, no heartbeat) from this SYNC number on.
    pub silent_at_sync: Option<u64>,
}

/// The CiA 402 mode of operation a drive runs in (object `6060h`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DriveMode {
    /// Cyclic synchronous position (8): the target position every SYNC.
    Csp,
    /// Cyclic synchronous velocity (9): the target velocity every SYNC.
    Csv,
}

impl DriveMode {
    /// The value of object `6060h` for this mode.
    pub fn code(self) -> i8 {
        match self {
            DriveMode::Csp => 8,
            DriveMode::Csv => 9,
        }
    }
}

/// A CiA 402 servo drive on the CANopen bus, driving one AXCFIL axis or spindle.
#[derive(Debug, Clone, PartialEq)]
pub struct CanDrive {
    /// AXCFIL process number (1..5).
    pub process: u32,
    /// AXCFIL axis name (`S` for a spindle).
    pub axis: char,
    /// Node id 1..127.
    pub node_id: u8,
    /// Drive position units per axis unit (mm, degree or revolution); finite and > 0.
    pub counts_per_unit: f64,
    /// The mode of operation.
    pub mode: DriveMode,
    /// Heartbeat producer time the master writes to `1017h`; the consumer allows 3× this.
    pub heartbeat: Duration,
    /// Extra SDO writes after the standard configuration, before NMT start.
    pub sdo: Vec<SdoWrite>,
    /// Test hooks of the simulated drive (`simulate = {…}`, `transport = "virtual"` only).
    pub simulate: DriveSimHooks,
    /// Where the entry's `node_id` is in io.toml (bytes), for errors found at start-up.
    pub span: std::ops::Range<usize>,
    /// A `csp` drive whose axis has an MCZ homing cycle (or whose AXCFIL is not known): it gets
    /// the homing PDOs (touch probe `60B8h`–`60BAh`, digital inputs `60FDh`); a drive of an axis
    /// without MCZ (an absolute encoder) needs none of those objects.
    pub homing: bool,
}

/// What a simulated drive on the virtual bus is told to do wrong (io.toml `simulate`), so that
/// faults can be rehearsed through `ncplc run`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct DriveSimHooks {
    /// Fault at this SYNC number with this `603Fh` code.
    pub fault: Option<(u64, u16)>,
    /// Stop the heartbeat at this SYNC number.
    pub heartbeat_stop: Option<u64>,
    /// Never reach *Operation enabled*.
    pub refuse_enable: bool,
    /// Abort every SDO write to this object (index, sub-index) with this abort code.
    pub sdo_abort: Option<(u16, u8, u32)>,
    /// The drive's speed is limited to this (drive units per second): a `csv` drive's velocity
    /// actual never exceeds it, as with a maximum motor speed set too low.
    pub max_speed: Option<u32>,
    /// The machine behind the simulated drive (home switch, zero impulses) in axis units: not
    /// from io.toml but from the simulated machine (`sim.toml`, AXCFIL) of a part run.
    pub machine: Option<crate::canopen::drive_sim::SimMachine>,
}

/// An axis the machine's AXCFIL declares, as the drive validation needs it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DeclaredAxis {
    /// Process number (1..5).
    pub process: u32,
    /// Axis name.
    pub name: char,
    /// TPA axis type as written (the Table 4.1 codes summed); 0 when the axis has no TPA.
    pub tpa: u32,
    /// The axis has an MCZ homing cycle (its drive latches the reference mark for it).
    pub homes: bool,
}

/// How the CANopen master reaches the bus.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TransportConfig {
    /// An in-process virtual bus (tests, demos).
    Virtual,
    /// A Linux SocketCAN interface.
    SocketCan {
        /// Interface name, e.g. `can0`.
        interface: String,
    },
    /// CAN frames over UDP in the cannelloni format.
    Cannelloni {
        /// Local UDP address to bind.
        local: SocketAddr,
        /// The peer's UDP address.
        remote: SocketAddr,
    },
}

/// The CANopen part of the map.
#[derive(Debug, Clone, PartialEq)]
pub struct CanopenConfig {
    /// How to reach the bus.
    pub transport: TransportConfig,
    /// Timeout of one SDO transfer at start.
    pub sdo_timeout: Duration,
    /// The nodes.
    pub nodes: Vec<CanNode>,
    /// The CiA 402 drives (`[[canopen.drive]]`).
    pub drives: Vec<CanDrive>,
}

/// A K/N byte window the HMI may write (holding registers).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HmiWindow {
    /// First byte as an offset in the flat image (K or N).
    pub start: usize,
    /// Number of bytes.
    pub len: usize,
}

/// The HMI / SCADA Modbus TCP server.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HmiConfig {
    /// Address to bind (127.0.0.1 unless the map names another).
    pub bind: SocketAddr,
    /// The writable windows.
    pub holding: Vec<HmiWindow>,
    /// The unit id it answers and what one client may cost.
    pub limits: HmiLimits,
}

/// The Modbus HMI server's unit id and limits (`[hmi]` keys; defaults in [`HmiLimits::default`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HmiLimits {
    /// The unit id requests must name (`unit`, default 1).
    pub unit: u8,
    /// Most open connections (`max_connections`, default 8).
    pub max_connections: usize,
    /// Most requests per second on one connection (`max_requests_per_s`, default 100).
    pub max_requests_per_s: u32,
    /// A connection without a request byte for this long is closed (`idle_timeout_ms`,
    /// default 60 000).
    pub idle_timeout: Duration,
}

impl Default for HmiLimits {
    fn default() -> HmiLimits {
        HmiLimits {
            unit: 1,
            max_connections: 8,
            max_requests_per_s: 100,
            idle_timeout: Duration::from_secs(60),
        }
    }
}

/// A validated I/O map.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct IoMap {
    /// The HMI server, when the map has `[hmi]`.
    pub hmi: Option<HmiConfig>,
    /// Modbus TCP devices.
    pub modbus: Vec<ModbusDevice>,
    /// The CANopen master, when the map has `[canopen]`.
    pub canopen: Option<CanopenConfig>,
    /// CPUs the drivers' I/O threads are pinned to (`[affinity] io_cpus`; empty = unpinned).
    pub io_cpus: Vec<usize>,
}

// ---- raw serde form -------------------------------------------------------------------------

/// The file as written, with spans for the diagnostics.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawMap {
    pub hmi: Option<Spanned<RawHmi>>,
    pub modbus: Option<RawModbus>,
    pub canopen: Option<Spanned<RawCanopen>>,
    pub affinity: Option<Spanned<RawAffinity>>,
    /// The OPC UA server's tables (`[identification]`, `[[stacklight]]`): validated by crate
    /// `opcua-server` (docs/opcua.md), accepted here (serde reads them; nothing else does).
    #[allow(dead_code)]
    pub identification: Option<toml::Value>,
    /// See `identification`.
    #[allow(dead_code)]
    pub stacklight: Option<toml::Value>,
    #[serde(default)]
    pub input: Vec<Spanned<RawMapping>>,
    #[serde(default)]
    pub output: Vec<Spanned<RawMapping>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawAffinity {
    pub io_cpus: Option<Spanned<Vec<Spanned<u64>>>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawHmi {
    pub bind: Option<Spanned<String>>,
    pub unit: Option<Spanned<u32>>,
    pub max_connections: Option<Spanned<u32>>,
    pub max_requests_per_s: Option<Spanned<u32>>,
    pub idle_timeout_ms: Option<Spanned<u64>>,
    #[serde(default)]
    pub holding: Vec<Spanned<RawWindow>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawWindow {
    pub byte: Spanned<String>,
    pub len: Option<Spanned<u32>>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawModbus {
    #[serde(default)]
    pub device: Vec<Spanned<RawModbusDevice>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawModbusDevice {
    pub name: Spanned<String>,
    pub address: Spanned<String>,
    pub unit: Option<Spanned<u32>>,
    pub timeout_ms: Option<Spanned<u64>>,
    pub poll_us: Option<Spanned<u64>>,
    pub write_connection: Option<Spanned<bool>>,
    pub direct_write: Option<Spanned<bool>>,
    pub alarm_ticks: Option<Spanned<u32>>,
    pub reconnect_ms: Option<Spanned<u64>>,
    pub reconnect_max_ms: Option<Spanned<u64>>,
    pub healthy: Option<Spanned<String>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCanopen {
    pub transport: Option<Spanned<String>>,
    pub interface: Option<Spanned<String>>,
    pub local: Option<Spanned<String>>,
    pub remote: Option<Spanned<String>>,
    pub sdo_timeout_ms: Option<Spanned<u64>>,
    #[serde(default)]
    pub node: Vec<Spanned<RawCanNode>>,
    #[serde(default)]
    pub drive: Vec<Spanned<RawCanDrive>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCanDrive {
    pub axis: Spanned<String>,
    pub process: Option<Spanned<u32>>,
    pub node_id: Spanned<u32>,
    pub counts_per_unit: Spanned<f64>,
    pub mode: Spanned<String>,
    pub heartbeat_ms: Option<Spanned<u64>>,
    #[serde(default)]
    pub sdo: Vec<Spanned<SdoWrite>>,
    pub simulate: Option<Spanned<RawDriveSim>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawDriveSim {
    pub fault_at_sync: Option<u64>,
    pub fault_code: Option<u16>,
    pub heartbeat_stop_at_sync: Option<u64>,
    #[serde(default)]
    pub refuse_enable: bool,
    pub sdo_abort: Option<RawSdoAbort>,
    pub max_speed: Option<u32>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawSdoAbort {
    pub index: u16,
    pub subindex: u8,
    pub code: u32,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCanNode {
    pub name: Spanned<String>,
    pub node_id: Spanned<u32>,
    pub heartbeat_ms: Option<Spanned<u64>>,
    pub healthy: Option<Spanned<String>>,
    #[serde(default)]
    pub sdo: Vec<Spanned<SdoWrite>>,
    pub simulate: Option<Spanned<RawNodeSim>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawNodeSim {
    pub silent_at_sync: Option<u64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawMapping {
    pub device: Spanned<String>,
    pub connector: Option<Spanned<u32>>,
    pub byte: Option<Spanned<String>>,
    pub len: Option<Spanned<u32>>,
    pub area: Option<Spanned<ModbusArea>>,
    pub address: Option<Spanned<u32>>,
    pub pdo: Option<Spanned<u32>>,
    pub offset: Option<Spanned<u32>>,
    pub fail: Option<Spanned<u32>>,
    pub safe: Option<Spanned<u32>>,
}
