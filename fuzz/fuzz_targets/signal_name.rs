#![no_main]
//! Signal names from arbitrary text never panic the parser, and a name that parses prints in a
//! canonical form that parses back to the same signal.
//! Work is bounded: the whole input must take at most 100 ms + 20 µs per byte of the thread's
//! CPU time (generous for sanitizer builds; a quadratic path on a 64 KB input blows it by orders
//! of magnitude).
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let started = ncplc_fuzz::CpuClock::start();
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
    let budget = std::time::Duration::from_micros(100_000 + 20 * data.len() as u64);
    assert!(started.elapsed() <= budget, "{} bytes took {:?}", data.len(), started.elapsed());
});
