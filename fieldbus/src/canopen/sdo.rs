//! SDO expedited transfers (up to 4 bytes): the request and response codec, the client transfers
//! the master uses at start, and the server side the simulated node uses.
//!
//! Command bytes: download request `0x23 | (4 - size) << 2` (`0x2F` 1 byte, `0x2B` 2, `0x23` 4),
//! download response `0x60`, upload request `0x40`, upload response `0x43 | (4 - size) << 2`,
//! abort `0x80` with a 32-bit abort code; bytes 1..2 index (little-endian), byte 3 sub-index,
//! bytes 4..7 data.

use std::time::Duration;

use super::transport::CanBus;
use super::{CanMsg, cob};
use crate::map::SdoWrite;

/// Abort code: object does not exist.
pub const ABORT_NO_OBJECT: u32 = 0x0602_0000;
/// Abort code: sub-index does not exist.
pub const ABORT_NO_SUBINDEX: u32 = 0x0609_0011;
/// Abort code: data type / length mismatch.
pub const ABORT_LENGTH: u32 = 0x0607_0010;
/// Abort code: attempt to write a read-only object.
pub const ABORT_READ_ONLY: u32 = 0x0601_0002;
/// Abort code: command specifier not valid.
pub const ABORT_COMMAND: u32 = 0x0504_0001;

/// Why an SDO transfer failed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SdoError {
    /// No answer within the timeout.
    #[error("SDO {index:04X}h/{subindex} timed out")]
    Timeout {
        /// Object index.
        index: u16,
        /// Sub-index.
        subindex: u8,
    },
    /// The node aborted the transfer.
    #[error("SDO {index:04X}h/{subindex} aborted with code {code:08X}h")]
    Abort {
        /// Object index.
        index: u16,
        /// Sub-index.
        subindex: u8,
        /// Abort code.
        code: u32,
    },
    /// The bus failed.
    #[error("bus error: {0}")]
    Bus(String),
    /// A size other than 1, 2 or 4 was requested.
    #[error("expedited size {0} is not 1, 2 or 4")]
    Size(u8),
}

/// A parsed SDO server response.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SdoResponse {
    /// Download (write) confirmed.
    Downloaded {
        /// Object index.
        index: u16,
        /// Sub-index.
        subindex: u8,
    },
    /// Upload (read) with its value and size in bytes.
    Uploaded {
        /// Object index.
        index: u16,
        /// Sub-index.
        subindex: u8,
        /// The value.
        value: u32,
        /// Size in bytes (4 when the node does not say).
        size: u8,
    },
    /// Transfer aborted.
    Aborted {
        /// Object index.
        index: u16,
        /// Sub-index.
        subindex: u8,
        /// Abort code.
        code: u32,
    },
}

fn frame(cmd: u8, index: u16, subindex: u8, value: u32) -> [u8; 8] {
    let i = index.to_le_bytes();
    let v = value.to_le_bytes();
    [cmd, i[0], i[1], subindex, v[0], v[1], v[2], v[3]]
}

/// An expedited download request writing `size` bytes of `value`.
pub fn download_request(
    index: u16,
    subindex: u8,
    value: u32,
    size: u8,
) -> Result<[u8; 8], SdoError> {
    if !matches!(size, 1 | 2 | 4) {
        return Err(SdoError::Size(size));
    }
    Ok(frame(0x23 | (4 - size) << 2, index, subindex, value))
}

/// An upload request.
pub fn upload_request(index: u16, subindex: u8) -> [u8; 8] {
    frame(0x40, index, subindex, 0)
}

/// Parses a server response; `None` for anything that is not an expedited response or an abort.
pub fn parse_response(data: &[u8]) -> Option<SdoResponse> {
    if data.len() < 8 {
        return None;
    }
    let index = u16::from_le_bytes([data[1], data[2]]);
    let subindex = data[3];
    let value = u32::from_le_bytes([data[4], data[5], data[6], data[7]]);
    match data[0] {
        0x60 => Some(SdoResponse::Downloaded { index, subindex }),
        0x80 => Some(SdoResponse::Aborted {
            index,
            subindex,
            code: value,
        }),
        c if c & 0xE0 == 0x40 && c & 0x02 != 0 => {
            let size = if c & 0x01 != 0 {
                4 - (c >> 2 & 0x03)
            } else {
                4
            };
            let mask = if size >= 4 {
                u32::MAX
            } else {
                (1u32 << (8 * u32::from(size))) - 1
            };
            Some(SdoResponse::Uploaded {
                index,
                subindex,
                value: value & mask,
                size,
            })
        }
        _ => None,
    }
}

/// What a server answers to a request, given read and write access to its object dictionary.
pub fn serve_request(
    data: &[u8],
    read: impl FnOnce(u16, u8) -> Result<(u32, u8), u32>,
    write: impl FnOnce(u16, u8, u32, u8) -> Result<(), u32>,
) -> Option<[u8; 8]> {
    if data.len() < 8 {
        return None;
    }
    let index = u16::from_le_bytes([data[1], data[2]]);
    let subindex = data[3];
    let value = u32::from_le_bytes([data[4], data[5], data[6], data[7]]);
    let cmd = data[0];
    let answer = match cmd >> 5 {
        // Initiate download; only expedited with size indicated.
        1 if cmd & 0x03 == 0x03 => {
            let size = 4 - (cmd >> 2 & 0x03);
            let mask = if size >= 4 {
                u32::MAX
            } else {
                (1u32 << (8 * u32::from(size))) - 1
            };
            match write(index, subindex, value & mask, size) {
                Ok(()) => frame(0x60, index, subindex, 0),
                Err(code) => frame(0x80, index, subindex, code),
            }
        }
        2 => match read(index, subindex) {
            Ok((v, size)) => frame(0x43 | (4 - size.clamp(1, 4)) << 2, index, subindex, v),
            Err(code) => frame(0x80, index, subindex, code),
        },
        _ => frame(0x80, index, subindex, ABORT_COMMAND),
    };
    Some(answer)
}

/// Waits for the SDO response of `node`, passing every other frame to `other`.
async fn response<B: CanBus>(
    bus: &mut B,
    node: u8,
    index: u16,
    subindex: u8,
    timeout: Duration,
    other: &mut impl FnMut(&CanMsg),
) -> Result<SdoResponse, SdoError> {
    let deadline = tokio::time::Instant::now() + timeout;
    loop {
        let msg = match tokio::time::timeout_at(deadline, bus.recv()).await {
            Err(_) => return Err(SdoError::Timeout { index, subindex }),
            Ok(Err(e)) => return Err(SdoError::Bus(e.to_string())),
            Ok(Ok(m)) => m,
        };
        if msg.id == u32::from(cob::SDO_TX) + u32::from(node) && !msg.extended {
            match parse_response(msg.payload()) {
                Some(
                    r @ (SdoResponse::Downloaded {
                        index: i,
                        subindex: s,
                    }
                    | SdoResponse::Uploaded {
                        index: i,
                        subindex: s,
                        ..
                    }),
                ) if i == index && s == subindex => return Ok(r),
                Some(SdoResponse::Aborted { code, .. }) => {
                    return Err(SdoError::Abort {
                        index,
                        subindex,
                        code,
                    });
                }
                _ => {}
            }
        } else {
            other(&msg);
        }
    }
}

/// Performs the expedited write `w` on `node`.
pub async fn download<B: CanBus>(
    bus: &mut B,
    node: u8,
    w: &SdoWrite,
    timeout: Duration,
    other: &mut impl FnMut(&CanMsg),
) -> Result<(), SdoError> {
    let (index, subindex) = (w.index, w.subindex);
    let req = download_request(index, subindex, w.value, w.size)?;
    bus.send(&CanMsg::new(cob::SDO_RX + u16::from(node), &req))
        .await
        .map_err(|e| SdoError::Bus(e.to_string()))?;
    response(bus, node, index, subindex, timeout, other)
        .await
        .map(|_| ())
}

/// Reads object `index`/`subindex` of `node`; returns the value and its size.
pub async fn upload<B: CanBus>(
    bus: &mut B,
    node: u8,
    index: u16,
    subindex: u8,
    timeout: Duration,
    other: &mut impl FnMut(&CanMsg),
) -> Result<(u32, u8), SdoError> {
    bus.send(&CanMsg::new(
        cob::SDO_RX + u16::from(node),
        &upload_request(index, subindex),
    ))
    .await
    .map_err(|e| SdoError::Bus(e.to_string()))?;
    match response(bus, node, index, subindex, timeout, other).await? {
        SdoResponse::Uploaded { value, size, .. } => Ok((value, size)),
        _ => Err(SdoError::Abort {
            index,
            subindex,
            code: ABORT_COMMAND,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn request_bytes_follow_the_command_specifiers() {
        assert_eq!(
            download_request(0x1017, 0, 100, 2).expect("size"),
            [0x2B, 0x17, 0x10, 0, 100, 0, 0, 0]
        );
        assert_eq!(
            download_request(0x6200, 1, 0xFF, 1).expect("size"),
            [0x2F, 0x00, 0x62, 1, 0xFF, 0, 0, 0]
        );
        assert_eq!(download_request(0x1000, 0, 1, 3), Err(SdoError::Size(3)));
        assert_eq!(upload_request(0x1000, 0), [0x40, 0x00, 0x10, 0, 0, 0, 0, 0]);
    }

    #[test]
    fn server_answers_reads_writes_and_aborts() {
        let up = serve_request(
            &upload_request(0x1000, 0),
            |_, _| Ok((0x000F_0191, 4)),
            |_, _, _, _| Ok(()),
        )
        .expect("answer");
        assert_eq!(
            parse_response(&up),
            Some(SdoResponse::Uploaded {
                index: 0x1000,
                subindex: 0,
                value: 0x000F_0191,
                size: 4
            })
        );
        let mut seen = None;
        let req = download_request(0x1017, 0, 0x1234_0064, 2).expect("size");
        let down = serve_request(
            &req,
            |_, _| Err(ABORT_NO_OBJECT),
            |i, s, v, n| {
                seen = Some((i, s, v, n));
                Ok(())
            },
        )
        .expect("answer");
        assert_eq!(
            seen,
            Some((0x1017, 0, 0x0064, 2)),
            "value masked to its size"
        );
        assert_eq!(
            parse_response(&down),
            Some(SdoResponse::Downloaded {
                index: 0x1017,
                subindex: 0
            })
        );
        let abort = serve_request(
            &upload_request(0x2000, 0),
            |_, _| Err(ABORT_NO_OBJECT),
            |_, _, _, _| Ok(()),
        )
        .expect("answer");
        assert_eq!(
            parse_response(&abort),
            Some(SdoResponse::Aborted {
                index: 0x2000,
                subindex: 0,
                code: ABORT_NO_OBJECT
            })
        );
        let one = serve_request(
            &upload_request(0x6000, 1),
            |_, _| Ok((0x5A, 1)),
            |_, _, _, _| Ok(()),
        )
        .expect("answer");
        assert_eq!(one[0], 0x4F);
        assert_eq!(
            parse_response(&one),
            Some(SdoResponse::Uploaded {
                index: 0x6000,
                subindex: 1,
                value: 0x5A,
                size: 1
            })
        );
        assert_eq!(parse_response(&[0x60, 0, 0]), None);
    }
}
