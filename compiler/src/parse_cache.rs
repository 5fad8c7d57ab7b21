//! Incremental parsing for an editor: the grammar's results for runs of statement lines
//! (segments), kept from one parse of a text to the next, so that a one-character edit re-parses
//! only the segment it touches.
//!
//! The parser reads chunks of whole statement lines ([`crate::parser`]); every statement line is
//! a complete item of the grammar, so a chunk parsed as consecutive segments gives what one pass
//! gives (the same argument as the parser's two-thread split, with the same fallback: a segment
//! that fails unrecoverably or runs into its end makes the whole chunk be parsed in one pass).
//!
//! Segments are cut content-defined (after a statement line whose text hashes to a multiple of
//! [`CUT_EVERY`], at least [`MIN_LINES`] and at most [`MAX_LINES`] lines), so an edit that adds or
//! removes a line moves only the cuts next to it. A segment's entry is keyed by everything its
//! lines and syntax diagnostics depend on: its text from its first token to its last, the text of
//! its first line before the first token, and the last four non-blank bytes before it (the "name
//! after `DEF`" check looks back there). Entries hold spans relative to the segment's start and are
//! shifted on reuse. Only the segments of the latest parse are kept: memory stays proportional to
//! the text.

use std::collections::HashMap;
use std::hash::Hasher;

use diag::Diagnostic;

use crate::ast::{Expr, ExprKind, Line, Span, Stmt, StmtKind, Target, TargetKind};
use crate::lexer::{Spanned, Tok};

/// A segment is cut after a line whose hash is a multiple of this (about one cut per this many lines).
const CUT_EVERY: u64 = 16;
/// Statement lines a segment holds at least (unless the chunk ends).
const MIN_LINES: usize = 4;
/// Statement lines a segment holds at most.
const MAX_LINES: usize = 64;

/// One parsed segment, spans relative to its start.
#[derive(Debug, Clone)]
struct Entry {
    lines: Vec<Line>,
    diagnostics: Vec<Diagnostic>,
    /// Parsed by the last [`ParseCache::begin`] generation.
    generation: u64,
}

/// Parsed segments of the previous texts, for [`crate::parser::parse_cached`].
#[derive(Debug, Default)]
pub struct ParseCache {
    entries: HashMap<String, Entry>,
    generation: u64,
    /// Segments reused and parsed in the latest parse.
    pub reused: usize,
    /// Segments the grammar ran on in the latest parse.
    pub parsed: usize,
}

/// How the grammar's result for some tokens came out.
pub(crate) struct Parsed {
    pub lines: Vec<Line>,
    pub diagnostics: Vec<Diagnostic>,
    /// The grammar failed unrecoverably or ran into the end of the tokens.
    pub whole_pass_needed: bool,
}

impl ParseCache {
    /// An empty cache.
    pub fn new() -> Self {
        ParseCache::default()
    }

    /// Starts a parse of a new text.
    pub(crate) fn begin(&mut self) {
        self.generation += 1;
        self.reused = 0;
        self.parsed = 0;
    }

    /// Ends a parse: only the segments it used are kept.
    pub(crate) fn end(&mut self) {
        let g = self.generation;
        self.entries.retain(|_, e| e.generation == g);
    }

    /// Parses one chunk of `tokens` of `text` segment by segment, reusing the entries of earlier
    /// parses; `parse` runs the grammar (with the syntax diagnostics made) on a token slice.
    pub(crate) fn parse_chunk<'a>(
        &mut self,
        text: &'a str,
        tokens: &[Spanned<'a>],
        parse: impl Fn(&[Spanned<'a>]) -> Parsed,
    ) -> Parsed {
        let mut lines = Vec::new();
        let mut diagnostics = Vec::new();
        for seg in segments(text, tokens) {
            let (Some(first), Some(last)) = (seg.first(), seg.last()) else {
                continue;
            };
            let (start, end) = (first.0, last.2);
            let key = key(text, start, end);
            if let Some(e) = self.entries.get_mut(&key) {
                e.generation = self.generation;
                self.reused += 1;
                lines.extend(e.lines.iter().cloned().map(|mut l| {
                    shift_line(&mut l, start, true);
                    l
                }));
                diagnostics.extend(e.diagnostics.iter().cloned().map(|mut d| {
                    d.span = d.span.start + start..d.span.end + start;
                    d
                }));
                continue;
            }
            self.parsed += 1;
            let p = parse(seg);
            if p.whole_pass_needed {
                return parse(tokens);
            }
            let mut entry = Entry {
                lines: p.lines.clone(),
                diagnostics: p.diagnostics.clone(),
                generation: self.generation,
            };
            for l in &mut entry.lines {
                shift_line(l, start, false);
            }
            for d in &mut entry.diagnostics {
                d.span = d.span.start.saturating_sub(start)..d.span.end.saturating_sub(start);
            }
            self.entries.insert(key, entry);
            lines.extend(p.lines);
            diagnostics.extend(p.diagnostics);
        }
        Parsed {
            lines,
            diagnostics,
            whole_pass_needed: false,
        }
    }
}

/// The key of the segment `start..end` of `text` (see the module header).
fn key(text: &str, start: usize, end: usize) -> String {
    let before = text.get(..start).unwrap_or("");
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let trimmed = before.trim_end().as_bytes();
    let look = &trimmed[trimmed.len().saturating_sub(4)..];
    let mut k = String::with_capacity(end - start + 16);
    k.push_str(&String::from_utf8_lossy(look));
    k.push('\u{1}');
    k.push_str(before.get(line_start..).unwrap_or(""));
    k.push('\u{1}');
    k.push_str(text.get(start..end).unwrap_or(""));
    k
}

/// Cuts `tokens` (whole statement lines) into segments (see the module header).
fn segments<'t, 'a>(text: &str, tokens: &'t [Spanned<'a>]) -> Vec<&'t [Spanned<'a>]> {
    let mut out = Vec::new();
    let (mut seg_start, mut line_start, mut lines) = (0usize, 0usize, 0usize);
    for (i, t) in tokens.iter().enumerate() {
        if t.1 != Tok::Newline {
            continue;
        }
        lines += 1;
        let line_text = text.get(tokens[line_start].0..t.2).unwrap_or("");
        line_start = i + 1;
        let cut =
            lines >= MAX_LINES || (lines >= MIN_LINES && fnv(line_text).is_multiple_of(CUT_EVERY));
        if cut {
            out.push(&tokens[seg_start..=i]);
            seg_start = i + 1;
            lines = 0;
        }
    }
    if seg_start < tokens.len() {
        out.push(&tokens[seg_start..]);
    }
    out
}

/// FNV-1a: a fixed hash, so that the cuts are the same in every process.
fn fnv(s: &str) -> u64 {
    let mut h = FnvHasher(0xcbf2_9ce4_8422_2325);
    h.write(s.as_bytes());
    h.finish()
}

struct FnvHasher(u64);

impl Hasher for FnvHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
    }
}

/// Moves a span by `by` bytes, forward (`add`) or back.
fn shift(s: &mut Span, by: usize, add: bool) {
    if add {
        *s = s.start + by..s.end + by;
    } else {
        *s = s.start.saturating_sub(by)..s.end.saturating_sub(by);
    }
}

fn shift_line(l: &mut Line, by: usize, add: bool) {
    match l {
        Line::Stmt(s) => shift_stmt(s, by, add),
        Line::If(e, s) => {
            shift_expr(e, by, add);
            shift(s, by, add);
        }
        Line::Else(s) | Line::EndIf(s) | Line::Dollar(s) => shift(s, by, add),
    }
}

fn shift_stmt(s: &mut Stmt, by: usize, add: bool) {
    shift(&mut s.span, by, add);
    match &mut s.kind {
        StmtKind::Assign { target, value, .. } => {
            shift_target(target, by, add);
            shift_expr(value, by, add);
        }
        StmtKind::Alias {
            name, signal_span, ..
        } => {
            shift(&mut name.span, by, add);
            shift(signal_span, by, add);
        }
        StmtKind::Var {
            name,
            ty,
            at,
            init,
            retain,
        } => {
            shift(&mut name.span, by, add);
            shift(&mut ty.span, by, add);
            shift(&mut ty.name.span, by, add);
            for a in ty.args.iter_mut().flatten() {
                shift_expr(a, by, add);
            }
            if let Some((_, s)) = at {
                shift(s, by, add);
            }
            if let Some(e) = init {
                shift_expr(e, by, add);
            }
            if let Some(s) = retain {
                shift(s, by, add);
            }
        }
        StmtKind::If {
            cond,
            then_body,
            else_body,
        } => {
            shift_expr(cond, by, add);
            for s in then_body.iter_mut().chain(else_body.iter_mut()) {
                shift_stmt(s, by, add);
            }
        }
        StmtKind::Error => {}
    }
}

fn shift_target(t: &mut Target, by: usize, add: bool) {
    shift(&mut t.span, by, add);
    match &mut t.kind {
        TargetKind::Signal(_) | TargetKind::Pulse(_) => {}
        TargetKind::Name(n) => shift(&mut n.span, by, add),
        TargetKind::Member(a, b) => {
            shift(&mut a.span, by, add);
            shift(&mut b.span, by, add);
        }
        TargetKind::Bit(inner, _) => shift_target(inner, by, add),
    }
}

fn shift_expr(e: &mut Expr, by: usize, add: bool) {
    shift(&mut e.span, by, add);
    match &mut e.kind {
        ExprKind::Bool(_)
        | ExprKind::Int(_)
        | ExprKind::Real(_)
        | ExprKind::Duration(_)
        | ExprKind::Signal(_)
        | ExprKind::Pulse(_)
        | ExprKind::Name(_)
        | ExprKind::Error => {}
        ExprKind::Member(inner, n) => {
            shift_expr(inner, by, add);
            shift(&mut n.span, by, add);
        }
        ExprKind::BitOf(inner, _, s) => {
            shift_expr(inner, by, add);
            shift(s, by, add);
        }
        ExprKind::Unary(_, inner) => shift_expr(inner, by, add),
        ExprKind::Binary(_, a, b) | ExprKind::Compare(_, a, b) => {
            shift_expr(a, by, add);
            shift_expr(b, by, add);
        }
        ExprKind::Call(n, args) => {
            shift(&mut n.span, by, add);
            for a in args {
                shift_expr(a, by, add);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parser::{parse, parse_cached};
    use proptest::prelude::*;

    #[test]
    fn a_one_character_edit_reparses_one_segment_and_gives_what_parse_gives() {
        let src = crate::synth::synthetic_program(2_000);
        let mut cache = ParseCache::new();
        assert_eq!(parse_cached("t", &src, &mut cache), parse("t", &src));
        let first = cache.parsed;
        assert!(first > 30, "{first} segments");
        // Edit a digit in the middle: V12 = … becomes V13 = …, or a signal's contact changes.
        let at = src.len() / 2 + src[src.len() / 2..].find('1').expect("a digit");
        let mut edited = src.clone();
        edited.replace_range(at..at + 1, "2");
        assert_eq!(parse_cached("t", &edited, &mut cache), parse("t", &edited));
        assert_eq!((cache.parsed, cache.reused), (1, first - 1));
        // A new statement early in the text shifts every later span: still reused, still exact.
        // It also moves the parser's chunk boundaries (after statement lines 256, 768 and 1792)
        // by one line, and a segment ends at a chunk's end: the first two segments (the new lines
        // change where the first content-defined cut falls) and the two beside each of the three
        // boundaries are parsed again, 8 of about 140.
        let edited = format!("U4A0 = I0A0 +\n  I0A1 ; new\n{edited}");
        assert_eq!(parse_cached("t", &edited, &mut cache), parse("t", &edited));
        assert!(cache.parsed <= 2 + 2 * 3, "{} parsed", cache.parsed);
        assert!(cache.reused >= first - 8, "{} reused", cache.reused);
    }

    #[test]
    fn syntax_errors_and_the_look_behind_of_def_are_exact() {
        let mut cache = ParseCache::new();
        let texts = [
            "U4A0 = I0A0\nDEF\nU10K5 = I0K0\n",
            "U4A0 = I0A0\n; DEF\nU10K5 = I0K0\n",
            "U4A0 = I0A0\n; xDEF\nU10K5 = I0K0\nENDIF\nIF I0A0 THEN\n$\n",
            "U4A0 = (I0A0\nU4A1 = 1\n",
        ];
        for t in texts {
            assert_eq!(parse_cached("t", t, &mut cache), parse("t", t), "{t:?}");
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]
        /// Random edit sequences over an example program: every cached parse equals `parse`.
        #[test]
        fn random_edits_parse_exactly(edits in proptest::collection::vec(
            (any::<prop::sample::Index>(), 0usize..6, "[ A-Z0-9=+*/()\\[\\];$\n.:]{0,8}"), 1..12)) {
            let mut text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../plc-programs/lathe/MP0/PLCPRG"))
                .expect("the lathe program");
            let mut cache = ParseCache::new();
            for (at, del, ins) in edits {
                let mut a = at.index(text.len() + 1);
                while !text.is_char_boundary(a) { a -= 1; }
                let mut b = (a + del).min(text.len());
                while !text.is_char_boundary(b) { b -= 1; }
                text.replace_range(a..b, &ins);
                prop_assert_eq!(parse_cached("t", &text, &mut cache), parse("t", &text));
            }
        }
    }
}
