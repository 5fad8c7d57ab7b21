#![no_main]
//! Arbitrary bytes read as PGCFIL never panic the reader or the PGCFIL decoder.
//! Work is bounded: the whole input must take at most 100 ms + 20 µs per byte of the thread's
//! CPU time (generous for sanitizer builds; a quadratic path on a 64 KB input blows it by orders
//! of magnitude).
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    ncplc_fuzz::within_linear_budget(data.len(), || {
        let (file, _) = characterization::reader::read_with(
            "PGCFIL",
            data,
            characterization::reader::Grammar::PGCFIL,
        );
        let _ = characterization::pgcfil::parse(&file);
    });
});
