//! Front end: lexes and parses one file and groups the flat items into blocks.
//!
//! MEFI blocks run from one `N` to the next (a block may span several lines); Fanuc blocks end at the
//! end of the line or at `;`. Everything before the first `%` (MEFI) is a preamble and is ignored; a
//! MEFI file that starts with `$PC` is a fixed-cycle file. Problems become located diagnostics; the
//! parser never panics and always returns what it could read.

use diag::{Diagnostic, Sink};
use lalrpop_util::ParseError;

use crate::ast::{Block, Decl, Item, ParsedFile, Val, Word};
use crate::codes;
use crate::lexer::{LexErrorKind, Lexer, Lit, Tok};
use crate::machine::Dialect;

/// The LALRPOP parser, generated from `src/grammar.lalrpop` into `src/grammar.rs` by
/// `scripts/gen-parsers.sh` and committed (the e2e test `generated_parsers` checks the grammar's hash in its header).
#[rustfmt::skip]
#[path = "grammar.rs"]
#[allow(clippy::all, clippy::unwrap_used, unused, missing_docs, unused_qualifications)]
mod grammar;

/// Largest magnitude of a stored parameter count (±69999.999).
pub const R_MAX: i64 = 69_999_999;

/// Parses `src` (the text of `file`) in `dialect`.
pub fn parse(dialect: Dialect, file: &str, src: &str) -> (ParsedFile, Vec<Diagnostic>) {
    parse_with(dialect, file, src, true)
}

/// Parses a macro file: like [`parse`], but a MEFI file without `%` header starts at its first byte.
pub fn parse_library(dialect: Dialect, file: &str, src: &str) -> (ParsedFile, Vec<Diagnostic>) {
    parse_with(dialect, file, src, false)
}

fn parse_with(
    dialect: Dialect,
    file: &str,
    src: &str,
    require_header: bool,
) -> (ParsedFile, Vec<Diagnostic>) {
    let mut sink = Sink::unbounded();
    let out = parse_unlocated(dialect, file, src, require_header, &mut Out(&mut sink));
    // Located in one pass at the end: scanning the text per diagnostic is quadratic (issue 12).
    let lines = diag::LineIndex::new(src);
    let diags = sink
        .into_vec()
        .into_iter()
        .map(|d| d.locate_in(src, &lines))
        .collect();
    (out, diags)
}

/// [`parse`] with the diagnostics pushed into `diags` (a sink that may store only the first of
/// them), marked to be located by [`crate::program::compile`] once it knows which it keeps.
pub(crate) fn parse_into(dialect: Dialect, file: &str, src: &str, diags: &mut Sink) -> ParsedFile {
    parse_unlocated(dialect, file, src, true, &mut Out(diags))
}

/// Where the parser's diagnostics go: a sink, each marked to be located at the end (locating only
/// the ones kept).
struct Out<'a>(&'a mut Sink);

impl Out<'_> {
    fn push(&mut self, d: Diagnostic) {
        self.0.push(crate::program::to_locate(d));
    }

    fn extend(&mut self, ds: impl IntoIterator<Item = Diagnostic>) {
        for d in ds {
            self.push(d);
        }
    }
}

/// [`parse_with`] with line and column of the diagnostics not yet filled in.
fn parse_unlocated(
    dialect: Dialect,
    file: &str,
    src: &str,
    require_header: bool,
    diags: &mut Out,
) -> ParsedFile {
    let mut out = ParsedFile::default();
    let start = match dialect {
        Dialect::Mefi => {
            let p = src.find('%');
            let c = src.find("$PC");
            match (p, c) {
                (Some(p), Some(c)) => p.min(c),
                (Some(p), None) => p,
                (None, Some(c)) => c,
                (None, None) if !require_header => 0,
                (None, None) if src.trim().is_empty() => {
                    diags.push(
                        Diagnostic::error(codes::HEADER, file, 0..0, "the partprogram is empty")
                            .with_hint("a MEFI partprogram is `%<number>` on its first line, then blocks such as `N1 G0 X0 Y0`, ended by a block with M02 or M30"),
                    );
                    return out;
                }
                (None, None) => {
                    diags.push(
                        Diagnostic::error(
                            codes::HEADER,
                            file,
                            0..0,
                            "the partprogram has no `%` header",
                        )
                        .with_hint("start the program with `%<number>` (1..999999)"),
                    );
                    return out;
                }
            }
        }
        Dialect::Fanuc => 0,
    };
    let mut next_line = 0;
    for line in src.split('\n') {
        let off = next_line;
        next_line += line.len() + 1;
        if dialect == Dialect::Mefi && line.trim_end_matches('\r').chars().count() > 80 {
            diags.push(
                Diagnostic::warning(codes::LONG_LINE, file, off..off + line.len(), "line longer than 80 characters")
                    .with_hint("the control reads at most 80 characters per line; continue the block on the next line"),
            );
        }
    }
    // Fanuc Macro B blocks are read by `macro_b::syntax`; the lexer sees them as blank text.
    let (blanked, macro_blocks) = if dialect == Dialect::Fanuc {
        let (t, blocks, d) = crate::macro_b::syntax::prepass(file, src);
        diags.extend(d);
        (t, blocks)
    } else {
        (None, Vec::new())
    };
    let lex_src = blanked.as_deref().unwrap_or(src);
    let mut lexer = Lexer::new(dialect, lex_src, start);
    let mut recovered = Vec::new();
    let result = grammar::ItemsParser::new().parse(&mut recovered, &mut lexer);
    for e in &lexer.errors {
        let msg = match e.kind {
            LexErrorKind::BadChar => {
                let text = src.get(e.span.clone()).unwrap_or("?");
                format!("`{text}` is not allowed here")
            }
            LexErrorKind::BadNumber => "number too long".to_string(),
        };
        diags.push(
            Diagnostic::error(codes::BAD_CHAR, file, e.span.clone(), msg)
                .with_hint(match dialect {
                    Dialect::Mefi => "outside `\"…\"` comments only upper-case addresses, digits, signs, `.`, `%`, `/`, `=`, `&` and `*` are allowed; a sign must touch its digits",
                    Dialect::Fanuc => "outside `( … )` comments only addresses, digits, signs and `.` are allowed",
                }),
        );
    }
    for r in recovered {
        if let Some(d) = parse_error(file, src, r.error) {
            diags.push(d);
        }
    }
    let items = match result {
        Ok(items) => items,
        Err(e) => {
            if let Some(d) = parse_error(file, src, e) {
                diags.push(d);
            }
            Vec::new()
        }
    };
    match dialect {
        Dialect::Mefi => group_mefi(file, src, &items, &mut out, diags, require_header),
        Dialect::Fanuc => group_fanuc(file, &items, macro_blocks, &mut out, diags),
    }
    out
}

fn parse_error(
    file: &str,
    src: &str,
    e: ParseError<usize, Tok, crate::lexer::LexError>,
) -> Option<Diagnostic> {
    let (span, msg) = match e {
        ParseError::InvalidToken { location } => {
            (location..location + 1, "invalid token".to_string())
        }
        ParseError::UnrecognizedEof { location, .. } => {
            (location..location, "unexpected end of file".to_string())
        }
        ParseError::UnrecognizedToken {
            token: (l, t, r), ..
        } => {
            if t == Tok::LexError {
                return None;
            }
            let msg = format!("unexpected `{}`", src.get(l..r).unwrap_or("?"));
            if let Some(hint) = letter_run_hint(src, l) {
                return Some(Diagnostic::error(codes::SYNTAX, file, l..r, msg).with_hint(hint));
            }
            (l..r, msg)
        }
        ParseError::ExtraToken { token: (l, _, r) } => (l..r, "unexpected token".to_string()),
        ParseError::User { .. } => return None,
    };
    Some(
        Diagnostic::error(codes::SYNTAX, file, span, msg)
            .with_hint("a word is an address letter followed by a number or by R<n>; a declaration is R<n>=<number>"),
    )
}

/// The three-letter instructions of the process logic (PGCFIL, seed 003 table of chapter 3): a
/// partprogram block holding one was meant for the process, not for the part.
const PROCESS_INSTRUCTIONS: &[&str] = &[
    "CLS", "DPT", "RED", "BNC", "DIS", "SCR", "BGT", "TOF", "WRT", "BLT", "RQU", "BEQ", "RQP",
    "BNE", "UCG", "BGE", "CLG", "BLE", "DCG", "EPP", "RPT", "DEF", "ERP", "FIL", "UAO", "TGL",
    "UOT", "DFP", "UIO", "EPF", "MIR", "SPA", "URT", "SPF", "SPP", "CLP", "DLY", "CAN", "RLG",
    "DLO", "CLO", "BSP", "DSA", "CRE", "ESP", "ASC", "DER", "DSC", "INP", "CTL", "OPN", "DAM",
    "OUT",
];

/// A "did you mean" for an unexpected letter that is part of a run of letters (a word of a block
/// is one letter and a number): the letter `O` typed for the digit `0` (`GO1`), a
/// process-logic instruction such as `RPT` or `EPP` (or a misspelling of one) in a partprogram.
/// Looks at the letters around byte `at` only (at most 64), so work per error is constant.
fn letter_run_hint(src: &str, at: usize) -> Option<String> {
    let b = src.as_bytes();
    let is_letter = |i: usize| b.get(i).is_some_and(|c| c.is_ascii_alphabetic());
    if !is_letter(at) {
        return None;
    }
    let mut start = at;
    while start > 0 && at - start < 64 && is_letter(start - 1) {
        start -= 1;
    }
    let mut end = at + 1;
    while end - start < 64 && is_letter(end) {
        end += 1;
    }
    let run = src.get(start..end)?.to_ascii_uppercase();
    if run.len() < 2 {
        return None;
    }
    let digit_after = b.get(end).is_some_and(u8::is_ascii_digit);
    if run.len() == 2 && run.as_bytes()[1] == b'O' && digit_after {
        let fixed = format!("{}0{}", &run[..1], src.get(end..end + 1).unwrap_or(""));
        return Some(format!(
            "did you mean `{fixed}`? `O` is a letter; the digit is `0`"
        ));
    }
    if run == "UEP" {
        // A system variable of the process (003:4607-4610), not a word: no block may set it here.
        return Some(
            "`UEP` (velocity feed-forward off) is a system variable of the process: set it with PGCFIL section 4 `ASS=UEP,1`; a partprogram block cannot change it"
                .to_string(),
        );
    }
    let known = PROCESS_INSTRUCTIONS.iter().find(|w| **w == run).copied();
    let meant = known.or_else(|| diag::nearest(&run, PROCESS_INSTRUCTIONS.iter().copied()))?;
    let lead = if known.is_some() {
        format!("`{meant}`")
    } else {
        format!("did you mean `{meant}`? That")
    };
    Some(format!(
        "{lead} is an instruction of the process logic (PGCFIL), not a partprogram word; a block holds words of one address letter and a number"
    ))
}

fn uint_of(src: &str, span: &std::ops::Range<usize>) -> Option<u64> {
    let t = src.get(span.clone())?.trim();
    if t.is_empty() || !t.bytes().all(|b| b.is_ascii_digit()) || t.len() > 12 {
        return None;
    }
    t.parse().ok()
}

fn decl(file: &str, p: Lit, v: Lit, span: std::ops::Range<usize>, diags: &mut Out) -> Option<Decl> {
    if p.point || p.signed || !(0..=95).contains(&p.int) {
        diags.push(
            Diagnostic::error(
                codes::BAD_PARAMETER,
                file,
                span,
                "parameter number must be 0..95",
            )
            .with_hint("parameters are R0 … R95, written without sign or point"),
        );
        return None;
    }
    let r = v.r_count();
    if r.abs() > R_MAX || (!v.point && v.int_digits > 8) || (v.point && v.int_digits > 5) {
        diags.push(
            Diagnostic::error(
                codes::OUT_OF_RANGE,
                file,
                span,
                "parameter value out of range",
            )
            .with_hint(
                "a parameter holds ±69999.999 (format +5.3 with a point, +8 digits without)",
            ),
        );
        return None;
    }
    Some(Decl {
        param: p.int as u8,
        r,
        span: (span.start, span.end),
    })
}

fn group_mefi(
    file: &str,
    src: &str,
    items: &[Item],
    out: &mut ParsedFile,
    diags: &mut Out,
    require_header: bool,
) {
    let mut cur: Option<Block> = None;
    let mut header_seen = false;
    let mut i = 0;
    let mut after_slash = false;
    while i < items.len() {
        let item = &items[i];
        i += 1;
        let was_slash = std::mem::replace(&mut after_slash, false);
        match item {
            Item::Percent(sp) => {
                if header_seen || cur.is_some() {
                    diags.push(Diagnostic::error(
                        codes::HEADER,
                        file,
                        sp.clone(),
                        "a second `%` header",
                    ));
                    continue;
                }
                header_seen = true;
                match items.get(i) {
                    Some(Item::Orphan(nsp)) => {
                        i += 1;
                        match uint_of(src, nsp) {
                            Some(n) if (1..=999_999).contains(&n) => out.number = Some(n as u32),
                            _ => diags.push(
                                Diagnostic::error(
                                    codes::HEADER,
                                    file,
                                    nsp.clone(),
                                    "invalid program number",
                                )
                                .with_hint(
                                    "the program number is 1..999999, without sign or point",
                                ),
                            ),
                        }
                    }
                    _ => diags.push(
                        Diagnostic::error(
                            codes::HEADER,
                            file,
                            sp.clone(),
                            "`%` without a program number",
                        )
                        .with_hint("write `%<number>`, e.g. `%35`"),
                    ),
                }
            }
            Item::CycleHeader(_) => {
                header_seen = true;
                out.cycle_file = true;
            }
            Item::Star(_) => break,
            Item::Comment(_) | Item::Eob(_) => {}
            Item::Slash(_) => match cur.as_mut() {
                Some(b) => {
                    b.skip = true;
                    after_slash = true;
                }
                None => {
                    after_slash = true;
                }
            },
            Item::Orphan(sp) => {
                if was_slash {
                    continue;
                }
                diags.push(
                    Diagnostic::error(codes::ORPHAN_NUMBER, file, sp.clone(), "number without an address")
                        .with_hint("a value must not contain spaces (`X36. 12`) and a sign must touch its digits (`X- 36.12`)"),
                );
            }
            Item::Error(_) => {}
            Item::Word('N', val, sp) => {
                if let Some(b) = cur.take() {
                    out.blocks.push(b);
                }
                let n = match val {
                    Val::Lit(l) if !l.point && !l.signed && (1..=99_999_999).contains(&l.int) => {
                        Some(l.int as u32)
                    }
                    Val::Param(_) | Val::Expr(_) => {
                        diags.push(
                            Diagnostic::error(
                                codes::NOT_PARAMETRISABLE,
                                file,
                                sp.clone(),
                                "the block number cannot be a parameter",
                            )
                            .with_hint("write the block number literally, e.g. `N10`"),
                        );
                        None
                    }
                    Val::Lit(_) => {
                        diags.push(
                            Diagnostic::error(
                                codes::OUT_OF_RANGE,
                                file,
                                sp.clone(),
                                "invalid block number",
                            )
                            .with_hint("block numbers are 1..99999999 without sign or point"),
                        );
                        None
                    }
                };
                cur = Some(Block {
                    n,
                    span: (sp.start, sp.end),
                    ..Block::default()
                });
            }
            Item::Word(a, val, sp) => match cur.as_mut() {
                Some(b) => {
                    b.words.push(Word {
                        addr: *a,
                        val: *val,
                        span: (sp.start, sp.end),
                    });
                    b.span.1 = sp.end;
                }
                None => no_block(file, sp.clone(), diags),
            },
            Item::Decl(p, v, sp) => match cur.as_mut() {
                Some(b) => {
                    if let Some(d) = decl(file, *p, *v, sp.clone(), diags) {
                        b.decls.push(d);
                    }
                    b.span.1 = sp.end;
                }
                None => no_block(file, sp.clone(), diags),
            },
        }
    }
    if let Some(b) = cur.take() {
        out.blocks.push(b);
    }
    if !header_seen && require_header {
        diags.push(
            Diagnostic::error(
                codes::HEADER,
                file,
                0..0,
                "the partprogram has no `%` header",
            )
            .with_hint("start the program with `%<number>`"),
        );
    }
}

fn no_block(file: &str, sp: std::ops::Range<usize>, diags: &mut Out) {
    diags.push(
        Diagnostic::error(codes::NO_BLOCK_NUMBER, file, sp, "word outside a block")
            .with_hint("every block starts with its number `N<n>`"),
    );
}

fn item_start(item: &Item) -> usize {
    match item {
        Item::Percent(r)
        | Item::Star(r)
        | Item::Slash(r)
        | Item::Eob(r)
        | Item::Comment(r)
        | Item::CycleHeader(r)
        | Item::Orphan(r)
        | Item::Word(_, _, r)
        | Item::Decl(_, _, r)
        | Item::Error(r) => r.start,
    }
}

fn group_fanuc(
    file: &str,
    items: &[Item],
    macro_blocks: Vec<Block>,
    out: &mut ParsedFile,
    diags: &mut Out,
) {
    let mut macros = macro_blocks.into_iter().peekable();
    let mut cur = Block::default();
    let mut started = false;
    let mut after_slash = false;
    let flush = |cur: &mut Block, started: &mut bool, out: &mut ParsedFile| {
        if *started && (cur.n.is_some() || !cur.words.is_empty() || !cur.decls.is_empty()) {
            out.blocks.push(std::mem::take(cur));
        } else {
            *cur = Block::default();
        }
        *started = false;
    };
    for item in items {
        while let Some(m) = macros.next_if(|m| m.span.0 <= item_start(item)) {
            flush(&mut cur, &mut started, out);
            out.blocks.push(m);
        }
        let was_slash = std::mem::replace(&mut after_slash, false);
        match item {
            Item::Eob(_) => flush(&mut cur, &mut started, out),
            Item::Percent(_) | Item::Comment(_) | Item::Error(_) | Item::Star(_) | Item::CycleHeader(_) => {}
            Item::Slash(sp) => {
                cur.skip = true;
                after_slash = true;
                if !started {
                    started = true;
                    cur.span = (sp.start, sp.end);
                }
            }
            Item::Orphan(sp) => {
                if !was_slash {
                    diags.push(
                        Diagnostic::error(codes::ORPHAN_NUMBER, file, sp.clone(), "number without an address")
                            .with_hint("a value must not contain spaces and a sign must touch its digits"),
                    );
                }
            }
            Item::Word('O', val, sp) => {
                match val {
                    Val::Lit(l) if !l.point && !l.signed && (0..=99_999).contains(&l.int) => {
                        // An O word starts a program: the first names the main program, each later one
                        // a further program of the file (it must open its own block).
                        flush(&mut cur, &mut started, out);
                        if out.number.is_none() && out.blocks.is_empty() && out.programs.is_empty() {
                            out.number = Some(l.int as u32);
                        } else {
                            out.programs.push((l.int as u32, out.blocks.len()));
                        }
                    }
                    _ => diags.push(
                        Diagnostic::error(codes::HEADER, file, sp.clone(), "invalid program number")
                            .with_hint("write `O<number>`, e.g. `O00023`"),
                    ),
                }
            }
            Item::Word('N', val, sp) => {
                if !started {
                    started = true;
                    cur.span = (sp.start, sp.end);
                }
                match val {
                    Val::Lit(l) if !l.point && !l.signed && (0..=99_999_999).contains(&l.int) => cur.n = Some(l.int as u32),
                    _ => diags.push(
                        Diagnostic::error(codes::OUT_OF_RANGE, file, sp.clone(), "invalid block number")
                            .with_hint("block numbers are N1..N99999"),
                    ),
                }
            }
            Item::Word(a, val, sp) => {
                if !started {
                    started = true;
                    cur.span = (sp.start, sp.end);
                }
                cur.words.push(Word { addr: *a, val: *val, span: (sp.start, sp.end) });
                cur.span.1 = sp.end;
            }
            Item::Decl(_, _, sp) => diags.push(
                Diagnostic::error(codes::R_WORD, file, sp.clone(), "`R<n>=` declarations are MEFI syntax")
                    .with_hint("the Fanuc/HAAS dialect has no R parameters; R is the arc radius or the canned-cycle R plane"),
            ),
        }
    }
    flush(&mut cur, &mut started, out);
    out.blocks.extend(macros);
}
