//! The lexer: source bytes → decoded text → tokens with byte spans, and the line rules.
//!
//! PLC sources come from DOS/Windows controllers: comments may hold CP866 or CP1251 bytes. The
//! front end therefore works on a *decoded* text ([`decode_source`]): valid UTF-8 is kept as it is,
//! anything else is decoded one byte → one character (CP866 or CP1251, whichever the bytes look
//! like). Every span and every diagnostic refers to that decoded text, and because a legacy byte
//! becomes exactly one character, columns still count the file's bytes.
//!
//! [`tokenize`] runs the logos DFA and applies the line rules of docs/plc-language.md §2: a newline ends a
//! statement unless a `(` or `[` is open or the line ends with a binary operator, `/`, `=`, `,` or
//! `:=`. Blank lines disappear. Lexer errors become [`Tok::Error`] tokens (so the parser's `!`
//! recovery can resynchronise) and are also returned as [`LexError`]s.

use logos::Logos;
use packets::Packet;

/// Decodes a PLC source file: UTF-8 when it is valid UTF-8, otherwise one character per byte in
/// CP866 or CP1251 (chosen by which one makes more Cyrillic lowercase letters).
pub fn decode_source(bytes: &[u8]) -> String {
    if let Ok(text) = std::str::from_utf8(bytes) {
        // A UTF-8 byte-order mark is not part of the program (editors do not count it either).
        return text.strip_prefix('\u{FEFF}').unwrap_or(text).to_string();
    }
    let cp866_lower = bytes
        .iter()
        .filter(|&&b| (0xA0..=0xAF).contains(&b))
        .count();
    let cp1251_letters = bytes.iter().filter(|&&b| b >= 0xC0).count();
    let table: Vec<char> = if cp866_lower > cp1251_letters {
        CP866_HIGH.chars().collect()
    } else {
        CP1251_HIGH.chars().collect()
    };
    bytes
        .iter()
        .map(|&b| {
            if b < 0x80 {
                char::from(b)
            } else {
                table
                    .get(usize::from(b - 0x80))
                    .copied()
                    .unwrap_or('\u{FFFD}')
            }
        })
        .collect()
}

/// A text with its [`diag::LineIndex`], for turning byte offsets into 1-based line and column
/// quickly (`diag::line_column` scans from the start of the text, too slow for thousands of lookups).
#[derive(Debug, Clone)]
pub struct LineIndex<'a> {
    text: &'a str,
    index: diag::LineIndex,
}

impl<'a> LineIndex<'a> {
    /// Indexes `text`.
    pub fn new(text: &'a str) -> Self {
        LineIndex {
            text,
            index: diag::LineIndex::new(text),
        }
    }

    /// 1-based line and column (in characters) of byte `offset`, as `diag::line_column` gives them.
    pub fn line_column(&self, offset: usize) -> (u32, u32) {
        self.index.line_column(self.text, offset)
    }

    /// Fills a diagnostic's line and column from its span.
    pub fn locate(&self, d: diag::Diagnostic) -> diag::Diagnostic {
        d.locate_in(self.text, &self.index)
    }
}

/// Characters of bytes 0x80..=0xFF in code page 866 (DOS Cyrillic).
const CP866_HIGH: &str = concat!(
    "АБВГДЕЖЗИЙКЛМНОПРСТУФХЦЧШЩЪЫЬЭЮЯ",
    "абвгдежзийклмноп",
    "░▒▓│┤╡╢╖╕╣║╗╝╜╛┐└┴┬├─┼╞╟╚╔╩╦╠═╬╧╨╤╥╙╘╒╓╫╪┘┌█▄▌▐▀",
    "рстуфхцчшщъыьэюя",
    "ЁёЄєЇїЎў°∙·√№¤■\u{A0}",
);

/// Characters of bytes 0x80..=0xFF in code page 1251 (Windows Cyrillic); 0x98 is unassigned.
const CP1251_HIGH: &str = concat!(
    "ЂЃ‚ѓ„…†‡€‰Љ‹ЊЌЋЏ",
    "ђ‘’“”•–—\u{98}™љ›њќћџ",
    "\u{A0}ЎўЈ¤Ґ¦§Ё©Є«¬\u{AD}®Ї",
    "°±Ііґµ¶·ё№є»јЅѕї",
    "АБВГДЕЖЗИЙКЛМНОПРСТУФХЦЧШЩЪЫЬЭЮЯ",
    "абвгдежзийклмнопрстуфхцчшщъыьэюя",
);

/// What went wrong in one token.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LexErrorKind {
    /// A character that starts no token (outside comments only ASCII is allowed).
    #[default]
    InvalidChar,
    /// A numeric literal whose value does not fit 32 bits (or a signal number that large).
    NumberTooLarge,
}

/// A lexer error with its span in the decoded text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LexError {
    /// What went wrong.
    pub kind: LexErrorKind,
    /// Byte span in the decoded text.
    pub span: std::ops::Range<usize>,
}

/// The letter before a signal's digits: `I`, `U`, `W` or `S`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SignalKind {
    /// `I<c><P><n>`, an input bit.
    I,
    /// `U<c><P><n>`, an output bit.
    U,
    /// `W<c><P><b>`, a byte of a connector.
    W,
    /// `S<P><B>`, a byte by linear index.
    S,
}

/// A signal name as written, numbers not yet range-checked (sema checks the limits).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct RawSignal {
    /// The leading letter.
    pub kind: SignalKind,
    /// Connector (0 for `S`).
    pub connector: u32,
    /// The packet.
    pub packet: Packet,
    /// Contact (I/U), byte in connector (W) or linear byte (S).
    pub number: u32,
}

/// One token. Letters are case-insensitive; identifiers keep their spelling (sema upper-cases them).
#[derive(Logos, Debug, Clone, PartialEq)]
#[logos(error = LexErrorKind)]
#[logos(skip r"[ \t\r\x0c\x1a]+")]
#[logos(skip(r";[^\n]*", allow_greedy = true))]
pub enum Tok<'a> {
    /// End of a statement line (only emitted when the line rules say the statement ends).
    #[regex(r"\n")]
    Newline,
    /// `I…`, `U…`, `W…` or `S…` signal name.
    #[regex(r"[IiUuWw][0-9]+[AaKkNnTt][0-9]+", signal, priority = 10)]
    #[regex(r"[Ss][AaKkNnTt][0-9]+", sys_signal, priority = 10)]
    Signal(RawSignal),
    /// `P<n>` one-shot.
    #[regex(r"[Pp][0-9]+", pulse, priority = 10)]
    Pulse(u32),
    /// Decimal or `H`-suffixed hexadecimal integer.
    #[regex(r"[0-9]+", decimal)]
    #[regex(r"[0-9][0-9A-Fa-f]*[Hh]", hex)]
    Int(u32),
    /// Real literal `2.5`.
    #[regex(r"[0-9]+\.[0-9]+", real)]
    Real(f64),
    /// Duration in milliseconds: `500ms`, `2s`, `1.5s`.
    #[regex(r"[0-9]+(\.[0-9]+)?([Mm][Ss]|[Ss])", duration)]
    Duration(f64),
    /// A name.
    #[regex(r"[A-Za-z][A-Za-z0-9_]*")]
    Ident(&'a str),
    /// `DEF`
    #[token("DEF", ignore(case))]
    Def,
    /// `AT`
    #[token("AT", ignore(case))]
    At,
    /// `RETAIN`
    #[token("RETAIN", ignore(case))]
    Retain,
    /// `SET`
    #[token("SET", ignore(case))]
    Set,
    /// `RES`
    #[token("RES", ignore(case))]
    Res,
    /// `IF`
    #[token("IF", ignore(case))]
    If,
    /// `THEN`
    #[token("THEN", ignore(case))]
    Then,
    /// `ELSE`
    #[token("ELSE", ignore(case))]
    Else,
    /// `END_IF`
    #[token("END_IF", ignore(case))]
    EndIf,
    /// `OR`
    #[token("OR", ignore(case))]
    OrKw,
    /// `AND`
    #[token("AND", ignore(case))]
    AndKw,
    /// `NOT`
    #[token("NOT", ignore(case))]
    NotKw,
    /// `XOR`
    #[token("XOR", ignore(case))]
    XorKw,
    /// `MOD`
    #[token("MOD", ignore(case))]
    Mod,
    /// `TRUE`
    #[token("TRUE", ignore(case))]
    True,
    /// `FALSE`
    #[token("FALSE", ignore(case))]
    False,
    /// `=`
    #[token("=")]
    Eq,
    /// `<>`
    #[token("<>")]
    Ne,
    /// `<`
    #[token("<")]
    Lt,
    /// `<=`
    #[token("<=")]
    Le,
    /// `>`
    #[token(">")]
    Gt,
    /// `>=`
    #[token(">=")]
    Ge,
    /// `[`
    #[token("[")]
    LBracket,
    /// `]`
    #[token("]")]
    RBracket,
    /// `(`
    #[token("(")]
    LParen,
    /// `)`
    #[token(")")]
    RParen,
    /// `+`
    #[token("+")]
    Plus,
    /// `-`
    #[token("-")]
    Minus,
    /// `*`
    #[token("*")]
    Star,
    /// `/`
    #[token("/")]
    Slash,
    /// `&`
    #[token("&")]
    Amp,
    /// `|`
    #[token("|")]
    Pipe,
    /// `^`
    #[token("^")]
    Caret,
    /// `~`
    #[token("~")]
    Tilde,
    /// `<<`
    #[token("<<")]
    Shl,
    /// `>>`
    #[token(">>")]
    Shr,
    /// `,`
    #[token(",")]
    Comma,
    /// `:`
    #[token(":")]
    Colon,
    /// `:=`
    #[token(":=")]
    Assign,
    /// `.`
    #[token(".")]
    Dot,
    /// `$`
    #[token("$")]
    Dollar,
    /// Stand-in for text the lexer could not read; never produced by logos itself.
    Error,
}

fn number(digits: &str, radix: u32) -> Result<u32, LexErrorKind> {
    let digits = digits.trim_start_matches('0');
    if digits.is_empty() {
        return Ok(0);
    }
    u32::from_str_radix(digits, radix).map_err(|_| LexErrorKind::NumberTooLarge)
}

fn decimal<'a>(lex: &mut logos::Lexer<'a, Tok<'a>>) -> Result<u32, LexErrorKind> {
    number(lex.slice(), 10)
}

fn hex<'a>(lex: &mut logos::Lexer<'a, Tok<'a>>) -> Result<u32, LexErrorKind> {
    let s = lex.slice();
    number(&s[..s.len() - 1], 16)
}

fn real<'a>(lex: &mut logos::Lexer<'a, Tok<'a>>) -> Result<f64, LexErrorKind> {
    lex.slice()
        .parse()
        .map_err(|_| LexErrorKind::NumberTooLarge)
}

fn duration<'a>(lex: &mut logos::Lexer<'a, Tok<'a>>) -> Result<f64, LexErrorKind> {
    let s = lex.slice().to_ascii_lowercase();
    let (num, scale) = match s.strip_suffix("ms") {
        Some(n) => (n, 1.0),
        None => (s.trim_end_matches('s'), 1000.0),
    };
    let v: f64 = num.parse().map_err(|_| LexErrorKind::NumberTooLarge)?;
    Ok(v * scale)
}

fn pulse<'a>(lex: &mut logos::Lexer<'a, Tok<'a>>) -> Result<u32, LexErrorKind> {
    number(&lex.slice()[1..], 10)
}

fn signal<'a>(lex: &mut logos::Lexer<'a, Tok<'a>>) -> Result<RawSignal, LexErrorKind> {
    let s = lex.slice();
    let kind = match s.as_bytes()[0].to_ascii_uppercase() {
        b'I' => SignalKind::I,
        b'U' => SignalKind::U,
        _ => SignalKind::W,
    };
    let body = &s[1..];
    let p = body
        .find(|c: char| c.is_ascii_alphabetic())
        .ok_or(LexErrorKind::InvalidChar)?;
    let packet = body[p..]
        .chars()
        .next()
        .and_then(Packet::from_letter)
        .ok_or(LexErrorKind::InvalidChar)?;
    Ok(RawSignal {
        kind,
        connector: number(&body[..p], 10)?,
        packet,
        number: number(&body[p + 1..], 10)?,
    })
}

fn sys_signal<'a>(lex: &mut logos::Lexer<'a, Tok<'a>>) -> Result<RawSignal, LexErrorKind> {
    let s = lex.slice();
    let packet = s[1..]
        .chars()
        .next()
        .and_then(Packet::from_letter)
        .ok_or(LexErrorKind::InvalidChar)?;
    Ok(RawSignal {
        kind: SignalKind::S,
        connector: 0,
        packet,
        number: number(&s[2..], 10)?,
    })
}

/// A token with its byte span `(start, token, end)`, the triple LALRPOP's external lexer expects.
pub type Spanned<'a> = (usize, Tok<'a>, usize);

impl Tok<'_> {
    /// True for tokens after which a line break continues the statement.
    fn continues_line(&self) -> bool {
        matches!(
            self,
            Tok::Eq
                | Tok::Ne
                | Tok::Lt
                | Tok::Le
                | Tok::Gt
                | Tok::Ge
                | Tok::Plus
                | Tok::Minus
                | Tok::Star
                | Tok::Slash
                | Tok::Amp
                | Tok::Pipe
                | Tok::Caret
                | Tok::Tilde
                | Tok::Shl
                | Tok::Shr
                | Tok::Comma
                | Tok::Assign
                | Tok::OrKw
                | Tok::AndKw
                | Tok::NotKw
                | Tok::XorKw
                | Tok::Mod
        )
    }

    /// True for keywords that can only start a line: a line break before one of them always ends
    /// the statement, even inside an unclosed bracket (limits the damage of a missing `)`).
    fn starts_line(&self) -> bool {
        matches!(
            self,
            Tok::Def | Tok::If | Tok::Else | Tok::EndIf | Tok::Set | Tok::Res | Tok::Dollar
        )
    }
}

/// Tokenizes decoded source text and applies the line rules; returns the tokens (ending with a
/// [`Tok::Newline`] when there is any token) and the lexer errors.
pub fn tokenize(text: &str) -> (Vec<Spanned<'_>>, Vec<LexError>) {
    let mut lexer = Lexer::new(text);
    let mut out: Vec<Spanned<'_>> = Vec::with_capacity(text.len() / 3);
    out.extend(lexer.by_ref());
    (out, lexer.errors)
}

/// A logos result with its span.
type Raw<'a> = (Result<Tok<'a>, LexErrorKind>, std::ops::Range<usize>);

/// The streaming form of [`tokenize`]: yields the same tokens one at a time and collects the
/// lexer errors as it goes, so that the parser can stop early on a file that is not a PLC program
/// without tokenizing (and keeping) the rest of it.
pub struct Lexer<'a> {
    lex: logos::Lexer<'a, Tok<'a>>,
    text_len: usize,
    /// The lexer errors of the tokens yielded so far (a run of invalid characters is one error).
    pub errors: Vec<LexError>,
    /// Open `(`/`[` of the current statement.
    depth: u32,
    /// A newline seen inside brackets: emitted only if the next token starts a new line.
    held_newline: Option<usize>,
    /// Nothing yielded yet, or the last token yielded was a newline.
    at_line_start: bool,
    /// The last token yielded continues the statement over a line break.
    last_continues: bool,
    /// A logos result read ahead while merging a run of invalid characters.
    peeked: Option<Raw<'a>>,
    /// A token to yield after the held newline that precedes it.
    queued: Option<Spanned<'a>>,
}

impl<'a> Lexer<'a> {
    /// A lexer at the start of `text`.
    pub fn new(text: &'a str) -> Self {
        Lexer {
            lex: Tok::lexer(text),
            text_len: text.len(),
            errors: Vec::new(),
            depth: 0,
            held_newline: None,
            at_line_start: true,
            last_continues: false,
            peeked: None,
            queued: None,
        }
    }

    fn next_raw(&mut self) -> Option<Raw<'a>> {
        self.peeked
            .take()
            .or_else(|| self.lex.next().map(|r| (r, self.lex.span())))
    }

    /// The next logos token, with a run of adjacent invalid characters of one kind merged into
    /// one [`Tok::Error`] (recorded in [`Lexer::errors`]).
    fn raw(&mut self) -> Option<Spanned<'a>> {
        let (result, span) = self.next_raw()?;
        let kind = match result {
            Ok(t) => return Some((span.start, t, span.end)),
            Err(kind) => kind,
        };
        let mut end = span.end;
        loop {
            match self.next_raw() {
                Some((Err(k), s)) if k == kind && s.start == end => end = s.end,
                other => {
                    self.peeked = other;
                    break;
                }
            }
        }
        self.errors.push(LexError {
            kind,
            span: span.start..end,
        });
        Some((span.start, Tok::Error, end))
    }

    fn emit(&mut self, t: Spanned<'a>) -> Spanned<'a> {
        self.at_line_start = t.1 == Tok::Newline;
        self.last_continues = t.1.continues_line();
        t
    }
}

impl<'a> Iterator for Lexer<'a> {
    type Item = Spanned<'a>;

    fn next(&mut self) -> Option<Spanned<'a>> {
        if let Some(t) = self.queued.take() {
            return Some(self.emit(t));
        }
        loop {
            let Some((start, tok, end)) = self.raw() else {
                if self.at_line_start {
                    return None;
                }
                let n = self.text_len;
                return Some(self.emit((n, Tok::Newline, n)));
            };
            if tok == Tok::Newline {
                let ends = !self.at_line_start && !self.last_continues;
                if ends && self.depth == 0 {
                    return Some(self.emit((start, Tok::Newline, end)));
                } else if ends && self.held_newline.is_none() {
                    self.held_newline = Some(start);
                }
                continue;
            }
            match tok {
                Tok::LParen | Tok::LBracket => self.depth += 1,
                Tok::RParen | Tok::RBracket => self.depth = self.depth.saturating_sub(1),
                _ => {}
            }
            if let Some(at) = self.held_newline.take().filter(|_| tok.starts_line()) {
                self.depth = 0;
                self.queued = Some((start, tok, end));
                return Some(self.emit((at, Tok::Newline, at + 1)));
            }
            return Some(self.emit((start, tok, end)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn toks(s: &str) -> Vec<Tok<'_>> {
        tokenize(s).0.into_iter().map(|(_, t, _)| t).collect()
    }

    #[test]
    fn line_index_agrees_with_diag() {
        let text = "ab\nдве\n\nx\u{FFFD}y\n";
        let index = LineIndex::new(text);
        for at in 0..=text.len() + 2 {
            assert_eq!(
                index.line_column(at),
                diag::line_column(text, at),
                "offset {at}"
            );
        }
    }

    #[test]
    fn code_page_tables_have_128_characters() {
        assert_eq!(CP866_HIGH.chars().count(), 128);
        assert_eq!(CP1251_HIGH.chars().count(), 128);
    }

    #[test]
    fn legacy_bytes_decode_one_character_each() {
        // "Привет" in CP1251 and CP866.
        let cp1251 = b";\xcf\xf0\xe8\xe2\xe5\xf2\nU1K0=I0K0";
        assert_eq!(decode_source(cp1251), ";Привет\nU1K0=I0K0");
        let cp866 = b";\x8f\xe0\xa8\xa2\xa5\xe2";
        assert_eq!(decode_source(cp866), ";Привет");
        assert_eq!(decode_source("\u{FEFF}U1K0=1".as_bytes()), "U1K0=1");
    }

    #[test]
    fn seed_line_tokens() {
        let sig = |kind, connector, packet, number| {
            Tok::Signal(RawSignal {
                kind,
                connector,
                packet,
                number,
            })
        };
        assert_eq!(
            toks("U150N0=[W3K0=91H]+u150n0*/I150N1 ; комментарий"),
            vec![
                sig(SignalKind::U, 150, Packet::N, 0),
                Tok::Eq,
                Tok::LBracket,
                sig(SignalKind::W, 3, Packet::K, 0),
                Tok::Eq,
                Tok::Int(0x91),
                Tok::RBracket,
                Tok::Plus,
                sig(SignalKind::U, 150, Packet::N, 0),
                Tok::Star,
                Tok::Slash,
                sig(SignalKind::I, 150, Packet::N, 1),
                Tok::Newline,
            ]
        );
        assert_eq!(
            toks("P2=SK1023"),
            vec![
                Tok::Pulse(2),
                Tok::Eq,
                sig(SignalKind::S, 0, Packet::K, 1023),
                Tok::Newline
            ]
        );
    }

    #[test]
    fn literals_and_keywords() {
        assert_eq!(
            toks("def x : dint := 0FFH 2.5 500ms 1.5s end_if"),
            vec![
                Tok::Def,
                Tok::Ident("x"),
                Tok::Colon,
                Tok::Ident("dint"),
                Tok::Assign,
                Tok::Int(255),
                Tok::Real(2.5),
                Tok::Duration(500.0),
                Tok::Duration(1500.0),
                Tok::EndIf,
                Tok::Newline
            ]
        );
    }

    #[test]
    fn line_continuation_rules() {
        // Operator at the end of the line, open parenthesis, blank lines.
        assert_eq!(
            toks("\n\nU1K0=I0K0+\n I0K1\n\nU1K1=(I0K0\n*I0K1)\n"),
            toks("U1K0=I0K0+I0K1\nU1K1=(I0K0*I0K1)\n")
        );
        // A comment after the operator does not end the statement.
        assert_eq!(
            toks("U1K0=I0K0+ ; more below\nI0K1"),
            toks("U1K0=I0K0+I0K1")
        );
        // A keyword that starts a line ends an unclosed bracket's statement.
        let t = toks("U1K0=(I0K0\nDEF x : BOOL\n");
        assert_eq!(t.iter().filter(|t| **t == Tok::Newline).count(), 2);
    }

    #[test]
    fn errors_are_tokens_and_runs_merge() {
        let (t, e) = tokenize("U1K0=I0K0 §§ I0K1\nP99999999999=1");
        assert_eq!(e.len(), 2);
        assert_eq!(e[0].kind, LexErrorKind::InvalidChar);
        assert_eq!(e[0].span, 10..14);
        assert_eq!(e[1].kind, LexErrorKind::NumberTooLarge);
        assert!(t.iter().any(|(_, t, _)| *t == Tok::Error));
    }
}
