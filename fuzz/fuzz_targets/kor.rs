#![no_main]
//! Correction table files (`TAB0.KOR`) from arbitrary bytes never panic the reader, for a mill and a
//! lathe, and every diagnostic span lies inside the text.
//! Work is bounded: the whole input must take at most 100 ms + 20 µs per byte of the thread's
//! CPU time (generous for sanitizer builds; a quadratic path on a 64 KB input blows it by orders
//! of magnitude).
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    ncplc_fuzz::within_linear_budget(data.len(), || {
        let text = String::from_utf8_lossy(data);
        for axes in [&['X', 'Y', 'Z'][..], &['X', 'Z'][..]] {
            let (table, diags) = partprogram::parse_kor("TAB0.KOR", &text, axes);
            assert!(diags.iter().all(|d| d.span.end <= text.len()));
            assert!(table.entries.keys().all(|n| (1..=99).contains(n)));
        }
    });
});
