#![no_main]
//! The cannelloni decoder never panics on garbage, and whatever it decodes re-encodes into a
//! datagram that decodes to the same sequence number and frames.
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    use fieldbus::canopen::cannelloni::{decode, encode};
    if let Ok((seq, frames)) = decode(data) {
        let again = encode(seq, &frames);
        assert_eq!(decode(&again), Ok((seq, frames)));
    }
});
