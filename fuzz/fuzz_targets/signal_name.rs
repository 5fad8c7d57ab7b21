#![no_main]
//! Signal names from arbitrary text never panic the parser, and a name that parses prints in a
//! canonical form that parses back to the same signal.
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
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
