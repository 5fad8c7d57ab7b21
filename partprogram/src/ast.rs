//! Syntax tree of a partprogram file: the flat items the grammar produces and the blocks built from them.

use std::ops::Range;

use crate::lexer::Lit;

/// The value of a word: a literal or a parameter reference `R<n>`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Val {
    /// A number as written.
    Lit(Lit),
    /// `R<n>`: the number after `R`.
    Param(Lit),
    /// A Fanuc macro expression: index into the block's [`crate::macro_b::Macro::exprs`].
    Expr(u32),
}

/// One item of the flat token-level parse.
#[derive(Debug, Clone, PartialEq)]
pub enum Item {
    /// `%`.
    Percent(Range<usize>),
    /// `*`.
    Star(Range<usize>),
    /// `/` block skip.
    Slash(Range<usize>),
    /// End of block (Fanuc).
    Eob(Range<usize>),
    /// A comment.
    Comment(Range<usize>),
    /// `$PC …` cycle-file header.
    CycleHeader(Range<usize>),
    /// A number or `=` that belongs to no word.
    Orphan(Range<usize>),
    /// A word: address letter (or `&`), value.
    Word(char, Val, Range<usize>),
    /// `R<n>=<value>`.
    Decl(Lit, Lit, Range<usize>),
    /// Unparseable text.
    Error(Range<usize>),
}

/// A word of a block after grouping.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Word {
    /// Address letter (`&` for length-correction control).
    pub addr: char,
    /// Literal or parameter reference.
    pub val: Val,
    /// Byte range in the file.
    pub span: (usize, usize),
}

/// A parameter declaration `R<n>=value` with the stored thousandths count.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Decl {
    /// Parameter number 0..=95.
    pub param: u8,
    /// Stored count r.
    pub r: i64,
    /// Byte range in the file.
    pub span: (usize, usize),
}

/// One block of a program.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Block {
    /// Block number (None for a Fanuc block without N).
    pub n: Option<u32>,
    /// Byte range of the whole block.
    pub span: (usize, usize),
    /// Words other than N and declarations, in written order.
    pub words: Vec<Word>,
    /// Declarations in written order.
    pub decls: Vec<Decl>,
    /// Block skip `/` present.
    pub skip: bool,
    /// Fanuc Macro B: the block's statement or the expressions of its words.
    pub mac: Option<Box<crate::macro_b::Macro>>,
}

/// A parsed file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ParsedFile {
    /// Program number after `%` (MEFI) or `O` (Fanuc).
    pub number: Option<u32>,
    /// True for a `$PC` fixed-cycle file.
    pub cycle_file: bool,
    /// The blocks in file order.
    pub blocks: Vec<Block>,
    /// Fanuc: every further `O<n>` of the file after the first program, with the index of its first
    /// block in [`ParsedFile::blocks`] (Fanuc loads every O-program of a file into memory).
    pub programs: Vec<(u32, usize)>,
}
