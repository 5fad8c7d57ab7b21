//! The two-thread parse (a long source cut at the line end nearest its middle) must give exactly
//! the one-thread result: the same syntax tree and the same diagnostics, also when lines around
//! the cut are broken in every way the recovery handles.

use compiler::parser::{parse, parse_with_threads};
use compiler::synth::synthetic_program;
use proptest::prelude::*;

/// Broken lines: syntax errors, a lexer error, unbalanced IF blocks, a second `$`.
const BROKEN: [&str; 8] = [
    "U100K0 = = I0K1",
    "U100K1 = I0K2 *",
    "IF I0K3 THEN",
    "END_IF",
    "ELSE",
    "U100K2 = I0K4 @ I0K5",
    "DEF : BOOL",
    "$",
];

fn same(src: &str) {
    let one = parse("t", src);
    let two = parse_with_threads("t", src, 2);
    assert_eq!(one, two);
}

#[test]
fn a_long_program_parses_the_same_on_two_threads() {
    let src = synthetic_program(3000);
    let (p, d) = parse("t", &src);
    assert_eq!(d, vec![]);
    assert!(p.fast.len() + p.slow.len() > 2500);
    same(&src);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    #[test]
    fn broken_lines_near_the_cut_give_the_same_result(
        edits in proptest::collection::vec((0.4f64..0.6, 0usize..BROKEN.len()), 1..6)
    ) {
        let src = synthetic_program(2500);
        let mut lines: Vec<&str> = src.lines().collect();
        for &(at, which) in &edits {
            let i = (lines.len() as f64 * at) as usize;
            lines.insert(i, BROKEN[which]);
        }
        let text = lines.join("\n") + "\n";
        let one = parse("t", &text);
        // IF, ELSE and END_IF can land where they pair up with the program's blocks or with each
        // other, which is legal; the other edits are errors wherever they land.
        if edits.iter().any(|&(_, which)| !matches!(BROKEN[which], "IF I0K3 THEN" | "ELSE" | "END_IF")) {
            prop_assert!(!one.1.is_empty(), "the edits are errors");
        }
        let two = parse_with_threads("t", &text, 2);
        prop_assert_eq!(one, two);
    }
}
