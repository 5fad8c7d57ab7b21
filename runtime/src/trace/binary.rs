//! The compact trace form: postcard records, each COBS-framed and ended by a 0x00 byte.
//!
//! The first frame is [`Frame::Header`] (format name, version, tick); every later frame is a
//! [`Frame::Tick`]. COBS lets a reader resynchronise after a damaged frame; this reader reports
//! the damaged frame instead, since a trace used for comparison must be complete.

use std::io::Write;

use serde::{Deserialize, Serialize};

use super::{TickRecord, Trace, TraceError, TraceSink, VERSION};

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
    Tick(TickRecord),
}

/// Streams records as COBS frames.
pub struct BinaryWriter<W: Write> {
    out: W,
}

impl<W: Write> BinaryWriter<W> {
    /// Writes the header frame.
    pub fn new(mut out: W, tick_ms: u32) -> Result<Self, TraceError> {
        let header = Frame::Header {
            format: FORMAT.into(),
            version: VERSION,
            tick_ms,
        };
        write_frame(&mut out, &header)?;
        Ok(BinaryWriter { out })
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

impl<W: Write> TraceSink for BinaryWriter<W> {
    fn record(&mut self, rec: &TickRecord) -> Result<(), TraceError> {
        write_frame(&mut self.out, &Frame::Tick(rec.clone()))
    }

    fn flush(&mut self) -> Result<(), TraceError> {
        self.out.flush()?;
        Ok(())
    }
}

/// Encodes a whole trace.
pub fn encode(trace: &Trace) -> Result<Vec<u8>, TraceError> {
    let mut out = Vec::new();
    let mut w = BinaryWriter::new(&mut out, trace.tick_ms)?;
    for r in &trace.ticks {
        TraceSink::record(&mut w, r)?;
    }
    Ok(out)
}

/// Decodes a whole binary trace.
pub fn decode(bytes: &[u8]) -> Result<Trace, TraceError> {
    let mut frames = bytes.split_inclusive(|&b| b == 0).enumerate();
    let bad = |frame: usize, message: String| TraceError::Binary { frame, message };
    let decode_one = |i: usize, raw: &[u8]| -> Result<Frame, TraceError> {
        if raw.last() != Some(&0) {
            return Err(bad(
                i,
                "truncated: the last frame has no 0x00 terminator".into(),
            ));
        }
        let mut buf = raw.to_vec();
        postcard::from_bytes_cobs::<Frame>(&mut buf)
            .map_err(|e| bad(i, format!("undecodable frame: {e}")))
    };
    let (i, first) = frames.next().ok_or_else(|| bad(0, "empty file".into()))?;
    let tick_ms = match decode_one(i, first)? {
        Frame::Header {
            format,
            version,
            tick_ms,
        } if format == FORMAT && version == VERSION && tick_ms > 0 => tick_ms,
        Frame::Header { version, .. } => {
            return Err(bad(
                i,
                format!("not a version-{VERSION} ncplc trace header (version {version})"),
            ));
        }
        Frame::Tick(_) => return Err(bad(i, "the first frame must be the header".into())),
    };
    let mut ticks: Vec<TickRecord> = Vec::new();
    for (i, raw) in frames {
        match decode_one(i, raw)? {
            Frame::Tick(r) => {
                if let Some(prev) = ticks.last()
                    && prev.t >= r.t
                {
                    return Err(bad(
                        i,
                        format!("tick {} does not follow tick {}", r.t, prev.t),
                    ));
                }
                ticks.push(r);
            }
            Frame::Header { .. } => return Err(bad(i, "a second header".into())),
        }
    }
    Ok(Trace { tick_ms, ticks })
}

#[cfg(test)]
mod tests {
    use super::*;
    use packets::Signal;

    fn sig(s: &str) -> Signal {
        s.parse().expect("signal")
    }

    #[test]
    fn round_trip_and_no_zero_inside_frames() {
        let trace = Trace {
            tick_ms: 1,
            ticks: vec![
                TickRecord {
                    t: 0,
                    inputs: vec![(sig("W3K0"), 0)],
                    outputs: vec![(sig("U4A0"), 1)],
                },
                TickRecord {
                    t: 300,
                    inputs: vec![(sig("I0A0"), 1)],
                    outputs: vec![],
                },
            ],
        };
        let bytes = encode(&trace).expect("encode");
        assert_eq!(bytes.iter().filter(|&&b| b == 0).count(), 3);
        assert_eq!(decode(&bytes).expect("decode"), trace);
        assert_eq!(Trace::from_bytes(&bytes).expect("detect"), trace);
    }

    #[test]
    fn truncation_is_reported() {
        let trace = Trace {
            tick_ms: 1,
            ticks: vec![TickRecord {
                t: 4,
                inputs: vec![],
                outputs: vec![],
            }],
        };
        let bytes = encode(&trace).expect("encode");
        let e = decode(&bytes[..bytes.len() - 1])
            .map_err(|e| e.to_string())
            .err();
        assert_eq!(
            e.as_deref(),
            Some("frame 1: truncated: the last frame has no 0x00 terminator")
        );
    }
}
