//! PGCFIL and IOCFIL decoding never panics: random token soup and mutated example files.

use characterization::reader::{Grammar, read, read_with};
use characterization::{iocfil, pgcfil};
use proptest::prelude::*;

const TOKENS: &[&str] = &[
    "NEW",
    "OLD",
    "*1",
    "*2",
    "*3",
    "*4",
    "*5",
    "*6",
    "*7",
    "PRO=",
    "NIP=",
    "TOF=",
    "GXX=",
    "NAM=",
    "NPD=",
    "MAS=",
    "FRO=",
    "SIM=",
    "ASS=",
    "TRI=",
    "JCL=",
    "TAS=",
    "INU=",
    "TGA=",
    "CAX=",
    "FIL=",
    "FLC=",
    "IN0=",
    "OU1=",
    "CLO=",
    "SPL=",
    "ALM=",
    "M03=",
    "GPS=",
    "ASM=",
    "TA1=",
    "AS1=",
    "UCDA=",
    "ADV=",
    "ADC=",
    "DAC=",
    "T01=",
    "T64=",
    "0",
    "1",
    "2",
    "99",
    "256",
    "65536",
    "-1",
    ".5",
    "FF",
    "C000",
    "Z",
    "XZ",
    "D",
    "U256K20",
    "I0A1",
    "FI1EOR/MP0",
    ",",
    ",",
    ",",
    " ",
    "\n",
    "\n",
    "\n",
    ";",
    "=",
    "é",
    "\r",
];

fn soup() -> impl Strategy<Value = String> {
    prop::collection::vec(prop::sample::select(TOKENS), 0..120).prop_map(|v| v.concat())
}

fn decode_both(src: &[u8]) -> usize {
    let (f, _) = read_with("PGCFIL", src, Grammar::PGCFIL);
    let (_, a) = pgcfil::parse(&f);
    let (f, _) = read("IOCFIL", src);
    let (_, b) = iocfil::parse(&f);
    a.len() + b.len()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(192))]

    #[test]
    fn token_soup_never_panics(src in soup()) {
        let n = decode_both(src.as_bytes());
        prop_assert!(n < 100_000);
    }

    #[test]
    fn mutated_examples_never_panic(drop in 0usize..70, insert in prop::sample::select(TOKENS), at in 0usize..70) {
        for base in [include_str!("../fixtures/pgcfil_nc110.txt"), include_str!("../fixtures/iocfil_example.txt")] {
            let mut lines: Vec<String> = base.lines().map(str::to_string).collect();
            if drop < lines.len() {
                lines.remove(drop);
            }
            let i = at.min(lines.len());
            lines.insert(i, insert.to_string());
            let src = lines.join("\n");
            let n = decode_both(src.as_bytes());
            prop_assert!(n < 100_000);
        }
    }
}

#[test]
fn the_same_input_gives_the_same_output() {
    let src = include_str!("../fixtures/iocfil_example.txt");
    let (f, _) = read("IOCFIL", src.as_bytes());
    let a = iocfil::parse(&f);
    let b = iocfil::parse(&f);
    assert_eq!(a, b);
    let json = serde_json::to_string(&a.0).unwrap_or_default();
    let back: iocfil::Iocfil = serde_json::from_str(&json).unwrap_or_default();
    assert_eq!(back, a.0);
}
