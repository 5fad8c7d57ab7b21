#![no_main]
//! The cannelloni decoder never panics on garbage, and whatever it decodes re-encodes into a
//! datagram that decodes to the same sequence number and frames.
//! Work is bounded: the whole input must take at most 100 ms + 20 µs per byte of the thread's
//! CPU time (generous for sanitizer builds; a quadratic path on a 64 KB input blows it by orders
//! of magnitude).
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    ncplc_fuzz::within_linear_budget(data.len(), || {
        use fieldbus::canopen::cannelloni::{decode, encode};
        if let Ok((seq, frames)) = decode(data) {
            let again = encode(seq, &frames);
            assert_eq!(decode(&again), Ok((seq, frames)));
        }
    });
});
