//! Screens the Modbus TCP request frames a client sends before tokio-modbus decodes them.
//!
//! tokio-modbus 0.17's request decoder trusts the counts inside a PDU: a *Write Multiple Coils*
//! (0x0F) whose quantity exceeds its byte count's bits indexes past the frame (a panic in any
//! build), and a *Write Multiple Registers* (0x10) or *Read/Write Multiple Registers* (0x17) with a
//! quantity above 32,767 overflows `quantity * 2` (a panic with overflow checks). Any client could
//! end its connection's task that way. The screen holds each frame back until all of it has
//! arrived (MBAP length 2..=254: the standard's 260-byte ADU), checks the quantities and byte counts
//! of those three functions against the ranges of the Modbus application protocol (§6.11, §6.12,
//! §6.17), and only then hands the frame's bytes on.
//!
//! Invariant: a frame is handed on unchanged and whole, or not at all; a refused frame (or an MBAP
//! length outside 2..=254) ends the connection with an `InvalidData` error, as tokio-modbus does
//! for the byte-count mismatches it detects itself. The bytes held back are at most one frame.

use std::fmt;

/// Largest MBAP length field: unit id + 253 bytes of PDU (an ADU of 260 bytes).
pub const MAX_MBAP_LEN: usize = 254;

/// Why a request frame was refused.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Refusal(String);

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Modbus request refused: {}", self.0)
    }
}

impl std::error::Error for Refusal {}

/// The request bytes of one connection: a checked prefix ready to hand on, then the start of the
/// next frame.
#[derive(Debug, Default)]
pub struct Screen {
    buf: Vec<u8>,
    /// Bytes at the front of `buf` that belong to checked frames.
    ready: usize,
}

impl Screen {
    /// An empty screen.
    pub fn new() -> Screen {
        Screen::default()
    }

    /// True when checked bytes wait to be handed on.
    pub fn has_ready(&self) -> bool {
        self.ready > 0
    }

    /// Adds bytes from the client and checks every frame they complete.
    pub fn push(&mut self, bytes: &[u8]) -> Result<(), Refusal> {
        self.buf.extend_from_slice(bytes);
        loop {
            let rest = &self.buf[self.ready..];
            if rest.len() < 6 {
                return Ok(());
            }
            let len = usize::from(u16::from_be_bytes([rest[4], rest[5]]));
            if !(2..=MAX_MBAP_LEN).contains(&len) {
                return Err(Refusal(format!(
                    "MBAP length {len} outside 2..={MAX_MBAP_LEN}"
                )));
            }
            if rest.len() < 6 + len {
                return Ok(());
            }
            check_pdu(&rest[7..6 + len])?;
            self.ready += 6 + len;
        }
    }

    /// Hands on as many checked bytes as `out` holds; returns how many.
    pub fn take(&mut self, out: &mut [u8]) -> usize {
        let n = self.ready.min(out.len());
        out[..n].copy_from_slice(&self.buf[..n]);
        self.buf.drain(..n);
        self.ready -= n;
        n
    }
}

fn be(p: &[u8], at: usize) -> Option<u16> {
    Some(u16::from_be_bytes([*p.get(at)?, *p.get(at + 1)?]))
}

/// The counts of a request PDU (function code first) are within the protocol's ranges. A PDU too
/// short to carry them passes: the decoder then reports the short frame itself.
fn check_pdu(pdu: &[u8]) -> Result<(), Refusal> {
    let refuse = |what: String| Err(Refusal(what));
    match pdu.first() {
        Some(0x0F) => {
            let (Some(qty), Some(&count)) = (be(pdu, 3), pdu.get(5)) else {
                return Ok(());
            };
            if !(1..=1968).contains(&qty) || usize::from(count) != usize::from(qty).div_ceil(8) {
                return refuse(format!(
                    "write multiple coils (0x0F): quantity {qty} with byte count {count} (1..=1968 coils in ⌈quantity/8⌉ bytes)"
                ));
            }
        }
        Some(0x10) => {
            let (Some(qty), Some(&count)) = (be(pdu, 3), pdu.get(5)) else {
                return Ok(());
            };
            if !(1..=123).contains(&qty) || usize::from(count) != 2 * usize::from(qty) {
                return refuse(format!(
                    "write multiple registers (0x10): quantity {qty} with byte count {count} (1..=123 registers in 2 × quantity bytes)"
                ));
            }
        }
        Some(0x17) => {
            let (Some(read), Some(write), Some(&count)) = (be(pdu, 3), be(pdu, 7), pdu.get(9))
            else {
                return Ok(());
            };
            if !(1..=125).contains(&read)
                || !(1..=121).contains(&write)
                || usize::from(count) != 2 * usize::from(write)
            {
                return refuse(format!(
                    "read/write multiple registers (0x17): read {read}, write {write} with byte count {count} (1..=125 read, 1..=121 written in 2 × quantity bytes)"
                ));
            }
        }
        _ => {}
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// MBAP header (transaction 7, unit 1) around `pdu`.
    fn frame(pdu: &[u8]) -> Vec<u8> {
        let len = u16::try_from(pdu.len() + 1).expect("len");
        let mut f = vec![0, 7, 0, 0];
        f.extend_from_slice(&len.to_be_bytes());
        f.push(1);
        f.extend_from_slice(pdu);
        f
    }

    fn all(s: &mut Screen) -> Vec<u8> {
        let mut out = vec![0; 600];
        let n = s.take(&mut out);
        out.truncate(n);
        out
    }

    #[test]
    fn frames_pass_whole_and_unchanged_whatever_the_reads() {
        let mut bytes = frame(&[0x04, 0, 0, 0, 1]);
        bytes.extend(frame(&[0x10, 0, 8, 0, 2, 4, 1, 2, 3, 4]));
        bytes.extend(frame(&[0x0F, 0, 0, 0, 9, 2, 0xFF, 1]));
        let mut s = Screen::new();
        let mut got = Vec::new();
        for b in &bytes {
            s.push(std::slice::from_ref(b)).expect("valid");
            got.extend(all(&mut s));
            // Nothing of a frame is handed on before its last byte.
            assert!(
                [0, 12, 12 + 17, 12 + 17 + 15].contains(&got.len()),
                "{}",
                got.len()
            );
        }
        assert_eq!(got, bytes);
    }

    #[test]
    fn counts_outside_the_protocol_are_refused() {
        // The frame the modbus_server fuzz target found: 0x10 with quantity 0xC013 (overflow).
        let crash = [0x31, 0, 0, 0, 0, 7, 0, 0x10, 0xFF, 0x2F, 0xC0, 0x13, 0];
        assert_eq!(
            Screen::new().push(&crash).map_err(|e| e.to_string()),
            Err("Modbus request refused: write multiple registers (0x10): quantity 49171 with byte count 0 (1..=123 registers in 2 × quantity bytes)".into())
        );
        // 100 coils in one byte: the decoder would index past the frame.
        assert!(
            Screen::new()
                .push(&frame(&[0x0F, 0, 0, 0, 100, 1, 0xFF]))
                .is_err()
        );
        assert!(Screen::new().push(&frame(&[0x0F, 0, 0, 0, 0, 0])).is_err());
        assert!(
            Screen::new()
                .push(&frame(&[0x10, 0, 0, 0, 124, 248]))
                .is_err()
        );
        assert!(
            Screen::new()
                .push(&frame(&[0x17, 0, 0, 0, 1, 0, 0, 0x80, 0, 0, 0]))
                .is_err()
        );
        assert!(
            Screen::new()
                .push(&frame(&[0x17, 0, 0, 0, 126, 0, 0, 0, 1, 2, 0, 0]))
                .is_err()
        );
        // Lengths outside the ADU.
        assert!(Screen::new().push(&[0, 1, 0, 0, 0, 255]).is_err());
        assert!(Screen::new().push(&[0, 1, 0, 0, 0, 1]).is_err());
        // The largest valid requests pass.
        let mut w = vec![0x10, 0, 0, 0, 123, 246];
        w.extend(std::iter::repeat_n(0, 246));
        let mut s = Screen::new();
        assert_eq!(s.push(&frame(&w)), Ok(()));
        assert_eq!(all(&mut s).len(), 7 + w.len());
    }
}
