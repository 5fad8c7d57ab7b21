//! The flat process image: packets A, K, N, T followed by the compiler's internal areas.
//!
//! The image is one `Vec<u8>` laid out as `packets` documents. At start packet T takes the IOCFIL
//! section-4 bytes and everything else is zero (retained data is restored on top by `retain`).

use packets::{PACKETS_LEN, Packet, is_a_input_connector};

/// The runtime's process image.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    bytes: Vec<u8>,
}

impl Image {
    /// A fresh image of `len` bytes (at least the packets) with packet T set from `t_init`.
    pub fn new(len: usize, t_init: &[u8]) -> Image {
        let mut bytes = vec![0u8; len.max(PACKETS_LEN)];
        let t = Packet::T.offset();
        let n = t_init.len().min(Packet::T.len());
        bytes[t..t + n].copy_from_slice(&t_init[..n]);
        Image { bytes }
    }

    /// The whole image.
    pub fn bytes(&self) -> &[u8] {
        &self.bytes
    }

    /// The whole image, mutable.
    pub fn bytes_mut(&mut self) -> &mut [u8] {
        &mut self.bytes
    }

    /// The packets part (A, K, N, T).
    pub fn packets(&self) -> &[u8] {
        &self.bytes[..PACKETS_LEN]
    }

    /// The packets part, mutable.
    pub fn packets_mut(&mut self) -> &mut [u8] {
        &mut self.bytes[..PACKETS_LEN]
    }

    /// Packet T.
    pub fn t_bytes(&self) -> &[u8] {
        let t = Packet::T.offset();
        &self.bytes[t..t + Packet::T.len()]
    }

    /// Replaces this image by one of `len` bytes for another program, keeping the packets.
    /// The compiler areas start zeroed (the caller migrates state into them).
    pub fn resized_for(&self, len: usize) -> Image {
        let mut bytes = vec![0u8; len.max(PACKETS_LEN)];
        bytes[..PACKETS_LEN].copy_from_slice(self.packets());
        Image { bytes }
    }

    /// Grows the image to `len` bytes (new bytes 0), keeping every byte it has.
    pub fn grow_to(&mut self, len: usize) {
        if self.bytes.len() < len {
            self.bytes.resize(len, 0);
        }
    }

    /// Puts the physical outputs in their safe state: every packet-A output connector to 0.
    pub fn clear_physical_outputs(&mut self) {
        for c in 0..Packet::A.connectors() {
            if !is_a_input_connector(c) {
                let at = Packet::A.offset() + 4 * c as usize;
                self.bytes[at..at + 4].fill(0);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn t_is_initialised_and_the_rest_is_zero() {
        let mut t = vec![0u8; 64];
        t[5] = 0x33;
        let img = Image::new(3000, &t);
        assert_eq!(img.bytes().len(), 3000);
        assert_eq!(img.bytes()[Packet::T.offset() + 5], 0x33);
        assert_eq!(img.bytes().iter().map(|&b| u32::from(b)).sum::<u32>(), 0x33);
    }

    #[test]
    fn safe_state_clears_only_output_connectors() {
        let mut img = Image::new(PACKETS_LEN, &[]);
        img.bytes_mut()[..128].fill(0xff);
        img.clear_physical_outputs();
        assert_eq!(img.bytes()[0], 0xff); // connector 0: input
        assert_eq!(img.bytes()[16], 0); // connector 4: output
        assert_eq!(img.bytes()[4 * 8], 0xff); // connector 8: input
        assert_eq!(img.bytes()[4 * 12 + 3], 0); // connector 12: output
    }
}
