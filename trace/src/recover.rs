//! Reading what a crashed recording left: every complete record of a `.partial` file up to the
//! first torn or damaged one (a record cut by `kill -9`, zeros after a power loss).
//!
//! A text record is complete when its line ends in `\n` and parses; a binary record when its COBS
//! frame ends in `0x00` and decodes. Used by `ncplc trace recover` and by `ncplc replay` on a
//! `.partial` file.

use super::{Trace, TraceError, binary, text};

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
        let n = self.trace.ticks.len();
        let last = self
            .trace
            .ticks
            .last()
            .map_or(String::new(), |r| format!(" (up to tick {})", r.t));
        format!(
            "recovered {n} record{}{last}; dropped {} byte{} of torn tail",
            if n == 1 { "" } else { "s" },
            self.dropped_bytes,
            if self.dropped_bytes == 1 { "" } else { "s" },
        )
    }
}

/// Reads the complete records of a possibly torn trace (text or binary). Fails only when not even
/// the header is complete.
pub fn recover(bytes: &[u8]) -> Result<Recovered, TraceError> {
    let is_text = bytes.iter().find(|b| !b.is_ascii_whitespace()) == Some(&b'{');
    let (sep, cut): (u8, fn(&TraceError) -> Option<usize>) = if is_text {
        (b'\n', |e| match e {
            // Lines are 1-based; keep the lines before the bad one.
            TraceError::Text { line, .. } => Some(line.saturating_sub(1)),
            _ => None,
        })
    } else {
        (0, |e| match e {
            TraceError::Binary { frame, .. } => Some(*frame),
            _ => None,
        })
    };
    // A text file may end in bytes that are not UTF-8 at all (a power loss leaves zeros or junk).
    let valid = if is_text {
        match std::str::from_utf8(bytes) {
            Ok(_) => bytes.len(),
            Err(e) => e.valid_up_to(),
        }
    } else {
        bytes.len()
    };
    // Whole records only: up to the last separator.
    let mut end = bytes[..valid]
        .iter()
        .rposition(|&b| b == sep)
        .map_or(0, |i| i + 1);
    let parse = |b: &[u8]| {
        if is_text {
            text::parse(b)
        } else {
            binary::decode(b)
        }
    };
    // A damaged record inside the file: keep the records before it. Parsing is deterministic, so
    // the second attempt on the shorter prefix succeeds unless the header itself is damaged.
    for _ in 0..2 {
        match parse(&bytes[..end]) {
            Ok(trace) => {
                return Ok(Recovered {
                    trace,
                    kept_bytes: end,
                    dropped_bytes: bytes.len() - end,
                });
            }
            Err(e) => match cut(&e) {
                Some(keep) if keep > 0 => {
                    end = bytes[..end]
                        .split_inclusive(|&b| b == sep)
                        .take(keep)
                        .map(<[u8]>::len)
                        .sum();
                }
                _ => return Err(e),
            },
        }
    }
    parse(&bytes[..end]).map(|trace| Recovered {
        trace,
        kept_bytes: end,
        dropped_bytes: bytes.len() - end,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::TickRecord;

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

    #[test]
    fn every_cut_of_a_binary_trace_recovers_the_whole_frames_before_it() {
        let bytes = binary::encode(&trace()).expect("encode");
        let ends: Vec<usize> = bytes
            .iter()
            .enumerate()
            .filter(|(_, b)| **b == 0)
            .map(|(i, _)| i + 1)
            .collect();
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
