//! CAN over UDP in the cannelloni format, and a [`CanBus`] over a UDP socket.
//!
//! One UDP datagram carries a header and any number of frames (written here from the format
//! description; no code of the GPL cannelloni project is used):
//!
//! ```text
//! header: version u8 (= 2) | op_code u8 (0 = DATA) | seq_no u8 | count u16 big-endian
//! frame:  can_id u32 big-endian, Linux flag bits (0x80000000 extended, 0x40000000 RTR, 0x20000000 error)
//!         len u8 (bit 0x80 set: a CAN FD frame, then one FD flags byte follows)
//!         data: len & 0x7F bytes (none for an RTR frame)
//! ```
//!
//! [`decode`] never panics: a short, oversized or otherwise malformed datagram is an error value.

use std::collections::VecDeque;
use std::io;
use std::net::SocketAddr;

use super::transport::CanBus;
use super::{CanMsg, MAX_DATA};

/// The format version this module speaks.
pub const VERSION: u8 = 2;
/// The DATA op code.
pub const OP_DATA: u8 = 0;
const EFF: u32 = 0x8000_0000;
const RTR: u32 = 0x4000_0000;
const ERR: u32 = 0x2000_0000;
const FD_LEN: u8 = 0x80;

/// Why a datagram is not a cannelloni DATA packet.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CannelloniError {
    /// Fewer than 5 header bytes.
    #[error("datagram of {0} bytes is shorter than the 5-byte header")]
    ShortHeader(usize),
    /// A version other than 2.
    #[error("unsupported cannelloni version {0}")]
    Version(u8),
    /// An op code other than DATA.
    #[error("op code {0} is not DATA")]
    OpCode(u8),
    /// The datagram ends inside frame `index`.
    #[error("datagram ends inside frame {index}")]
    Truncated {
        /// Index of the frame that is cut short.
        index: usize,
    },
    /// A data length past 8 (classic) or 64 (FD).
    #[error("frame {index} has data length {len}")]
    Length {
        /// Index of the frame.
        index: usize,
        /// The length given.
        len: u8,
    },
    /// Bytes left over after `count` frames.
    #[error("{0} bytes left after the last frame")]
    Trailing(usize),
}

/// Encodes `frames` as one DATA datagram with sequence number `seq`.
pub fn encode(seq: u8, frames: &[CanMsg]) -> Vec<u8> {
    let mut out = vec![VERSION, OP_DATA, seq];
    out.extend_from_slice(&(frames.len().min(usize::from(u16::MAX)) as u16).to_be_bytes());
    for f in frames.iter().take(usize::from(u16::MAX)) {
        let mut id = if f.extended {
            (f.id & 0x1FFF_FFFF) | EFF
        } else {
            f.id & 0x7FF
        };
        if f.rtr {
            id |= RTR;
        }
        out.extend_from_slice(&id.to_be_bytes());
        let len = f.len.min(if f.fd { 64 } else { 8 });
        if f.fd {
            out.push(len | FD_LEN);
            out.push(0);
        } else {
            out.push(len);
        }
        if !f.rtr {
            out.extend_from_slice(&f.data[..usize::from(len)]);
        }
    }
    out
}

/// Decodes one datagram into its sequence number and frames (error frames are skipped).
pub fn decode(buf: &[u8]) -> Result<(u8, Vec<CanMsg>), CannelloniError> {
    if buf.len() < 5 {
        return Err(CannelloniError::ShortHeader(buf.len()));
    }
    if buf[0] != VERSION {
        return Err(CannelloniError::Version(buf[0]));
    }
    if buf[1] != OP_DATA {
        return Err(CannelloniError::OpCode(buf[1]));
    }
    let seq = buf[2];
    let count = usize::from(u16::from_be_bytes([buf[3], buf[4]]));
    let mut at = 5;
    let mut frames = Vec::with_capacity(count.min(256));
    for index in 0..count {
        let head = buf
            .get(at..at + 5)
            .ok_or(CannelloniError::Truncated { index })?;
        let raw_id = u32::from_be_bytes([head[0], head[1], head[2], head[3]]);
        let len_byte = head[4];
        at += 5;
        let fd = len_byte & FD_LEN != 0;
        if fd {
            buf.get(at).ok_or(CannelloniError::Truncated { index })?;
            at += 1;
        }
        let len = len_byte & !FD_LEN;
        if usize::from(len) > if fd { MAX_DATA } else { 8 } {
            return Err(CannelloniError::Length { index, len });
        }
        let rtr = raw_id & RTR != 0;
        let mut data = [0u8; MAX_DATA];
        if !rtr {
            let bytes = buf
                .get(at..at + usize::from(len))
                .ok_or(CannelloniError::Truncated { index })?;
            data[..bytes.len()].copy_from_slice(bytes);
            at += usize::from(len);
        }
        if raw_id & ERR != 0 {
            continue;
        }
        let extended = raw_id & EFF != 0;
        let id = if extended {
            raw_id & 0x1FFF_FFFF
        } else {
            raw_id & 0x7FF
        };
        frames.push(CanMsg {
            id,
            extended,
            rtr,
            fd,
            len,
            data,
        });
    }
    if at != buf.len() {
        return Err(CannelloniError::Trailing(buf.len() - at));
    }
    Ok((seq, frames))
}

/// A [`CanBus`] that exchanges cannelloni datagrams with one UDP peer.
pub struct UdpBus {
    socket: tokio::net::UdpSocket,
    peer: SocketAddr,
    seq: u8,
    pending: VecDeque<CanMsg>,
    /// Datagrams dropped because they did not decode.
    pub bad_datagrams: u64,
}

impl UdpBus {
    /// Binds `local` and talks to `peer`.
    pub async fn bind(local: SocketAddr, peer: SocketAddr) -> io::Result<UdpBus> {
        let socket = tokio::net::UdpSocket::bind(local).await?;
        Ok(UdpBus {
            socket,
            peer,
            seq: 0,
            pending: VecDeque::new(),
            bad_datagrams: 0,
        })
    }

    /// The bound local address.
    pub fn local_addr(&self) -> io::Result<SocketAddr> {
        self.socket.local_addr()
    }
}

impl CanBus for UdpBus {
    async fn send(&mut self, msg: &CanMsg) -> io::Result<()> {
        let dgram = encode(self.seq, std::slice::from_ref(msg));
        self.seq = self.seq.wrapping_add(1);
        self.socket.send_to(&dgram, self.peer).await.map(|_| ())
    }

    async fn recv(&mut self) -> io::Result<CanMsg> {
        let mut buf = [0u8; 2048];
        loop {
            if let Some(m) = self.pending.pop_front() {
                return Ok(m);
            }
            // `recv_from` is cancel-safe; frames are queued only after a whole datagram decoded.
            let (n, from) = self.socket.recv_from(&mut buf).await?;
            if from != self.peer {
                continue;
            }
            match decode(&buf[..n]) {
                Ok((_, frames)) => self.pending.extend(frames),
                Err(_) => self.bad_datagrams += 1,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fd_ext() -> CanMsg {
        let mut data = [0u8; MAX_DATA];
        for (i, b) in data.iter_mut().enumerate().take(12) {
            *b = i as u8;
        }
        CanMsg {
            id: 0x1ABC_DEF0,
            extended: true,
            rtr: false,
            fd: true,
            len: 12,
            data,
        }
    }

    #[test]
    fn encodes_the_documented_layout() {
        let bytes = encode(7, &[CanMsg::new(0x181, &[0xAA, 0xBB])]);
        assert_eq!(bytes, [2, 0, 7, 0, 1, 0, 0, 0x01, 0x81, 2, 0xAA, 0xBB]);
    }

    #[test]
    fn round_trip_of_classic_fd_extended_and_rtr_frames() {
        let rtr = CanMsg {
            rtr: true,
            len: 4,
            data: [0; MAX_DATA],
            ..CanMsg::new(0x701, &[])
        };
        let frames = [
            CanMsg::new(0x181, &[1, 2, 3]),
            fd_ext(),
            rtr,
            CanMsg::new(0x80, &[]),
        ];
        let (seq, back) = decode(&encode(200, &frames)).expect("decodes");
        assert_eq!(seq, 200);
        assert_eq!(back, frames);
    }

    #[test]
    fn malformed_datagrams_are_errors() {
        assert_eq!(decode(&[2, 0, 1]), Err(CannelloniError::ShortHeader(3)));
        assert_eq!(decode(&[3, 0, 1, 0, 0]), Err(CannelloniError::Version(3)));
        assert_eq!(decode(&[2, 1, 1, 0, 0]), Err(CannelloniError::OpCode(1)));
        assert_eq!(
            decode(&[2, 0, 1, 0, 1, 0, 0, 1]),
            Err(CannelloniError::Truncated { index: 0 })
        );
        assert_eq!(
            decode(&[2, 0, 1, 0, 1, 0, 0, 1, 0x81, 9]),
            Err(CannelloniError::Length { index: 0, len: 9 })
        );
        assert_eq!(
            decode(&[2, 0, 1, 0, 0, 9]),
            Err(CannelloniError::Trailing(1))
        );
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(256))]
        #[test]
        fn garbage_never_panics(bytes in proptest::collection::vec(proptest::prelude::any::<u8>(), 0..300)) {
            let _ = decode(&bytes);
        }

        #[test]
        fn garbage_after_a_valid_header_never_panics(count in 0u16..40, tail in proptest::collection::vec(proptest::prelude::any::<u8>(), 0..300)) {
            let mut bytes = vec![2, 0, 0];
            bytes.extend_from_slice(&count.to_be_bytes());
            bytes.extend_from_slice(&tail);
            let _ = decode(&bytes);
        }
    }

    #[tokio::test]
    async fn udp_loopback_carries_frames_and_skips_garbage() {
        let mut a = UdpBus::bind(
            "127.0.0.1:0".parse().expect("addr"),
            "127.0.0.1:9".parse().expect("addr"),
        )
        .await
        .expect("bind a");
        let mut b = UdpBus::bind(
            "127.0.0.1:0".parse().expect("addr"),
            a.local_addr().expect("a"),
        )
        .await
        .expect("bind b");
        a.peer = b.local_addr().expect("b");
        a.socket.send_to(&[1, 2, 3], a.peer).await.expect("garbage");
        a.send(&fd_ext()).await.expect("send");
        let got = tokio::time::timeout(std::time::Duration::from_secs(2), b.recv())
            .await
            .expect("in time")
            .expect("recv");
        assert_eq!(got, fd_ext());
        assert_eq!(b.bad_datagrams, 1);
    }
}
