//! Bounded work on hostile input (issue 12), counted, not timed: the PLC front end stops reading
//! after 50 statement lines in a row with errors (1011) and at a NUL byte (1010), so what it
//! reports for the start of a file does not depend on how much more of it there is.

use compiler::{MachineContext, compile};

fn codes(src: &[u8]) -> Vec<(u32, u32, u32)> {
    compile("PLCPRG", src, &MachineContext::lathe_like())
        .diagnostics
        .iter()
        .map(|d| (d.code, d.line, d.column))
        .collect()
}

/// `n` lines `U1K0==I0K0`, each a syntax error at column 6.
fn bad_lines(n: usize) -> String {
    "U1K0==I0K0\n".repeat(n)
}

#[test]
fn fifty_bad_lines_in_a_row_stop_the_reader() {
    let fifty: Vec<(u32, u32, u32)> = (1..=50).map(|l| (1003, l, 6)).collect();
    // Exactly 50: nothing follows, so nothing is given up.
    assert_eq!(codes(bad_lines(50).as_bytes()), fifty);
    // One more line: 1011 at the end of line 50 (column 11, after `U1K0==I0K0`) first (the cause,
    // never hidden by the CLI's per-file cap), then the 50 errors.
    let mut stopped = vec![(1011, 50, 11)];
    stopped.extend(fifty.iter().copied());
    assert_eq!(codes(bad_lines(51).as_bytes()), stopped);
    assert_eq!(codes(bad_lines(100_000).as_bytes()), stopped);
}

#[test]
fn a_good_line_resets_the_count_and_every_error_is_reported() {
    // 49 bad lines, one good one, 49 bad ones, ... 300 times over: never 50 in a row.
    let block = format!("{}U1K1=I0K0\n", bad_lines(49));
    let all = codes(block.repeat(300).as_bytes());
    assert!(!all.iter().any(|&(c, _, _)| c == 1011));
    // The good lines drive U1K1 300 times (1401 from the checker); the syntax errors are all there.
    let d: Vec<_> = all.into_iter().filter(|&(c, _, _)| c == 1003).collect();
    assert_eq!(d.len(), 49 * 300);
    assert!(d.iter().all(|&(_, _, col)| col == 6));
    assert_eq!(d[49], (1003, 51, 6));
    assert_eq!(d[d.len() - 1], (1003, 300 * 50 - 1, 6));
}

#[test]
fn comments_and_blank_lines_do_not_break_a_run() {
    let src = "U1K0==I0K0\n; note\n\n".repeat(60);
    let d = codes(src.as_bytes());
    assert_eq!(d.len(), 51);
    assert_eq!(d[0], (1011, 148, 11));
    assert_eq!(d[50], (1003, 148, 6));
}

#[test]
fn a_nul_byte_stops_at_its_line_and_nothing_is_checked() {
    // Line 1 is read (its undefined name would be 1207 if the program were checked); line 2
    // holds the NUL at byte 15 (line 2, column 6).
    let c = compile(
        "PLCPRG",
        b"U1K0=NOPE\nU1K1=\0I0K1\nU1K2==\n",
        &MachineContext::lathe_like(),
    );
    let d: Vec<(u32, u32, u32)> = c
        .diagnostics
        .iter()
        .map(|d| (d.code, d.line, d.column))
        .collect();
    assert_eq!(d, vec![(1010, 2, 6)]);
    assert!(c.program.is_none());
}

#[test]
fn random_text_reports_the_same_whatever_follows() {
    // The reader stops early (at 44 KB for this seed), so 100 KB and 2 MB of the same random
    // text give the same report.
    let short = diag::random_text(100_000, 12);
    let long = diag::random_text(2_000_000, 12);
    let ctx = MachineContext::lathe_like();
    let a = compile("PLCPRG", &short, &ctx).diagnostics;
    let b = compile("PLCPRG", &long, &ctx).diagnostics;
    assert_eq!(a, b);
    assert_eq!(b.first().map(|d| d.code), Some(1011));
    assert!(b.iter().all(|d| d.span.start < 100_000));
}

#[test]
fn an_if_block_across_chunks_compiles_whole() {
    // 600 statements inside one IF: the block spans the first chunks (256, 512 statement lines)
    // and is nested after all of them are parsed.
    let src = format!(
        "DEF X : INT\nIF I0K0 THEN\n{}END_IF\nU1K0 = [X > 5]\n",
        "X = X + 1\n".repeat(600)
    );
    let c = compile("PLCPRG", src.as_bytes(), &MachineContext::lathe_like());
    let errors: Vec<_> = c.diagnostics.iter().filter(|d| d.is_error()).collect();
    assert_eq!(errors, Vec::<&diag::Diagnostic>::new());
    // 600 assignments + the IF + the last assignment.
    assert_eq!(c.stats.statements, 602);
    assert!(c.program.is_some());
}

#[test]
fn a_source_over_2_mib_is_refused_unread_and_one_at_the_limit_is_read() {
    // A comment line of 64 bytes repeated: exactly the limit, then one byte more.
    let line = format!("; {}\n", "c".repeat(61));
    let at_limit = line.repeat(compiler::MAX_SOURCE_BYTES / line.len());
    assert_eq!(at_limit.len(), compiler::MAX_SOURCE_BYTES);
    let read = codes(at_limit.as_bytes());
    assert!(!read.iter().any(|&(c, _, _)| c == 1012), "{read:?}");
    let over = format!("{at_limit} ");
    assert_eq!(codes(over.as_bytes()), [(1012, 1, 1)]);
    let c = compile("PLCPRG", over.as_bytes(), &MachineContext::lathe_like());
    assert_eq!(
        c.diagnostics[0].message,
        "the PLC program has more than 2097152 bytes (2 MiB), the most a PLC source may have"
    );
    assert!(c.program.is_none());
    // From a file: a 50 MB source is read only to the limit plus one byte, and refused the same.
    let dir = std::env::temp_dir().join(format!("front-bounded-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let path = dir.join("PLCPRG");
    std::fs::write(&path, line.repeat(50_000_000 / line.len())).expect("write");
    let bytes = compiler::read_source(&path).expect("read");
    assert_eq!(bytes.len(), compiler::MAX_SOURCE_BYTES + 1);
    assert_eq!(codes(&bytes), [(1012, 1, 1)]);
    std::fs::write(&path, &at_limit).expect("write");
    assert_eq!(
        compiler::read_source(&path).expect("read"),
        at_limit.as_bytes()
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}
