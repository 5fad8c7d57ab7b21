//! The logos lexer shared by both dialects.
//!
//! MEFI (CNC8x6) text and Fanuc/HAAS text use the same token set: address letters, signed numbers that
//! keep their digits and decimal point, `"…"` comments (MEFI) or `( … )` comments (Fanuc), `%`, `*`, `/`,
//! `=`, `&` and, for Fanuc, the end of block (a line end or `;`). Lexer errors never abort: the adapter
//! [`Lexer`] turns them into [`Tok::LexError`] tokens and records a located message so that the parser
//! can resynchronise.

use std::ops::Range;

use logos::Logos;

use crate::machine::Dialect;

/// A number as written: sign, digits and whether it had a decimal point.
///
/// 16 bytes (a program keeps one per word): the integer part and the fraction rounded to three
/// and to four digits are stored, the values in thousandths and ten-thousandths are computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Lit {
    /// The integer as written without a point (`100` → 100); for a number with a point, the digits
    /// before the point; negative for a negative number (at most 12 digits).
    pub int: i64,
    /// The fraction in thousandths, rounded half away from zero (0..=1000).
    frac3: u16,
    /// The fraction in ten-thousandths, rounded half away from zero (0..=10000).
    frac4: u16,
    /// True when the number had a decimal point.
    pub point: bool,
    /// True when a sign was written.
    pub signed: bool,
    /// True when the number was negative.
    pub negative: bool,
    /// Number of digits after the point.
    pub frac_digits: u8,
}

impl Lit {
    /// The value times 1000, fraction rounded half away from zero to three digits (`36.12` → 36120,
    /// `100` → 100000, `1.2345` → 1235).
    pub fn milli(&self) -> i64 {
        self.signed_value(self.int.abs() * 1000 + i64::from(self.frac3))
    }

    /// The value times 10 000, rounded half away from zero (the 0.0001 in resolution of inch values).
    pub fn e4(&self) -> i64 {
        self.signed_value(self.int.abs() * 10_000 + i64::from(self.frac4))
    }

    /// Number of digits before the point (leading zeros not counted).
    pub fn int_digits(&self) -> u8 {
        let mut n = self.int.unsigned_abs();
        let mut digits = 0;
        while n > 0 {
            n /= 10;
            digits += 1;
        }
        digits
    }

    fn signed_value(&self, magnitude: i64) -> i64 {
        if self.negative { -magnitude } else { magnitude }
    }

    /// The value as a thousandths count under the R-parameter rule: without a point the written integer,
    /// with a point the value times 1000.
    pub fn r_count(&self) -> i64 {
        if self.point { self.milli() } else { self.int }
    }

    /// The value as a float in the written unit, rounded to 0.001.
    pub fn value(&self) -> f64 {
        self.milli() as f64 / 1000.0
    }

    /// The value rounded to 0.0001 (inch programs, resolution 0.0001 in).
    pub fn value4(&self) -> f64 {
        self.e4() as f64 / 10_000.0
    }
}

/// Reads a number as written (sign, digits, point) into a [`Lit`].
pub(crate) fn parse_number(s: &str) -> Option<Lit> {
    let (negative, signed, body) = match s.as_bytes().first()? {
        b'-' => (true, true, &s[1..]),
        b'+' => (false, true, &s[1..]),
        _ => (false, false, s),
    };
    let (ip, fp, point) = match body.find('.') {
        Some(i) => (&body[..i], &body[i + 1..], true),
        None => (body, "", false),
    };
    // A token may carry a second point ("2.52.5" in a Macro B block): not a number.
    if !fp.bytes().all(|c| c.is_ascii_digit()) {
        return None;
    }
    let ip_trim = ip.trim_start_matches('0');
    if ip_trim.len() > 12 {
        return None;
    }
    let int: i64 = if ip_trim.is_empty() {
        0
    } else {
        ip_trim.parse().ok()?
    };
    // Fraction digits rounded half away from zero to 3 (mm resolution) and 4 (inch) decimals.
    let digit = |i: usize| fp.as_bytes().get(i).map_or(0, |c| i64::from(c - b'0'));
    let frac3 = (0..3).fold(0, |f, i| f * 10 + digit(i)) + i64::from(digit(3) >= 5);
    let frac4 = (0..4).fold(0, |f, i| f * 10 + digit(i)) + i64::from(digit(4) >= 5);
    // At most 12 integer digits: `milli()` and `e4()` cannot overflow.
    let sign = if negative { -1 } else { 1 };
    Some(Lit {
        int: sign * int,
        frac3: u16::try_from(frac3).ok()?,
        frac4: u16::try_from(frac4).ok()?,
        point,
        signed,
        negative,
        frac_digits: u8::try_from(fp.len()).unwrap_or(u8::MAX),
    })
}

/// Why a piece of text is not a token.
#[derive(Debug, Clone, Default, PartialEq)]
pub enum LexErrorKind {
    /// A character that is not part of the language (outside comments).
    #[default]
    BadChar,
    /// A number too long to represent.
    BadNumber,
}

/// Raw MEFI tokens produced by logos.
#[derive(Logos, Debug, Clone, PartialEq)]
#[logos(error = LexErrorKind)]
#[logos(skip r"[ \t\r\n]+")]
enum MefiTok {
    #[token("%")]
    Percent,
    #[token("*")]
    Star,
    #[token("/")]
    Slash,
    #[token("=")]
    Eq,
    #[token("&")]
    Amp,
    #[regex(r"[A-Z]", |lex| lex.slice().as_bytes()[0] as char)]
    Letter(char),
    #[regex(r"[+-]?([0-9]+(\.[0-9]*)?|\.[0-9]+)", |lex| parse_number(lex.slice()).ok_or(LexErrorKind::BadNumber))]
    Number(Lit),
    #[regex(r#""[^"\r\n]*"?"#, allow_greedy = true)]
    Comment,
    #[regex(r"\$PC[^\r\n]*", allow_greedy = true)]
    CycleHeader,
}

/// Raw Fanuc/HAAS tokens produced by logos.
#[derive(Logos, Debug, Clone, PartialEq)]
#[logos(error = LexErrorKind)]
#[logos(skip r"[ \t]+")]
enum FanucTok {
    #[token("%")]
    Percent,
    #[token("/")]
    Slash,
    #[token("=")]
    Eq,
    #[regex(r"(\r\n|\r|\n|;)")]
    Eob,
    #[regex(r"[A-Za-z]", |lex| (lex.slice().as_bytes()[0] as char).to_ascii_uppercase())]
    Letter(char),
    #[regex(r"[+-]?([0-9]+(\.[0-9]*)?|\.[0-9]+)", |lex| parse_number(lex.slice()).ok_or(LexErrorKind::BadNumber))]
    Number(Lit),
    #[regex(r"\([^)\r\n]*\)?", allow_greedy = true)]
    Comment,
}

/// Parser tokens (both dialects).
#[derive(Debug, Clone, PartialEq)]
pub enum Tok {
    /// `%`.
    Percent,
    /// `*` (MEFI physical end).
    Star,
    /// `/` block skip.
    Slash,
    /// `=`.
    Eq,
    /// The block-number address `N`.
    N,
    /// The parameter address `R`.
    R,
    /// The program-number address `O` (Fanuc).
    O,
    /// Any other address letter, or `&`.
    Addr(char),
    /// A number.
    Num(Lit),
    /// A comment.
    Comment,
    /// End of block (Fanuc line end or `;`).
    Eob,
    /// The `$PC` header of a fixed-cycle file.
    CycleHeader,
    /// A lexer error (recorded separately).
    LexError,
}

/// A lexer error with its byte range.
#[derive(Debug, Clone, PartialEq)]
pub struct LexError {
    /// What went wrong.
    pub kind: LexErrorKind,
    /// Where.
    pub span: Range<usize>,
}

/// Token stream adapter for the lalrpop parser; stops at a MEFI `*` (everything after it is ignored).
pub struct Lexer<'a> {
    inner: Inner<'a>,
    offset: usize,
    done: bool,
    /// Lexer errors seen so far.
    pub errors: Vec<LexError>,
    /// Fanuc: the Macro B pieces the lexer steps over ([`Lexer::skipping`]).
    gaps: Option<Gaps<'a>>,
}

/// The text between the pieces a lexer steps over: the whole text, the pieces (byte ranges in
/// file order, none inside another) and the next piece to step over.
struct Gaps<'a> {
    src: &'a str,
    pieces: &'a [(usize, usize)],
    next: usize,
}

enum Inner<'a> {
    Mefi(logos::SpannedIter<'a, MefiTok>),
    Fanuc(logos::SpannedIter<'a, FanucTok>),
}

impl<'a> Lexer<'a> {
    /// Lexes `src` starting at byte `offset` (the preamble before `%` is skipped by the caller).
    pub fn new(dialect: Dialect, src: &'a str, offset: usize) -> Self {
        let text = &src[offset..];
        let inner = match dialect {
            Dialect::Mefi => Inner::Mefi(MefiTok::lexer(text).spanned()),
            Dialect::Fanuc => Inner::Fanuc(FanucTok::lexer(text).spanned()),
        };
        Lexer {
            inner,
            offset,
            done: false,
            errors: Vec::new(),
            gaps: None,
        }
    }

    /// Lexes Fanuc text `src` without the byte ranges `pieces` (in file order, each after a line
    /// end or `;` and ending at one or at the end: no token runs into one), as if they were blank:
    /// the tokens of the text between them, with their places in `src`. The Macro B blocks are
    /// stepped over this way instead of being blanked in a copy of the text.
    pub fn skipping(src: &'a str, pieces: &'a [(usize, usize)]) -> Self {
        let first = pieces.first().map_or(src.len(), |p| p.0);
        let mut lx = Lexer::new(Dialect::Fanuc, src.get(..first).unwrap_or(""), 0);
        lx.gaps = Some(Gaps {
            src,
            pieces,
            next: 0,
        });
        lx
    }

    /// Moves on to the text after the next piece; false when there is none.
    fn next_gap(&mut self) -> bool {
        let Some(g) = &mut self.gaps else {
            return false;
        };
        let Some(&(_, start)) = g.pieces.get(g.next) else {
            return false;
        };
        g.next += 1;
        let end = g.pieces.get(g.next).map_or(g.src.len(), |p| p.0);
        self.offset = start;
        self.inner = Inner::Fanuc(FanucTok::lexer(g.src.get(start..end).unwrap_or("")).spanned());
        true
    }

    /// The next raw token of the current text, mapped to a parser token.
    fn raw(&mut self) -> Option<(Result<Tok, LexErrorKind>, Range<usize>)> {
        Some(match &mut self.inner {
            Inner::Mefi(it) => {
                let (r, s) = it.next()?;
                let t = r.map(|t| match t {
                    MefiTok::Percent => Tok::Percent,
                    MefiTok::Star => Tok::Star,
                    MefiTok::Slash => Tok::Slash,
                    MefiTok::Eq => Tok::Eq,
                    MefiTok::Amp => Tok::Addr('&'),
                    MefiTok::Letter(c) => letter(c),
                    MefiTok::Number(l) => Tok::Num(l),
                    MefiTok::Comment => Tok::Comment,
                    MefiTok::CycleHeader => Tok::CycleHeader,
                });
                (t, s)
            }
            Inner::Fanuc(it) => {
                let (r, s) = it.next()?;
                let t = r.map(|t| match t {
                    FanucTok::Percent => Tok::Percent,
                    FanucTok::Slash => Tok::Slash,
                    FanucTok::Eq => Tok::Eq,
                    FanucTok::Eob => Tok::Eob,
                    FanucTok::Letter(c) => letter(c),
                    FanucTok::Number(l) => Tok::Num(l),
                    FanucTok::Comment => Tok::Comment,
                });
                (t, s)
            }
        })
    }
}

fn letter(c: char) -> Tok {
    match c {
        'N' => Tok::N,
        'R' => Tok::R,
        'O' => Tok::O,
        c => Tok::Addr(c),
    }
}

impl Iterator for Lexer<'_> {
    type Item = Result<(usize, Tok, usize), LexError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.done {
            return None;
        }
        let (res, span) = loop {
            if let Some(t) = self.raw() {
                break t;
            }
            if !self.next_gap() {
                return None;
            }
        };
        let span = span.start + self.offset..span.end + self.offset;
        Some(Ok(match res {
            Ok(Tok::Star) => {
                self.done = true;
                (span.start, Tok::Star, span.end)
            }
            Ok(t) => (span.start, t, span.end),
            Err(kind) => {
                self.errors.push(LexError {
                    kind,
                    span: span.clone(),
                });
                (span.start, Tok::LexError, span.end)
            }
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tokens (with their places) and errors of `lx`.
    fn all(mut lx: Lexer) -> (Vec<(usize, Tok, usize)>, Vec<LexError>) {
        let toks = lx.by_ref().filter_map(Result::ok).collect();
        (toks, lx.errors)
    }

    #[test]
    fn stepping_over_pieces_lexes_as_the_text_with_them_blank() {
        let src = "O1\n#1=2\nN1 G01 X1.@ (a;b) ; #2=[#1]\r\nWHILE [#1 LT 3] DO 1\nX2.\n#3=1";
        let pieces = crate::macro_b::syntax::prepass(src);
        // `#1=2`, `#2=[#1]` (after the `;` outside the comment), the WHILE line, `#3=1` at the end.
        assert_eq!(pieces.len(), 4);
        let mut blanked = src.as_bytes().to_vec();
        for &(s, e) in &pieces {
            blanked[s..e].fill(b' ');
        }
        let blanked = String::from_utf8(blanked).unwrap_or_default();
        let want = all(Lexer::new(Dialect::Fanuc, &blanked, 0));
        let got = all(Lexer::skipping(src, &pieces));
        assert_eq!(got.0, want.0);
        assert_eq!(
            got.1.iter().map(|e| e.span.clone()).collect::<Vec<_>>(),
            want.1.iter().map(|e| e.span.clone()).collect::<Vec<_>>()
        );
        // The `@` is the one error, at its place in the text.
        assert_eq!(got.1.len(), 1);
        assert_eq!(&src[got.1[0].span.clone()], "@");
    }
}
