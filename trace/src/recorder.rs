//! Turning a running image into trace records: which inputs a latch changed and which written
//! signals changed value during a tick.

use packets::{Dir, PACKETS_LEN, Packet, Signal};

use super::SignalValue;

/// Tracks the written signals' values from one tick's end to the next (all zero before tick 0).
#[derive(Debug, Clone)]
pub struct OutputTracker {
    /// Distinct image bytes holding written signals, ascending.
    offsets: Vec<usize>,
    /// For each offset, the signals in that byte.
    groups: Vec<Vec<Signal>>,
    /// The value of each offset's byte at the end of the previous tick.
    prev: Vec<u8>,
}

impl OutputTracker {
    /// A tracker for `written` (the program's written signals).
    pub fn new(written: &[Signal]) -> OutputTracker {
        let mut sigs: Vec<Signal> = written.to_vec();
        sigs.sort_by_key(|s| (s.image_byte(), s.bit().map_or(8, i32::from), *s));
        sigs.dedup();
        let mut offsets: Vec<usize> = Vec::new();
        let mut groups: Vec<Vec<Signal>> = Vec::new();
        for s in sigs {
            if offsets.last() != Some(&s.image_byte()) {
                offsets.push(s.image_byte());
                groups.push(Vec::new());
            }
            if let Some(g) = groups.last_mut() {
                g.push(s);
            }
        }
        let prev = vec![0; offsets.len()];
        OutputTracker {
            offsets,
            groups,
            prev,
        }
    }

    /// A tracker for a new program that continues from `old`'s last values (online change).
    pub fn continue_from(&self, written: &[Signal], image: &[u8]) -> OutputTracker {
        let mut t = OutputTracker::new(written);
        for (i, &off) in t.offsets.iter().enumerate() {
            // Bytes the old program tracked keep their last published value; new ones start from
            // the current image so that they report only real changes.
            t.prev[i] = match self.offsets.binary_search(&off) {
                Ok(j) => self.prev[j],
                Err(_) => image.get(off).copied().unwrap_or(0),
            };
        }
        t
    }

    /// Appends the written signals whose value differs from the previous call, and remembers the
    /// current values.
    pub fn diff(&mut self, image: &[u8], out: &mut Vec<SignalValue>) {
        for (i, &off) in self.offsets.iter().enumerate() {
            let cur = image.get(off).copied().unwrap_or(0);
            let old = self.prev[i];
            if cur != old {
                for s in &self.groups[i] {
                    let (a, b) = (value_in_byte(s, old), value_in_byte(s, cur));
                    if a != b {
                        out.push((*s, b));
                    }
                }
                self.prev[i] = cur;
            }
        }
    }
}

/// The value `s` has when its byte holds `byte`.
pub fn value_in_byte(s: &Signal, byte: u8) -> u8 {
    match s.bit() {
        Some(b) => (byte >> b) & 1,
        None => byte,
    }
}

/// Finds the input changes a latch made (by comparing the packets before and after it).
#[derive(Debug, Clone)]
pub struct InputDiff {
    before: Vec<u8>,
    byte_inputs: Vec<bool>,
}

/// The part of the image the I/O may write: packets A, K and N.
const INPUT_LEN: usize = Packet::T.offset();

impl Default for InputDiff {
    fn default() -> Self {
        InputDiff::new(&default_byte_inputs())
    }
}

/// The CNC→PLC bytes of the interface map that are recorded as bytes: MODE, MCODE, MIMM, SCODE, TCODE.
pub fn default_byte_inputs() -> Vec<Signal> {
    (2u16..=5)
        .flat_map(|c| {
            (0u8..4).map(move |i| Signal::Byte {
                packet: Packet::K,
                connector: c,
                index: i,
            })
        })
        .collect()
}

impl InputDiff {
    /// A differ that records the bytes in `byte_inputs` as `W` signals and everything else as bits.
    pub fn new(byte_inputs: &[Signal]) -> InputDiff {
        let mut flags = vec![false; INPUT_LEN];
        for s in byte_inputs {
            if let Some(f) = flags.get_mut(s.image_byte()) {
                *f = true;
            }
        }
        InputDiff {
            before: vec![0; INPUT_LEN],
            byte_inputs: flags,
        }
    }

    /// Remembers the packets before the latch.
    pub fn before_latch(&mut self, image: &[u8]) {
        let n = INPUT_LEN.min(image.len());
        self.before[..n].copy_from_slice(&image[..n]);
    }

    /// Appends what the latch changed.
    pub fn after_latch(&self, image: &[u8], out: &mut Vec<SignalValue>) {
        let n = INPUT_LEN.min(image.len()).min(PACKETS_LEN);
        for (at, (&old, &new)) in self.before[..n].iter().zip(&image[..n]).enumerate() {
            if old == new {
                continue;
            }
            let (packet, rel) = if at < Packet::K.offset() {
                (Packet::A, at)
            } else if at < Packet::N.offset() {
                (Packet::K, at - Packet::K.offset())
            } else {
                (Packet::N, at - Packet::N.offset())
            };
            let connector = (rel / 4) as u16;
            if self.byte_inputs[at] {
                out.push((
                    Signal::Byte {
                        packet,
                        connector,
                        index: (rel % 4) as u8,
                    },
                    new,
                ));
                continue;
            }
            for bit in 0..8u8 {
                if (old ^ new) & (1 << bit) != 0 {
                    let contact = (rel % 4) as u8 * 8 + bit;
                    out.push((
                        Signal::Bit {
                            dir: Dir::In,
                            packet,
                            connector,
                            contact,
                        },
                        (new >> bit) & 1,
                    ));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sig(s: &str) -> Signal {
        s.parse().expect("signal")
    }

    #[test]
    fn only_changed_written_signals_are_reported() {
        let mut t = OutputTracker::new(&[sig("U4A0"), sig("U4A1"), sig("W14K0")]);
        let mut img = vec![0u8; PACKETS_LEN];
        let mut out = Vec::new();
        t.diff(&img, &mut out);
        assert!(out.is_empty());
        sig("U4A1").write(&mut img, 1);
        sig("U4A7").write(&mut img, 1); // not written by the program
        sig("W14K0").write(&mut img, 100);
        t.diff(&img, &mut out);
        assert_eq!(out, vec![(sig("U4A1"), 1), (sig("W14K0"), 100)]);
        out.clear();
        t.diff(&img, &mut out);
        assert!(out.is_empty());
        sig("U4A1").write(&mut img, 0);
        t.diff(&img, &mut out);
        assert_eq!(out, vec![(sig("U4A1"), 0)]);
    }

    #[test]
    fn latch_changes_become_bits_or_bytes() {
        let mut d = InputDiff::default();
        let mut img = vec![0u8; PACKETS_LEN];
        sig("I1A29").write(&mut img, 1);
        d.before_latch(&img);
        sig("I1A29").write(&mut img, 0);
        sig("I0A5").write(&mut img, 1);
        sig("W3K0").write(&mut img, 0x03);
        let mut out = Vec::new();
        d.after_latch(&img, &mut out);
        assert_eq!(
            out,
            vec![(sig("I0A5"), 1), (sig("I1A29"), 0), (sig("W3K0"), 3)]
        );
    }
}
