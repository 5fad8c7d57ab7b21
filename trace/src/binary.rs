//! The compact trace form: postcard records, each COBS-framed and ended by a 0x00 byte.
//!
//! The first frame is [`Frame::Header`] (format name, version, tick); every later frame is a
//! [`Frame::Tick`]: the tick as a difference from the previous record's, and each signal as one
//! varint `image byte × 9 + bit` (bit 8 = the whole byte) with its value. Input bits read back as
//! `I…`, output bits as `U…` (the same address). COBS lets a reader resynchronise after a damaged frame; this reader reports
//! the damaged frame instead, since a trace used for comparison must be complete.

use std::io::Write;

use serde::{Deserialize, Serialize};

use packets::{Dir, Packet, Signal};

use super::{
    AxisId, AxisValue, DriveSample, NodeLoss, OperatorCommand, PartHeader, TickRecord, Trace,
    TraceError, TraceSink, VERSION,
};

/// The name in the header frame.
pub const FORMAT: &str = "ncplc-trace";

/// One frame of a binary trace.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub enum Frame {
    /// The first frame.
    Header {
        /// Always [`FORMAT`].
        format: String,
        /// The format version.
        version: u32,
        /// The logic tick in ms.
        tick_ms: u32,
    },
    /// One tick's changes.
    Tick(CompactTick),
    /// The `forced` values of the [`Frame::Tick`] that follows (written only when there are any,
    /// so traces without HMI forces keep their encoding).
    Forced(Vec<(u32, u8)>),
    /// The part-run header (a [`PartHeader`] as JSON), right after [`Frame::Header`].
    Part(String),
    /// The `positions` of the [`Frame::Tick`] that follows: (process, axis letter, f64 bits).
    Positions(Vec<(u8, char, u64)>),
    /// The operator `commands` of the [`Frame::Tick`] that follows, as their JSON array.
    Commands(String),
    /// The `drives` of the [`Frame::Tick`] that follows, as their JSON array.
    Drives(String),
    /// The `nodes_lost` of the [`Frame::Tick`] that follows, as their JSON array (last, so that
    /// older traces decode unchanged).
    NodesLost(String),
}

/// A [`TickRecord`] in compact form.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct CompactTick {
    /// Ticks since the previous record (the first: since tick 0).
    pub dt: u64,
    /// Inputs as (key, value).
    pub inputs: Vec<(u32, u8)>,
    /// Outputs as (key, value).
    pub outputs: Vec<(u32, u8)>,
}

fn key(s: &Signal) -> u32 {
    s.image_byte() as u32 * 9 + u32::from(s.bit().unwrap_or(8))
}

fn from_key(k: u32, dir: Dir) -> Option<Signal> {
    let at = (k / 9) as usize;
    let bit = (k % 9) as u8;
    let packet = Packet::ALL
        .into_iter()
        .find(|p| at >= p.offset() && at < p.offset() + p.len())?;
    let rel = at - packet.offset();
    let connector = (rel / 4) as u16;
    Some(if bit == 8 {
        Signal::Byte {
            packet,
            connector,
            index: (rel % 4) as u8,
        }
    } else {
        Signal::Bit {
            dir,
            packet,
            connector,
            contact: (rel % 4) as u8 * 8 + bit,
        }
    })
}

impl CompactTick {
    fn new(r: &TickRecord, prev_t: u64) -> CompactTick {
        let pack = |l: &[(Signal, u8)]| l.iter().map(|(s, v)| (key(s), *v)).collect();
        CompactTick {
            dt: r.t - prev_t,
            inputs: pack(&r.inputs),
            outputs: pack(&r.outputs),
        }
    }

    fn expand(&self, prev_t: u64) -> Option<TickRecord> {
        let unpack = |l: &[(u32, u8)], dir| -> Option<Vec<(Signal, u8)>> {
            l.iter()
                .map(|&(k, v)| from_key(k, dir).map(|s| (s, v)))
                .collect()
        };
        Some(TickRecord {
            nodes_lost: Vec::new(),
            t: prev_t.checked_add(self.dt)?,
            inputs: unpack(&self.inputs, Dir::In)?,
            outputs: unpack(&self.outputs, Dir::Out)?,
            forced: Vec::new(),
            positions: Vec::new(),
            commands: Vec::new(),
            drives: Vec::new(),
        })
    }
}

/// Streams records as COBS frames.
pub struct BinaryWriter<W: Write> {
    out: W,
    prev_t: u64,
}

impl<W: Write> BinaryWriter<W> {
    /// Writes the header frame.
    pub fn new(out: W, tick_ms: u32) -> Result<Self, TraceError> {
        Self::with_part(out, tick_ms, None)
    }

    /// Writes the header frame and, for a part run, the [`Frame::Part`] frame.
    pub fn with_part(
        mut out: W,
        tick_ms: u32,
        part: Option<&PartHeader>,
    ) -> Result<Self, TraceError> {
        let header = Frame::Header {
            format: FORMAT.into(),
            version: VERSION,
            tick_ms,
        };
        write_frame(&mut out, &header)?;
        if let Some(p) = part {
            let json = serde_json::to_string(p).map_err(|e| TraceError::Binary {
                frame: 1,
                message: e.to_string(),
            })?;
            write_frame(&mut out, &Frame::Part(json))?;
        }
        Ok(BinaryWriter { out, prev_t: 0 })
    }

    /// The underlying writer (the durable recorder stages each frame in a buffer).
    pub fn get_mut(&mut self) -> &mut W {
        &mut self.out
    }
}

fn write_frame(out: &mut dyn Write, frame: &Frame) -> Result<(), TraceError> {
    let bytes = postcard::to_stdvec_cobs(frame).map_err(|e| TraceError::Binary {
        frame: 0,
        message: format!("cannot encode: {e}"),
    })?;
    out.write_all(&bytes)?;
    Ok(())
}

/// A record's list as the JSON a frame carries.
fn to_json<T: Serialize>(list: &T) -> Result<String, TraceError> {
    serde_json::to_string(list).map_err(|e| TraceError::Binary {
        frame: 0,
        message: format!("cannot encode: {e}"),
    })
}

/// Keeps the JSON list of frame `i` for the tick frame that follows; a second such frame before
/// that tick, or JSON that does not read, is an error naming `frames` / `what`.
fn pending_json<T: serde::de::DeserializeOwned>(
    slot: &mut Option<(usize, Vec<T>)>,
    i: usize,
    json: &str,
    frames: &str,
    what: &str,
) -> Result<(), TraceError> {
    if slot.is_some() {
        return Err(TraceError::Binary {
            frame: i,
            message: format!("two {frames} frames without a tick between"),
        });
    }
    let list = serde_json::from_str(json).map_err(|e| TraceError::Binary {
        frame: i,
        message: format!("{what}: {e}"),
    })?;
    *slot = Some((i, list));
    Ok(())
}

impl<W: Write> TraceSink for BinaryWriter<W> {
    fn record(&mut self, rec: &TickRecord) -> Result<(), TraceError> {
        if !rec.forced.is_empty() {
            let forced = rec.forced.iter().map(|(s, v)| (key(s), *v)).collect();
            write_frame(&mut self.out, &Frame::Forced(forced))?;
        }
        if !rec.positions.is_empty() {
            let pos = rec
                .positions
                .iter()
                .map(|(a, bits)| (a.process, a.axis, *bits))
                .collect();
            write_frame(&mut self.out, &Frame::Positions(pos))?;
        }
        if !rec.commands.is_empty() {
            write_frame(&mut self.out, &Frame::Commands(to_json(&rec.commands)?))?;
        }
        if !rec.drives.is_empty() {
            write_frame(&mut self.out, &Frame::Drives(to_json(&rec.drives)?))?;
        }
        if !rec.nodes_lost.is_empty() {
            write_frame(&mut self.out, &Frame::NodesLost(to_json(&rec.nodes_lost)?))?;
        }
        let frame = Frame::Tick(CompactTick::new(rec, self.prev_t));
        self.prev_t = rec.t;
        write_frame(&mut self.out, &frame)
    }

    fn flush(&mut self) -> Result<(), TraceError> {
        self.out.flush()?;
        Ok(())
    }
}

/// Encodes a whole trace.
pub fn encode(trace: &Trace) -> Result<Vec<u8>, TraceError> {
    let mut out = Vec::new();
    let mut w = BinaryWriter::with_part(&mut out, trace.tick_ms, trace.part.as_ref())?;
    for r in &trace.ticks {
        TraceSink::record(&mut w, r)?;
    }
    Ok(out)
}

/// Decodes a whole binary trace.
pub fn decode(bytes: &[u8]) -> Result<Trace, TraceError> {
    crate::reader::Reader::with_form(bytes, Some(false))?.collect_trace()
}

/// A located error of frame `frame` (0-based).
fn bad(frame: usize, message: String) -> TraceError {
    TraceError::Binary { frame, message }
}

/// Decodes frame `i` in place: `raw` is its bytes with the 0x00 terminator.
pub(crate) fn decode_frame(i: usize, raw: &mut [u8]) -> Result<Frame, TraceError> {
    if raw.last() != Some(&0) {
        return Err(bad(
            i,
            "truncated: the last frame has no 0x00 terminator".into(),
        ));
    }
    postcard::from_bytes_cobs::<Frame>(raw).map_err(|e| bad(i, format!("undecodable frame: {e}")))
}

/// Reads the header frame (frame `i`, its bytes with the terminator): the tick.
pub(crate) fn decode_header(i: usize, raw: &mut [u8]) -> Result<u32, TraceError> {
    // A first frame that does not decode: most likely not a trace at all (a wrong file name).
    let first = decode_frame(i, raw).map_err(|e| match e {
        TraceError::Binary { message, .. } => bad(
            i,
            format!(
                "not an ncplc trace: neither a text trace (a JSON header line first) nor a binary one ({message})"
            ),
        ),
        other => other,
    })?;
    match first {
        Frame::Header {
            format,
            version,
            tick_ms,
        } if format == FORMAT && version == VERSION && tick_ms > 0 => Ok(tick_ms),
        Frame::Header { version, .. } => Err(bad(
            i,
            format!("not a version-{VERSION} ncplc trace header (version {version})"),
        )),
        Frame::Tick(_)
        | Frame::Forced(_)
        | Frame::Part(_)
        | Frame::Positions(_)
        | Frame::Commands(_)
        | Frame::Drives(_)
        | Frame::NodesLost(_) => Err(bad(i, "the first frame must be the header".into())),
    }
}

/// Reads the frames after the header one at a time: the lists a tick frame's leading frames
/// carry wait here for it.
#[derive(Debug, Default)]
pub(crate) struct Decoder {
    prev_t: Option<u64>,
    forced: Option<(usize, Vec<(u32, u8)>)>,
    positions: Option<(usize, Vec<AxisValue>)>,
    commands: Option<(usize, Vec<OperatorCommand>)>,
    drives: Option<(usize, Vec<DriveSample>)>,
    nodes_lost: Option<(usize, Vec<NodeLoss>)>,
}

impl Decoder {
    /// Decodes frame `i` (after the header; `raw` with its terminator): the record a tick frame
    /// completes, the part-run header of frame 1, or nothing for a leading list.
    pub(crate) fn frame(&mut self, i: usize, raw: &mut [u8]) -> Result<Decoded, TraceError> {
        match decode_frame(i, raw)? {
            Frame::Part(json) if i == 1 => Ok(Decoded::Part(
                serde_json::from_str::<PartHeader>(&json)
                    .map_err(|e| bad(i, format!("part header: {e}")))?,
            )),
            Frame::Part(_) => Err(bad(i, "a part header after the first frames".into())),
            Frame::Positions(list) => {
                if self.positions.is_some() {
                    return Err(bad(i, "two position frames without a tick between".into()));
                }
                let list = list
                    .into_iter()
                    .map(|(process, axis, bits)| (AxisId { process, axis }, bits))
                    .collect();
                self.positions = Some((i, list));
                Ok(Decoded::Nothing)
            }
            Frame::Commands(json) => {
                pending_json(&mut self.commands, i, &json, "command", "operator commands")?;
                Ok(Decoded::Nothing)
            }
            Frame::Drives(json) => {
                pending_json(&mut self.drives, i, &json, "drive", "drive feedback")?;
                Ok(Decoded::Nothing)
            }
            Frame::NodesLost(json) => {
                pending_json(
                    &mut self.nodes_lost,
                    i,
                    &json,
                    "lost-node",
                    "lost I/O nodes",
                )?;
                Ok(Decoded::Nothing)
            }
            Frame::Forced(list) => {
                if self.forced.is_some() {
                    return Err(bad(i, "two forced frames without a tick between".into()));
                }
                self.forced = Some((i, list));
                Ok(Decoded::Nothing)
            }
            Frame::Tick(c) => {
                let mut r = c
                    .expand(self.prev_t.unwrap_or(0))
                    .ok_or_else(|| bad(i, "a signal outside the packets".into()))?;
                if let Some((_, list)) = self.forced.take() {
                    r.forced = list
                        .iter()
                        .map(|&(k, v)| from_key(k, Dir::Out).map(|s| (s, v)))
                        .collect::<Option<_>>()
                        .ok_or_else(|| bad(i, "a forced signal outside the packets".into()))?;
                }
                if let Some((_, list)) = self.positions.take() {
                    r.positions = list;
                }
                if let Some((_, list)) = self.commands.take() {
                    r.commands = list;
                }
                if let Some((_, list)) = self.drives.take() {
                    r.drives = list;
                }
                if let Some((_, list)) = self.nodes_lost.take() {
                    r.nodes_lost = list;
                }
                if let Some(prev) = self.prev_t
                    && c.dt == 0
                {
                    return Err(bad(i, format!("tick {} does not follow tick {prev}", r.t)));
                }
                self.prev_t = Some(r.t);
                Ok(Decoded::Record(r))
            }
            Frame::Header { .. } => Err(bad(i, "a second header".into())),
        }
    }

    /// At the end of the file: a leading list without its tick frame is a truncation.
    pub(crate) fn finish(&self) -> Result<(), TraceError> {
        if let Some((i, _)) = self.forced {
            return Err(bad(i, "truncated: a forced frame without its tick".into()));
        }
        if let Some((i, _)) = self.commands {
            return Err(bad(i, "truncated: a command frame without its tick".into()));
        }
        if let Some((i, _)) = self.drives {
            return Err(bad(i, "truncated: a drive frame without its tick".into()));
        }
        if let Some((i, _)) = self.nodes_lost {
            return Err(bad(
                i,
                "truncated: a lost-node frame without its tick".into(),
            ));
        }
        if let Some((i, _)) = self.positions {
            return Err(bad(
                i,
                "truncated: a position frame without its tick".into(),
            ));
        }
        Ok(())
    }
}

/// What one frame after the header gave.
#[derive(Debug)]
pub(crate) enum Decoded {
    /// A complete record.
    Record(TickRecord),
    /// The part-run header (frame 1 only).
    Part(PartHeader),
    /// A list kept for the next tick frame.
    Nothing,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sig(s: &str) -> Signal {
        s.parse().expect("signal")
    }

    #[test]
    fn round_trip_and_no_zero_inside_frames() {
        let trace = Trace {
            part: None,
            tick_ms: 1,
            ticks: vec![
                TickRecord {
                    nodes_lost: Vec::new(),
                    commands: Vec::new(),
                    drives: Vec::new(),
                    t: 0,
                    inputs: vec![(sig("W3K0"), 0)],
                    outputs: vec![(sig("U4A0"), 1)],
                    forced: vec![],
                    positions: Vec::new(),
                },
                TickRecord {
                    nodes_lost: Vec::new(),
                    commands: Vec::new(),
                    drives: Vec::new(),
                    t: 300,
                    inputs: vec![(sig("I0A0"), 1)],
                    outputs: vec![],
                    forced: vec![(sig("U4A1"), 0)],
                    positions: Vec::new(),
                },
            ],
        };
        let bytes = encode(&trace).expect("encode");
        assert_eq!(bytes.iter().filter(|&&b| b == 0).count(), 4);
        assert_eq!(decode(&bytes).expect("decode"), trace);
        assert_eq!(Trace::from_bytes(&bytes).expect("detect"), trace);
    }

    #[test]
    fn a_part_header_and_positions_survive_both_forms() {
        let x = AxisId {
            process: 1,
            axis: 'X',
        };
        let trace = Trace {
            tick_ms: 10,
            ticks: vec![
                TickRecord {
                    t: 0,
                    positions: vec![(x, 0)],
                    ..TickRecord::default()
                },
                TickRecord {
                    t: 3,
                    inputs: vec![(sig("W4K0"), 176)],
                    positions: vec![(x, 0.1f64.to_bits())],
                    ..TickRecord::default()
                },
            ],
            part: Some(PartHeader {
                kernel: "cnc 0.1.0".into(),
                process: 1,
                program: Some("PART1".into()),
                crc32: Some("536205d9".into()),
                mdi: vec!["G00 X1".into()],
                ..PartHeader::default()
            }),
        };
        assert_eq!(
            decode(&encode(&trace).expect("encode")).expect("decode"),
            trace
        );
        let mut text = Vec::new();
        trace.write_text(&mut text).expect("text");
        assert_eq!(
            String::from_utf8_lossy(&text),
            "{\"format\":\"ncplc-trace\",\"version\":1,\"tick_ms\":10,\"part\":{\"kernel\":\"cnc 0.1.0\",\"process\":1,\"program\":\"PART1\",\"crc32\":\"536205d9\",\"mdi\":[\"G00 X1\"]}}\n\
             {\"t\":0,\"pos\":{\"1X\":\"0000000000000000\"}}\n\
             {\"t\":3,\"in\":{\"W4K0\":176},\"pos\":{\"1X\":\"3fb999999999999a\"}}\n"
        );
        assert_eq!(super::super::text::parse(&text).expect("parse"), trace);
    }

    #[test]
    fn drive_feedback_survives_both_forms() {
        use crate::{DriveFaultRecord, DriveSample, HeaderDrive};
        let x = AxisId {
            process: 1,
            axis: 'X',
        };
        let trace = Trace {
            tick_ms: 10,
            ticks: vec![TickRecord {
                t: 200,
                drives: vec![DriveSample {
                    axis: x,
                    values: vec![Some(1.5f64.to_bits()), None],
                    statusword: 0x0208,
                    age: 2,
                    fault: Some(DriveFaultRecord {
                        node: 3,
                        code: 0x5530,
                        cause: "drive".into(),
                    }),
                    inputs: 0,
                    probe_status: 0,
                    probe: None,
                }],
                ..TickRecord::default()
            }],
            part: Some(PartHeader {
                kernel: "cnc 0.1.0".into(),
                process: 1,
                drives: vec![HeaderDrive { axis: x, node: 3 }],
                ..PartHeader::default()
            }),
        };
        assert_eq!(
            decode(&encode(&trace).expect("encode")).expect("decode"),
            trace
        );
        let mut text = Vec::new();
        trace.write_text(&mut text).expect("text");
        let lines: Vec<&str> = std::str::from_utf8(&text).expect("utf8").lines().collect();
        assert_eq!(
            lines,
            [
                r#"{"format":"ncplc-trace","version":1,"tick_ms":10,"part":{"kernel":"cnc 0.1.0","process":1,"drives":[{"axis":{"process":1,"axis":"X"},"node":3}]}}"#,
                r#"{"t":200,"drives":[{"axis":{"process":1,"axis":"X"},"values":[4609434218613702656,null],"statusword":520,"age":2,"fault":{"node":3,"code":21808,"cause":"drive"}}]}"#
            ]
        );
        assert_eq!(super::super::text::parse(&text).expect("parse"), trace);
        // age 1 is the rule and is not written.
        let mut one = trace.clone();
        one.ticks[0].drives[0].age = 1;
        let mut text = Vec::new();
        one.write_text(&mut text).expect("text");
        assert!(!String::from_utf8_lossy(&text).contains("age"));
        assert_eq!(super::super::text::parse(&text).expect("parse"), one);
    }

    /// The homing feedback (`60FDh`, the touch probe) is written only when there is some: a
    /// trace written before it (the record above) reads with none.
    #[test]
    fn homing_feedback_survives_both_forms() {
        use crate::DriveSample;
        let trace = Trace {
            tick_ms: 10,
            ticks: vec![TickRecord {
                t: 7,
                drives: vec![DriveSample {
                    axis: AxisId {
                        process: 1,
                        axis: 'Z',
                    },
                    values: vec![Some(50.0f64.to_bits())],
                    statusword: 0x0237,
                    age: 1,
                    fault: None,
                    inputs: 4,
                    probe_status: 3,
                    probe: Some(100.0f64.to_bits()),
                }],
                ..TickRecord::default()
            }],
            part: None,
        };
        assert_eq!(
            decode(&encode(&trace).expect("encode")).expect("decode"),
            trace
        );
        let mut text = Vec::new();
        trace.write_text(&mut text).expect("text");
        let text = String::from_utf8(text).expect("utf8");
        assert_eq!(
            text.lines().nth(1),
            Some(
                r#"{"t":7,"drives":[{"axis":{"process":1,"axis":"Z"},"values":[4632233691727265792],"statusword":567,"inputs":4,"probe_status":3,"probe":4636737291354636288}]}"#
            )
        );
        assert_eq!(
            super::super::text::parse(text.as_bytes()).expect("parse"),
            trace
        );
    }

    #[test]
    fn lost_io_nodes_survive_both_forms() {
        let trace = Trace {
            tick_ms: 10,
            ticks: vec![TickRecord {
                t: 208,
                nodes_lost: vec![crate::NodeLoss {
                    name: "dio1".into(),
                    node: 2,
                    why: "heartbeat lost".into(),
                }],
                ..TickRecord::default()
            }],
            part: None,
        };
        assert_eq!(
            decode(&encode(&trace).expect("encode")).expect("decode"),
            trace
        );
        let mut text = Vec::new();
        trace.write_text(&mut text).expect("text");
        let text = String::from_utf8(text).expect("utf8");
        assert_eq!(
            text.lines().nth(1),
            Some(r#"{"t":208,"nodes_lost":[{"name":"dio1","node":2,"why":"heartbeat lost"}]}"#)
        );
        assert_eq!(
            super::super::text::parse(text.as_bytes()).expect("parse"),
            trace
        );
    }

    #[test]
    fn operator_commands_survive_both_forms() {
        let cmd = |command| OperatorCommand {
            process: 1,
            command,
            role: Some(hmi::Role::Operator),
        };
        let trace = Trace {
            tick_ms: 10,
            ticks: vec![
                TickRecord {
                    t: 4,
                    commands: vec![cmd(hmi::Command::Hold)],
                    drives: Vec::new(),
                    ..TickRecord::default()
                },
                TickRecord {
                    t: 9,
                    inputs: vec![(sig("I0A3"), 1)],
                    commands: vec![
                        cmd(hmi::Command::Mode { mode: "MDI".into() }),
                        cmd(hmi::Command::Mdi {
                            line: "G00 X-30".into(),
                        }),
                    ],
                    ..TickRecord::default()
                },
            ],
            part: Some(PartHeader {
                kernel: "cnc 0.1.0".into(),
                process: 1,
                ..PartHeader::default()
            }),
        };
        assert_eq!(
            decode(&encode(&trace).expect("encode")).expect("decode"),
            trace
        );
        let mut text = Vec::new();
        trace.write_text(&mut text).expect("text");
        let lines: Vec<&str> = std::str::from_utf8(&text).expect("utf8").lines().collect();
        assert_eq!(
            &lines[1..],
            [
                r#"{"t":4,"cmd":[{"process":1,"command":"hold","role":"operator"}]}"#,
                r#"{"t":9,"in":{"I0A3":1},"cmd":[{"process":1,"command":"mode","mode":"MDI","role":"operator"},{"process":1,"command":"mdi","line":"G00 X-30","role":"operator"}]}"#
            ]
        );
        assert_eq!(super::super::text::parse(&text).expect("parse"), trace);
        // An unknown command is an error naming the line.
        let bad = format!(
            "{}\n{}\n",
            lines[0], r#"{"t":4,"cmd":[{"process":1,"command":"jump"}]}"#
        );
        let e = super::super::text::parse(bad.as_bytes())
            .expect_err("unknown command")
            .to_string();
        assert!(
            e.starts_with("line 2: \"cmd\": unknown variant `jump`"),
            "{e}"
        );
    }

    /// The error `decode` gives for `bytes`, as text.
    fn decode_error(bytes: &[u8]) -> Option<String> {
        decode(bytes).map_err(|e| e.to_string()).err()
    }

    #[test]
    fn truncation_is_reported() {
        let trace = Trace {
            part: None,
            tick_ms: 1,
            ticks: vec![TickRecord {
                t: 4,
                ..TickRecord::default()
            }],
        };
        let bytes = encode(&trace).expect("encode");
        assert_eq!(
            decode_error(&bytes[..bytes.len() - 1]).as_deref(),
            Some("frame 1: truncated: the last frame has no 0x00 terminator")
        );
    }

    #[test]
    fn a_file_that_is_no_trace_is_named_so() {
        assert_eq!(
            decode_error(b"root:x:0:0:root:/root:/bin/bash\n").as_deref(),
            Some(
                "frame 0: not an ncplc trace: neither a text trace (a JSON header line first) nor a binary one (truncated: the last frame has no 0x00 terminator)"
            )
        );
    }

    fn arb_signal(dir: Dir) -> impl proptest::strategy::Strategy<Value = Signal> {
        use proptest::prelude::*;
        (0usize..4, 0u16..256, 0u8..32, any::<bool>()).prop_map(move |(p, c, n, byte)| {
            let packet = Packet::ALL[p];
            let connector = c % packet.connectors();
            if byte {
                Signal::Byte {
                    packet,
                    connector,
                    index: n % 4,
                }
            } else {
                Signal::Bit {
                    dir,
                    packet,
                    connector,
                    contact: n,
                }
            }
        })
    }

    proptest::proptest! {
        #![proptest_config(proptest::test_runner::Config::with_cases(128))]
        #[test]
        fn binary_and_text_round_trip_any_trace(
            gaps in proptest::collection::vec(1u64..100_000, 0..20),
            ins in proptest::collection::vec((arb_signal(Dir::In), proptest::prelude::any::<u8>()), 0..40),
            outs in proptest::collection::vec((arb_signal(Dir::Out), proptest::prelude::any::<u8>()), 0..40),
        ) {
            let mut t = 0;
            let mut ticks = Vec::new();
            for (i, g) in gaps.iter().enumerate() {
                let fix = |(s, v): &(Signal, u8)| (*s, if s.bit().is_some() { v & 1 } else { *v });
                let mut inputs: Vec<_> = ins.iter().skip(i).step_by(3).map(fix).collect();
                let mut outputs: Vec<_> = outs.iter().skip(i).step_by(3).map(fix).collect();
                inputs.sort_by_key(|(s, _)| crate::text::canonical_key(s));
                inputs.dedup_by_key(|(s, _)| *s);
                outputs.sort_by_key(|(s, _)| crate::text::canonical_key(s));
                outputs.dedup_by_key(|(s, _)| *s);
                let forced = if i % 2 == 1 { outputs.clone() } else { Vec::new() };
                ticks.push(TickRecord {
                    nodes_lost: Vec::new(),
                    commands: Vec::new(),
                    drives: Vec::new(),
                    t,
                    inputs,
                    outputs,
                    forced,
                    positions: Vec::new(),
                });
                t += g;
            }
            let trace = Trace {
        tick_ms: 3,
        ticks,
        part: None,
    };
            let bytes = encode(&trace).expect("encode");
            proptest::prop_assert_eq!(&decode(&bytes).expect("decode"), &trace);
            let mut text = Vec::new();
            trace.write_text(&mut text).expect("text");
            proptest::prop_assert_eq!(&crate::text::parse(&text).expect("parse"), &trace);
        }
    }
}
