#![no_main]
//! Differential fuzzing of the two back ends: whatever PLC source compiles runs bit-identically
//! on the interpreter and on the cranelift JIT. The input is `source`, optionally followed by a
//! NUL byte and poke bytes: each 3-byte group `(offset lo, offset hi, value)` writes one image
//! byte; a `0xFF 0xFF` offset ends a tick. At most 16 ticks run.
use std::sync::Arc;

use compiler::{Engine, Interpreter, MachineContext};

/// The machine context, built once (parsing the built-in interface map per input was most of an
/// execution).
static CTX: std::sync::LazyLock<MachineContext> = std::sync::LazyLock::new(|| MachineContext {
    time_slow_ms: 0,
    ..MachineContext::lathe_like()
});

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let (src, pokes) = match data.iter().position(|&b| b == 0) {
        Some(i) => (&data[..i], &data[i + 1..]),
        None => (data, &[][..]),
    };
    let Some(p) = compiler::compile("fuzz", src, &CTX).program else {
        return;
    };
    let p = Arc::new(p);
    let mut interp = Interpreter::new(p.clone());
    let mut jit = compiler::jit::compile(&p).expect("a validated program always JIT-compiles");
    let (mut a, mut b) = (p.new_image(), p.new_image());
    let mut ticks: Vec<Vec<(usize, u8)>> = vec![Vec::new()];
    for g in pokes.chunks_exact(3) {
        let at = usize::from(u16::from_le_bytes([g[0], g[1]]));
        if at == 0xFFFF {
            ticks.push(Vec::new());
        } else if let Some(t) = ticks.last_mut() {
            t.push((at % a.len().max(1), g[2]));
        }
    }
    for (t, tick) in ticks.iter().take(16).enumerate() {
        for &(at, v) in tick {
            if at < a.len() {
                a[at] = v;
                b[at] = v;
            }
        }
        interp.tick(&mut a);
        jit.tick(&mut b);
        let diff: Vec<_> = (0..a.len())
            .filter(|&i| a[i] != b[i])
            .map(|i| (i, a[i], b[i]))
            .collect();
        assert!(diff.is_empty(), "tick {t}: (offset, interp, jit) {diff:?}");
    }
});
