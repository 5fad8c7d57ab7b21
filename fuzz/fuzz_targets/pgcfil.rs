#![no_main]
//! Arbitrary bytes read as PGCFIL never panic the reader or the PGCFIL decoder.
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let (file, _) = characterization::reader::read_with(
        "PGCFIL",
        data,
        characterization::reader::Grammar::PGCFIL,
    );
    let _ = characterization::pgcfil::parse(&file);
});
