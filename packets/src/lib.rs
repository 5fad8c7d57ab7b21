//! The NC-xxx signal packets and the addresses of the signals in them.
//!
//! The logic exchanges signals with the world through four packets (docs/plc-language.md §3.1):
//!
//! | packet | connectors | bytes | what it holds |
//! |---|---|---|---|
//! | A | 0..31 | 128 | physical I/O; connector `c` is an input when `c mod 8 < 4`, else an output |
//! | K | 0..255 | 1024 | CNC ↔ logic interface (process signals) |
//! | N | 0..255 | 1024 | CNC ↔ logic interface (further signals) |
//! | T | 0..15 | 64 | byte constants from IOCFIL section 4 |
//!
//! Each connector has 32 contacts in 4 bytes: contact `n` of connector `c` is bit `n mod 8` of byte
//! `4c + n div 8` of the packet, lowest contact = least significant bit.
//!
//! # The image layout
//! The runtime keeps one flat byte image. The packets come first, at fixed offsets that every crate
//! shares ([`Packet::offset`]); the compiler appends its internal areas (variables, timer, counter
//! and pulse state, the retain area) after [`PACKETS_LEN`].
//!
//! ```text
//! 0      A (128)   128    K (1024)   1152   N (1024)   2176   T (64)   2240   compiler areas …
//! ```
//!
//! # Text forms
//! `I<c><P><n>` an input bit, `U<c><P><n>` an output bit, `W<c><P><b>` a byte, `S<P><B>` a byte by
//! linear index. [`Signal`] parses and prints them; printing uses the canonical form without
//! leading zeros (`W03K1` prints as `W3K1`).

pub mod io;

pub use io::{IoAlarm, PacketIo};

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

/// Byte length of the four packets together; the compiler's areas start here.
pub const PACKETS_LEN: usize = 128 + 1024 + 1024 + 64;

/// One of the four signal packets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Packet {
    /// Physical inputs and outputs.
    A,
    /// CNC ↔ logic interface.
    K,
    /// CNC ↔ logic interface, second packet.
    N,
    /// Byte constants initialised from IOCFIL section 4.
    T,
}

impl Packet {
    /// All packets in image order.
    pub const ALL: [Packet; 4] = [Packet::A, Packet::K, Packet::N, Packet::T];

    /// Offset of the packet's first byte in the flat image.
    pub const fn offset(self) -> usize {
        match self {
            Packet::A => 0,
            Packet::K => 128,
            Packet::N => 128 + 1024,
            Packet::T => 128 + 1024 + 1024,
        }
    }

    /// Number of bytes in the packet.
    pub const fn len(self) -> usize {
        match self {
            Packet::A => 128,
            Packet::K | Packet::N => 1024,
            Packet::T => 64,
        }
    }

    /// Always false: every packet has bytes (here for the `len`/`is_empty` convention).
    pub const fn is_empty(self) -> bool {
        self.len() == 0
    }

    /// Number of connectors (4 bytes each).
    pub const fn connectors(self) -> u16 {
        (self.len() / 4) as u16
    }

    /// The packet's letter.
    pub const fn letter(self) -> char {
        match self {
            Packet::A => 'A',
            Packet::K => 'K',
            Packet::N => 'N',
            Packet::T => 'T',
        }
    }

    /// The packet named by `c` (case-insensitive).
    pub fn from_letter(c: char) -> Option<Packet> {
        match c.to_ascii_uppercase() {
            'A' => Some(Packet::A),
            'K' => Some(Packet::K),
            'N' => Some(Packet::N),
            'T' => Some(Packet::T),
            _ => None,
        }
    }
}

/// True when connector `c` of packet A is an input connector (`c mod 8 < 4`).
pub const fn is_a_input_connector(c: u16) -> bool {
    c % 8 < 4
}

/// Direction prefix of a bit signal: `I` read by the logic, `U` written by it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Dir {
    /// `I`: an input to the logic.
    In,
    /// `U`: an output of the logic.
    Out,
}

/// A signal address: one bit or one byte of a packet.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Signal {
    /// Bit `contact` (0..31) of `connector`, with its direction prefix.
    Bit {
        /// `I` or `U`.
        dir: Dir,
        /// The packet.
        packet: Packet,
        /// Connector number.
        connector: u16,
        /// Contact 0..31.
        contact: u8,
    },
    /// Byte `index` (0..3) of `connector` (`W<c><P><b>`).
    Byte {
        /// The packet.
        packet: Packet,
        /// Connector number.
        connector: u16,
        /// Byte 0..3 of the connector.
        index: u8,
    },
}

impl Signal {
    /// The packet the signal is in.
    pub fn packet(&self) -> Packet {
        match *self {
            Signal::Bit { packet, .. } | Signal::Byte { packet, .. } => packet,
        }
    }

    /// Byte offset inside the packet.
    pub fn packet_byte(&self) -> usize {
        match *self {
            Signal::Bit {
                connector, contact, ..
            } => connector as usize * 4 + contact as usize / 8,
            Signal::Byte {
                connector, index, ..
            } => connector as usize * 4 + index as usize,
        }
    }

    /// Byte offset in the flat image.
    pub fn image_byte(&self) -> usize {
        self.packet().offset() + self.packet_byte()
    }

    /// Bit number in its byte (`None` for a byte signal).
    pub fn bit(&self) -> Option<u8> {
        match *self {
            Signal::Bit { contact, .. } => Some(contact % 8),
            Signal::Byte { .. } => None,
        }
    }

    /// Reads the signal's value from a flat image: 0/1 for a bit, 0..255 for a byte.
    pub fn read(&self, image: &[u8]) -> u8 {
        let byte = image.get(self.image_byte()).copied().unwrap_or(0);
        match self.bit() {
            Some(bit) => (byte >> bit) & 1,
            None => byte,
        }
    }

    /// Writes `value` (a bit uses only `value != 0`) into a flat image; out-of-range is ignored.
    pub fn write(&self, image: &mut [u8], value: u8) {
        let at = self.image_byte();
        let Some(byte) = image.get_mut(at) else {
            return;
        };
        match self.bit() {
            Some(bit) => {
                if value != 0 {
                    *byte |= 1 << bit;
                } else {
                    *byte &= !(1 << bit);
                }
            }
            None => *byte = value,
        }
    }
}

impl fmt::Display for Signal {
    /// The canonical text form: `I0A5`, `U10K0`, `W3K0`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Signal::Bit {
                dir,
                packet,
                connector,
                contact,
            } => {
                let d = if dir == Dir::In { 'I' } else { 'U' };
                write!(f, "{d}{connector}{}{contact}", packet.letter())
            }
            Signal::Byte {
                packet,
                connector,
                index,
            } => write!(f, "W{connector}{}{index}", packet.letter()),
        }
    }
}

/// Why a signal name did not parse.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SignalError {
    /// The text is not of the form `I…`, `U…`, `W…` or `S…`.
    #[error("`{0}` is not a signal name (I<c><P><n>, U<c><P><n>, W<c><P><b> or S<P><B>)")]
    Syntax(String),
    /// The connector number is past the packet's last connector.
    #[error("connector {connector} is out of range for packet {packet:?} (0..{max})")]
    Connector {
        /// The packet.
        packet: Packet,
        /// The connector given.
        connector: u32,
        /// The highest connector.
        max: u16,
    },
    /// A bit contact past 31.
    #[error("contact {0} is out of range (0..31)")]
    Contact(u32),
    /// A byte index past 3 (`W`) or past the packet (`S`).
    #[error("byte {index} is out of range (0..{max})")]
    ByteIndex {
        /// The byte given.
        index: u32,
        /// The highest byte.
        max: usize,
    },
}

impl FromStr for Signal {
    type Err = SignalError;

    /// Parses `I0A5`, `u10k0`, `W03K1`, `S K 12` style names (case-insensitive, leading zeros allowed).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let syntax = || SignalError::Syntax(s.to_string());
        let up = s.trim().to_ascii_uppercase();
        let mut chars = up.chars();
        let kind = chars.next().ok_or_else(syntax)?;
        let rest: &str = chars.as_str();
        let digits_end = rest
            .find(|c: char| !c.is_ascii_digit())
            .ok_or_else(syntax)?;
        if kind == 'S' {
            if digits_end != 0 {
                return Err(syntax());
            }
            let packet = rest
                .chars()
                .next()
                .and_then(Packet::from_letter)
                .ok_or_else(syntax)?;
            let num = &rest[1..];
            if num.is_empty() || !num.bytes().all(|b| b.is_ascii_digit()) {
                return Err(syntax());
            }
            let b: u32 = num.parse().map_err(|_| syntax())?;
            if b as usize >= packet.len() {
                return Err(SignalError::ByteIndex {
                    index: b,
                    max: packet.len() - 1,
                });
            }
            let b = b as usize;
            return Ok(Signal::Byte {
                packet,
                connector: (b / 4) as u16,
                index: (b % 4) as u8,
            });
        }
        if digits_end == 0 {
            return Err(syntax());
        }
        let connector: u32 = rest[..digits_end].parse().map_err(|_| syntax())?;
        let tail = &rest[digits_end..];
        let packet = tail
            .chars()
            .next()
            .and_then(Packet::from_letter)
            .ok_or_else(syntax)?;
        let num = &tail[1..];
        if num.is_empty() || !num.bytes().all(|b| b.is_ascii_digit()) {
            return Err(syntax());
        }
        let n: u32 = num.parse().map_err(|_| syntax())?;
        if connector >= u32::from(packet.connectors()) {
            return Err(SignalError::Connector {
                packet,
                connector,
                max: packet.connectors() - 1,
            });
        }
        let connector = connector as u16;
        match kind {
            'I' | 'U' => {
                if n > 31 {
                    return Err(SignalError::Contact(n));
                }
                let dir = if kind == 'I' { Dir::In } else { Dir::Out };
                Ok(Signal::Bit {
                    dir,
                    packet,
                    connector,
                    contact: n as u8,
                })
            }
            'W' => {
                if n > 3 {
                    return Err(SignalError::ByteIndex { index: n, max: 3 });
                }
                Ok(Signal::Byte {
                    packet,
                    connector,
                    index: n as u8,
                })
            }
            _ => Err(syntax()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sig(s: &str) -> Signal {
        s.parse().expect("valid signal")
    }

    #[test]
    fn offsets_follow_the_documented_layout() {
        assert_eq!(Packet::A.offset(), 0);
        assert_eq!(Packet::K.offset(), 128);
        assert_eq!(Packet::N.offset(), 1152);
        assert_eq!(Packet::T.offset(), 2176);
        assert_eq!(PACKETS_LEN, 2240);
        assert_eq!(Packet::T.connectors(), 16);
    }

    #[test]
    fn bit_addresses_map_to_bytes_and_bits() {
        let s = sig("I1A29");
        assert_eq!(s.image_byte(), 4 + 3);
        assert_eq!(s.bit(), Some(5));
        assert_eq!(sig("U10K5").image_byte(), 128 + 40);
        assert_eq!(sig("W3K0").image_byte(), 128 + 12);
        assert_eq!(sig("SK13"), sig("W3K1"));
        assert_eq!(sig("W03K1").to_string(), "W3K1");
        assert_eq!(sig("u150n0").to_string(), "U150N0");
    }

    #[test]
    fn out_of_range_names_are_rejected_with_the_reason() {
        assert_eq!(
            "U32A0".parse::<Signal>(),
            Err(SignalError::Connector {
                packet: Packet::A,
                connector: 32,
                max: 31
            })
        );
        assert_eq!("I0K32".parse::<Signal>(), Err(SignalError::Contact(32)));
        assert_eq!(
            "W0T4".parse::<Signal>(),
            Err(SignalError::ByteIndex { index: 4, max: 3 })
        );
        assert_eq!(
            "ST64".parse::<Signal>(),
            Err(SignalError::ByteIndex { index: 64, max: 63 })
        );
        assert!(matches!(
            "X1K0".parse::<Signal>(),
            Err(SignalError::Syntax(_))
        ));
        assert!(matches!(
            "U1K".parse::<Signal>(),
            Err(SignalError::Syntax(_))
        ));
    }

    #[test]
    fn read_and_write_touch_only_their_bit() {
        let mut image = vec![0u8; PACKETS_LEN];
        let s = sig("U4A3");
        s.write(&mut image, 1);
        assert_eq!(image[16], 0b1000);
        assert_eq!(s.read(&image), 1);
        sig("U4A0").write(&mut image, 1);
        s.write(&mut image, 0);
        assert_eq!(image[16], 0b1);
    }

    proptest::proptest! {
        #[test]
        fn display_parse_round_trip(dir in 0u8..2, p in 0usize..4, c in 0u16..256, n in 0u8..32) {
            let packet = Packet::ALL[p];
            let connector = c % packet.connectors();
            let dir = if dir == 0 { Dir::In } else { Dir::Out };
            let s = Signal::Bit { dir, packet, connector, contact: n };
            proptest::prop_assert_eq!(s.to_string().parse::<Signal>(), Ok(s));
            let b = Signal::Byte { packet, connector, index: n % 4 };
            proptest::prop_assert_eq!(b.to_string().parse::<Signal>(), Ok(b));
        }

        #[test]
        fn arbitrary_text_never_panics(s in ".{0,12}") {
            let _ = s.parse::<Signal>();
        }
    }
}
