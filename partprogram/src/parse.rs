//! Front end: lexes and parses one file and hands its items on to the block grouping ([`crate::group`])
//! chunk by chunk, so that the items of a whole file never exist at once.
//!
//! MEFI blocks run from one `N` to the next (a block may span several lines); Fanuc blocks end at the
//! end of the line or at `;`. Everything before the first `%` (MEFI) is a preamble and is ignored; a
//! MEFI file that starts with `$PC` is a fixed-cycle file. Problems become located diagnostics; the
//! parser never panics and always returns what it could read.

use diag::{Diagnostic, Sink};
use lalrpop_util::ParseError;

use crate::ast::{Block, ParsedFile};
use crate::codes;
use crate::group::Grouper;
use crate::lexer::{LexErrorKind, Lexer, Tok};
use crate::machine::Dialect;

/// The LALRPOP parser, generated from `src/grammar.lalrpop` into `src/grammar.rs` by
/// `scripts/gen-parsers.sh` and committed (the e2e test `generated_parsers` checks the grammar's hash in its header).
#[rustfmt::skip]
#[path = "grammar.rs"]
#[allow(clippy::all, clippy::unwrap_used, unused, missing_docs, unused_qualifications)]
mod grammar;

/// Largest magnitude of a stored parameter count (±69999.999).
pub const R_MAX: i64 = 69_999_999;

/// Parses `src` (the text of `file`) in `dialect`; the diagnostics come in source order.
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
    parse_chunked(dialect, file, src, require_header, CHUNK_TOKENS)
}

/// [`parse_with`] with chunks of about `chunk_tokens` tokens (the tests compare chunk sizes).
fn parse_chunked(
    dialect: Dialect,
    file: &str,
    src: &str,
    require_header: bool,
    chunk_tokens: usize,
) -> (ParsedFile, Vec<Diagnostic>) {
    let mut sink = Sink::unbounded();
    let mut blocks = Vec::new();
    let mut out = parse_unlocated(
        dialect,
        file,
        src,
        require_header,
        chunk_tokens,
        &mut Out::new(&mut sink, &mut |p, _| {
            if let Piece::Block(b) = p {
                blocks.push(b)
            }
        }),
    );
    // Without the spare room of the last doubling: the blocks live as long as the compile.
    blocks.shrink_to_fit();
    out.blocks = blocks;
    // Located in one pass at the end: scanning the text per diagnostic is quadratic (issue 12).
    let mut diags = sink.into_vec();
    let offsets: Vec<usize> = diags.iter().map(|d| d.span.start).collect();
    for (d, (line, column)) in diags.iter_mut().zip(diag::line_columns(src, &offsets)) {
        (d.line, d.column) = (line, column);
    }
    // In source order (stable: diagnostics at one place keep the order they were found in), the
    // order `compile` reports them in, whatever the chunks the parser read.
    diags.sort_by_key(|d| d.span.start);
    (out, diags)
}

/// [`parse`] with the diagnostics pushed into `diags` (a sink that may store only the first of
/// them), marked to be located by [`crate::program::compile`] once it knows which it keeps, and
/// every block (and Fanuc program start) handed to `block` as soon as it is complete, in file
/// order, with the sink as it is then ([`ParsedFile::blocks`] stays empty); `require_header`: a
/// MEFI file must start with `%` (a macro file without one starts at its first byte).
pub(crate) fn parse_streaming(
    dialect: Dialect,
    file: &str,
    src: &str,
    require_header: bool,
    diags: &mut Sink,
    block: &mut dyn FnMut(Piece, &Sink),
) -> ParsedFile {
    parse_unlocated(
        dialect,
        file,
        src,
        require_header,
        CHUNK_TOKENS,
        &mut Out::new(diags, block),
    )
}

/// What the parser hands on as it reads a file, in file order.
pub(crate) enum Piece {
    /// A finished block.
    Block(Block),
    /// Fanuc: the `O<n>` naming the file's first program ([`ParsedFile::number`]), before its
    /// first block.
    Number(u32),
    /// Fanuc: an `O<n>` starting a further program of the file ([`ParsedFile::programs`]); the
    /// blocks after it belong to it.
    Program(u32),
}

/// Where the parser's diagnostics go (a sink, each marked to be located at the end, locating only
/// the ones kept) and where its blocks and program starts go (a callback, given the sink as it is
/// then).
pub(crate) struct Out<'a> {
    sink: &'a mut Sink,
    block: &'a mut dyn FnMut(Piece, &Sink),
}

impl<'a> Out<'a> {
    /// Diagnostics into `sink`, blocks and program starts to `block`.
    pub(crate) fn new(sink: &'a mut Sink, block: &'a mut dyn FnMut(Piece, &Sink)) -> Self {
        Out { sink, block }
    }

    /// Pushes `d`, to be located at the end.
    pub(crate) fn push(&mut self, d: Diagnostic) {
        self.sink.push(crate::program::to_locate(d));
    }

    /// Hands on the finished block `b`.
    pub(crate) fn emit(&mut self, b: Block) {
        (self.block)(Piece::Block(b), self.sink);
    }

    /// Hands on a program start (Fanuc `O<n>`).
    pub(crate) fn piece(&mut self, p: Piece) {
        (self.block)(p, self.sink);
    }
}

/// Tokens the parser reads in one call: at most about [`CHUNK_TOKENS`] of them, ending where one
/// item ends and the next begins, so that the items of the file are handed on chunk by chunk.
///
/// A chunk ends before token `t` only when the token before it ends every item it can be part of
/// (`%`, `*`, `/`, an end of block, a comment, a `$PC` header, a lexer error or a number) and `t`
/// is not `=` (the one token that continues an item after a number: `R1=5`). Every other token
/// starts an item there, so the parser, which reduces the same way on such a `t` as on the end of
/// the input, reads the same items with the same errors as when it reads the whole file at once.
struct Chunk<'l, 'a> {
    lexer: &'l mut Lexer<'a>,
    /// The token that ended the previous chunk: the first of the next one.
    pending: Option<(usize, Tok, usize)>,
    /// Tokens handed out in this chunk.
    count: usize,
    /// Tokens after which the chunk may end.
    max: usize,
    /// True when the last token handed out ends every item it can be part of.
    at_item_end: bool,
    /// True once the lexer is exhausted.
    ended: bool,
    /// True from the end of a chunk until the next call of the parser: the end of input stays put.
    paused: bool,
}

/// Tokens after which a chunk may end (thousands of items: the parser's call overhead is negligible,
/// the items of one chunk a few hundred kilobytes at most).
const CHUNK_TOKENS: usize = 4096;

impl Iterator for Chunk<'_, '_> {
    type Item = Result<(usize, Tok, usize), crate::lexer::LexError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.paused || self.ended {
            return None;
        }
        let tok = match self.pending.take() {
            Some(t) => t,
            None => match self.lexer.next() {
                Some(Ok(t)) => t,
                Some(Err(e)) => return Some(Err(e)),
                None => {
                    self.ended = true;
                    return None;
                }
            },
        };
        if self.count >= self.max && self.at_item_end && tok.1 != Tok::Eq {
            self.pending = Some(tok);
            self.paused = true;
            return None;
        }
        self.count += 1;
        self.at_item_end = matches!(
            tok.1,
            Tok::Percent
                | Tok::Star
                | Tok::Slash
                | Tok::Eob
                | Tok::Comment
                | Tok::CycleHeader
                | Tok::LexError
                | Tok::Num(_)
        );
        Some(Ok(tok))
    }
}

/// [`parse_with`] with line and column of the diagnostics not yet filled in. The items are grouped
/// into blocks chunk by chunk as the parser reads them, and each block is handed on through
/// `diags` ([`Out::emit`]) once complete: what is held besides the text is one chunk of items
/// (see [`Chunk`]) and what the receiver of the blocks keeps.
fn parse_unlocated(
    dialect: Dialect,
    file: &str,
    src: &str,
    require_header: bool,
    chunk_tokens: usize,
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
    // Fanuc Macro B blocks are read by `macro_b::syntax`; the lexer steps over them as if they
    // were blank text, and the grouping reads each where the items reach it.
    let pieces = if dialect == Dialect::Fanuc {
        crate::macro_b::syntax::prepass(src)
    } else {
        Vec::new()
    };
    let mut lexer = if dialect == Dialect::Fanuc {
        Lexer::skipping(src, &pieces)
    } else {
        Lexer::new(dialect, src, start)
    };
    let mut group = Grouper::new(dialect, require_header, &pieces);
    let parser = grammar::ItemsParser::new();
    let mut recovered = Vec::new();
    let mut chunk = Chunk {
        lexer: &mut lexer,
        pending: None,
        count: 0,
        max: chunk_tokens,
        at_item_end: false,
        ended: false,
        paused: false,
    };
    loop {
        chunk.count = 0;
        chunk.paused = false;
        let result = parser.parse(&mut recovered, &mut chunk);
        for e in chunk.lexer.errors.drain(..) {
            let msg = match e.kind {
                LexErrorKind::BadChar => {
                    let text = src.get(e.span.clone()).unwrap_or("?");
                    format!("`{text}` is not allowed here")
                }
                LexErrorKind::BadNumber => "number too long".to_string(),
            };
            diags.push(
                Diagnostic::error(codes::BAD_CHAR, file, e.span, msg)
                    .with_hint(match dialect {
                        Dialect::Mefi => "outside `\"…\"` comments only upper-case addresses, digits, signs, `.`, `%`, `/`, `=`, `&` and `*` are allowed; a sign must touch its digits",
                        Dialect::Fanuc => "outside `( … )` comments only addresses, digits, signs and `.` are allowed",
                    }),
            );
        }
        for r in recovered.drain(..) {
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
        for item in items {
            group.feed(file, src, item, &mut out, diags);
        }
        if chunk.ended || chunk.pending.is_none() {
            break;
        }
    }
    group.finish(file, src, diags);
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
    let (meant, known) = crate::process_words::instruction_meant(&run)?;
    let lead = if known {
        format!("`{meant}`")
    } else {
        format!("did you mean `{meant}`? That")
    };
    Some(format!(
        "{lead} is an instruction of the process logic (PGCFIL), not a partprogram word; a block holds words of one address letter and a number"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Texts whose items end at awkward places: words split by errors, `=` after a number,
    /// a `%` whose number is in the next chunk, lexer errors next to numbers, `*`, macro blocks.
    const TRICKY: &[&str] = &[
        "%\n5 N1 X1. X= 5 R1=5 R2= X R3=R4 N R5 = = 7 / 9 N2 X1.2.3 Y\n",
        "% 35\nN1 G01 X1 Y2 F100.\nN2 R1=2.5 R2=99999999999 R96=1 G26 R5=01020304\nN3 X R\nN4 M30\n* N5 X1\n",
        "%12\n/ 4 N1 X1 / N2 /Y2 ? N3 X1?2 Z-- 1 X- 2 \"comment\" N4 \"open\nN5 M02\n",
        "$PC cycles\nN1 G79 L81 X1 N2 G70\n%\n%3\n",
        "G01 X1. F100.\nG01 Q1.\n%\nG01 X1. F100.\nG01 Q1.\n",
        "O0023\nN1 G01 X1. (c) Y2; N2 X3\n#1=[#2+1]\nIF [#1 GT 2] GOTO 10\nR1=5\nX1. 5 / 6\nN10 O12 M30\nO0024\nG0 X0 #3=1\nN-1 WHILE [#1 LT 3] DO1\nEND1\n",
        "N1 X1 X2 X3 X4 X5 X6 X7 X8 X9 =\n= 1 = 2 R R R 1 = 2 = 3 %\n",
    ];

    #[test]
    fn chunked_parsing_reads_what_the_whole_file_gives() {
        let mut texts: Vec<String> = TRICKY.iter().map(|t| t.to_string()).collect();
        let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
        for dir in [
            "plc-programs/lathe/nc",
            "plc-programs/mill/nc",
            "fuzz/seeds/partprogram",
        ] {
            let Ok(rd) = std::fs::read_dir(format!("{root}/{dir}")) else {
                continue;
            };
            for e in rd.flatten() {
                if let Ok(b) = std::fs::read(e.path()) {
                    texts.push(String::from_utf8_lossy(&b).into_owned());
                }
            }
        }
        assert!(
            texts.len() > 20,
            "the programs of the repository were found"
        );
        for text in &texts {
            for dialect in [Dialect::Mefi, Dialect::Fanuc] {
                for header in [true, false] {
                    let whole = parse_chunked(dialect, "F", text, header, usize::MAX);
                    for n in [1, 2, 3, 5, 8] {
                        let chunked = parse_chunked(dialect, "F", text, header, n);
                        assert_eq!(chunked, whole, "chunks of {n}, {dialect:?}, text:\n{text}");
                    }
                }
            }
        }
    }

    #[test]
    fn chunks_end_only_between_items() {
        // With chunks of one token, every token after a number or a one-token item starts a chunk;
        // `R1=5` stays one declaration and `X R2` one word.
        let (out, diags) = parse_chunked(Dialect::Mefi, "F", "%1\nN1 R1=5 X R2 Y3\n", true, 1);
        assert_eq!(out.number, Some(1));
        assert_eq!(out.blocks.len(), 1);
        assert_eq!(out.blocks[0].decls.len(), 1);
        let words: Vec<char> = out.blocks[0].words.iter().map(|w| w.addr).collect();
        assert_eq!(words, ['X', 'Y']);
        // Only the missing M02/M30 would be reported, later: the parse itself is clean.
        assert!(diags.is_empty(), "{diags:?}");
    }
}
