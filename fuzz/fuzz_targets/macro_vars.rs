#![no_main]
//! Retained Macro B variable files (`nc/MACROVARS`) from arbitrary bytes never panic the reader,
//! every diagnostic span lies inside the text, every value read is a finite `#500`–`#999`, and a
//! file read without errors, written and read again gives the same values bit for bit.
//! Work is bounded: at most 100 ms + 20 µs per byte.
use partprogram::macro_b::retained::{format_retained, parse_retained};

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    ncplc_fuzz::within_linear_budget(data.len(), || {
        let text = String::from_utf8_lossy(data);
        let (vars, diags) = parse_retained("MACROVARS", &text);
        assert!(diags.iter().all(|d| d.span.end <= text.len()));
        assert!(
            vars.values
                .iter()
                .all(|(n, v)| (500..=999).contains(n) && v.is_finite())
        );
        if diags.is_empty() {
            let again = format_retained(&vars);
            let (back, diags) = parse_retained("MACROVARS", &again);
            assert!(diags.is_empty(), "{again}");
            let bits = |r: &partprogram::macro_b::retained::Retained| {
                r.values
                    .iter()
                    .map(|(n, v)| (*n, v.to_bits()))
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(&back), bits(&vars));
        }
    });
});
