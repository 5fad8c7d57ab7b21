//! Block grouping: turns the parser's flat items into blocks, one item at a time.
//!
//! MEFI blocks run from one `N` to the next (a block may span several lines); Fanuc blocks end at the
//! end of the line or at `;`. The groupers are resumable: [`Grouper::feed`] takes the items in file
//! order as the parser hands them on, [`Grouper::finish`] closes the last block. They keep only the
//! block being built (and, for MEFI, a `%` waiting for its number), so grouping a file holds the
//! largest block, not the file's items (issue 23, item 4). Every finished block is handed on at
//! once through [`Out::emit`] (the compile checks it there and keeps it only while it may run).
//! Fed the items of a file in order, they push the same diagnostics in the same order as grouping
//! the whole list at once did.

use std::ops::Range;

use diag::Diagnostic;

use crate::ast::{Block, Decl, Item, ParsedFile, Val, Word};
use crate::codes;
use crate::lexer::Lit;
use crate::machine::Dialect;
use crate::parse::{Out, Piece, R_MAX};

/// The grouping state of one file in either dialect.
pub(crate) enum Grouper<'p> {
    /// MEFI: blocks from `N` to `N`.
    Mefi(Mefi),
    /// Fanuc: blocks to the end of the line, with the Macro B blocks read before parsing.
    Fanuc(Fanuc<'p>),
}

impl<'p> Grouper<'p> {
    /// A grouper for `dialect`; `macro_pieces` (Fanuc: the byte ranges of the Macro B blocks, in
    /// file order, which the lexer steps over) are read and placed among the blocks by their
    /// position.
    pub(crate) fn new(
        dialect: Dialect,
        require_header: bool,
        macro_pieces: &'p [(usize, usize)],
    ) -> Self {
        match dialect {
            Dialect::Mefi => Grouper::Mefi(Mefi {
                require_header,
                cur: None,
                header_seen: false,
                after_slash: false,
                percent: None,
                stopped: false,
            }),
            Dialect::Fanuc => Grouper::Fanuc(Fanuc {
                macros: macro_pieces,
                next_macro: 0,
                cur: Block::default(),
                started: false,
                after_slash: false,
                emitted: 0,
            }),
        }
    }

    /// Takes the next item of the file.
    pub(crate) fn feed(
        &mut self,
        file: &str,
        src: &str,
        item: Item,
        out: &mut ParsedFile,
        diags: &mut Out,
    ) {
        match self {
            Grouper::Mefi(g) => g.feed(file, src, item, out, diags),
            Grouper::Fanuc(g) => g.feed(file, src, item, out, diags),
        }
    }

    /// Closes the file: the last block, and the checks that need the whole file.
    pub(crate) fn finish(self, file: &str, src: &str, diags: &mut Out) {
        match self {
            Grouper::Mefi(g) => g.finish(file, diags),
            Grouper::Fanuc(g) => g.finish(file, src, diags),
        }
    }
}

/// MEFI grouping state.
pub(crate) struct Mefi {
    require_header: bool,
    cur: Option<Block>,
    header_seen: bool,
    after_slash: bool,
    /// A `%` header whose number (the next item, when it is a bare number) is still to come.
    percent: Option<Range<usize>>,
    /// Set at the physical end `*`: later items are ignored.
    stopped: bool,
}

impl Mefi {
    fn feed(&mut self, file: &str, src: &str, item: Item, out: &mut ParsedFile, diags: &mut Out) {
        if self.stopped {
            return;
        }
        if let Some(sp) = self.percent.take() {
            match item {
                Item::Orphan(nsp) => {
                    match uint_of(src, &nsp) {
                        Some(n) if (1..=999_999).contains(&n) => out.number = Some(n as u32),
                        _ => diags.push(
                            Diagnostic::error(codes::HEADER, file, nsp, "invalid program number")
                                .with_hint(
                                    "the program number is 1..999999, without sign or point",
                                ),
                        ),
                    }
                    return;
                }
                _ => diags.push(
                    Diagnostic::error(codes::HEADER, file, sp, "`%` without a program number")
                        .with_hint("write `%<number>`, e.g. `%35`"),
                ),
            }
        }
        let was_slash = std::mem::replace(&mut self.after_slash, false);
        match item {
            Item::Percent(sp) => {
                if self.header_seen || self.cur.is_some() {
                    diags.push(Diagnostic::error(
                        codes::HEADER,
                        file,
                        sp,
                        "a second `%` header",
                    ));
                    return;
                }
                self.header_seen = true;
                self.percent = Some(sp);
            }
            Item::CycleHeader(_) => {
                self.header_seen = true;
                out.cycle_file = true;
            }
            Item::Star(_) => self.stopped = true,
            Item::Comment(_) | Item::Eob(_) | Item::Error(_) => {}
            Item::Slash(_) => {
                if let Some(b) = self.cur.as_mut() {
                    b.skip = true;
                }
                self.after_slash = true;
            }
            Item::Orphan(sp) => {
                if !was_slash {
                    diags.push(
                        Diagnostic::error(codes::ORPHAN_NUMBER, file, sp, "number without an address")
                            .with_hint("a value must not contain spaces (`X36. 12`) and a sign must touch its digits (`X- 36.12`)"),
                    );
                }
            }
            Item::Word('N', val, sp) => {
                if let Some(b) = self.cur.take() {
                    push_block(diags, b);
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
                self.cur = Some(Block {
                    n,
                    span: (sp.start, sp.end),
                    ..Block::default()
                });
            }
            Item::Word(a, val, sp) => match self.cur.as_mut() {
                Some(b) => {
                    b.words.push(Word {
                        addr: a,
                        val,
                        span: (sp.start, sp.end),
                    });
                    b.span.1 = sp.end;
                }
                None => no_block(file, sp, diags),
            },
            Item::Decl(p, v, sp) => match self.cur.as_mut() {
                Some(b) => {
                    b.span.1 = sp.end;
                    if let Some(d) = decl(file, p, v, sp, diags) {
                        b.decls.push(d);
                    }
                }
                None => no_block(file, sp, diags),
            },
        }
    }

    fn finish(mut self, file: &str, diags: &mut Out) {
        if let Some(sp) = self.percent.take() {
            diags.push(
                Diagnostic::error(codes::HEADER, file, sp, "`%` without a program number")
                    .with_hint("write `%<number>`, e.g. `%35`"),
            );
        }
        if !self.header_seen && self.require_header {
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
        // After the file's own diagnostics: the checks of the last block come after them.
        if let Some(b) = self.cur.take() {
            push_block(diags, b);
        }
    }
}

/// Fanuc grouping state.
pub(crate) struct Fanuc<'p> {
    /// The Macro B pieces of the file: each is read when the items reach it.
    macros: &'p [(usize, usize)],
    /// The first piece not reached yet.
    next_macro: usize,
    cur: Block,
    started: bool,
    after_slash: bool,
    /// Blocks handed on so far.
    emitted: usize,
}

impl Fanuc<'_> {
    /// Ends the current block: kept when it holds anything.
    fn flush(&mut self, diags: &mut Out) {
        if self.started
            && (self.cur.n.is_some() || !self.cur.words.is_empty() || !self.cur.decls.is_empty())
        {
            push_block(diags, std::mem::take(&mut self.cur));
            self.emitted += 1;
        } else {
            self.cur = Block::default();
        }
        self.started = false;
    }

    fn start(&mut self, sp: &Range<usize>) {
        if !self.started {
            self.started = true;
            self.cur.span = (sp.start, sp.end);
        }
    }

    /// Reads the Macro B piece `span` of `src`: its block is handed on, or its error pushed.
    fn macro_piece(&mut self, file: &str, src: &str, span: (usize, usize), diags: &mut Out) {
        let text = src.get(span.0..span.1).unwrap_or("");
        match crate::macro_b::syntax::parse_block(file, text, span.0) {
            Ok(m) => {
                self.flush(diags);
                diags.emit(m);
                self.emitted += 1;
            }
            Err(d) => diags.push(d),
        }
    }

    fn feed(&mut self, file: &str, src: &str, item: Item, out: &mut ParsedFile, diags: &mut Out) {
        let at = item_start(&item);
        // The lexer steps over a piece: no item lies inside it, so its start orders it.
        while let Some(&m) = self.macros.get(self.next_macro).filter(|m| m.0 <= at) {
            self.next_macro += 1;
            self.macro_piece(file, src, m, diags);
        }
        let was_slash = std::mem::replace(&mut self.after_slash, false);
        match item {
            Item::Eob(_) => self.flush(diags),
            Item::Percent(_)
            | Item::Comment(_)
            | Item::Error(_)
            | Item::Star(_)
            | Item::CycleHeader(_) => {}
            Item::Slash(sp) => {
                self.cur.skip = true;
                self.after_slash = true;
                self.start(&sp);
            }
            Item::Orphan(sp) => {
                if !was_slash {
                    diags.push(
                        Diagnostic::error(codes::ORPHAN_NUMBER, file, sp, "number without an address")
                            .with_hint("a value must not contain spaces and a sign must touch its digits"),
                    );
                }
            }
            Item::Word('O', val, sp) => match val {
                Val::Lit(l) if !l.point && !l.signed && (0..=99_999).contains(&l.int) => {
                    // An O word starts a program: the first names the main program, each later one
                    // a further program of the file (it must open its own block).
                    self.flush(diags);
                    let num = l.int as u32;
                    if out.number.is_none() && self.emitted == 0 && out.programs.is_empty() {
                        out.number = Some(num);
                        diags.piece(Piece::Number(num));
                    } else {
                        out.programs.push((num, self.emitted));
                        diags.piece(Piece::Program(num));
                    }
                }
                _ => diags.push(
                    Diagnostic::error(codes::HEADER, file, sp, "invalid program number")
                        .with_hint("write `O<number>`, e.g. `O00023`"),
                ),
            },
            Item::Word('N', val, sp) => {
                self.start(&sp);
                match val {
                    Val::Lit(l) if !l.point && !l.signed && (0..=99_999_999).contains(&l.int) => {
                        self.cur.n = Some(l.int as u32)
                    }
                    _ => diags.push(
                        Diagnostic::error(codes::OUT_OF_RANGE, file, sp, "invalid block number")
                            .with_hint("block numbers are N1..N99999"),
                    ),
                }
            }
            Item::Word(a, val, sp) => {
                self.start(&sp);
                self.cur.words.push(Word {
                    addr: a,
                    val,
                    span: (sp.start, sp.end),
                });
                self.cur.span.1 = sp.end;
            }
            Item::Decl(_, _, sp) => diags.push(
                Diagnostic::error(codes::R_WORD, file, sp, "`R<n>=` declarations are MEFI syntax")
                    .with_hint("the Fanuc/HAAS dialect has no R parameters; R is the arc radius or the canned-cycle R plane"),
            ),
        }
    }

    fn finish(mut self, file: &str, src: &str, diags: &mut Out) {
        self.flush(diags);
        while let Some(&m) = self.macros.get(self.next_macro) {
            self.next_macro += 1;
            self.macro_piece(file, src, m, diags);
        }
    }
}

/// Hands on a finished block, its words and declarations without spare capacity (a block of two
/// words would otherwise hold room for four: a program keeps every block).
fn push_block(diags: &mut Out, mut b: Block) {
    b.words.shrink_to_fit();
    b.decls.shrink_to_fit();
    diags.emit(b);
}

fn uint_of(src: &str, span: &Range<usize>) -> Option<u64> {
    let t = src.get(span.clone())?.trim();
    if t.is_empty() || !t.bytes().all(|b| b.is_ascii_digit()) || t.len() > 12 {
        return None;
    }
    t.parse().ok()
}

fn decl(file: &str, p: Lit, v: Lit, span: Range<usize>, diags: &mut Out) -> Option<Decl> {
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
    if r.abs() > R_MAX || (!v.point && v.int_digits() > 8) || (v.point && v.int_digits() > 5) {
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

fn no_block(file: &str, sp: Range<usize>, diags: &mut Out) {
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
