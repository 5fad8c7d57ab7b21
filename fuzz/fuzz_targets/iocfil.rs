#![no_main]
//! Arbitrary bytes read as IOCFIL never panic the reader or the IOCFIL decoder.
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let (file, _) = characterization::reader::read("IOCFIL", data);
    let _ = characterization::iocfil::parse(&file);
});
