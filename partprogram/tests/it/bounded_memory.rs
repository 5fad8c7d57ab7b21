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

/// A Fanuc mill (X, Y, Z) without a macro folder.
fn fanuc_mill() -> partprogram::MachineSpec {
    partprogram::MachineSpec::new(partprogram::Dialect::Fanuc, &['X', 'Y', 'Z'])
}

/// The shape of `tests/gen/error_dense.py`'s Fanuc partprogram: pairs of lines, two MEFI
/// declarations (2033 each: the Fanuc dialect has no R parameters), then a negative block number
/// (2009) and a program number with a point (2003); no line makes a block.
fn dense_fanuc(pairs: usize) -> String {
    let mut src = String::from("O0001\n");
    for _ in 0..pairs {
        src.push_str("R1=1. R2=2.\nN-1 O1.5\n");
    }
    src
}

#[test]
fn a_capped_fanuc_compile_keeps_exactly_max_diagnostics_and_counts_the_rest() {
    let pairs = 20_000;
    let src = dense_fanuc(pairs);
    let (prog, kept, hidden) = compile_capped(&fanuc_mill(), "DENSE", &src, 6);
    assert!(prog.is_none());
    let got: Vec<(u32, u32, u32)> = kept.iter().map(|d| (d.code, d.line, d.column)).collect();
    assert_eq!(
        got,
        [
            (2033, 2, 1),
            (2033, 2, 7),
            (2009, 3, 1),
            (2003, 3, 5),
            (2033, 4, 1),
            (2033, 4, 7),
        ]
    );
    assert_eq!(
        hidden,
        [Hidden {
            file: "DENSE".into(),
            errors: 4 * pairs - 6,
            warnings: 0
        }]
    );
    let (_, all) = compile(&fanuc_mill(), "DENSE", &src);
    assert_eq!(all.len(), 4 * pairs);
    assert_eq!(all[..6], kept[..]);
}

/// What a capped compile of an error-dense program may hold at its peak besides the text, derived
/// by hand from what it keeps: one chunk of parser items (at most 4096 tokens and the one that
/// ends the chunk; the vector may have doubled its capacity once more), the `max` stored
/// diagnostics (a message and a hint of a few hundred bytes each: 2 KiB is generous) and 1 MiB for
/// the machine, its macro folder (the lathe's is 2 KB of text) and the parser's tables. No term
/// grows with the input: 5 MB of text stored at even one byte per byte would exceed it.
fn bound(max: usize) -> usize {
    2 * 4097 * std::mem::size_of::<partprogram::ast::Item>() + max * 2048 + (1 << 20)
}

#[test]
fn a_capped_compile_of_5_mb_holds_no_structure_per_input_byte() {
    let max = 100;
    assert!(
        bound(max) < 5_000_000 / 2,
        "the bound is below half a byte per byte"
    );
    for (name, spec, src) in [
        ("MEFI", common::lathe(), dense(5_000_000 / 22)),
        ("Fanuc", fanuc_mill(), dense_fanuc(5_000_000 / 21)),
    ] {
        assert!(src.len() >= 4_999_000, "{name}: {} bytes", src.len());
        let ((prog, kept, hidden), peak) =
            crate::peak_alloc::peak_during(|| compile_capped(&spec, "DENSE", &src, max));
        assert!(prog.is_none());
        eprintln!("{name}: peak {peak} bytes, bound {}", bound(max));
        assert_eq!(kept.len(), max, "{name}");
        let counted: usize = hidden.iter().map(|h| h.errors + h.warnings).sum();
        assert!(counted > 900_000, "{name}: {counted} diagnostics counted");
        assert!(
            peak <= bound(max),
            "{name}: peak {peak} bytes for {} bytes of text (bound {})",
            src.len(),
            bound(max)
        );
    }
}
