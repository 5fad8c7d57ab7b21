//! Reading what a crashed recording left: every complete record of a `.partial` file up to the
//! first torn or damaged one (a record cut by `kill -9`, zeros after a power loss).
//!
//! A text record is complete when its line ends in `\n` and parses; a binary record when its COBS
//! frame ends in `0x00` and decodes. Used by `ncplc trace recover` and by `ncplc replay` on a
//! `.partial` file.

use std::io::BufRead;

use super::reader::Reader;
use super::{TickRecord, Trace, TraceError};

/// What [`recover`] read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Recovered {
    /// The complete records.
    pub trace: Trace,
    /// Bytes of the file the records came from.
    pub kept_bytes: usize,
    /// Bytes after them that were dropped (the torn tail).
    pub dropped_bytes: usize,
}

impl Recovered {
    /// One line for the user: what was kept and what was dropped.
    pub fn summary(&self) -> String {
        let last = self.trace.ticks.last().map(|r| r.t);
        summary(self.trace.ticks.len(), last, self.dropped_bytes as u64)
    }
}

/// One line for the user: `n` records kept up to tick `last`, `dropped` bytes of torn tail.
pub fn summary(n: usize, last: Option<u64>, dropped: u64) -> String {
    let last = last.map_or(String::new(), |t| format!(" (up to tick {t})"));
    format!(
        "recovered {n} record{}{last}; dropped {dropped} byte{} of torn tail",
        if n == 1 { "" } else { "s" },
        if dropped == 1 { "" } else { "s" },
    )
}

/// Reads the complete records of a possibly torn trace (text or binary). Fails only when not even
/// the header is complete.
pub fn recover(bytes: &[u8]) -> Result<Recovered, TraceError> {
    let mut ticks = Vec::new();
    let (reader, kept) = recover_each(bytes, |r| ticks.push(r))?;
    let kept = usize::try_from(kept).unwrap_or(bytes.len());
    Ok(Recovered {
        trace: Trace {
            tick_ms: reader.tick_ms,
            ticks,
            part: reader.part,
        },
        kept_bytes: kept,
        dropped_bytes: bytes.len() - kept,
    })
}

/// [`recover`] of a stream: hands each complete record to `each` as it is read (so a torn file
/// of any length is recovered in constant memory) and returns the header and the bytes the
/// records came from.
pub fn recover_each(
    input: impl BufRead,
    mut each: impl FnMut(TickRecord),
) -> Result<(super::reader::Header, u64), TraceError> {
    let mut reader = Reader::recovering(input)?;
    let header = reader.header().clone();
    while let Some(Ok(r)) = reader.next() {
        each(r);
    }
    Ok((header, reader.complete_bytes()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::binary;

    fn trace() -> Trace {
        let sig = |s: &str| s.parse().expect("signal");
        Trace {
            part: None,
            tick_ms: 2,
            ticks: vec![
                TickRecord {
                    nodes_lost: Vec::new(),
                    commands: Vec::new(),
                    drives: Vec::new(),
                    forced: Vec::new(),
                    positions: Vec::new(),
                    t: 0,
                    inputs: vec![(sig("I0A5"), 1)],
                    outputs: vec![(sig("U4A0"), 1)],
                },
                TickRecord {
                    nodes_lost: Vec::new(),
                    commands: Vec::new(),
                    drives: Vec::new(),
                    forced: Vec::new(),
                    positions: Vec::new(),
                    t: 7,
                    inputs: vec![],
                    outputs: vec![(sig("U4A0"), 0)],
                },
            ],
        }
    }

    /// Where each record of `bytes` ends (after its `sep`).
    fn ends_of(bytes: &[u8], sep: u8) -> Vec<usize> {
        bytes
            .iter()
            .enumerate()
            .filter(|(_, b)| **b == sep)
            .map(|(i, _)| i + 1)
            .collect()
    }

    #[test]
    fn every_cut_of_a_binary_trace_recovers_the_whole_frames_before_it() {
        let bytes = binary::encode(&trace()).expect("encode");
        let ends = ends_of(&bytes, 0);
        assert_eq!(ends.len(), 3);
        for cut in ends[0]..=bytes.len() {
            let r = recover(&bytes[..cut]).expect("recover");
            let whole = ends.iter().filter(|&&e| e <= cut).count() - 1;
            assert_eq!(r.trace.ticks, trace().ticks[..whole], "cut at {cut}");
            assert_eq!(r.kept_bytes, ends[whole]);
            assert_eq!(r.dropped_bytes, cut - ends[whole]);
        }
        // Not even a header: an error.
        assert!(recover(&bytes[..ends[0] - 1]).is_err());
    }

    #[test]
    fn every_cut_of_a_text_trace_keeps_the_lines_that_end_before_it() {
        let mut bytes = Vec::new();
        trace().write_text(&mut bytes).expect("text");
        let ends = ends_of(&bytes, b'\n');
        assert_eq!(ends.len(), 3);
        for cut in ends[0]..=bytes.len() {
            // A last line without its line end is torn even when it parses (`{"t":7}` cut
            // before `\n`), as a crash leaves it.
            let r = recover(&bytes[..cut]).expect("recover");
            let whole = ends.iter().filter(|&&e| e <= cut).count() - 1;
            assert_eq!(r.trace.ticks, trace().ticks[..whole], "cut at {cut}");
            assert_eq!(
                (r.kept_bytes, r.dropped_bytes),
                (ends[whole], cut - ends[whole])
            );
            // Read as a stream through a small buffer: the same records and bytes.
            let mut ticks = Vec::new();
            let reader = std::io::BufReader::with_capacity(3, &bytes[..cut]);
            let (header, kept) = recover_each(reader, |t| ticks.push(t)).expect("stream");
            assert_eq!((ticks, kept), (r.trace.ticks.clone(), ends[whole] as u64));
            assert_eq!(header.tick_ms, 2);
        }
        assert!(recover(&bytes[..ends[0] - 1]).is_err(), "a torn header");
    }

    #[test]
    fn a_text_trace_with_junk_after_a_power_loss_keeps_its_complete_lines() {
        let mut bytes = Vec::new();
        trace().write_text(&mut bytes).expect("text");
        let whole = bytes.len();
        bytes.extend_from_slice(b"{\"t\":9,\"out\":{\"U4");
        bytes.extend_from_slice(&[0, 0, 0xff, b'\n']);
        let r = recover(&bytes).expect("recover");
        assert_eq!(r.trace, trace());
        assert_eq!(r.kept_bytes, whole);
        assert_eq!(r.dropped_bytes, 21);
        assert_eq!(
            r.summary(),
            "recovered 2 records (up to tick 7); dropped 21 bytes of torn tail"
        );
    }

    #[test]
    fn a_zeroed_binary_tail_is_dropped() {
        let mut bytes = binary::encode(&trace()).expect("encode");
        let whole = bytes.len();
        bytes.extend_from_slice(&[0; 16]);
        let r = recover(&bytes).expect("recover");
        assert_eq!(r.trace, trace());
        assert_eq!((r.kept_bytes, r.dropped_bytes), (whole, 16));
    }
}
