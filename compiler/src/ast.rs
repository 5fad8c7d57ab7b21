//! The syntax tree of a PLC program, exactly as written, with byte spans into the decoded text.
//!
//! The parser keeps syntactic distinctions that sema needs to judge (e.g. `+` vs `OR`, `/` vs
//! `NOT`), so that the meaning of an operator can follow the operand types (docs/plc-language.md §5).
//! Names are stored upper-cased (the language is case-insensitive).

use std::ops::Range;

use crate::lexer::RawSignal;

/// A byte span in the decoded source text.
pub type Span = Range<usize>;

/// A name with its span, upper-cased.
#[derive(Debug, Clone, PartialEq)]
pub struct Name {
    /// The name in upper case.
    pub text: String,
    /// Where it is written.
    pub span: Span,
}

/// A constant, variable or operator expression.
#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    /// What the expression is.
    pub kind: ExprKind,
    /// Where it is written.
    pub span: Span,
}

/// The kinds of expression.
#[derive(Debug, Clone, PartialEq)]
pub enum ExprKind {
    /// `TRUE` / `FALSE`.
    Bool(bool),
    /// Integer literal (decimal or `H` hex).
    Int(u32),
    /// Real literal.
    Real(f64),
    /// Duration literal, in milliseconds.
    Duration(f64),
    /// A signal name.
    Signal(RawSignal),
    /// A one-shot `P<n>`.
    Pulse(u32),
    /// A symbolic name.
    Name(String),
    /// `x.NAME` (timer `.ET`, counter `.CV`, …).
    Member(Box<Expr>, Name),
    /// `x.n`, bit `n` of an integer.
    BitOf(Box<Expr>, u32, Span),
    /// A prefix operator.
    Unary(UnOp, Box<Expr>),
    /// An infix operator.
    Binary(BinOp, Box<Expr>, Box<Expr>),
    /// `[a op b]`.
    Compare(CmpOp, Box<Expr>, Box<Expr>),
    /// `NAME(args)`: a function, a conversion or an inline timer.
    Call(Name, Vec<Expr>),
    /// Text the parser could not read (already reported).
    Error,
}

/// Prefix operators.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnOp {
    /// `/` (BOOL NOT).
    Slash,
    /// `NOT`.
    Not,
    /// `-` (negation).
    Neg,
    /// `~` (bitwise complement).
    BitNot,
}

/// Infix operators as written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinOp {
    /// `+`: OR on BOOL, addition on numbers.
    Plus,
    /// `-`.
    Minus,
    /// `*`: AND on BOOL, multiplication on numbers.
    Star,
    /// `/`: division (an error between BOOLs).
    Slash,
    /// `MOD`.
    Mod,
    /// `OR`.
    OrKw,
    /// `AND`.
    AndKw,
    /// `XOR`.
    XorKw,
    /// `&`.
    Amp,
    /// `|`.
    Pipe,
    /// `^`.
    Caret,
    /// `<<`.
    Shl,
    /// `>>`.
    Shr,
}

/// Comparison operators (inside brackets).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CmpOp {
    /// `=`.
    Eq,
    /// `<>`.
    Ne,
    /// `<`.
    Lt,
    /// `<=`.
    Le,
    /// `>`.
    Gt,
    /// `>=`.
    Ge,
}

/// The left side of an assignment.
#[derive(Debug, Clone, PartialEq)]
pub struct Target {
    /// What is assigned.
    pub kind: TargetKind,
    /// Where it is written.
    pub span: Span,
}

/// Kinds of assignment target.
#[derive(Debug, Clone, PartialEq)]
pub enum TargetKind {
    /// A signal.
    Signal(RawSignal),
    /// A one-shot `P<n>`.
    Pulse(u32),
    /// A name (variable, alias, timer or counter input).
    Name(Name),
    /// `c.R`, `c.LD`.
    Member(Name, Name),
    /// `x.n`: bit `n` of an integer name or byte signal.
    Bit(Box<Target>, u32),
}

/// How an assignment writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AssignKind {
    /// `t = x`: coil.
    Coil,
    /// `SET t = x`.
    Set,
    /// `RES t = x`.
    Res,
}

/// The type part of `DEF name : …`.
#[derive(Debug, Clone, PartialEq)]
pub struct TypeSpec {
    /// The type or function-block name (`DINT`, `TON`, …).
    pub name: Name,
    /// Arguments of a timer or counter (`TON(2s)`); `None` for a plain type.
    pub args: Option<Vec<Expr>>,
    /// The whole type part.
    pub span: Span,
}

/// One statement.
#[derive(Debug, Clone, PartialEq)]
pub struct Stmt {
    /// What the statement is.
    pub kind: StmtKind,
    /// The statement's text (its first line for an `IF`).
    pub span: Span,
}

/// Kinds of statement.
#[derive(Debug, Clone, PartialEq)]
pub enum StmtKind {
    /// `target = value`, `SET …`, `RES …`.
    Assign {
        /// Coil, set or reset.
        kind: AssignKind,
        /// The written place.
        target: Target,
        /// The value.
        value: Expr,
    },
    /// `DEF name = signal`.
    Alias {
        /// The new name.
        name: Name,
        /// The signal it stands for.
        signal: RawSignal,
        /// Where the signal is written.
        signal_span: Span,
    },
    /// `DEF name : type [AT signal] [:= init] [RETAIN]`.
    Var {
        /// The new name.
        name: Name,
        /// Its type (or timer/counter kind with preset).
        ty: TypeSpec,
        /// `AT` signal of a typed view.
        at: Option<(RawSignal, Span)>,
        /// Initial value.
        init: Option<Expr>,
        /// Span of `RETAIN` when given.
        retain: Option<Span>,
    },
    /// `IF cond THEN … [ELSE …] END_IF`.
    If {
        /// The condition.
        cond: Expr,
        /// Statements run when it holds.
        then_body: Vec<Stmt>,
        /// Statements run when it does not.
        else_body: Vec<Stmt>,
    },
    /// A line the parser could not read (already reported).
    Error,
}

/// A parsed program: the FAST part and the SLOW part (after a `$` line).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Program {
    /// Statements before the `$` line.
    pub fast: Vec<Stmt>,
    /// Statements after the `$` line.
    pub slow: Vec<Stmt>,
    /// Span of the separating `$`, when there is one.
    pub separator: Option<Span>,
}

/// One line as the grammar sees it; [`crate::parser`] nests the `IF` blocks.
#[derive(Debug, Clone, PartialEq)]
pub enum Line {
    /// A simple statement (boxed: keeps the parser's symbol stack small and fast).
    Stmt(Box<Stmt>),
    /// `IF cond THEN`.
    If(Box<Expr>, Span),
    /// `ELSE`.
    Else(Span),
    /// `END_IF`.
    EndIf(Span),
    /// `$`.
    Dollar(Span),
}
