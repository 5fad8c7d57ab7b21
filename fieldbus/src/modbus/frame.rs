//! Modbus TCP framing of the output writes the client sends on its write connection.
//!
//! The write connection frames its requests itself (instead of going through tokio-modbus) so that
//! the scan thread can put a request on the wire with one non-blocking `send` ([`super::writer`]).
//! A request is an MBAP header (transaction id, protocol 0, length, unit id) followed by a "write
//! multiple coils" (function 15) or "write multiple registers" (function 16) PDU; the device's
//! answer echoes the function, address and quantity, or carries an exception code. The byte ↔ item
//! order is the crate's ([`super`]): a coil mapping's bytes are sent as they are (bit `n` of byte
//! `i` = coil `address + 8i + n`, which is Modbus's own packing), a register mapping's bytes go in
//! pairs, low byte first.

use crate::map::ModbusArea;

/// Largest Modbus TCP frame: a 7-byte MBAP header and a PDU of at most 253 bytes.
pub const MAX_ADU: usize = 260;
/// MBAP header: transaction id, protocol id, length (each 2 bytes), unit id.
const HEADER: usize = 7;
/// Most data bytes one write request carries (1968 coils or 123 registers at most).
const MAX_DATA: usize = 246;

/// Why a request cannot be framed or an answer does not fit its request.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum FrameError {
    /// Outputs can only go to coils or holding registers.
    #[error("outputs cannot be written to a read-only table")]
    ReadOnly,
    /// Nothing to write, or more than one request carries.
    #[error("{0} bytes do not fit one write request")]
    BadLength(usize),
    /// The MBAP header is not Modbus TCP (protocol id, length field).
    #[error("the answer's MBAP header is malformed")]
    BadHeader,
    /// The answer belongs to another transaction or unit.
    #[error("answer to transaction {got}, expected {want}")]
    WrongTransaction {
        /// The answer's transaction id.
        got: u16,
        /// The request's transaction id.
        want: u16,
    },
    /// The PDU is not the echo of the request nor an exception to it.
    #[error("the answer does not match the write request")]
    Mismatch,
}

/// What a write request asked for, to check the device's answer against.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WriteRequest {
    /// Transaction id of the MBAP header.
    pub tid: u16,
    /// Unit id.
    pub unit: u8,
    /// Function code: 15 (coils) or 16 (holding registers).
    pub function: u8,
    /// First item.
    pub address: u16,
    /// Number of items.
    pub quantity: u16,
}

/// The device's answer to a write.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Answer {
    /// The device applied the write.
    Done,
    /// The device refused it with this Modbus exception code.
    Exception(u8),
}

impl WriteRequest {
    /// Frames the write of `bytes` to `area` from item `address` into `out`; returns the request
    /// and the frame's length.
    pub fn encode(
        tid: u16,
        unit: u8,
        area: ModbusArea,
        address: u16,
        bytes: &[u8],
        out: &mut [u8; MAX_ADU],
    ) -> Result<(WriteRequest, usize), FrameError> {
        if bytes.is_empty() || bytes.len() > MAX_DATA {
            return Err(FrameError::BadLength(bytes.len()));
        }
        let (function, quantity, data_len) = match area {
            ModbusArea::Coils => (15u8, bytes.len() * 8, bytes.len()),
            ModbusArea::HoldingRegisters => {
                let regs = bytes.len().div_ceil(2);
                (16u8, regs, regs * 2)
            }
            ModbusArea::DiscreteInputs | ModbusArea::InputRegisters => {
                return Err(FrameError::ReadOnly);
            }
        };
        // Both fit: data_len ≤ 246 + 1 and quantity ≤ 1968.
        let quantity = quantity as u16;
        let pdu_len = 6 + data_len;
        out[0..2].copy_from_slice(&tid.to_be_bytes());
        out[2..4].copy_from_slice(&[0, 0]);
        out[4..6].copy_from_slice(&((pdu_len + 1) as u16).to_be_bytes());
        out[6] = unit;
        out[7] = function;
        out[8..10].copy_from_slice(&address.to_be_bytes());
        out[10..12].copy_from_slice(&quantity.to_be_bytes());
        out[12] = data_len as u8;
        let data = &mut out[13..13 + data_len];
        if function == 15 {
            data.copy_from_slice(bytes);
        } else {
            for (k, pair) in data.chunks_exact_mut(2).enumerate() {
                pair[0] = bytes.get(2 * k + 1).copied().unwrap_or(0);
                pair[1] = bytes[2 * k];
            }
        }
        let req = WriteRequest {
            tid,
            unit,
            function,
            address,
            quantity,
        };
        Ok((req, HEADER + pdu_len))
    }

    /// Parses the answer at the start of `buf`: `Ok(None)` while it is incomplete, else the
    /// answer and how many bytes it took.
    pub fn parse_answer(&self, buf: &[u8]) -> Result<Option<(usize, Answer)>, FrameError> {
        if buf.len() < HEADER {
            return Ok(None);
        }
        let tid = u16::from_be_bytes([buf[0], buf[1]]);
        let protocol = u16::from_be_bytes([buf[2], buf[3]]);
        let len = usize::from(u16::from_be_bytes([buf[4], buf[5]]));
        if protocol != 0 || !(2..=254).contains(&len) {
            return Err(FrameError::BadHeader);
        }
        if tid != self.tid || buf[6] != self.unit {
            return Err(FrameError::WrongTransaction {
                got: tid,
                want: self.tid,
            });
        }
        let total = 6 + len;
        let Some(pdu) = buf.get(HEADER..total) else {
            return Ok(None);
        };
        let answer = match pdu {
            [f, a0, a1, q0, q1]
                if *f == self.function
                    && u16::from_be_bytes([*a0, *a1]) == self.address
                    && u16::from_be_bytes([*q0, *q1]) == self.quantity =>
            {
                Answer::Done
            }
            [f, code] if *f == self.function | 0x80 => Answer::Exception(*code),
            _ => return Err(FrameError::Mismatch),
        };
        Ok(Some((total, answer)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coils_go_as_the_bytes_are_and_registers_low_byte_first() {
        let mut out = [0u8; MAX_ADU];
        let (req, n) = WriteRequest::encode(
            0x0102,
            3,
            ModbusArea::Coils,
            100,
            &[0b0000_0101, 0x80],
            &mut out,
        )
        .expect("frames");
        assert_eq!(
            &out[..n],
            &[1, 2, 0, 0, 0, 9, 3, 15, 0, 100, 0, 16, 2, 0b0000_0101, 0x80]
        );
        assert_eq!((req.function, req.address, req.quantity), (15, 100, 16));
        let (req, n) = WriteRequest::encode(
            7,
            1,
            ModbusArea::HoldingRegisters,
            7,
            &[0xCD, 0xAB, 0x01],
            &mut out,
        )
        .expect("frames");
        assert_eq!(
            &out[..n],
            &[
                0, 7, 0, 0, 0, 11, 1, 16, 0, 7, 0, 2, 4, 0xAB, 0xCD, 0x00, 0x01
            ]
        );
        assert_eq!((req.function, req.quantity), (16, 2));
    }

    #[test]
    fn read_only_tables_and_bad_lengths_are_refused() {
        let mut out = [0u8; MAX_ADU];
        let enc = |area, bytes: &[u8], out: &mut [u8; MAX_ADU]| {
            WriteRequest::encode(1, 1, area, 0, bytes, out).map(|(_, n)| n)
        };
        assert_eq!(
            enc(ModbusArea::DiscreteInputs, &[1], &mut out),
            Err(FrameError::ReadOnly)
        );
        assert_eq!(
            enc(ModbusArea::Coils, &[], &mut out),
            Err(FrameError::BadLength(0))
        );
        assert_eq!(
            enc(ModbusArea::Coils, &[0; 247], &mut out),
            Err(FrameError::BadLength(247))
        );
        assert_eq!(enc(ModbusArea::Coils, &[0; 246], &mut out), Ok(259));
    }

    #[test]
    fn answers_are_checked_against_their_request() {
        let req = WriteRequest {
            tid: 9,
            unit: 1,
            function: 15,
            address: 100,
            quantity: 32,
        };
        let ok = [0, 9, 0, 0, 0, 6, 1, 15, 0, 100, 0, 32];
        assert_eq!(req.parse_answer(&ok[..5]), Ok(None));
        assert_eq!(req.parse_answer(&ok[..11]), Ok(None));
        assert_eq!(req.parse_answer(&ok), Ok(Some((12, Answer::Done))));
        let mut two = ok.to_vec();
        two.extend_from_slice(&ok);
        assert_eq!(req.parse_answer(&two), Ok(Some((12, Answer::Done))));
        assert_eq!(
            req.parse_answer(&[0, 9, 0, 0, 0, 3, 1, 0x8F, 2]),
            Ok(Some((9, Answer::Exception(2))))
        );
        assert_eq!(
            req.parse_answer(&[0, 8, 0, 0, 0, 6, 1, 15, 0, 100, 0, 32]),
            Err(FrameError::WrongTransaction { got: 8, want: 9 })
        );
        assert_eq!(
            req.parse_answer(&[0, 9, 0, 1, 0, 6, 1, 15, 0, 100, 0, 32]),
            Err(FrameError::BadHeader)
        );
        assert_eq!(
            req.parse_answer(&[0, 9, 0, 0, 0, 0, 1]),
            Err(FrameError::BadHeader)
        );
        assert_eq!(
            req.parse_answer(&[0, 9, 0, 0, 0, 6, 1, 15, 0, 101, 0, 32]),
            Err(FrameError::Mismatch)
        );
        assert_eq!(
            req.parse_answer(&[0, 9, 0, 0, 0, 3, 1, 0x90, 2]),
            Err(FrameError::Mismatch)
        );
    }
}
