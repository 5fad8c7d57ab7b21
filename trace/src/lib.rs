//! I/O traces: per tick, the inputs applied and the outputs that changed.
//!
//! One record schema ([`TickRecord`]) with two encodings: JSON Lines for CI and hand-written tests
//! ([`text`]) and postcard + COBS for long captures ([`binary`]). [`Trace::load`] reads either
//! (a text trace starts with `{`). [`recorder`] turns a running image into records and [`compare`]
//! finds where a replay departs from a trace.
//!
//! | module | concept |
//! |---|---|
//! | [`text`], [`binary`] | the two encodings of one [`Trace`] |
//! | [`reader`] | a trace of either form read record by record (constant memory) |
//! | [`recorder`] | a running image's changes as [`TickRecord`]s |
//! | [`durable`] | the recording's writer thread (`<file>.partial`, periodic sync, rename at the end) |
//! | [`recover`] | the complete records of a torn `.partial` |
//! | [`positions`] | a part run's per-change axis positions and their exact comparison |
//! | [`compare`] | where a replay departs from a trace (divergence report) |
//!
//! **Invariants:** this crate knows packets and bytes only (no program, scheduler or kernel): it
//! depends on `packets`, and on `hmi` for the operator command a record carries, nothing else of
//! ours. Both encodings carry the same records; a trace
//! read from either and written to the other compares equal. Nothing here panics on input bytes.

pub mod binary;
pub mod compare;
pub mod durable;
pub mod positions;
pub mod reader;
pub mod recorder;
pub mod recover;
pub mod text;

use std::io::Write;
use std::path::Path;

use packets::Signal;

pub use durable::{DurableOptions, DurableSink};
use serde::{Deserialize, Serialize};

/// The trace format version written and understood.
pub const VERSION: u32 = 1;

/// A signal and its value (0/1 for a bit, 0..255 for a byte).
pub type SignalValue = (Signal, u8);

/// The changes of one tick.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct TickRecord {
    /// Tick number, from 0.
    pub t: u64,
    /// Values written into the image at the start of the tick, before the scan.
    pub inputs: Vec<SignalValue>,
    /// Written signals whose value at the end of the tick differs from the end of the previous one.
    pub outputs: Vec<SignalValue>,
    /// Values an HMI force put back into the image after the scan (where the logic had changed
    /// them); a replay writes them after its scan, so a session with forces replays exactly.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub forced: Vec<SignalValue>,
    /// Axis positions of a part run that changed during the tick (the simulated drives' actual
    /// positions after the kernel's step, as f64 bits so that a comparison is exact).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub positions: Vec<AxisValue>,
    /// Operator commands (START, HOLD, RESET, mode, MDI from the HMI) the kernel accepted at the
    /// boundary before this tick; a replay gives them to its kernel before the tick's latch.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub commands: Vec<OperatorCommand>,
    /// The bus drives' feedback the kernel took at this tick's latch (a part run on CiA 402
    /// drives), recorded when it differs from the last recorded one; a replay feeds the last
    /// recorded feedback to its kernel instead of the bus.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub drives: Vec<DriveSample>,
    /// The I/O nodes the CANopen master declared lost at this tick's latch (its heartbeat
    /// consumer): the kernel's stopping alarm; a replay raises it again at the same tick.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub nodes_lost: Vec<NodeLoss>,
}

impl TickRecord {
    /// The record of tick `t` with nothing in it (what a recording ends with, and a test's start).
    pub fn at(t: u64) -> TickRecord {
        TickRecord {
            t,
            ..TickRecord::default()
        }
    }
}

/// An I/O node lost at one tick: its io.toml name, node id and why (the master's fault text).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct NodeLoss {
    /// The node's name in io.toml.
    pub name: String,
    /// The node id.
    pub node: u8,
    /// Why it is lost (`heartbeat lost`, `no answer`, …).
    pub why: String,
}

/// One bus drive's feedback for one logic tick: the answers to that tick's SYNCs.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct DriveSample {
    /// The axis (`S` for a spindle).
    pub axis: AxisId,
    /// Per interpolation tick, the drive's actual value as f64 bits (position for `csp`,
    /// velocity for `csv`); `null` where the drive gave no healthy answer.
    pub values: Vec<Option<u64>>,
    /// The statusword of the last answer (`6041h`).
    pub statusword: u16,
    /// Whose set points the answers answer: those of `age` ticks before (1, the previous
    /// tick's, is the rule and is not written; a late master in real time makes it more).
    #[serde(default = "one", skip_serializing_if = "is_one")]
    pub age: u32,
    /// The drive's fault, while it has one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fault: Option<DriveFaultRecord>,
    /// The digital inputs `60FDh` of the last answer (`csp` drives; bit 2: the home switch); 0
    /// is not written (traces written before homing on drives read as 0).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub inputs: u32,
    /// The touch probe status `60B9h` of the last answer; 0 is not written.
    #[serde(default, skip_serializing_if = "is_zero16")]
    pub probe_status: u16,
    /// The touch probe's latched position (`60BAh`, axis units on the drive's scale) as f64
    /// bits, while the drive says it stored one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub probe: Option<u64>,
}

#[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
fn is_zero(v: &u32) -> bool {
    *v == 0
}

#[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
fn is_zero16(v: &u16) -> bool {
    *v == 0
}

fn one() -> u32 {
    1
}

#[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
fn is_one(v: &u32) -> bool {
    *v == 1
}

/// A drive fault as a trace records it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct DriveFaultRecord {
    /// Node id.
    pub node: u8,
    /// The error code (`603Fh`, or the CiA 301 code of the master's own cause).
    pub code: u16,
    /// `drive`, `heartbeat`, `nmt` or `enable`.
    pub cause: String,
}

/// A drive of a part run on the bus, as the trace header names it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct HeaderDrive {
    /// The axis (`S` for a spindle).
    pub axis: AxisId,
    /// Node id.
    pub node: u8,
}

/// An operator command as a trace records it: `{"process":1,"command":"hold"}` (the body of
/// `POST /api/command`).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct OperatorCommand {
    /// The process, 1..5.
    pub process: u8,
    /// What the operator did.
    #[serde(flatten)]
    pub command: hmi::Command,
    /// The role of the HMI session that sent it (`"role":"operator"`; absent in traces written
    /// before roles, which read as before).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub role: Option<hmi::Role>,
}

/// An axis of a part-run trace: its process and letter, written `1X` (process 1, axis X).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct AxisId {
    /// The process, 1..5.
    pub process: u8,
    /// The axis letter.
    pub axis: char,
}

impl std::fmt::Display for AxisId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}{}", self.process, self.axis)
    }
}

impl std::str::FromStr for AxisId {
    type Err = String;

    fn from_str(s: &str) -> Result<AxisId, String> {
        let mut chars = s.chars();
        let process = chars
            .next()
            .and_then(|c| c.to_digit(10))
            .filter(|p| (1..=5).contains(p));
        let axis = chars.next().filter(|c| c.is_ascii_uppercase());
        match (process, axis, chars.next()) {
            (Some(p), Some(axis), None) => Ok(AxisId {
                process: p as u8,
                axis,
            }),
            _ => Err(format!(
                "`{s}` is not an axis (process 1..5 and a letter: `1X`)"
            )),
        }
    }
}

/// An axis and its position as the bits of an f64.
pub type AxisValue = (AxisId, u64);

/// What a part-run trace needs to re-run the CNC kernel in a replay: the partprograms, their
/// content hashes, and the operator's settings of `ncplc run`.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct PartHeader {
    /// The kernel that recorded the trace (the `cnc` crate's version and its trace revision).
    pub kernel: String,
    /// The process that runs `program` (`--process`).
    pub process: u8,
    /// The `--dialect` override, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dialect: Option<String>,
    /// The program as given to `--program` (a name in `<machine>/nc/` or a path), if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub program: Option<String>,
    /// CRC-32 of the program's text, 8 hex digits.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crc32: Option<String>,
    /// The `--mdi` blocks, in order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub mdi: Vec<String>,
    /// The `--kor-change` correction table (the file as given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kor_change: Option<String>,
    /// The programs of other processes (`sim.toml [cnc] programs`): process, name, CRC-32.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub others: Vec<OtherProgram>,
    /// Every other file the programs' compile read (macros and cycles, the correction table,
    /// `nc/CONSTANTS`, `nc/DIALECT`), relative to the machine directory, in name order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub files: Vec<FileCrc>,
    /// The retained macro variables' file `nc/MACROVARS` as the run read it at its start (absent:
    /// no file, every `#500`–`#999` null); a replay plans from this text, not the file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub macro_vars: Option<String>,
    /// The axes that ran on CiA 402 drives (`--io canopen` with `[[canopen.drive]]`); a replay
    /// feeds their recorded feedback to the kernel.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub drives: Vec<HeaderDrive>,
    /// The packet-A input bytes that reached the scan over the bus from simulated I/O nodes
    /// carrying the part script and the plant (`--io canopen` on the virtual transport); a replay
    /// takes them from the recorded inputs, not from its kernel.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub bus_inputs: Vec<u16>,
}

/// A file a part run read and its CRC-32.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct FileCrc {
    /// Path relative to the machine directory (`macros/L9001`, `MP0/TAB0.KOR`).
    pub file: String,
    /// CRC-32 of its content, 8 hex digits.
    pub crc32: String,
}

/// A program of another process named in a [`PartHeader`].
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct OtherProgram {
    /// The process.
    pub process: u8,
    /// The program name (in `<machine>/nc/`) or path.
    pub program: String,
    /// CRC-32 of its text, 8 hex digits.
    pub crc32: String,
}

/// A whole trace in memory.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Trace {
    /// The logic tick the trace was recorded with, in ms.
    pub tick_ms: u32,
    /// Records in increasing tick order.
    pub ticks: Vec<TickRecord>,
    /// The partprograms a part run recorded with (None: a logic-only trace).
    pub part: Option<PartHeader>,
}

/// Why a trace could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum TraceError {
    /// The file could not be read or written.
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// A text line is malformed.
    #[error("line {line}: {message}")]
    Text {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A binary frame is malformed.
    #[error("frame {frame}: {message}")]
    Binary {
        /// 0-based frame number.
        frame: usize,
        /// What is wrong.
        message: String,
    },
}

impl Trace {
    /// Number of ticks the trace covers (last record's tick + 1; 0 when empty).
    pub fn len_ticks(&self) -> u64 {
        self.ticks.last().map_or(0, |r| r.t + 1)
    }

    /// Reads a trace file in either form.
    pub fn load(path: &Path) -> Result<Trace, TraceError> {
        reader::Reader::open(path)?.collect_trace()
    }

    /// Parses a trace in either form (text when it starts with `{` after blanks).
    pub fn from_bytes(bytes: &[u8]) -> Result<Trace, TraceError> {
        reader::Reader::new(bytes)?.collect_trace()
    }

    /// Writes the trace in text form.
    pub fn write_text(&self, out: &mut dyn Write) -> Result<(), TraceError> {
        let mut w = text::TextWriter::with_part(out, self.tick_ms, self.part.as_ref())?;
        for r in &self.ticks {
            w.record(r)?;
        }
        Ok(())
    }
}

/// A streaming trace sink (used by `ncplc run --record`).
pub trait TraceSink {
    /// Writes one tick's record (only called when something changed, or to mark the end).
    fn record(&mut self, rec: &TickRecord) -> Result<(), TraceError>;
    /// Flushes buffered data.
    fn flush(&mut self) -> Result<(), TraceError>;
    /// Ends the recording: flushes and, for a file, puts it in place (see [`create_sink`]).
    fn finish(&mut self) -> Result<(), TraceError> {
        self.flush()
    }
}

/// Opens a file sink with the default [`DurableOptions`]: binary when the path ends in `.ptrace`
/// or `.bin`, text otherwise.
pub fn create_sink(path: &Path, tick_ms: u32) -> Result<Box<dyn TraceSink>, TraceError> {
    create_sink_with(path, tick_ms, DurableOptions::default())
}

/// Opens a file sink (see [`durable`]).
///
/// The records stream into `<path>.partial`; [`TraceSink::finish`] syncs it and renames it over
/// `path`. A run that dies mid-recording therefore leaves the existing file at `path` (often a
/// golden trace) intact and the ticks recorded so far in `<path>.partial`, readable with
/// [`recover`].
pub fn create_sink_with(
    path: &Path,
    tick_ms: u32,
    options: DurableOptions,
) -> Result<Box<dyn TraceSink>, TraceError> {
    create_part_sink(path, tick_ms, None, options)
}

/// [`create_sink_with`] for a part run: the header names the partprograms (`part`).
pub fn create_part_sink(
    path: &Path,
    tick_ms: u32,
    part: Option<&PartHeader>,
    options: DurableOptions,
) -> Result<Box<dyn TraceSink>, TraceError> {
    let binary = matches!(
        path.extension().and_then(|e| e.to_str()),
        Some("ptrace" | "bin")
    );
    Ok(Box::new(DurableSink::create_with_part(
        path,
        partial_path(path),
        tick_ms,
        part,
        binary,
        options,
    )?))
}

/// Where [`create_sink`] streams a recording until it is finished.
pub fn partial_path(path: &Path) -> std::path::PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".partial");
    path.with_file_name(name)
}

/// A sink that keeps records in memory (tests, benchmarks, `--update`).
#[derive(Debug, Clone, Default)]
pub struct MemorySink(pub std::sync::Arc<std::sync::Mutex<Vec<TickRecord>>>);

impl TraceSink for MemorySink {
    fn record(&mut self, rec: &TickRecord) -> Result<(), TraceError> {
        if let Ok(mut v) = self.0.lock() {
            v.push(rec.clone());
        }
        Ok(())
    }

    fn flush(&mut self) -> Result<(), TraceError> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_finished_recording_replaces_the_file_and_leaves_no_partial() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("golden.jsonl");
        std::fs::write(&path, "old golden trace").expect("seed");
        let mut sink = create_sink(&path, 10).expect("sink");
        sink.record(&TickRecord::at(0)).expect("record");
        sink.record(&TickRecord::at(5)).expect("record");
        sink.finish().expect("finish");
        sink.finish().expect("a second finish is harmless");
        assert!(!partial_path(&path).exists());
        let trace = Trace::load(&path).expect("load");
        assert_eq!(trace.tick_ms, 10);
        assert_eq!(trace.ticks.iter().map(|r| r.t).collect::<Vec<_>>(), [0, 5]);
    }

    #[test]
    fn an_unfinished_recording_keeps_the_old_file_and_its_ticks_in_partial() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("golden.ptrace");
        std::fs::write(&path, "old golden trace").expect("seed");
        {
            let mut sink = create_sink(&path, 10).expect("sink");
            sink.record(&TickRecord::at(3)).expect("record");
            // dropped without finish: the run died (the drop drains the ring)
        }
        assert_eq!(
            std::fs::read_to_string(&path).expect("old"),
            "old golden trace"
        );
        let partial = Trace::load(&partial_path(&path)).expect("partial loads");
        assert_eq!(partial.ticks.iter().map(|r| r.t).collect::<Vec<_>>(), [3]);
    }
}
