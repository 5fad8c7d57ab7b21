//! The scan benchmark's generated program (shared by `benches/scan.rs` and the
//! `scan_profile` example that callgrind runs).

/// A deterministic program of `n` statements: ladder rungs over K/N bits, byte comparisons,
/// arithmetic on bytes, SET/RES, pulses and inline timers, with a FAST and a SLOW part.
pub fn source(n: usize) -> String {
    let mut s = String::with_capacity(n * 40);
    let mut x: u32 = 12345;
    let mut rnd = |m: u32| {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        x % m
    };
    for i in 0..n {
        if i == n * 7 / 10 {
            s.push_str("$\n");
        }
        let (c, b) = (100 + rnd(150), rnd(32));
        let bit = |r: &mut dyn FnMut(u32) -> u32| format!("U{}K{}", 100 + r(150), r(32));
        match i % 10 {
            0..=4 => {
                let (a, b2, d) = (bit(&mut rnd), bit(&mut rnd), bit(&mut rnd));
                s.push_str(&format!("U{c}K{b}={a}*/{b2}+I0A{}*{d}\n", rnd(32)));
            }
            5 => s.push_str(&format!(
                "U{c}N{b}=[W{}K0={}H]+U{c}N{b}*/I0K1\n",
                rnd(10),
                rnd(10) * 10 + 1
            )),
            6 => s.push_str(&format!(
                "W{c}N{}=W{}N{}+W3K0\n",
                rnd(4),
                100 + rnd(150),
                rnd(4)
            )),
            7 => s.push_str(&format!("SET U{c}K{b}={}\n", bit(&mut rnd))),
            8 => s.push_str(&format!("P{}={}\n", (i / 10) % 1024, bit(&mut rnd))),
            _ => s.push_str(&format!(
                "U{c}K{b}=TON({}*I0A{}, {}ms)\n",
                bit(&mut rnd),
                rnd(32),
                10 * rnd(50)
            )),
        }
    }
    s
}
