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

/// The shape of `tests/gen/numbered.py`'s DENSEN.nc: `%1`, then blocks N1, N2, … alternating
/// `N<i> G01 X<a>. K1.` (K has no meaning in MEFI blocks: 2038) and a jump back
/// `N<i> G73 L<1 + i/2 mod 5000>` (its target is a block before it), and no M02/M30 (2032).
fn dense_numbered(blocks: usize) -> String {
    let mut src = String::from("%1\n");
    for i in 1..=blocks {
        if i % 2 == 1 {
            src.push_str(&format!("N{i} G01 X{}. K1.\n", i % 100));
        } else {
            src.push_str(&format!("N{i} G73 L{}\n", 1 + (i / 2) % 5000));
        }
    }
    src
}

#[test]
fn a_capped_compile_of_numbered_blocks_keeps_the_first_diagnostics_and_counts_the_rest() {
    let blocks = 20_000;
    let src = dense_numbered(blocks);
    let (prog, kept, hidden) = compile_capped(&common::lathe(), "DENSE", &src, 6);
    assert!(prog.is_none());
    let got: Vec<(u32, u32, u32)> = kept.iter().map(|d| (d.code, d.line, d.column)).collect();
    // `N1 G01 X1. K1.`: K in column 12; the last, `N19999 G01 X99. K1.` on line 20,000: 17.
    assert_eq!(
        got,
        [
            (2032, 1, 1),
            (2038, 2, 12),
            (2038, 4, 12),
            (2038, 6, 12),
            (2038, 8, 12),
            (2038, 10, 12),
        ]
    );
    // One error per odd block and the warning; 5 errors and the warning are kept.
    assert_eq!(
        hidden,
        [Hidden {
            file: "DENSE".into(),
            errors: blocks / 2 - 5,
            warnings: 0
        }]
    );
    let (_, all) = compile(&common::lathe(), "DENSE", &src);
    assert_eq!(all.len(), 1 + blocks / 2);
    assert_eq!(all[..6], kept[..]);
    assert_eq!((all[blocks / 2].line, all[blocks / 2].column), (20_000, 17));
}

#[test]
fn numbered_blocks_are_checked_against_each_other_without_being_kept() {
    // Errors first, so that no block is kept; then a duplicate number, a jump forward to a block
    // that exists, one to a block that does not, and a subprogram call of a missing subprogram.
    let src = "%1\nN1 K1.\nN2 G73 L5\nN3 G73 L9\nN2 X1.\nN5 G71 L7\nN6 M30\n";
    let (prog, diags) = compile(&common::lathe(), "F", src);
    assert!(prog.is_none());
    let got: Vec<(u32, u32, u32)> = diags.iter().map(|d| (d.code, d.line, d.column)).collect();
    assert_eq!(
        got,
        [(2038, 2, 4), (2018, 4, 1), (2005, 5, 1), (2019, 6, 1)]
    );
}

/// Heap a compressed bitmap of block numbers may take per 65,536 numbers: an array container of
/// up to 4,096 `u16` that has doubled once (16 KiB) while it becomes an 8 KiB bitmap.
const BITMAP_CONTAINER: usize = 16 << 10;

/// What a capped compile of the numbered error-dense program whose largest block number is
/// `max_n` may hold at its peak besides the text: [`bound`] for the parser and the diagnostics of
/// six phases (parse, units, checks, links, M functions, recursion: `max` each), and two bitmaps of
/// block numbers (the file's, the unit's), a container per 65,536 numbers each. No block is kept
/// (the first one has an error) and the jumps go back, so none waits for linking.
fn bound_numbered(max: usize, max_n: usize) -> usize {
    bound(6 * max) + 2 * BITMAP_CONTAINER * (max_n / 65_536 + 1)
}

#[test]
fn a_capped_compile_of_numbered_blocks_holds_no_block() {
    let max = 100;
    let mut peaks = Vec::new();
    for mb in [1, 5] {
        // `N<i> G01 X<a>. K1.` and `N<i> G73 L<j>` average under 20 bytes.
        let blocks = mb * 1_000_000 / 16;
        let src = dense_numbered(blocks);
        assert!(src.len() >= mb * 1_000_000, "{mb} MB: {} bytes", src.len());
        let ((prog, kept, hidden), peak) =
            crate::peak_alloc::peak_during(|| compile_capped(&common::lathe(), "DENSE", &src, max));
        assert!(prog.is_none());
        assert_eq!(kept.len(), max);
        let counted: usize = hidden.iter().map(|h| h.errors + h.warnings).sum();
        assert_eq!(counted + max, 1 + blocks.div_ceil(2));
        let b = bound_numbered(max, blocks);
        eprintln!("numbered {mb} MB ({blocks} blocks): peak {peak} bytes, bound {b}");
        assert!(peak <= b, "{mb} MB: peak {peak} bytes (bound {b})");
        peaks.push((peak, blocks));
    }
    // 5 MB may hold more than 1 MB only by the bitmap containers of its further numbers.
    let [(p1, b1), (p5, b5)] = peaks[..] else {
        unreachable!()
    };
    let margin = 2 * BITMAP_CONTAINER * (b5 / 65_536 - b1 / 65_536);
    assert!(
        p5 <= p1 + margin,
        "1 MB: {p1} bytes, 5 MB: {p5} bytes (margin {margin})"
    );
}

/// The shape of `tests/gen/numbered.py`'s DENSENF.nc: `O0001`, then `N<i> G01 X<a>. E1.` (address
/// E is refused: 2008 on every block).
fn dense_numbered_fanuc(blocks: usize) -> String {
    let mut src = String::from("O0001\n");
    for i in 1..=blocks {
        src.push_str(&format!("N{i} G01 X{}. E1.\n", i % 100));
    }
    src
}

/// [`bound_numbered`] for Fanuc: the parser, the diagnostics of seven sinks (parse, units, checks,
/// links, M functions, recursion, control flow: `max` each) and one bitmap of block numbers (the
/// unit's: Fanuc numbers are unique per program, not per file). No block is kept and no block
/// calls or jumps, so nothing waits for a target.
fn bound_numbered_fanuc(max: usize, max_n: usize) -> usize {
    bound(7 * max) + BITMAP_CONTAINER * (max_n / 65_536 + 1)
}

#[test]
fn a_capped_fanuc_compile_of_numbered_blocks_holds_no_block() {
    let max = 100;
    let mut peaks = Vec::new();
    for mb in [1, 5] {
        // `N<i> G01 X<a>. E1.` averages over 16 bytes.
        let blocks = mb * 1_000_000 / 16;
        let src = dense_numbered_fanuc(blocks);
        assert!(src.len() >= mb * 1_000_000, "{mb} MB: {} bytes", src.len());
        let ((prog, kept, hidden), peak) =
            crate::peak_alloc::peak_during(|| compile_capped(&fanuc_mill(), "DENSE", &src, max));
        assert!(prog.is_none());
        assert_eq!(kept.len(), max);
        // `N1 G01 X1. E1.`: E in column 12 of line 2; one error per block.
        assert_eq!((kept[0].code, kept[0].line, kept[0].column), (2008, 2, 12));
        let counted: usize = hidden.iter().map(|h| h.errors + h.warnings).sum();
        assert_eq!(counted + max, blocks);
        let b = bound_numbered_fanuc(max, blocks);
        eprintln!("numbered Fanuc {mb} MB ({blocks} blocks): peak {peak} bytes, bound {b}");
        assert!(peak <= b, "{mb} MB: peak {peak} bytes (bound {b})");
        peaks.push((peak, blocks));
    }
    // 5 MB may hold more than 1 MB only by the bitmap containers of its further numbers.
    let [(p1, b1), (p5, b5)] = peaks[..] else {
        unreachable!()
    };
    let margin = BITMAP_CONTAINER * (b5 / 65_536 - b1 / 65_536);
    assert!(
        p5 <= p1 + margin,
        "1 MB: {p1} bytes, 5 MB: {p5} bytes (margin {margin})"
    );
}

/// A numbered Fanuc program where every other block is a Macro B statement: `O0001`, then pairs
/// `N<i> #1 = #1 + <k>` and `N<i+1> G01 X<a>. E1.` (2008 on every second block).
fn dense_macro_fanuc(pairs: usize) -> String {
    let mut src = String::from("O0001\n");
    for i in 0..pairs {
        let n = 2 * i + 1;
        src.push_str(&format!(
            "N{n} #1 = #1 + {}\nN{} G01 X{}. E1.\n",
            i % 7,
            n + 1,
            i % 100
        ));
    }
    src
}

#[test]
fn a_capped_compile_of_macro_blocks_holds_their_places_not_their_blocks() {
    // The Macro B blocks are found before lexing (the lexer steps over them) and read when the
    // grouping reaches them: until then each is its byte range, 16 bytes (the vector may have
    // doubled: 32). Besides the text, the peak is the numbered bound and those ranges: no copy of
    // the text (5 MB would exceed it).
    let max = 100;
    for mb in [1, 5] {
        // A pair averages over 32 bytes.
        let pairs = mb * 1_000_000 / 32;
        let src = dense_macro_fanuc(pairs);
        assert!(src.len() >= mb * 1_000_000, "{mb} MB: {} bytes", src.len());
        let ((prog, kept, hidden), peak) =
            crate::peak_alloc::peak_during(|| compile_capped(&fanuc_mill(), "DENSE", &src, max));
        assert!(prog.is_none());
        // `N2 G01 X0. E1.`: E in column 12 of line 3.
        assert_eq!((kept[0].code, kept[0].line, kept[0].column), (2008, 3, 12));
        let counted: usize = hidden.iter().map(|h| h.errors + h.warnings).sum();
        assert_eq!(counted + max, pairs);
        let b = bound_numbered_fanuc(max, 2 * pairs) + 32 * pairs;
        eprintln!("macro Fanuc {mb} MB ({pairs} pairs): peak {peak} bytes, bound {b}");
        assert!(peak <= b, "{mb} MB: peak {peak} bytes (bound {b})");
    }
}

#[test]
fn a_capped_compile_of_forward_gotos_holds_only_those_still_waiting() {
    // Pairs `N<n> IF [#1 GT 1] GOTO <n+2>` and `N<n+1> G01 X<a>. E1.`: each GOTO jumps forward to
    // the next pair and waits for its target only until it comes, so at most one waits at a time;
    // the last one's target never comes (2018 at the end). The peak is that of the macro blocks
    // above: a record per GOTO (56 bytes) would exceed it.
    let max = 100;
    for mb in [1, 5] {
        let pairs = mb * 1_000_000 / 40;
        let mut src = String::from("O0001\n");
        for i in 0..pairs {
            let n = 2 * i + 1;
            src.push_str(&format!(
                "N{n} IF [#1 GT 1] GOTO {}\nN{} G01 X{}. E1.\n",
                n + 2,
                n + 1,
                i % 100
            ));
        }
        assert!(src.len() >= mb * 1_000_000, "{mb} MB: {} bytes", src.len());
        let ((prog, _, hidden), peak) =
            crate::peak_alloc::peak_during(|| compile_capped(&fanuc_mill(), "DENSE", &src, max));
        assert!(prog.is_none());
        let counted: usize = hidden.iter().map(|h| h.errors + h.warnings).sum();
        assert_eq!(counted + max, pairs + 1);
        let b = bound_numbered_fanuc(max, 2 * pairs) + 32 * pairs;
        eprintln!("forward GOTOs {mb} MB ({pairs} pairs): peak {peak} bytes, bound {b}");
        assert!(peak <= b, "{mb} MB: peak {peak} bytes (bound {b})");
        // The one that never came is reported (with the cap 0: every diagnostic).
        if mb == 1 {
            let (_, all) = compile(&fanuc_mill(), "DENSE", &src);
            let last = all.iter().filter(|d| d.code == 2018).collect::<Vec<_>>();
            assert_eq!(last.len(), 1);
            assert_eq!(last[0].line as usize, 2 * pairs);
        }
    }
}

#[test]
fn numbered_fanuc_blocks_are_checked_against_each_other_without_being_kept() {
    // An error first, so that no block is kept; then an M97 forward to a line that exists and one
    // to a line that does not, a duplicate number (a warning), GOTOs back and forward to blocks
    // that exist and one to a block that does not, a loop never closed and an M98 of a missing
    // program.
    let src = "O0001\nN1 G01 X1. E1.\nN2 M97 P5\nN3 M97 P19\nN2 G00 X2.\nN5 GOTO 3\nN6 GOTO 8\n\
               N7 IF [#1 GT 1] GOTO 99\nN8 WHILE [#1 LT 2] DO 1\nN9 M98 P4444\nM30\n";
    let (prog, diags) = compile(&fanuc_mill(), "F", src);
    assert!(prog.is_none());
    let got: Vec<(u32, u32, u32)> = diags.iter().map(|d| (d.code, d.line, d.column)).collect();
    assert_eq!(
        got,
        [
            (2008, 2, 12),
            (2018, 4, 1),
            (2005, 5, 1),
            (2018, 8, 1),
            (2037, 9, 1),
            (2019, 10, 1)
        ]
    );
}

/// The shape of `tests/gen/numbered.py`'s VALIDN.nc: `%1`, `N1 G01 X0 Z0 F100.`, blocks
/// `N<i> G01 X<a>. Z-<b>.` and `N<k> M30`.
fn valid_numbered(blocks: usize) -> String {
    let mut src = String::from("%1\nN1 G01 X0 Z0 F100.\n");
    for i in 2..blocks {
        src.push_str(&format!("N{i} G01 X{}. Z-{}.\n", i % 100, i % 97));
    }
    src.push_str(&format!("N{blocks} M30\n"));
    src
}

#[test]
fn a_valid_numbered_program_keeps_a_compact_block() {
    use partprogram::ast::Word;
    use partprogram::lexer::Lit;
    use partprogram::program::CBlock;
    use std::mem::size_of;
    // A literal is its integer part and two rounded fractions; a word its address, value and span.
    assert_eq!(size_of::<Lit>(), 16);
    assert_eq!(size_of::<Word>(), 48);
    let mut held = Vec::new();
    for blocks in [1_000, 101_000] {
        let src = valid_numbered(blocks);
        let ((prog, diags, _), peak, h) = crate::peak_alloc::peak_and_held(|| {
            compile_capped(&common::lathe(), "VALID", &src, 100)
        });
        assert!(prog.is_some(), "{diags:?}");
        // The program holds a copy of the text.
        held.push((h - src.len(), peak - src.len()));
        drop(prog);
    }
    // Rounded to the nearest byte: a few bytes a thread-local or the allocator's bookkeeping may
    // keep in one of the two runs and not the other must not change the per-block figure (the
    // exact difference is 100,000 blocks' worth; truncating made one byte less fail the test).
    let per_block = (held[1].0 - held[0].0 + 50_000) / 100_000;
    let peak_per_block = (held[1].1 - held[0].1 + 50_000) / 100_000;
    // Each block: the compiled block, its three words (no spare room), 8 bytes of the unit's
    // number index and 4 of the native code's region table (`region_of`); nothing else grows with
    // the blocks.
    let expected = size_of::<CBlock>() + 3 * size_of::<Word>() + 8 + 4;
    eprintln!(
        "held {per_block} B per block (CBlock {} B), peak {peak_per_block} B per block",
        size_of::<CBlock>()
    );
    assert_eq!(per_block, expected);
    // At the peak, the block vector may have doubled once beyond the blocks (and the word being
    // parsed is one chunk: constant).
    assert!(
        peak_per_block <= expected + size_of::<CBlock>(),
        "peak {peak_per_block} B per block"
    );
}

#[test]
fn checking_the_plan_of_a_valid_program_holds_no_canonical_block() {
    // `nc check` runs a valid program to find its geometric errors: besides the compiled program
    // it holds the executor's state and the radius compensation's look-ahead, not the plan, so
    // 100,000 more blocks add to its peak only the MEFI frame's jump counter of each block of the
    // unit (an `i64`: 800,000 bytes), not the plan's 101,000 canonical blocks of several hundred
    // bytes each.
    let mut peaks = Vec::new();
    for blocks in [1_000, 101_000] {
        let src = valid_numbered(blocks);
        let (prog, diags) = compile(&common::lathe(), "VALID", &src);
        let Some(prog) = prog else {
            panic!("{diags:?}")
        };
        let (checked, peak) = crate::peak_alloc::peak_during(|| {
            partprogram::check_plan(&prog, partprogram::PlanOptions::default())
        });
        // Every block runs once: N1, N2 … N<blocks> (M30).
        assert_eq!(checked, Ok(blocks as u64));
        let planned = partprogram::plan(&prog, partprogram::PlanOptions::default());
        assert_eq!(planned.map(|p| p.executed).ok(), Some(blocks as u64));
        eprintln!("check_plan of {blocks} blocks: peak {peak} bytes");
        peaks.push(peak);
    }
    let counters = 100_000 * std::mem::size_of::<i64>();
    assert!(peaks[1] <= peaks[0] + counters + 4096, "peaks {peaks:?}");
}

#[test]
fn a_planned_canonical_block_of_a_valid_program_has_a_known_size() {
    // What `run --program` holds per block of a valid program (it plans the whole program before
    // the first tick): the canonical block and its end point, one (axis, mm) pair of 16 bytes per
    // axis of the lathe (X, Z); the plan has no spare room. 100,000 more blocks hold exactly
    // 100,000 times that.
    use partprogram::Canon;
    use std::mem::size_of;
    assert_eq!(size_of::<Canon>(), 288);
    let mut held = Vec::new();
    for blocks in [1_000, 101_000] {
        let src = valid_numbered(blocks);
        let (prog, _) = compile(&common::lathe(), "VALID", &src);
        let Some(prog) = prog else {
            panic!("not compiled")
        };
        let (plan, _, h) = crate::peak_alloc::peak_and_held(|| {
            partprogram::plan(&prog, partprogram::PlanOptions::default())
                .map(|p| p.blocks)
                .map_err(|(_, d)| d)
        });
        let Ok(plan) = plan else {
            panic!("not planned")
        };
        // One canonical block per block: N1 … N<blocks> (M30 is an auxiliary block).
        assert_eq!((plan.len(), plan.capacity()), (blocks, blocks));
        held.push(h);
    }
    assert_eq!(held[1] - held[0], 100_000 * (size_of::<Canon>() + 2 * 16));
}

/// An error-dense macro file `L9002` of the shape of [`dense_numbered`] (`%9002`, `N1 G79 L9002`,
/// then `N<i> G01 X<a>. K1.` and `N<i> G73 L<j>` alternating, `G70` last) in a MEFI machine's
/// macro folder.
fn dense_macro_folder(blocks: usize) -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut src = String::from("%9002\nN1 G79 L9002\n");
    for i in 2..=blocks {
        if i % 2 == 1 {
            src.push_str(&format!("N{i} G01 X{}. K1.\n", i % 100));
        } else {
            src.push_str(&format!("N{i} G73 L{}\n", 2 + (i / 2) % 5000));
        }
    }
    src.push_str(&format!("N{} G70\n", blocks + 1));
    std::fs::write(dir.path().join("L9002"), src).expect("write");
    dir
}

#[test]
fn an_error_dense_macro_file_is_held_no_more_than_a_main_file() {
    let max = 100;
    let mut peaks = Vec::new();
    for mb in [1, 5] {
        let blocks = mb * 1_000_000 / 16;
        let folder = dense_macro_folder(blocks);
        let len = std::fs::metadata(folder.path().join("L9002"))
            .expect("L9002")
            .len() as usize;
        assert!(len >= mb * 1_000_000, "{mb} MB: {len} bytes");
        let mut m = common::lathe();
        m.macro_dir = folder.path().to_path_buf();
        let main = "%1\nN1 G01 X1. F100.\nN2 M30\n";
        let ((prog, kept, hidden), peak) =
            crate::peak_alloc::peak_during(|| compile_capped(&m, "MAIN", main, max));
        assert!(prog.is_none());
        // The macro file's first `max` errors are kept, the rest counted: one error (2038) per
        // block with K, as in a main file.
        assert_eq!(kept.len(), max);
        let first: Vec<_> = kept
            .iter()
            .take(4)
            .map(|d| (d.file.as_str(), d.code, d.line, d.column))
            .collect();
        assert!(
            kept.iter()
                .all(|d| d.file == "macros/L9002" && d.code == 2038),
            "{first:?}"
        );
        let counted: usize = hidden.iter().map(|h| h.errors + h.warnings).sum();
        assert_eq!(counted + max, (blocks - 1) / 2);
        // The file's text (read whole, kept to locate the diagnostics) and what a main file of
        // the same blocks may hold; no block, no uncapped diagnostic list.
        let b = 2 * len + bound_numbered(max, blocks);
        eprintln!("macro file {mb} MB ({blocks} blocks): peak {peak} bytes, bound {b}");
        assert!(peak <= b, "{mb} MB: peak {peak} bytes (bound {b})");
        peaks.push((peak, len, blocks));
    }
    // 5 MB holds more than 1 MB only by its text and the bitmap containers of its numbers.
    let [(p1, l1, b1), (p5, l5, b5)] = peaks[..] else {
        unreachable!()
    };
    let margin = 2 * (l5 - l1) + 2 * BITMAP_CONTAINER * (b5 / 65_536 - b1 / 65_536);
    assert!(
        p5 <= p1 + margin,
        "1 MB: {p1} bytes, 5 MB: {p5} bytes (margin {margin})"
    );
}

#[test]
fn a_capped_compile_of_forward_jumps_holds_only_those_still_waiting() {
    // `N<i> G01 X<a>. K1.` (2038) and `N<i> G73 L<i + 5>`: every jump waits for a block three
    // lines on, then leaves; before, each stayed until linking (a 50 MB file took 235 MB).
    let max = 100;
    let mut peaks = Vec::new();
    for mb in [1, 5] {
        let blocks: usize = mb * 1_000_000 / 16;
        let mut src = String::from("%1\n");
        for i in 1..=blocks {
            if i % 2 == 1 {
                src.push_str(&format!("N{i} G01 X{}. K1.\n", i % 100));
            } else {
                src.push_str(&format!("N{i} G73 L{}\n", i + 5));
            }
        }
        src.push_str(&format!("N{} M30\n", blocks + 10));
        let ((prog, kept, hidden), peak) =
            crate::peak_alloc::peak_during(|| compile_capped(&common::lathe(), "FWD", &src, max));
        assert!(prog.is_none());
        assert_eq!(kept.len(), max);
        // One 2038 per odd block; L is at most 9999 (2009 for each jump beyond); the jumps of
        // the last blocks go beyond the last block and miss their target (2018).
        let counted: usize = hidden.iter().map(|h| h.errors + h.warnings).sum();
        let jumps =
            |keep: &dyn Fn(usize) -> bool| (2..=blocks).step_by(2).filter(|&i| keep(i)).count();
        let out_of_range = jumps(&|i| i + 5 > 9999);
        let missing = jumps(&|i| i + 5 > blocks);
        assert_eq!(counted + max, blocks.div_ceil(2) + out_of_range + missing);
        let b = bound_numbered(max, blocks);
        eprintln!("forward jumps {mb} MB ({blocks} blocks): peak {peak} bytes, bound {b}");
        assert!(peak <= b, "{mb} MB: peak {peak} bytes (bound {b})");
        peaks.push((peak, blocks));
    }
    let [(p1, b1), (p5, b5)] = peaks[..] else {
        unreachable!()
    };
    let margin = 2 * BITMAP_CONTAINER * (b5 / 65_536 - b1 / 65_536);
    assert!(
        p5 <= p1 + margin,
        "1 MB: {p1} bytes, 5 MB: {p5} bytes (margin {margin})"
    );
}

#[test]
fn a_plan_of_a_loop_free_program_is_allocated_once() {
    // The plan starts with room for one canonical block per compiled block: without it the vector
    // doubled its way to 101,000 blocks, holding the old and the new buffer at each step (a 50 MB
    // program's plan is hundreds of megabytes, and `run --program` took 1.50 GB instead of 1.24).
    let src = valid_numbered(101_000);
    let (prog, diags) = compile(&common::lathe(), "VALID", &src);
    let Some(prog) = prog else {
        panic!("{diags:?}")
    };
    let (planned, peak) = crate::peak_alloc::peak_during(|| {
        partprogram::plan(&prog, partprogram::PlanOptions::default()).ok()
    });
    let plan = planned.expect("a valid program plans");
    assert_eq!(plan.executed, 101_000);
    let canon = plan.blocks.capacity() * std::mem::size_of::<partprogram::Canon>();
    assert_eq!(plan.blocks.capacity(), plan.blocks.len());
    // Beside the plan, the executor's own state (measured: 4.1 MB, the MEFI frame's jump counter
    // per block of the unit among it); growing by doubling, the peak was 41.8 MB (the old and the
    // new buffer of its last step).
    eprintln!(
        "plan of {} blocks: {canon} bytes, peak {peak}",
        plan.blocks.len()
    );
    assert!(peak <= canon + canon / 4, "peak {peak}, plan {canon}");
}
