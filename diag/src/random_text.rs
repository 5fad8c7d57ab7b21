//! Deterministic random input for the bounded-work benchmarks and tests (issue 12): every reader
//! must get through 50 MB of it in time linear in its length.

/// `len` bytes of random printable ASCII with a newline about every 32 characters (like the
/// issue's measurement), from `seed` (xorshift64*: the same seed gives the same text everywhere).
pub fn random_text(len: usize, seed: u64) -> Vec<u8> {
    let mut state = seed | 1;
    let mut out = Vec::with_capacity(len);
    while out.len() < len {
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        let r = state.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 32;
        // 98 outcomes: 95 printable characters and 3 newlines.
        let k = (r % 98) as u8;
        out.push(if k >= 95 { b'\n' } else { b' ' + k });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn random_text_is_printable_and_reproducible() {
        let a = random_text(10_000, 7);
        assert_eq!(a, random_text(10_000, 7));
        assert_ne!(a, random_text(10_000, 8));
        assert!(a.iter().all(|&b| b == b'\n' || (b' '..=b'~').contains(&b)));
        let lines = a.iter().filter(|&&b| b == b'\n').count();
        // 3 in 98 bytes are newlines: about 306 in 10,000.
        assert!((200..420).contains(&lines), "{lines}");
    }
}
