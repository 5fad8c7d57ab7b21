//! The parser driver: tokens → LALRPOP grammar → flat lines → [`ast::Program`] with nested `IF`
//! blocks and the FAST/SLOW split, plus located syntax diagnostics.
//!
//! Recovery is per line: the grammar's `!` rule swallows a bad line up to its end, so one mistake
//! costs one diagnostic and the rest of the file is still checked. A second `$` line ends the
//! program text; whatever follows it is one error ([`codes::TEXT_AFTER_END`]).

use diag::Diagnostic;
use lalrpop_util::ParseError;

use crate::ast::{BinOp, Expr, ExprKind, Line, Program, Span, Stmt, StmtKind};
use crate::lexer::{self, LexErrorKind, Spanned, Tok};
use crate::parse_cache::{ParseCache, Parsed};
use crate::sema::codes;

/// The LALRPOP parser, generated from `src/grammar.lalrpop` into `src/grammar.rs` by
/// `scripts/gen-parsers.sh` and committed (the e2e test `generated_parsers` checks the grammar's hash in its header).
#[rustfmt::skip]
#[path = "grammar.rs"]
#[allow(clippy::all, clippy::unwrap_used, unused, missing_docs, unused_qualifications)]
mod grammar;

/// Parses decoded source `text` of `file`; diagnostics are located (line and column filled in).
pub fn parse(file: &str, text: &str) -> (Program, Vec<Diagnostic>) {
    parse_with_threads(file, text, 1)
}

/// Statement lines in a row with an error after which the parser stops (error
/// [`codes::GAVE_UP`]): the file is not a PLC program, and one error per line of it would only
/// bury the cause (the characterization reader's 971 does the same).
pub const MAX_BAD_LINES: usize = 50;

/// Statement lines of the first chunk the parser reads; every further chunk is twice as long, so
/// random text stops after a few kilobytes while a long program is parsed in a few large chunks.
const FIRST_CHUNK_LINES: usize = 256;

/// [`parse`] on up to `threads` threads (0: the available cores): a long chunk is cut at the line
/// end nearest its middle and both halves go through the grammar at once. The result is always
/// exactly [`parse`]'s.
///
/// The text is lexed and parsed in chunks of whole statement lines (every line is a complete item
/// of the grammar, so the chunks give what one pass gives). Reading stops at a NUL byte
/// ([`codes::NOT_TEXT`]), at the second `$` line ([`codes::TEXT_AFTER_END`]) and after
/// [`MAX_BAD_LINES`] bad statement lines in a row ([`codes::GAVE_UP`]): work and memory stay
/// bounded by what is read, whatever the file.
pub fn parse_with_threads(file: &str, text: &str, threads: usize) -> (Program, Vec<Diagnostic>) {
    parse_inner(file, text, threads, None)
}

/// [`parse`] reusing the segments of earlier texts that `cache` holds (an editor's parse after an
/// edit; see [`crate::parse_cache`]); the result is always exactly [`parse`]'s.
pub fn parse_cached(file: &str, text: &str, cache: &mut ParseCache) -> (Program, Vec<Diagnostic>) {
    cache.begin();
    let r = parse_inner(file, text, 1, Some(&mut *cache));
    cache.end();
    r
}

fn parse_inner(
    file: &str,
    text: &str,
    threads: usize,
    mut cache: Option<&mut ParseCache>,
) -> (Program, Vec<Diagnostic>) {
    let threads = match threads {
        0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
        n => n,
    };
    let mut stop: Option<Diagnostic> = None;
    let mut readable = text;
    if let Some(at) = text.find('\0') {
        readable = &text[..text[..at].rfind('\n').map_or(0, |i| i + 1)];
        stop = Some(
            Diagnostic::error(codes::NOT_TEXT, file, at..at + 1, format!("NUL byte at byte {at}: {file} is not a text file"))
                .with_hint("a PLC program is plain text; check that the right file is named (reading stopped at the line of the NUL)"),
        );
    }
    let mut lexer = lexer::Lexer::new(readable);
    let mut syntax: Vec<Diagnostic> = Vec::new();
    let mut all_lines: Vec<Line> = Vec::new();
    let mut dollars = DollarLines::default();
    let mut bad_run = 0usize;
    let mut chunk_lines = FIRST_CHUNK_LINES;
    // Lexer errors at or after this offset are not reported (text after the end or the stop).
    let mut cut = readable.len();
    'chunks: loop {
        let mut tokens: Vec<Spanned<'_>> = Vec::new();
        let mut statements = 0;
        let mut after_end = None;
        while statements < chunk_lines {
            let Some(t) = lexer.next() else { break };
            let newline = t.1 == Tok::Newline;
            let second_dollar = dollars.see(&t);
            tokens.push(t);
            if newline {
                statements += 1;
            }
            if second_dollar {
                after_end = Some(lexer.next().map(|t| t.0));
                break;
            }
        }
        if tokens.is_empty() {
            break;
        }
        let first_new = syntax.len();
        if let Some(cache) = cache.as_deref_mut() {
            // Syntax errors are worded from the readable text only: a segment's diagnostics
            // depend on its own tokens, so the cache may reuse them after any edit elsewhere
            // (an end-of-text error beside a later NUL once read past the end of `readable`).
            let p = cache.parse_chunk(readable, &tokens, |t| parsed(file, readable, t));
            syntax.extend(p.diagnostics);
            all_lines.extend(p.lines);
        } else {
            let (lines, recovered) = if threads > 1 && tokens.len() >= SPLIT_TOKENS {
                parse_lines_split(&tokens)
            } else {
                parse_lines(&tokens).0
            };
            for r in recovered {
                if let Some(d) = syntax_diagnostic(file, readable, r.error) {
                    syntax.push(d);
                }
            }
            all_lines.extend(lines);
        }
        // Statement lines with an error, in order: a lexer error or a syntax error inside.
        let mut starts: Vec<usize> = lexer
            .errors
            .iter()
            .rev()
            .take_while(|e| e.span.start >= tokens[0].0)
            .map(|e| e.span.start)
            .chain(syntax[first_new..].iter().map(|d| d.span.start))
            .collect();
        starts.sort_unstable();
        let mut errs = starts.into_iter().peekable();
        for &(at, ref tok, end) in &tokens {
            if *tok != Tok::Newline {
                continue;
            }
            let mut bad = false;
            while errs.next_if(|&s| s < end).is_some() {
                bad = true;
            }
            bad_run = if bad { bad_run + 1 } else { 0 };
            if bad_run == MAX_BAD_LINES {
                let more = tokens.last().is_some_and(|t| t.2 > end) || lexer.next().is_some();
                if more {
                    cut = end;
                    stop = Some(
                        Diagnostic::error(codes::GAVE_UP, file, at..at, format!("{MAX_BAD_LINES} statement lines in a row have errors; reading of {file} stopped here"))
                            .with_hint("is this the right file? A PLC program is `DEF` lines, statements such as `U4A0 = I0A0 * I0A1`, `IF … THEN` blocks and `;` comments"),
                    );
                    syntax.retain(|d| d.span.start < end);
                    break 'chunks;
                }
            }
        }
        if let Some(next) = after_end {
            if let Some(start) = next {
                cut = start;
                syntax.push(
                    Diagnostic::error(
                        codes::TEXT_AFTER_END,
                        file,
                        start..text.len(),
                        "text after the second `$` line",
                    )
                    .with_hint(
                        "a second `$` ends the program; delete what follows it or remove that `$`",
                    ),
                );
            }
            break;
        }
        chunk_lines = chunk_lines.saturating_mul(2);
    }
    let mut diags: Vec<Diagnostic> = lexer
        .errors
        .iter()
        .filter(|e| e.span.start < cut)
        .map(|e| match e.kind {
            LexErrorKind::InvalidChar => Diagnostic::error(codes::INVALID_CHAR, file, e.span.clone(), format!("invalid character `{}`", text.get(e.span.clone()).unwrap_or("?")))
                .with_hint("outside a `;` comment only ASCII letters, digits, operators and brackets are allowed"),
            LexErrorKind::NumberTooLarge => Diagnostic::error(codes::NUMBER_TOO_LARGE, file, e.span.clone(), format!("number `{}` is too large", text.get(e.span.clone()).unwrap_or("?")))
                .with_hint("numbers must fit 32 bits (at most 4294967295 or 0FFFFFFFFH)"),
        })
        .collect();
    diags.append(&mut syntax);
    let program = if stop.is_some() {
        // Block structure of a file read only in part would be follow-on noise.
        nest(file, all_lines, &mut Vec::new())
    } else {
        nest(file, all_lines, &mut diags)
    };
    diags.extend(stop);
    if diags.is_empty() {
        return (program, diags);
    }
    let lines = lexer::LineIndex::new(text);
    let diags = diags.into_iter().map(|d| lines.locate(d)).collect();
    (program, diags)
}

/// True when the parser stopped reading `diagnostics`' file early (a NUL byte or too many bad
/// lines in a row): the program is incomplete and is not checked further.
pub fn stopped_early(diagnostics: &[Diagnostic]) -> bool {
    diagnostics
        .iter()
        .any(|d| d.code == codes::NOT_TEXT || d.code == codes::GAVE_UP)
}

/// Finds `$` lines in a token stream: the first splits FAST from SLOW, the second ends the text.
#[derive(Debug, Default)]
struct DollarLines {
    seen: usize,
    /// The previous token was a `$` at the start of a line.
    dollar_at_start: bool,
    /// The previous token was a newline (or there was none).
    after_newline: bool,
    started: bool,
}

impl DollarLines {
    /// Takes the next token; true when it ends the second `$` line.
    fn see(&mut self, t: &Spanned<'_>) -> bool {
        let at_start = !self.started || self.after_newline;
        self.started = true;
        let ends_dollar_line = self.dollar_at_start && t.1 == Tok::Newline;
        self.dollar_at_start = at_start && t.1 == Tok::Dollar;
        self.after_newline = t.1 == Tok::Newline;
        if ends_dollar_line {
            self.seen += 1;
        }
        ends_dollar_line && self.seen == 2
    }
}

/// Sources shorter than this many tokens are parsed on one thread.
const SPLIT_TOKENS: usize = 20_000;

type Recovered<'a> = Vec<lalrpop_util::ErrorRecovery<usize, Tok<'a>, ()>>;

/// Runs the grammar over `tokens`. An unrecoverable error becomes one more recovered error and no
/// lines; the flag says it happened.
fn parse_lines<'a>(tokens: &[Spanned<'a>]) -> ((Vec<Line>, Recovered<'a>), bool) {
    let mut recovered = Vec::new();
    let input = tokens.iter().cloned().map(Ok::<_, ()>);
    match grammar::LinesParser::new().parse(&mut recovered, input) {
        Ok(lines) => ((lines, recovered), false),
        Err(e) => {
            recovered.push(lalrpop_util::ErrorRecovery {
                error: e,
                dropped_tokens: Vec::new(),
            });
            ((Vec::new(), recovered), true)
        }
    }
}

/// [`parse_lines`] with the syntax diagnostics made, for [`ParseCache::parse_chunk`].
fn parsed<'a>(file: &str, text: &str, tokens: &[Spanned<'a>]) -> Parsed {
    let ((lines, recovered), failed) = parse_lines(tokens);
    let eof = recovered
        .iter()
        .any(|e| matches!(e.error, ParseError::UnrecognizedEof { .. }));
    let diagnostics = recovered
        .into_iter()
        .filter_map(|r| syntax_diagnostic(file, text, r.error))
        .collect();
    Parsed {
        lines,
        diagnostics,
        whole_pass_needed: failed || eof,
    }
}

/// [`parse_lines`] of two halves at once. Every line is a complete item of the grammar (IF blocks
/// are nested afterwards), so cutting right after a line end and concatenating the results gives
/// what one pass gives; when a half fails unrecoverably or runs into its end (never expected), the
/// whole is parsed again in one pass.
fn parse_lines_split<'a>(tokens: &[Spanned<'a>]) -> (Vec<Line>, Recovered<'a>) {
    let mid = tokens.len() / 2;
    let cut = tokens[mid..]
        .iter()
        .position(|t| t.1 == Tok::Newline)
        .map(|i| mid + i + 1)
        .filter(|&c| c < tokens.len());
    let Some(cut) = cut else {
        return parse_lines(tokens).0;
    };
    let (first, second) = tokens.split_at(cut);
    let (a, b) = std::thread::scope(|s| {
        let h = s.spawn(|| parse_lines(second));
        (parse_lines(first), h.join())
    });
    let ends_early = |r: &Recovered<'_>| {
        r.iter()
            .any(|e| matches!(e.error, ParseError::UnrecognizedEof { .. }))
    };
    match (a, b) {
        (((mut lines, mut rec), false), Ok(((more, more_rec), false))) if !ends_early(&rec) => {
            lines.extend(more);
            rec.extend(more_rec);
            (lines, rec)
        }
        _ => parse_lines(tokens).0,
    }
}

/// Binding strength of a binary operator (higher binds tighter); every level is left-associative:
/// OR < `|` < `^` < `&` < shifts < `+ -` < XOR < `* / MOD AND`.
pub(crate) fn precedence(op: BinOp) -> u8 {
    match op {
        BinOp::OrKw => 0,
        BinOp::Pipe => 1,
        BinOp::Caret => 2,
        BinOp::Amp => 3,
        BinOp::Shl | BinOp::Shr => 4,
        BinOp::Plus | BinOp::Minus => 5,
        BinOp::XorKw => 6,
        BinOp::Star | BinOp::Slash | BinOp::Mod | BinOp::AndKw => 7,
    }
}

/// An operand with the byte range of its tokens (parentheses included, unlike its span).
type Operand = (usize, Expr, usize);

/// Nests `first (op operand)*` by precedence. A binary node spans the tokens of both operands,
/// as a node of a tiered grammar would; a lone operand is returned as it is.
pub(crate) fn climb(first: Operand, rest: Vec<(BinOp, Operand)>) -> Expr {
    if rest.is_empty() {
        return first.1;
    }
    let mut it = rest.into_iter().peekable();
    climb_from(first, 0, &mut it).1
}

fn climb_from(
    mut lhs: Operand,
    min: u8,
    it: &mut std::iter::Peekable<std::vec::IntoIter<(BinOp, Operand)>>,
) -> Operand {
    while let Some(p) = it.peek().map(|(op, _)| precedence(*op)) {
        if p < min {
            break;
        }
        let Some((op, mut rhs)) = it.next() else {
            break;
        };
        while it.peek().is_some_and(|(next, _)| precedence(*next) > p) {
            rhs = climb_from(rhs, p + 1, it);
        }
        let (l, r) = (lhs.0, rhs.2);
        lhs = (
            l,
            Expr {
                kind: ExprKind::Binary(op, Box::new(lhs.1), Box::new(rhs.1)),
                span: l..r,
            },
            r,
        );
    }
    lhs
}

fn describe(text: &str, l: usize, t: &Tok<'_>, r: usize) -> String {
    match t {
        Tok::Newline => "end of line".to_string(),
        _ => format!("`{}`", text.get(l..r).unwrap_or("?")),
    }
}

fn friendly(expected: &[String]) -> String {
    let names: Vec<&str> = expected
        .iter()
        .map(|e| match e.trim_matches('"') {
            "\\n" => "end of line",
            "signal" => "a signal",
            "pulse" => "a one-shot P<n>",
            "int" => "a number",
            "real" => "a real number",
            "duration" => "a duration",
            "name" => "a name",
            other => other,
        })
        .collect();
    if names.len() > 10 {
        return "an operand (signal, name, number, `(`, `[`) or an operator".to_string();
    }
    let quoted: Vec<String> = names
        .iter()
        .map(|n| {
            if n.starts_with("a ") || n.starts_with("an ") || *n == "end of line" {
                n.to_string()
            } else {
                format!("`{n}`")
            }
        })
        .collect();
    quoted.join(", ")
}

/// The keywords of the language, for "did you mean" on a misspelled one (`ENDIF` → `END_IF`).
const KEYWORDS: &[&str] = &[
    "DEF", "AT", "RETAIN", "SET", "RES", "IF", "THEN", "ELSE", "END_IF", "OR", "AND", "NOT", "XOR",
    "MOD", "TRUE", "FALSE",
];

/// "did you mean `END_IF`?" when the unexpected token is a name close to a keyword, or ends a
/// line that is one such word alone (`ENDIF` reads as the start of an assignment).
fn keyword_suggestion(text: &str, at: usize, t: &Tok) -> Option<String> {
    let word = match t {
        Tok::Ident(w) => w.to_string(),
        Tok::Newline => {
            let at = at.min(text.len());
            let start = text.get(..at)?.rfind('\n').map_or(0, |i| i + 1);
            let line = text.get(start..at)?.trim();
            let single = !line.is_empty()
                && line.len() <= 64
                && line.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_');
            if !single {
                return None;
            }
            line.to_string()
        }
        _ => return None,
    };
    diag::did_you_mean(&word, KEYWORDS.iter().copied())
}

fn syntax_diagnostic(
    file: &str,
    text: &str,
    e: ParseError<usize, Tok<'_>, ()>,
) -> Option<Diagnostic> {
    Some(match e {
        // The lexer already reported the unreadable text.
        ParseError::UnrecognizedToken {
            token: (_, Tok::Error, _),
            ..
        } => return None,
        ParseError::UnrecognizedToken {
            token: (l, t, r),
            expected,
        } => {
            let what = describe(text, l, &t, r);
            let span = if r > l {
                l..r
            } else {
                l..(l + 1).min(text.len())
            };
            // Only the bytes just before the token are looked at: work per error stays constant.
            let after_def = text.get(..l).map(str::trim_end).is_some_and(|b| {
                let n = b.len();
                n >= 3
                    && b.as_bytes()[n - 3..].eq_ignore_ascii_case(b"DEF")
                    && (n == 3 || b.as_bytes()[n - 4] != b'_')
            });
            if after_def && !matches!(t, Tok::Newline | Tok::Error) {
                let kind = match t {
                    Tok::Signal(_) => "a signal",
                    Tok::Pulse(_) => "a one-shot",
                    _ => "a keyword or symbol",
                };
                return Some(
                    Diagnostic::error(codes::RESERVED_NAME, file, span, format!("{what} is {kind}, not a name"))
                        .with_hint("a name is letters, digits and `_`, starts with a letter and must not look like a signal (U10K5), a one-shot (P2) or a keyword"),
                );
            }
            let mut hint = format!("expected {}", friendly(&expected));
            if let Some(s) = keyword_suggestion(text, l, &t) {
                hint = format!("{s} {hint}");
            }
            Diagnostic::error(codes::SYNTAX, file, span, format!("unexpected {what}"))
                .with_hint(hint)
        }
        ParseError::UnrecognizedEof { location, expected } => {
            let start = location.min(text.len());
            Diagnostic::error(
                codes::UNEXPECTED_EOF,
                file,
                start..start,
                "the file ends inside a statement",
            )
            .with_hint(format!("expected {}", friendly(&expected)))
        }
        ParseError::ExtraToken { token: (l, t, r) } => {
            let what = describe(text, l, &t, r);
            Diagnostic::error(codes::SYNTAX, file, l..r, format!("unexpected {what}"))
                .with_hint("one statement per line")
        }
        ParseError::InvalidToken { location } => {
            Diagnostic::error(codes::SYNTAX, file, location..location, "unreadable token")
                .with_hint("check the spelling")
        }
        ParseError::User { .. } => return None,
    })
}

/// An `IF` under construction.
struct Frame {
    cond: crate::ast::Expr,
    span: Span,
    then_body: Vec<Stmt>,
    else_body: Option<Vec<Stmt>>,
}

fn push(stack: &mut [Frame], top: &mut Vec<Stmt>, stmt: Stmt) {
    match stack.last_mut() {
        Some(f) => match &mut f.else_body {
            Some(e) => e.push(stmt),
            None => f.then_body.push(stmt),
        },
        None => top.push(stmt),
    }
}

/// Nests `IF` blocks and splits the program at the first `$` line.
fn nest(file: &str, lines: Vec<Line>, diags: &mut Vec<Diagnostic>) -> Program {
    let mut program = Program::default();
    let mut stack: Vec<Frame> = Vec::new();
    let mut in_slow = false;
    for line in lines {
        let top = if in_slow {
            &mut program.slow
        } else {
            &mut program.fast
        };
        match line {
            Line::Stmt(s) => push(&mut stack, top, *s),
            Line::If(cond, span) => stack.push(Frame {
                cond: *cond,
                span,
                then_body: Vec::new(),
                else_body: None,
            }),
            Line::Else(span) => match stack.last_mut() {
                Some(f) if f.else_body.is_none() => f.else_body = Some(Vec::new()),
                Some(_) => diags.push(
                    Diagnostic::error(
                        codes::ELSE_WITHOUT_IF,
                        file,
                        span,
                        "second `ELSE` in one `IF`",
                    )
                    .with_hint("an `IF` has at most one `ELSE`; close it with `END_IF` first"),
                ),
                None => diags.push(
                    Diagnostic::error(codes::ELSE_WITHOUT_IF, file, span, "`ELSE` without `IF`")
                        .with_hint("`ELSE` belongs between `IF … THEN` and `END_IF`"),
                ),
            },
            Line::EndIf(span) => match stack.pop() {
                Some(f) => {
                    let stmt = Stmt {
                        kind: StmtKind::If {
                            cond: f.cond,
                            then_body: f.then_body,
                            else_body: f.else_body.unwrap_or_default(),
                        },
                        span: f.span,
                    };
                    push(&mut stack, top, stmt);
                }
                None => diags.push(
                    Diagnostic::error(
                        codes::END_IF_WITHOUT_IF,
                        file,
                        span,
                        "`END_IF` without `IF`",
                    )
                    .with_hint("every `END_IF` closes an earlier `IF … THEN` line"),
                ),
            },
            Line::Dollar(span) => {
                if !stack.is_empty() {
                    diags.push(
                        Diagnostic::error(
                            codes::DOLLAR_IN_IF,
                            file,
                            span,
                            "`$` inside an `IF` block",
                        )
                        .with_hint("close the `IF` with `END_IF` before the `$` line"),
                    );
                } else if program.separator.is_none() {
                    program.separator = Some(span);
                    in_slow = true;
                }
            }
        }
    }
    // Close what is still open so that sema checks the statements inside; report each IF.
    while let Some(f) = stack.pop() {
        diags.push(
            Diagnostic::error(
                codes::IF_WITHOUT_END_IF,
                file,
                f.span.clone(),
                "`IF` without `END_IF`",
            )
            .with_hint("add an `END_IF` line after the block"),
        );
        let top = if in_slow {
            &mut program.slow
        } else {
            &mut program.fast
        };
        let stmt = Stmt {
            kind: StmtKind::If {
                cond: f.cond,
                then_body: f.then_body,
                else_body: f.else_body.unwrap_or_default(),
            },
            span: f.span,
        };
        push(&mut stack, top, stmt);
    }
    program
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ast::*;

    fn codes_of(src: &str) -> Vec<(u32, u32, u32)> {
        parse("t.plc", src)
            .1
            .iter()
            .map(|d| (d.code, d.line, d.column))
            .collect()
    }

    #[test]
    fn seed_fragments_parse_without_diagnostics() {
        let src = ";comment line\nU180K0=I0K2\nU170K7=/I1A29\nU10K5=U150N0*/I150N1\nU150N2=/U250N0+U250N0\n\
                   U150N0=[W3K0=91H]+U150N0*/[W3K0=90H]*/I0K1\nU10K10=I0K2*/U150N0\nP2=U100K0\nU100K0=P2\n$\n";
        let (p, d) = parse("t.plc", src);
        assert_eq!(d, vec![]);
        assert_eq!(p.fast.len(), 8);
        assert_eq!(p.slow.len(), 0);
        assert!(p.separator.is_some());
    }

    #[test]
    fn precedence_or_below_and_below_not() {
        let (p, d) = parse("t", "U1K0=I0K0+I0K1*/I0K2");
        assert_eq!(d, vec![]);
        let StmtKind::Assign { value, .. } = &p.fast[0].kind else {
            panic!("assignment expected")
        };
        let ExprKind::Binary(BinOp::Plus, _, rhs) = &value.kind else {
            panic!("+ at the top: {value:?}")
        };
        let ExprKind::Binary(BinOp::Star, _, not) = &rhs.kind else {
            panic!("* below +")
        };
        assert!(matches!(not.kind, ExprKind::Unary(UnOp::Slash, _)));
    }

    /// The value of the first statement as `(lhs op rhs)@start..end` with names and numbers as
    /// leaves (`op` as the `BinOp` debug name).
    fn tree(src: &str) -> String {
        fn show(e: &Expr, text: &str) -> String {
            match &e.kind {
                ExprKind::Binary(op, a, b) => format!(
                    "({} {op:?} {})@{}..{}",
                    show(a, text),
                    show(b, text),
                    e.span.start,
                    e.span.end
                ),
                _ => text[e.span.clone()].to_string(),
            }
        }
        let (p, d) = parse("t", src);
        assert_eq!(d, vec![], "{src}");
        let StmtKind::Assign { value, .. } = &p.fast[0].kind else {
            panic!("assignment expected")
        };
        show(value, src)
    }

    #[test]
    fn binary_operators_nest_by_precedence_left_to_right() {
        assert_eq!(tree("X=A-B-C"), "((A Minus B)@2..5 Minus C)@2..7");
        assert_eq!(
            tree("X=A+B*C-D"),
            "((A Plus (B Star C)@4..7)@2..7 Minus D)@2..9"
        );
        // Every tier, lowest first: each operator's right operand holds all the tighter ones.
        assert_eq!(
            tree("X=A OR B|C^D&E<<F+G XOR H*I"),
            "(A OrKw (B Pipe (C Caret (D Amp (E Shl (F Plus (G XorKw (H Star I)@24..27)@18..27)@16..27)@13..27)@11..27)@9..27)@7..27)@2..27"
        );
        // The same operators from tightest to loosest nest to the left.
        assert_eq!(
            tree("X=A*B XOR C+D>>E&F^G|H OR I"),
            "((((((((A Star B)@2..5 XorKw C)@2..11 Plus D)@2..13 Shr E)@2..16 Amp F)@2..18 Caret G)@2..20 Pipe H)@2..22 OrKw I)@2..27"
        );
        // A parenthesized operand: the node's span covers the parentheses, the operand's not.
        assert_eq!(tree("X=(A+B)*C"), "((A Plus B)@3..6 Star C)@2..9");
        assert_eq!(tree("X=(A+B)"), "(A Plus B)@3..6");
    }

    #[test]
    fn if_blocks_nest_and_split_fast_slow() {
        let src = "IF I0K0 THEN\nU1K0=1\nIF I0K1 THEN\nU1K1=1\nEND_IF\nELSE\nU1K2=1\nEND_IF\n$\nU1K3=I0K3\n";
        let (p, d) = parse("t", src);
        assert_eq!(d, vec![]);
        assert_eq!(p.fast.len(), 1);
        let StmtKind::If {
            then_body,
            else_body,
            ..
        } = &p.fast[0].kind
        else {
            panic!("IF expected")
        };
        assert_eq!(then_body.len(), 2);
        assert_eq!(else_body.len(), 1);
        assert_eq!(p.slow.len(), 1);
    }

    #[test]
    fn every_bad_line_is_reported_and_the_rest_parses() {
        let src = "U1K0=\nU1K1==I0K0\nU1K2=I0K0\nU1K3=I0K0 I0K1\nU1K4=§\n";
        let (p, d) = parse("t", src);
        // Line 1 continues onto line 2 (ends with `=`), so the first error is on line 2.
        assert_eq!(
            d.iter()
                .map(|d| (d.code, d.line, d.column))
                .collect::<Vec<_>>(),
            vec![(1001, 5, 6), (1003, 2, 5), (1003, 4, 11)]
        );
        assert_eq!(
            p.fast
                .iter()
                .filter(|s| matches!(s.kind, StmtKind::Assign { .. }))
                .count(),
            1
        );
    }

    #[test]
    fn block_structure_errors() {
        assert_eq!(
            codes_of("ELSE\nEND_IF\nIF I0K0 THEN\nU1K0=1\n"),
            vec![(1006, 1, 1), (1007, 2, 1), (1008, 3, 1)]
        );
        assert_eq!(codes_of("IF I0K0 THEN\n$\nEND_IF\n"), vec![(1009, 2, 1)]);
        assert_eq!(
            codes_of("U1K0=1\n$\nU1K1=1\n$\nU1K2=1\ngarbage ]]\n"),
            vec![(1005, 5, 1)]
        );
    }

    #[test]
    fn eof_inside_brackets() {
        assert_eq!(codes_of("U1K0=(I0K0"), vec![(1003, 1, 11)]);
    }

    #[test]
    fn names_that_look_like_signals_or_keywords() {
        assert_eq!(
            codes_of("DEF U10K5 = I0K0\nDEF P2 : BOOL\ndef THEN : BOOL\nDEF X = 5"),
            vec![(1202, 1, 5), (1202, 2, 5), (1202, 3, 5), (1003, 4, 9)]
        );
    }
}
