//! Modbus TCP: the remote-I/O client driver, the HMI/SCADA server and a remote-I/O device simulator.
//!
//! Byte ↔ Modbus item convention (both directions, client and server): in a bit table byte `i` of a
//! mapping holds items `address + 8i .. address + 8i + 7`, item `address + 8i + n` = bit `n` of the
//! byte; in a register table register `address + k` holds bytes `2k` (low 8 bits) and `2k + 1`
//! (high 8 bits).

pub mod client;
pub mod frame;
pub mod guard;
pub mod screen;
pub mod server;
pub mod sim;
pub mod writer;

/// Unpacks Modbus bits into bytes (bit `n` of byte `i` = `bits[8i + n]`); missing bits read as 0.
pub fn bits_to_bytes(bits: &[bool], out: &mut [u8]) {
    for (i, byte) in out.iter_mut().enumerate() {
        let mut v = 0u8;
        for n in 0..8 {
            if bits.get(i * 8 + n).copied().unwrap_or(false) {
                v |= 1 << n;
            }
        }
        *byte = v;
    }
}

/// Packs bytes into Modbus bits (8 per byte, least significant bit first).
pub fn bytes_to_bits(bytes: &[u8]) -> Vec<bool> {
    bytes
        .iter()
        .flat_map(|b| (0..8).map(move |n| b >> n & 1 == 1))
        .collect()
}

/// Unpacks registers into bytes (low byte first); missing registers read as 0.
pub fn regs_to_bytes(regs: &[u16], out: &mut [u8]) {
    for (i, byte) in out.iter_mut().enumerate() {
        let r = regs.get(i / 2).copied().unwrap_or(0);
        *byte = if i % 2 == 0 {
            (r & 0xFF) as u8
        } else {
            (r >> 8) as u8
        };
    }
}

/// Packs bytes into registers (low byte first; an odd last byte leaves the high byte 0).
pub fn bytes_to_regs(bytes: &[u8]) -> Vec<u16> {
    bytes
        .chunks(2)
        .map(|c| u16::from(c[0]) | u16::from(c.get(1).copied().unwrap_or(0)) << 8)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bit_and_register_packing_round_trip_with_the_documented_order() {
        let bits = bytes_to_bits(&[0b0000_0101, 0x80]);
        assert_eq!(bits.len(), 16);
        assert_eq!(
            bits.iter()
                .enumerate()
                .filter(|(_, b)| **b)
                .map(|(i, _)| i)
                .collect::<Vec<_>>(),
            [0, 2, 15]
        );
        let mut out = [0u8; 2];
        bits_to_bytes(&bits, &mut out);
        assert_eq!(out, [5, 0x80]);
        assert_eq!(bytes_to_regs(&[0x34, 0x12, 0x78]), [0x1234, 0x0078]);
        let mut out = [0u8; 3];
        regs_to_bytes(&[0x1234, 0x0078], &mut out);
        assert_eq!(out, [0x34, 0x12, 0x78]);
    }
}
