//! Bounded diagnostics on an error-dense partprogram (issue 23, item 4): `compile_capped` keeps
//! exactly `max` diagnostics of the file, counts the rest exactly, and keeps the first of what an
//! uncapped `compile` reports.

use crate::common;

use diag::Hidden;
use partprogram::{compile, compile_capped};

/// The shape of `tests/gen/error_dense.py`'s partprogram: `%` without a number (2003), then pairs
/// of lines whose five words stand outside any block (2004 each: a MEFI block starts with `N`),
/// and no M02/M30 (warning 2032).
fn dense(pairs: usize) -> String {
    let mut src = String::from("%\n");
    for _ in 0..pairs {
        src.push_str("G01 X1. F100.\nG01 Q1.\n");
    }
    src
}

#[test]
fn a_capped_compile_keeps_exactly_max_diagnostics_and_counts_the_rest() {
    let pairs = 20_000;
    let src = dense(pairs);
    let (prog, kept, hidden) = compile_capped(&common::lathe(), "DENSE", &src, 10);
    assert!(prog.is_none());
    let got: Vec<(u32, u32, u32)> = kept.iter().map(|d| (d.code, d.line, d.column)).collect();
    assert_eq!(
        got,
        [
            (2003, 1, 1),
            (2032, 1, 1),
            (2004, 2, 1),
            (2004, 2, 5),
            (2004, 2, 9),
            (2004, 3, 1),
            (2004, 3, 5),
            (2004, 4, 1),
            (2004, 4, 5),
            (2004, 4, 9),
        ]
    );
    // 1 + 5 per pair errors and one warning in all; 9 errors and the warning are kept.
    assert_eq!(
        hidden,
        [Hidden {
            file: "DENSE".into(),
            errors: 1 + 5 * pairs - 9,
            warnings: 0
        }]
    );
    let (_, all) = compile(&common::lathe(), "DENSE", &src);
    assert_eq!(all.len(), 2 + 5 * pairs);
    assert_eq!(all[..10], kept[..]);
}
