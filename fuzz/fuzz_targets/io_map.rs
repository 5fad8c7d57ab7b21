#![no_main]
//! I/O maps from arbitrary text never panic the reader; a map comes back exactly when there is no error.
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Ok(s) = std::str::from_utf8(data) {
        let declared = fieldbus::DeclaredConnectors {
            inputs: vec![0, 1, 2],
            outputs: vec![4, 5, 6],
        };
        let (map, diags) = fieldbus::parse_map(s, "io.toml", &declared);
        assert_eq!(map.is_some(), !diags.iter().any(|d| d.is_error()));
    }
});
