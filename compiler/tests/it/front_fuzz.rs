//! Robustness: arbitrary bytes and mutated programs never panic the compiler, and every
//! compilation either yields a program or at least one located error.

use compiler::{MachineContext, compile};
use proptest::prelude::*;

fn check_contract(bytes: &[u8]) -> Result<(), TestCaseError> {
    let c = compile("p", bytes, &MachineContext::lathe_like());
    for d in &c.diagnostics {
        prop_assert!(d.line >= 1 && d.column >= 1, "unlocated: {d:?}");
        prop_assert!(
            d.span.start <= d.span.end && d.span.end <= c.text.len(),
            "span outside the text: {d:?}"
        );
        prop_assert!((1000..2000).contains(&d.code));
    }
    if c.program.is_none() {
        prop_assert!(
            c.diagnostics.iter().any(|d| d.is_error()),
            "no program and no error"
        );
    } else {
        prop_assert!(
            c.diagnostics.iter().all(|d| !d.is_error()),
            "a program despite errors"
        );
    }
    Ok(())
}

/// Fragments of the language, so that random programs get past the lexer often.
const PIECES: &[&str] = &[
    "U4A0", "I0A1", "W3K0", "SK12", "P2", "DEF ", "X", " : ", "DINT", "TON(", "2s", ")", "(", "[",
    "]", "=", "+", "*", "/", "-", "<>", ":=", "91H", "250", "1.5", "IF ", " THEN", "ELSE",
    "END_IF", "SET ", "RES ", "$", "\n", " ", ";c\n", ".", "ET", ",", "\u{fffd}", "\r\n", "MIN(",
    "BYTE(", "U10K5", "I0K2", "I1A29", "MFIN", "MSTB",
];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        check_contract(&bytes)?;
    }

    #[test]
    fn token_soup_never_panics(pieces in proptest::collection::vec(0..PIECES.len(), 0..80)) {
        let text: String = pieces.into_iter().map(|i| PIECES[i]).collect();
        check_contract(text.as_bytes())?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn mutated_example_program_never_panics(cut in 0usize..6000, insert in 0..PIECES.len()) {
        let src = include_str!("../../../plc-programs/mill/MP0/PLCPRG");
        let at = cut % src.len();
        let at = (0..=at).rev().find(|&i| src.is_char_boundary(i)).unwrap_or(0);
        let text = format!("{}{}{}", &src[..at], PIECES[insert], &src[at..]);
        check_contract(text.as_bytes())?;
    }
}
