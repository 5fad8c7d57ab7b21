#![no_main]
//! Interface maps from arbitrary text never panic the reader: every error has a code in 1601..1608
//! and a span inside the text, and a map that parses merges with the default map without a panic.
//! Work is bounded: the whole input must take at most 100 ms + 20 µs per byte of the thread's
//! CPU time (generous for sanitizer builds; a quadratic path on a 64 KB input blows it by orders
//! of magnitude).
/// The built-in map, parsed once (it is the same for every input).
static BUILTIN: std::sync::LazyLock<compiler::InterfaceMap> =
    std::sync::LazyLock::new(compiler::InterfaceMap::builtin);

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    ncplc_fuzz::within_linear_budget(data.len(), || {
        if let Ok(s) = std::str::from_utf8(data) {
            let checked = compiler::InterfaceMap::parse_all("interface.toml", s)
                .and_then(|o| BUILTIN.clone().with_overrides(o));
            if let Err(errors) = checked {
                assert!(!errors.is_empty());
                for e in &errors {
                    assert!((1601..=1608).contains(&e.code()));
                    if let Some(span) = e.span() {
                        assert!(span.start <= span.end && span.end <= s.len());
                    }
                    let _ = e.to_diagnostic(Some(s));
                }
            }
        }
    });
});
