//! Fanuc Custom Macro B: `#` variables, `[ ]` expressions, functions, `IF`/`WHILE`/`GOTO` and `G65`
//! calls in the Fanuc/HAAS dialect.
//!
//! [`syntax`] reads a macro block (any Fanuc block holding `#`, `[`, a keyword or `G65`) into a
//! [`Macro`]: one statement or NC words whose values may be expressions ([`crate::ast::Val::Expr`]).
//! [`eval`] is the reference interpreter of expressions (values are `f64`, the null value `#0` is a
//! NaN); [`flow`] pairs `WHILE … DO m` with `END m` and resolves literal `GOTO` targets at compile
//! time; [`retained`] is the file of the retained `#500`–`#999`; [`native`] compiles runs of macro-only blocks with cranelift (through [`crate::jit`]) into
//! functions that give the same variables, block counts and errors bit for bit. The executor side
//! (system variables, calls) is `fanuc_exec::macros`.

pub mod eval;
pub mod flow;
pub mod native;
pub mod retained;
pub mod syntax;

/// A binary operator of a macro expression.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinOp {
    /// `+`.
    Add,
    /// `-`.
    Sub,
    /// `*`.
    Mul,
    /// `/`.
    Div,
    /// `MOD`: remainder of the operands rounded to integers.
    Mod,
    /// `AND`: bitwise on the operands truncated to integers.
    And,
    /// `OR`: bitwise.
    Or,
    /// `XOR`: bitwise.
    Xor,
    /// `EQ`: null equals only null.
    Eq,
    /// `NE`.
    Ne,
    /// `GT` (null counts as 0).
    Gt,
    /// `GE`.
    Ge,
    /// `LT`.
    Lt,
    /// `LE`.
    Le,
}

/// A one-argument function of a macro expression (angles in degrees).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Func {
    /// `SIN`.
    Sin,
    /// `COS`.
    Cos,
    /// `TAN`.
    Tan,
    /// `ASIN` (−90..90).
    Asin,
    /// `ACOS` (0..180).
    Acos,
    /// `ATAN[a]` with one argument (−90..90).
    Atan,
    /// `SQRT`.
    Sqrt,
    /// `ABS`.
    Abs,
    /// `ROUND`: to the nearest integer, half away from zero.
    Round,
    /// `FIX`: towards zero.
    Fix,
    /// `FUP`: away from zero.
    Fup,
    /// `LN`.
    Ln,
    /// `EXP`.
    Exp,
    /// `BIN`: BCD to binary.
    Bin,
    /// `BCD`: binary to BCD.
    Bcd,
}

/// A macro expression.
#[derive(Debug, Clone, PartialEq)]
pub enum Expr {
    /// A number.
    Num(f64),
    /// `#n` with a literal number.
    Var(u32),
    /// `#[expr]`: a computed variable number.
    VarAt(Box<Expr>),
    /// Unary minus.
    Neg(Box<Expr>),
    /// A binary operation.
    Bin(BinOp, Box<Expr>, Box<Expr>),
    /// A function call.
    Call(Func, Box<Expr>),
    /// `ATAN[a]/[b]` or `ATAN[a,b]`: the angle of the vector (b, a), 0..360.
    Atan2(Box<Expr>, Box<Expr>),
}

/// The variable an assignment writes.
#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    /// `#n`.
    Var(u32),
    /// `#[expr]`.
    At(Expr),
}

/// A macro statement (one per block).
#[derive(Debug, Clone, PartialEq)]
pub enum Stmt {
    /// `#i = expr`.
    Assign(Target, Expr),
    /// `IF [cond] GOTO n`.
    IfGoto(Expr, Expr),
    /// `IF [cond] THEN #i = expr`.
    IfThen(Expr, Target, Expr),
    /// `WHILE [cond] DO m` (`None`: a bare `DO m`, an endless loop).
    While(Option<Expr>, u8),
    /// `END m`.
    End(u8),
    /// `GOTO n`.
    Goto(Expr),
    /// `G65 P<p> L<l>` with arguments: (local variable number, value).
    Call {
        /// The program number.
        p: u32,
        /// Repeat count.
        l: u32,
        /// Arguments by local variable number (argument specification I).
        args: Vec<(u8, Expr)>,
    },
}

/// The macro part of a block: its statement, or the expressions its words refer to.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Macro {
    /// The statement (None: an NC block with expression words).
    pub stmt: Option<Stmt>,
    /// Expressions of `Val::Expr(i)` words.
    pub exprs: Vec<Expr>,
}

/// Local variable of G65 argument address `a` under Fanuc's argument specification I (A #1, B #2,
/// C #3, I #4, J #5, K #6, D #7, E #8, F #9, H #11, M #13, Q #17, R #18, S #19, T #20, U #21, V #22,
/// W #23, X #24, Y #25, Z #26); None for G, L, N, O, P.
pub fn argument_var(a: char) -> Option<u8> {
    Some(match a {
        'A' => 1,
        'B' => 2,
        'C' => 3,
        'I' => 4,
        'J' => 5,
        'K' => 6,
        'D' => 7,
        'E' => 8,
        'F' => 9,
        'H' => 11,
        'M' => 13,
        'Q' => 17,
        'R' => 18,
        'S' => 19,
        'T' => 20,
        'U' => 21,
        'V' => 22,
        'W' => 23,
        'X' => 24,
        'Y' => 25,
        'Z' => 26,
        _ => return None,
    })
}

/// True for a variable number the plan keeps in its flat table: #1–#33 (locals of the current
/// level), #100–#199 and #500–#999 (common).
pub fn is_plain(n: u32) -> bool {
    matches!(n, 1..=33 | 100..=199 | 500..=999)
}

/// Size of the flat variable table (slot n is variable #n for [`is_plain`] numbers).
pub const SLOTS: usize = 1000;

/// The hidden slot of the flat table (not a plain variable: `#99` cannot be named) holding the
/// sequence number of the latest executed block that had one, null before the first: what
/// `#4114`/`#4314` read. Both back ends store it at the head of every block with an `N`.
pub const SEQ_SLOT: usize = 99;
