//! Retained data: the T bytes the logic wrote, the RETAIN variables and the MUSPE flag, kept in
//! one file that is replaced atomically.
//!
//! File layout: `NCRT` magic, format version (u32 LE), payload length (u32 LE), CRC-32 of the
//! payload (u32 LE), then the postcard-encoded [`RetainRecord`]. A save writes a temporary file in
//! the same directory, syncs it, renames it over the old file and syncs the directory, so a reader
//! (even after `kill -9` or power loss) sees either the previous complete record or the new one.

use std::fs;
use std::ops::Range;
use std::path::{Path, PathBuf};

use packets::{Packet, Signal};
use serde::{Deserialize, Serialize};

const MAGIC: &[u8; 4] = b"NCRT";
const FORMAT_VERSION: u32 = 1;
const HEADER_LEN: usize = 16;

/// What is kept across restarts.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct RetainRecord {
    /// Save counter, increasing.
    pub seq: u64,
    /// MUSPE (U10K0) at the time of the save: the logic allowed the data to be kept.
    pub muspe: bool,
    /// Packet T (64 bytes).
    pub t_bytes: Vec<u8>,
    /// The layout fingerprint of the retain area ([`crate::program::ProgramMeta::retain_layout`]).
    pub layout: u64,
    /// The retain area's bytes.
    pub retain: Vec<u8>,
}

/// Why retained data could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum RetainError {
    /// File system error.
    #[error("retain file {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// The file exists but is not a complete, valid record.
    #[error("retain file {path} is damaged: {reason}")]
    Corrupt {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: DecodeError,
    },
}

/// Why bytes are not a valid retain record.
#[derive(Debug, thiserror::Error)]
pub enum DecodeError {
    /// Too short, or the `NCRT` magic is missing.
    #[error("no NCRT header")]
    NoHeader,
    /// Written by another format version.
    #[error("format version {found} (expected {FORMAT_VERSION})")]
    Version {
        /// The version in the header.
        found: u32,
    },
    /// The payload is shorter or longer than the header says (a torn write).
    #[error("payload is {actual} bytes, header says {header}")]
    Length {
        /// Bytes after the header.
        actual: usize,
        /// The length in the header.
        header: usize,
    },
    /// The CRC-32 of the payload does not match.
    #[error("checksum mismatch")]
    Checksum,
    /// The payload passed the checksum but does not decode.
    #[error("undecodable record: {0}")]
    Payload(#[from] postcard::Error),
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> RetainError + '_ {
    move |source| RetainError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Encodes a record with its header.
pub fn encode(rec: &RetainRecord) -> Vec<u8> {
    let payload = postcard::to_stdvec(rec).unwrap_or_default();
    let mut out = Vec::with_capacity(HEADER_LEN + payload.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&(payload.len() as u32).to_le_bytes());
    out.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
    out.extend_from_slice(&payload);
    out
}

/// Decodes and verifies a record (`Err` carries the reason).
pub fn decode(bytes: &[u8]) -> Result<RetainRecord, DecodeError> {
    if bytes.len() < HEADER_LEN || &bytes[..4] != MAGIC {
        return Err(DecodeError::NoHeader);
    }
    let word = |i: usize| u32::from_le_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    if word(4) != FORMAT_VERSION {
        return Err(DecodeError::Version { found: word(4) });
    }
    let len = word(8) as usize;
    let payload = &bytes[HEADER_LEN..];
    if payload.len() != len {
        return Err(DecodeError::Length {
            actual: payload.len(),
            header: len,
        });
    }
    if crc32fast::hash(payload) != word(12) {
        return Err(DecodeError::Checksum);
    }
    Ok(postcard::from_bytes(payload)?)
}

/// Writes `rec` to `path` atomically (temporary file, fsync, rename, fsync of the directory).
pub fn save(path: &Path, rec: &RetainRecord) -> Result<(), RetainError> {
    crate::atomic_file::write(path, &encode(rec)).map_err(io_err(path))
}

/// Reads the record at `path`: `Ok(None)` when there is no file.
pub fn load(path: &Path) -> Result<Option<RetainRecord>, RetainError> {
    match fs::read(path) {
        Ok(bytes) => decode(&bytes)
            .map(Some)
            .map_err(|reason| RetainError::Corrupt {
                path: path.to_path_buf(),
                reason,
            }),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(io_err(path)(e)),
    }
}

/// The MUSPE signal (U10K0).
pub const MUSPE: Signal = Signal::Bit {
    dir: packets::Dir::Out,
    packet: Packet::K,
    connector: 10,
    contact: 0,
};

/// Which parts of the image are retained for one program.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RetainLayout {
    /// Image offsets of the packet-T bytes the program writes.
    pub t_written: Vec<usize>,
    /// The retain area.
    pub retain: Range<usize>,
    /// Its layout fingerprint.
    pub layout: u64,
}

impl RetainLayout {
    /// The layout for a program writing `written`, with retain area `retain`.
    pub fn new(written: &[Signal], retain: Range<usize>, layout: u64) -> RetainLayout {
        let mut t_written: Vec<usize> = written
            .iter()
            .filter(|s| s.packet() == Packet::T)
            .map(Signal::image_byte)
            .collect();
        t_written.sort_unstable();
        t_written.dedup();
        RetainLayout {
            t_written,
            retain,
            layout,
        }
    }

    /// Takes a snapshot of the retained parts of `image`.
    pub fn snapshot(&self, image: &[u8], seq: u64) -> RetainRecord {
        let t = Packet::T.offset();
        RetainRecord {
            seq,
            muspe: MUSPE.read(image) == 1,
            t_bytes: image
                .get(t..t + Packet::T.len())
                .map(<[u8]>::to_vec)
                .unwrap_or_default(),
            layout: self.layout,
            retain: image
                .get(self.retain.clone())
                .map(<[u8]>::to_vec)
                .unwrap_or_default(),
        }
    }

    /// True when the retained parts of `image` differ from `rec`.
    pub fn differs(&self, image: &[u8], rec: &RetainRecord) -> bool {
        let t = Packet::T.offset();
        (MUSPE.read(image) == 1) != rec.muspe
            || image.get(t..t + Packet::T.len()) != Some(rec.t_bytes.as_slice())
            || image.get(self.retain.clone()) != Some(rec.retain.as_slice())
    }

    /// Restores `rec` into `image` (PGCFIL `OLD`): only when MUSPE was 1; the T bytes the program
    /// writes always, the retain area only when its layout is unchanged. Returns what was restored.
    pub fn restore(&self, rec: &RetainRecord, image: &mut [u8]) -> Restored {
        if !rec.muspe {
            return Restored::NotAllowed;
        }
        let t = Packet::T.offset();
        for &at in &self.t_written {
            if let (Some(&v), Some(dst)) = (rec.t_bytes.get(at - t), image.get_mut(at)) {
                *dst = v;
            }
        }
        if rec.layout == self.layout && rec.retain.len() == self.retain.len() {
            if let Some(dst) = image.get_mut(self.retain.clone()) {
                dst.copy_from_slice(&rec.retain);
            }
            Restored::All
        } else {
            Restored::TOnly
        }
    }
}

/// The outcome of [`RetainLayout::restore`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Restored {
    /// MUSPE was 0 at the last save: nothing restored.
    NotAllowed,
    /// T bytes restored; the retain area's layout changed, so it starts from zero.
    TOnly,
    /// T bytes and the retain area restored.
    All,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn save_load_round_trip_and_corruption_is_detected() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("retain.bin");
        assert!(load(&path).expect("no file").is_none());
        let rec = RetainRecord {
            seq: 7,
            muspe: true,
            t_bytes: vec![1; 64],
            layout: 9,
            retain: vec![1, 2, 3],
        };
        save(&path, &rec).expect("save");
        assert_eq!(load(&path).expect("load"), Some(rec.clone()));
        let mut bytes = fs::read(&path).expect("read");
        let last = bytes.len() - 1;
        bytes[last] ^= 0x40;
        fs::write(&path, &bytes).expect("write");
        assert!(matches!(
            load(&path),
            Err(RetainError::Corrupt {
                reason: DecodeError::Checksum,
                ..
            })
        ));
        fs::write(&path, &bytes[..10]).expect("write");
        assert!(matches!(load(&path), Err(RetainError::Corrupt { .. })));
    }

    #[test]
    fn restore_needs_muspe_and_a_matching_layout() {
        let w3t0: Signal = "W3T0".parse().expect("sig");
        let layout = RetainLayout::new(&[w3t0, "U4A0".parse().expect("sig")], 3000..3004, 42);
        let mut image = vec![0u8; 3004];
        w3t0.write(&mut image, 0x55);
        image[2176] = 0x11; // T byte the program does not write
        image[3000..3004].copy_from_slice(&[9, 8, 7, 6]);
        MUSPE.write(&mut image, 1);
        let rec = layout.snapshot(&image, 1);
        assert!(!layout.differs(&image, &rec));
        let mut fresh = vec![0u8; 3004];
        assert_eq!(layout.restore(&rec, &mut fresh), Restored::All);
        assert_eq!(w3t0.read(&fresh), 0x55);
        assert_eq!(fresh[2176], 0);
        assert_eq!(&fresh[3000..3004], &[9, 8, 7, 6]);
        let other = RetainLayout::new(&[w3t0], 3000..3004, 43);
        let mut fresh = vec![0u8; 3004];
        assert_eq!(other.restore(&rec, &mut fresh), Restored::TOnly);
        assert_eq!(&fresh[3000..3004], &[0, 0, 0, 0]);
        let no = RetainRecord {
            muspe: false,
            ..rec
        };
        assert_eq!(layout.restore(&no, &mut fresh), Restored::NotAllowed);
    }
}
