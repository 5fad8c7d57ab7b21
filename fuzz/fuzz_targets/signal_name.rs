#![no_main]
//! Signal names from arbitrary text never panic the parser, and a name that parses prints in a
//! canonical form that parses back to the same signal.
//! Work is bounded: the whole input must take at most 100 ms + 20 µs per byte of the thread's
//! CPU time (generous for sanitizer builds; a quadratic path on a 64 KB input blows it by orders
//! of magnitude).
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    ncplc_fuzz::within_linear_budget(data.len(), || {
        if let Ok(s) = std::str::from_utf8(data) {
            if let Ok(sig) = s.parse::<packets::Signal>() {
                let canonical = sig.to_string();
                assert_eq!(
                    canonical.parse::<packets::Signal>(),
                    Ok(sig),
                    "{s:?} -> {canonical:?}"
                );
            }
        }
    });
});
