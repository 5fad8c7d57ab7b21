#![no_main]
//! The cannelloni decoder never panics on garbage, and whatever it decodes re-encodes into a
//! datagram it decodes again.
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Ok((seq, frames)) = fieldbus::canopen::cannelloni::decode(data) {
        let again = fieldbus::canopen::cannelloni::encode(seq, &frames);
        assert!(fieldbus::canopen::cannelloni::decode(&again).is_ok());
    }
});
