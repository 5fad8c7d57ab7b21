#![no_main]
//! I/O maps from arbitrary text never panic the reader; a map comes back exactly when there is no error.
//! Work is bounded: the whole input must take at most 100 ms + 20 µs per byte of the thread's
//! CPU time (generous for sanitizer builds; a quadratic path on a 64 KB input blows it by orders
//! of magnitude).
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    ncplc_fuzz::within_linear_budget(data.len(), || {
        if let Ok(s) = std::str::from_utf8(data) {
            let declared = fieldbus::DeclaredConnectors {
                inputs: vec![0, 1, 2],
                outputs: vec![4, 5, 6],
            };
            let (map, diags) = fieldbus::parse_map(s, "io.toml", &declared);
            assert_eq!(map.is_some(), !diags.iter().any(|d| d.is_error()));
        }
    });
});
