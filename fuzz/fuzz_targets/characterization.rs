#![no_main]
//! Arbitrary bytes read as FCRSYS and as AXCFIL never panic the reader, the FCRSYS validator or
//! the AXCFIL validator, and every diagnostic they report lies inside the decoded text.
//! Work is bounded: the whole input must take at most 100 ms + 20 µs per byte of the thread's
//! CPU time (generous for sanitizer builds; a quadratic path on a 64 KB input blows it by orders
//! of magnitude).
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    ncplc_fuzz::within_linear_budget(data.len(), || {
        use characterization::reader::{Grammar, read, read_with};
        let (fc, mut d) = read_with("FCRSYS", data, Grammar::FCRSYS);
        d.extend(characterization::fcrsys::validate(&fc).1);
        let (ax, more) = read("AXCFIL", data);
        d.extend(more);
        d.extend(characterization::axcfil::validate(&ax).1);
        for x in &d {
            assert!(x.span.end <= fc.text.len().max(ax.text.len()));
        }
    });
});
