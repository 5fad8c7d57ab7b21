#![no_main]
//! Signal names from arbitrary text never panic the parser.
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Ok(s) = std::str::from_utf8(data) {
        let _ = s.parse::<packets::Signal>();
    }
});
