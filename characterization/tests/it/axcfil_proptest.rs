//! Arbitrary bytes never panic the reader, FCRSYS or AXCFIL, and always end in diagnostics with
//! spans inside the decoded text; mutated example files keep that property.

use characterization::reader::{Grammar, read, read_with};
use characterization::{axcfil, fcrsys};
use proptest::prelude::*;

const TOKENS: &[&str] = &[
    "*1",
    "*2",
    "*3",
    "*4",
    "*",
    "NBP=",
    "TIM=",
    "PRO=",
    "COM=",
    "IN1=",
    "IN2=",
    "CAS=",
    "ACC=",
    "NAS=",
    "TPA=",
    "NTC=",
    "RAP=",
    "GAS=",
    "PAS=",
    "SKW=",
    "MCZ=",
    "POS=",
    "SRV=",
    "MAN=",
    "GM0=",
    "GM1=",
    "FRC=",
    "LO1=",
    "MFC=",
    "CUB=",
    "SW1=",
    "TSM=",
    "ASM=",
    "POM=",
    "ZNO=",
    "FBF=",
    "HWC=",
    "ATR=",
    "GRA=",
    "FOPP=",
    "FTP=",
    "ADG=",
    "LAS=",
    "E001=",
    "E002=",
    "NM0=",
    "NAC=",
    "FEG=",
    "MP0=",
    "AXCONF,",
    "HDD=",
    "IDE=",
    "1",
    "2",
    "0",
    "ECDF",
    "820",
    "41",
    "X",
    "Z",
    "S",
    "XZS",
    "U10K5",
    "I0A8",
    "-201",
    ".5",
    ",",
    ",,",
    "\n",
    "\r\n",
    ";",
    " ",
    "\u{430}",
    "TABT/MP0",
    "C:\\CNC32\\MP0",
];

fn check_all(bytes: &[u8]) -> usize {
    let (fc, mut d) = read_with("FCRSYS", bytes, Grammar::FCRSYS);
    d.extend(fcrsys::validate(&fc).1);
    let (ax, more) = read("AXCFIL", bytes);
    d.extend(more);
    d.extend(axcfil::validate(&ax).1);
    for x in &d {
        assert!(
            x.span.start <= x.span.end && x.span.end <= ax.text.len(),
            "{x:?}"
        );
        assert!(x.code > 0 && !x.message.is_empty());
    }
    d.len()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn arbitrary_bytes_end_in_diagnostics(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        // A file without `*1`, `*2`, `*3` always lacks sections, so there is always a diagnostic.
        prop_assert!(check_all(&bytes) > 0);
    }

    #[test]
    fn token_soup_never_panics(tokens in proptest::collection::vec(proptest::sample::select(TOKENS), 0..120)) {
        let text: String = tokens.concat();
        check_all(text.as_bytes());
    }

    #[test]
    fn mutated_example_never_panics(cut in 0usize..4000, insert in proptest::sample::select(TOKENS)) {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/FX-46.txt");
        let mut text = std::fs::read_to_string(path).unwrap_or_default();
        let at = cut.min(text.len());
        if text.is_char_boundary(at) {
            text.insert_str(at, insert);
        }
        check_all(text.as_bytes());
    }
}
