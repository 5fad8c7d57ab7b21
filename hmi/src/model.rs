//! What the HMI shows and what it asks for: the published [`Snapshot`], the static [`Catalog`] of
//! names and source, the [`MachineStatus`] interface the runtime fills, and the [`Request`]s that
//! travel back to the scan.

use std::sync::Arc;

use packets::Signal;
use serde::{Deserialize, Serialize, Serializer};

/// One published state of the running controller (the latest value of the live channel).
#[derive(Debug, Clone, Default, Serialize)]
pub struct Snapshot {
    /// Ticks run so far.
    pub tick: u64,
    /// The running engine (`jit`, `interp`).
    pub engine: String,
    /// The logic tick in ms.
    pub tick_ms: u32,
    /// Scan timing.
    pub scan: ScanStats,
    /// Packets A, K, N and T as hex (two digits per image byte, packet order).
    #[serde(serialize_with = "hex")]
    pub image: Vec<u8>,
    /// Active forces, in image order.
    #[serde(serialize_with = "signal_values")]
    pub forced: Vec<(Signal, u8)>,
    /// Machine-wide alarms (I/O, overrun trips, the scripted CNC's timeouts) until acknowledged.
    pub alarms: Vec<AlarmEntry>,
    /// The PLC's messages (docs/plc-messages.md) until acknowledged, oldest first.
    pub messages: Vec<MessageEntry>,
    /// Online change: compiling, running since tick N, or the diagnostics of a refused edit.
    pub online: String,
    /// Per-process CNC state.
    pub machine: MachineStatus,
    /// True after the overrun limit tripped the safe state.
    pub tripped: bool,
    /// Power flow from the scan: `[line, value]` per statement of the PLC program (the assigned
    /// value, or the condition of IF/SET/RES/one-shot/timer/counter inputs), in source order of
    /// the statements; empty when the program was not compiled for it.
    pub flow: Vec<(u32, f64)>,
    /// Power flow is switched on (`POST /api/flow`, `--hmi-flow`); `flow` fills once the scan
    /// runs the instrumented program.
    pub flow_enabled: bool,
    /// Where MDI lines were compiled so far (None: no CNC kernel runs).
    pub mdi_compiles: Option<MdiCompiles>,
    /// The tool path of each process with interpolated axes (served by `GET /api/toolpath/<P>`,
    /// not sent on `/ws`).
    #[serde(skip)]
    pub toolpaths: Vec<Toolpath>,
}

/// One entry of an alarm list: listed from the tick it was raised until it is acknowledged
/// (`POST /api/command {"command":"ack"}`) and its cause has gone.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct AlarmEntry {
    /// The message.
    pub text: String,
    /// Its cause still holds.
    pub active: bool,
    /// The operator acknowledged it while its cause held.
    pub acknowledged: bool,
    /// The tick it was (last) raised at.
    pub tick: u64,
}

/// One PLC message (docs/plc-messages.md): listed from the tick its request bit rose until it is
/// acknowledged and its bit has fallen, with the alarm lists' rules.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct MessageEntry {
    /// The process whose request bits raised it (1..5).
    pub process: u8,
    /// The message number (1..64).
    pub number: u8,
    /// Its text from the message file (`PLC message n` without one).
    pub text: String,
    /// OPC UA severity 1..1000 (from MSGPRIO at the rising edge).
    pub severity: u16,
    /// Its request bit is still 1.
    pub active: bool,
    /// The operator acknowledged it while its bit was 1.
    pub acknowledged: bool,
    /// The tick whose scan raised it (the trace record with the bit's rising edge).
    pub tick: u64,
}

/// The tool path of one process in the plane of two of its axes.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Toolpath {
    /// Process number, 1-based.
    pub process: u8,
    /// Changes whenever another program is loaded (the page fetches the path again).
    pub id: u64,
    /// The drawn axes: (horizontal, vertical), e.g. `["Z","X"]` on a lathe.
    pub axes: [String; 2],
    /// The loaded program's name.
    pub program: String,
    /// The programmed path from the plan (rapids and feeds), shared between snapshots.
    #[serde(serialize_with = "shared")]
    pub programmed: Arc<Vec<PathPiece>>,
    /// Set points sampled since the program was loaded (at most a few thousand points: a point is
    /// kept when the set point has moved on from the last one).
    pub actual: Vec<[f64; 2]>,
}

/// A drawn piece of the programmed path.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PathPiece {
    /// Rapid traverse (drawn dashed) or feed (solid).
    pub rapid: bool,
    /// Points in the view's (horizontal, vertical) coordinates.
    pub points: Vec<[f64; 2]>,
}

/// Where the MDI lines of a run were compiled and planned: on the HMI's request thread (beside
/// the scan) or on the scan thread itself (the axes moved between the compile and the scan's
/// load, or the CLI's `--mdi`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct MdiCompiles {
    /// Compiled on the request thread.
    pub requests: u64,
    /// Compiled on the scan thread.
    pub scan: u64,
}

/// Scan timing figures.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ScanStats {
    /// Median scan time in µs (of the scans sampled at each published frame).
    pub scan_p50_us: f64,
    /// Longest scan time in µs.
    pub scan_max_us: f64,
    /// Overruns so far.
    pub overruns: u64,
}

/// The CNC side as the Machine page shows it; the runtime fills what it knows.
#[derive(Debug, Clone, Default, Serialize)]
pub struct MachineStatus {
    /// One entry per process 1..NBP.
    pub processes: Vec<ProcessStatus>,
}

/// One process (channel) of the CNC.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ProcessStatus {
    /// Process number, 1-based.
    pub process: u8,
    /// Operating mode (`AUTO`, `STEP`, `MDI`, `MANU`, `MANJ`, `HOME`, `IDLE` from the kernel, or
    /// the raw MODE byte as `code N`).
    pub mode: Option<String>,
    /// Interpreter state: `idle`, `running`, `held` (feed hold in effect) or `paused`.
    pub state: Option<String>,
    /// Machine on (e-stop chain closed, no stopping alarm).
    pub on: Option<bool>,
    /// Every axis with a homing cycle is homed.
    pub homed: Option<bool>,
    /// The running partprogram's name.
    pub program: Option<String>,
    /// The current block's number (its N word), when it has one.
    pub block: Option<u64>,
    /// The current block's position in the program, 1-based.
    pub block_index: Option<u64>,
    /// The current block's source line.
    pub block_source: Option<String>,
    /// Axes with command, actual and following error.
    pub axes: Vec<AxisStatus>,
    /// Feed override in %.
    pub feed_override: Option<u32>,
    /// Spindle override in %.
    pub spindle_override: Option<u32>,
    /// Rapid override in %.
    pub rapid_override: Option<u32>,
    /// Actual spindle speed (rev/min).
    pub spindle_speed: Option<f64>,
    /// Path speed of the interpolator (mm/min; 0 when stopped or held).
    pub path_speed: Option<f64>,
    /// The current block's codes: motion (G00/G01/G02/G03/G04), F, S, T and its M functions.
    pub active_codes: Vec<String>,
    /// The modal codes in effect at the current block: motion mode, plane, F, S, T, spindle
    /// and coolant M functions (from the kernel's program; empty without a kernel).
    pub modal_codes: Vec<String>,
    /// This process's alarms until acknowledged.
    pub alarms: Vec<AlarmEntry>,
    /// The [`Toolpath::id`] of this process's tool path (none: no interpolated axes).
    pub toolpath: Option<u64>,
    /// Completed M/S/T handshakes and strobe timeouts of this process.
    pub handshakes: Option<HandshakeCounts>,
    /// Which commands this process accepts now (empty: commands are not wired).
    pub commands: Vec<String>,
}

/// One axis' position readout.
#[derive(Debug, Clone, Default, Serialize)]
pub struct AxisStatus {
    /// Axis name (`X`, `Z`, …).
    pub name: String,
    /// Commanded position.
    pub command: f64,
    /// Actual position.
    pub actual: f64,
    /// Command minus actual.
    pub following_error: f64,
    /// The SRV limit in force: `stand-by` (at rest), `VFF` (moving with feed-forward) or
    /// `no-VFF` (moving without); empty without a kernel.
    pub limit: String,
    /// Its value in mm (0 = unchecked).
    pub limit_mm: f64,
    /// The largest |following error| since power-on (mm).
    pub largest: f64,
}

/// M/S/T handshake counts of a process.
#[derive(Debug, Clone, Default, Serialize)]
pub struct HandshakeCounts {
    /// M functions completed.
    pub m: u64,
    /// S functions completed.
    pub s: u64,
    /// T functions completed.
    pub t: u64,
    /// Strobe timeouts.
    pub timeouts: u64,
}

/// A named signal of the Signals page.
#[derive(Debug, Clone, Serialize)]
pub struct NamedSignal {
    /// The name.
    pub name: String,
    /// The address.
    #[serde(serialize_with = "display")]
    pub signal: Signal,
    /// Where the name comes from: `interface` (the interface map) or `program` (a `DEF` alias).
    pub origin: &'static str,
    /// What it means (interface map), or empty.
    pub meaning: String,
}

/// One line of the PLC source with the signal its statement writes (the Program page).
#[derive(Debug, Clone, Serialize)]
pub struct SourceLine {
    /// 1-based line number.
    pub line: usize,
    /// The text.
    pub text: String,
    /// Packet signals written on this line (their value after the scan is the rung's result).
    pub writes: Vec<String>,
    /// Packet signals read on this line.
    pub reads: Vec<String>,
}

/// Static facts of the running machine: names and the PLC source.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Catalog {
    /// The machine directory's name.
    pub machine: String,
    /// Interface-map names and program aliases.
    pub names: Vec<NamedSignal>,
    /// The PLC source file name.
    pub source_name: String,
    /// The PLC source, line by line.
    pub source: Vec<SourceLine>,
}

impl Catalog {
    /// The signal named `text`: an address (`I0A3`) or a name of the catalog.
    pub fn resolve(&self, text: &str) -> Option<Signal> {
        if let Ok(s) = text.parse::<Signal>() {
            return Some(s);
        }
        self.names.iter().find(|n| n.name == text).map(|n| n.signal)
    }
}

/// An operator command for a CNC process (the same channel the CLI uses; traces record it in the
/// same JSON form).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "command", rename_all = "lowercase")]
pub enum Command {
    /// CYCLE START.
    Start,
    /// FEED HOLD.
    Hold,
    /// RESET.
    Reset,
    /// Select an operating mode.
    Mode {
        /// The mode's name.
        mode: String,
    },
    /// Run one MDI line.
    Mdi {
        /// The line.
        line: String,
    },
    /// Acknowledge the alarms (of the process, or all without one).
    Ack,
}

/// A request from the HMI to the scan, applied at the next tick boundary.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Request {
    /// Write a value once (the program may overwrite it).
    Write(Signal, u8),
    /// Force a value before and after every scan.
    Force(Signal, u8),
    /// Remove one force.
    Unforce(Signal),
    /// Remove every force.
    UnforceAll,
    /// Switch power flow on (true) or off.
    Flow(bool),
    /// An operator command for process `process` (0 for `ack`: every process and the machine).
    Command {
        /// 1-based process number; 0 only with [`Command::Ack`].
        process: u8,
        /// What to do.
        command: Command,
    },
}

/// What the scan answers: the tick that applied the request, or why it refused it.
pub type Reply = Result<u64, String>;

/// A request with the channel its reply goes back on.
#[derive(Debug)]
pub struct Envelope {
    /// The request.
    pub request: Request,
    /// The role of the session that sent it (traces record it with a command).
    pub role: crate::security::Role,
    /// Where the scan sends its answer.
    pub reply: tokio::sync::oneshot::Sender<Reply>,
}

/// The shared, immutable part of a snapshot stream.
pub type SharedSnapshot = Arc<Snapshot>;

fn hex<S: Serializer>(bytes: &[u8], s: S) -> Result<S::Ok, S::Error> {
    const DIGITS: &[u8; 16] = b"0123456789abcdef";
    let mut out = String::with_capacity(bytes.len() * 2);
    for b in bytes {
        out.push(char::from(DIGITS[usize::from(b >> 4)]));
        out.push(char::from(DIGITS[usize::from(b & 15)]));
    }
    s.serialize_str(&out)
}

fn shared<S: Serializer, T: Serialize>(v: &Arc<T>, s: S) -> Result<S::Ok, S::Error> {
    T::serialize(v, s)
}

fn display<S: Serializer>(sig: &Signal, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(sig)
}

fn signal_values<S: Serializer>(list: &[(Signal, u8)], s: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeSeq;
    let mut seq = s.serialize_seq(Some(list.len()))?;
    for (sig, v) in list {
        seq.serialize_element(&serde_json::json!({"signal": sig.to_string(), "value": v}))?;
    }
    seq.end()
}
