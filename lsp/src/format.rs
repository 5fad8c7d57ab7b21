//! The formatter (`ncplc fmt`, `textDocument/formatting`): layout only, never a token changed.
//!
//! Rules: every statement line is indented two spaces per enclosing `IF` (an `ELSE` and its
//! `END_IF` at the level of their `IF`); a line that continues a statement (docs/plc-language.md
//! §2, decided by the lexer's line rules) gets four more; a comment-only line is indented like the
//! next statement; the `$` line stands at the left margin; trailing blanks, `\r` and blank lines at
//! the end are removed and the text ends with one newline. Comments are kept byte for byte.
//!
//! Invariants (property-tested): `format(format(x)) == format(x)`, and the compiled program of
//! `format(x)` equals that of `x` (tokens and line numbers are unchanged).

use compiler::lexer::{Tok, tokenize};

/// The characters the lexer skips between tokens (compiler/src/lexer.rs). Only these are trimmed:
/// any other whitespace (a vertical tab, a no-break space) is a token to the lexer, an invalid one,
/// and removing it would change the program and its diagnostics (fuzz target `lsp_edits`).
const LEXER_BLANKS: &[char] = &[' ', '\t', '\r', '\x0c', '\x1a'];

/// How one physical line is laid out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// No tokens: blank or comment only.
    Empty,
    /// Starts a statement whose first token is this.
    Start(Head),
    /// Continues the statement begun on an earlier line.
    Continue,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Head {
    If,
    Else,
    EndIf,
    Dollar,
    Other,
}

/// The formatted text of `src`.
pub fn format(src: &str) -> String {
    let (bom, body) = match src.strip_prefix('\u{FEFF}') {
        Some(b) => ("\u{FEFF}", b),
        None => ("", src),
    };
    let lines: Vec<&str> = body.split('\n').collect();
    let kinds = kinds(body, lines.len());
    let mut out = String::with_capacity(body.len() + 64);
    out.push_str(bom);
    let mut depth = 0usize;
    let mut stmt_indent = 0usize;
    let mut pending: Vec<&str> = Vec::new();
    let emit = |out: &mut String, indent: usize, l: &str| {
        // A U+FEFF first in the file would become its byte-order mark, which the compiler skips:
        // inside a line it is an invalid character, so a blank keeps it off the start.
        let indent = if out.is_empty() && l.starts_with('\u{FEFF}') {
            indent.max(1)
        } else {
            indent
        };
        if !l.is_empty() {
            out.extend(std::iter::repeat_n(' ', indent));
            out.push_str(l);
        }
        out.push('\n');
    };
    for (i, raw) in lines.iter().enumerate() {
        let l = raw.trim_matches(LEXER_BLANKS);
        match kinds[i] {
            Kind::Empty => pending.push(l),
            Kind::Continue => {
                for p in pending.drain(..) {
                    emit(&mut out, stmt_indent + 4, p);
                }
                emit(&mut out, stmt_indent + 4, l);
            }
            Kind::Start(head) => {
                let indent = match head {
                    Head::Dollar => 0,
                    Head::Else | Head::EndIf => 2 * depth.saturating_sub(1),
                    Head::If | Head::Other => 2 * depth,
                };
                for p in pending.drain(..) {
                    emit(&mut out, indent, p);
                }
                emit(&mut out, indent, l);
                stmt_indent = indent;
                match head {
                    Head::If => depth += 1,
                    Head::EndIf => depth = depth.saturating_sub(1),
                    _ => {}
                }
            }
        }
    }
    for p in pending.drain(..) {
        emit(&mut out, 2 * depth, p);
    }
    // One final newline, no blank lines before it.
    let keep = out.trim_end_matches('\n').len();
    out.truncate(keep);
    if out.len() > bom.len() {
        out.push('\n');
    }
    out
}

/// The kind of each of the `n` physical lines of `body`.
fn kinds(body: &str, n: usize) -> Vec<Kind> {
    let mut kinds = vec![Kind::Empty; n];
    let (toks, _) = tokenize(body);
    let mut line = 0usize;
    let mut open = false;
    let newlines: Vec<usize> = body
        .bytes()
        .enumerate()
        .filter(|&(_, b)| b == b'\n')
        .map(|(i, _)| i)
        .collect();
    for (s, t, _) in &toks {
        if *t == Tok::Newline {
            open = false;
            continue;
        }
        // Advance to the physical line of this token.
        while line < newlines.len() && newlines[line] < *s {
            line += 1;
        }
        if let Some(k) = kinds.get_mut(line)
            && *k == Kind::Empty
        {
            *k = if open {
                Kind::Continue
            } else {
                Kind::Start(match t {
                    Tok::If => Head::If,
                    Tok::Else => Head::Else,
                    Tok::EndIf => Head::EndIf,
                    Tok::Dollar => Head::Dollar,
                    _ => Head::Other,
                })
            };
        }
        open = true;
    }
    kinds
}

#[cfg(test)]
mod tests {
    use super::*;
    use compiler::MachineContext;
    use proptest::prelude::*;

    #[test]
    fn if_zones_continuations_and_comments_are_laid_out() {
        let src = "  U4A0 = I0A0 *   \r\nI0A1 ; and\nIF I0A2 THEN\n; inside\nU4A1 = 1\n    IF I0A3 THEN\nU4A2 = 1\nEND_IF\n ELSE\nU4A3 = (I0A4 +\n\n I0A5)\nEND_IF\n  $\nU5A0 = I1A0\n\n\n";
        let want = "U4A0 = I0A0 *\n    I0A1 ; and\nIF I0A2 THEN\n  ; inside\n  U4A1 = 1\n  IF I0A3 THEN\n    U4A2 = 1\n  END_IF\nELSE\n  U4A3 = (I0A4 +\n\n      I0A5)\nEND_IF\n$\nU5A0 = I1A0\n";
        assert_eq!(format(src), want);
        assert_eq!(format(want), want);
        assert_eq!(format(""), "");
        assert_eq!(format("\n\n"), "");
    }

    #[test]
    fn a_no_break_space_mark_is_never_moved_to_the_start() {
        // Found by lsp_edits: U+FEFF inside the first line is an invalid character; trimming the
        // blank before it made it the file's byte-order mark (skipped), and the next pass then
        // trimmed the line after it. One blank keeps it where it is.
        let src = "\t\u{feff}\t\tU4A0 = 1\n";
        assert_eq!(format(src), " \u{feff}\t\tU4A0 = 1\n");
        assert_eq!(format(&format(src)), format(src));
        assert_eq!(errors(src), errors(&format(src)));
        assert_eq!(errors(src), [1001]);
        // A real byte-order mark stays, and the line after it is laid out as any first line.
        assert_eq!(
            format("\u{feff}\t\u{feff}U4A0 = 1\n"),
            "\u{feff}\u{feff}U4A0 = 1\n"
        );
        assert_eq!(format("\n\t\u{feff}U4A0 = 1\n"), "\n\u{feff}U4A0 = 1\n");
    }

    #[test]
    fn only_what_the_lexer_skips_is_trimmed() {
        // Found by the lsp_edits fuzz target: `&` continues the statement onto the next line,
        // the vertical tab after it (an invalid character, a token) ends it. Trimming the tab
        // made the next pass indent the following line as a continuation.
        let src = "U4A0 = I0A0 &\u{b}\n; note\nU4A1 = I0A1\n";
        assert_eq!(format(src), src);
        assert_eq!(format("\u{a0}U4A0 = 1 \t\x0c\x1a\r\n"), "\u{a0}U4A0 = 1\n");
        assert_eq!(
            format("U4A0 = I0A0 +\t\r\nI0A1\n"),
            "U4A0 = I0A0 +\n    I0A1\n"
        );
    }

    fn program(src: &str) -> Option<compiler::ir::Program> {
        compiler::compile("t", src.as_bytes(), &MachineContext::lathe_like()).program
    }

    /// The code of each diagnostic of `src` (formatting moves columns, and an error at the end
    /// of the text up when blank lines at the end go).
    fn errors(src: &str) -> Vec<u32> {
        compiler::compile("t", src.as_bytes(), &MachineContext::lathe_like())
            .diagnostics
            .iter()
            .map(|d| d.code)
            .collect()
    }

    #[test]
    fn the_bundled_programs_compile_to_the_same_program_formatted() {
        for m in ["lathe", "mill"] {
            let path = format!(
                "{}/../plc-programs/{m}/MP0/PLCPRG",
                env!("CARGO_MANIFEST_DIR")
            );
            let src = String::from_utf8(std::fs::read(&path).expect("read")).expect("utf-8");
            let f = format(&src);
            assert_eq!(format(&f), f, "{m}");
            let ctx = crate::machine::Machine::for_file(std::path::Path::new(&path)).ctx;
            let a = compiler::compile("t", src.as_bytes(), &ctx);
            let b = compiler::compile("t", f.as_bytes(), &ctx);
            assert!(a.program.is_some(), "{m}");
            assert_eq!(a.program, b.program, "{m}");
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]
        /// Lines of statements, IFs, continuations, comments and junk in any order and
        /// indentation: formatting is idempotent and never changes what compiles.
        #[test]
        fn format_is_idempotent_and_keeps_the_program(lines in proptest::collection::vec((0usize..4, prop::sample::select(vec![
            "U4A0 = I0A0 *", "I0A1", "IF I0A2 THEN", "ELSE", "END_IF", "U4A1 = (I0A3 +", "I0A4)",
            "; comment ; with ;", "", "$", "DEF t : TON(2s)", "t = I1A0", "U5A0 = t", "SET U4A2 = P1",
            "P1 = I0A5", "U4A3 = ]", "  \t", "W14K0 = 100 ; FOV", "U4A0 = I0A0 &\u{b}",
            "\u{a0}I0A1 \u{a0}", "\x0cI0A2 *\x1a", "\u{feff}U4A1 = 1",
        ])), 0..30)) {
            let src: String = lines.iter().map(|(i, l)| format!("{}{l}\n", " ".repeat(*i))).collect();
            let f = format(&src);
            prop_assert_eq!(format(&f), f.clone());
            prop_assert_eq!(program(&src), program(&f));
            prop_assert_eq!(errors(&src), errors(&f));
        }
    }
}
