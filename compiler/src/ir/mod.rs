//! The typed intermediate representation shared by the interpreter and the cranelift JIT, and the
//! layout of the flat memory image both engines work on.
//!
//! The front end lowers the checked AST into a [`Program`] with a [`ProgramBuilder`]: it declares
//! variables, timers, counters and pulses (getting ids back) and hands over the FAST and SLOW
//! statement lists. The builder lays out the image, cuts the SLOW part into slices and checks every
//! type rule below ([`Program::validate`]); engines only ever see validated programs.
//!
//! # The image layout
//! All state lives in one flat `&mut [u8]`; engines keep no state of their own, so the runtime can
//! snapshot, replay and migrate it. Multi-byte values are little-endian and need no alignment.
//!
//! ```text
//! offset  size  what
//! 0       128   packet A                      (packets::Packet::A.offset())
//! 128     1024  packet K
//! 1152    1024  packet N
//! 2176    64    packet T
//! 2240    16    scan header: u32 next SLOW slice index (HDR_NEXT_SLICE), u32 fault flags
//!               (HDR_FAULTS; bit 0 FAULT_DIV_ZERO, sticky until the runtime clears it), 8 reserved
//! 2256    …     variables (non-RETAIN), each at an offset aligned to its size; BOOL is one byte 0/1
//! …       1 ea. pulses P<n>: bit 0 the pulse value, bit 1 the previous input
//! …       8 ea. timers (4-aligned): i32 ET (ms) at +0, flags at +4: bit 0 Q, bit 1 previous IN,
//!               bit 2 running (TOF, TP)
//! …       8 ea. counters (4-aligned): i32 CV at +0, flags at +4: bit 1 previous count input,
//!               bit 2 the stored R (CTU) or LD (CTD) input
//! …       …     the RETAIN area: RETAIN variables ([`Program::retain_range`])
//! ```
//! [`Program::image_len`] is the total length. At start the runtime zeroes the image and calls
//! [`Program::init_image`] (writes `:=` initial values of non-RETAIN variables).
//!
//! # Typing rules (checked by [`Program::validate`])
//! Every expression has a static type ([`Expr::ty`]); the front end inserts [`Expr::Convert`] so
//! that both operands of a binary operator have the operator's type. BOOL operators are
//! [`BinOp::And`]/[`BinOp::Or`]/[`BinOp::Xor`] and [`Expr::Not`]; arithmetic `Add Sub Mul Div Mod`,
//! `Min Max` on numbers (`Mod` only on integers); bitwise ops and shifts only on integers.
//!
//! # Semantics both engines implement bit for bit
//! - Integer arithmetic wraps in the operand type. Division or MOD by zero gives 0 and sets
//!   `FAULT_DIV_ZERO`; `MIN / -1` wraps to `MIN`, `MIN MOD -1` is 0; MOD takes the dividend's sign.
//! - Shifts: the amount is the right operand read as unsigned; an amount ≥ the bit width gives 0
//!   (and for `>>` of a negative signed value, -1). `>>` is arithmetic for INT/DINT.
//! - REAL/LREAL: IEEE operations, no fused ops; the result of `+ - * /` and of REAL↔LREAL
//!   conversion is replaced by the canonical quiet NaN (`0x7FC0_0000` / `0x7FF8_0000_0000_0000`)
//!   when it is a NaN. Float division by zero gives ±inf/NaN and no fault. `MIN(a,b)` is
//!   `if b < a {b} else {a}`, `MAX(a,b)` `if b > a {b} else {a}`, `LIMIT(lo,x,hi)` = `MIN(MAX(x,lo),hi)`.
//! - Conversions: integer → integer keeps the low bits (sign-extending a signed source);
//!   float → integer saturates to i64 (NaN → 0) and then keeps the low bits; integer → float rounds
//!   to nearest; `BOOL(x)` is `x <> 0` (NaN → TRUE); BOOL → number is 0/1.
//! - `BCD(x)` reads the bits of x as unsigned, keeps the low `2 * size` decimal digits and packs them
//!   one per nibble; `BIN(x)` reads the bits as unsigned and adds nibble `i` × 10^i (wrapping).
//! - `ABS` wraps (`ABS(-32768)` is -32768 for INT) and is the identity on unsigned types; on
//!   floats it clears the sign bit. Unary minus wraps; on floats it flips the sign bit.
//! - A BOOL variable reads as `byte <> 0` and is written as 0/1.
//! - Timers, counters and pulses follow docs/plc-language.md §4.1/§4.2; the exact update rules are on
//!   [`Stmt::Timer`], [`Stmt::CounterCount`], [`Stmt::CounterReset`] and [`Stmt::Pulse`].
//! - A tick runs the FAST part, then SLOW slice `i = next` (0 when `next` is out of range) and
//!   stores `(i + 1) mod slices`. A program without SLOW part leaves the header untouched.

mod builder;
pub mod flow;
mod idle;
mod program;
mod validate;

pub use builder::{COST_UNITS_PER_MS, ProgramBuilder, slice_cost, split_slices};
pub use idle::{IdleFacts, SteadyTimer};
pub use program::{
    CounterDecl, CounterKind, Program, PulseDecl, SlotKind, StateSlot, TimerDecl, TimerKind,
    VarDecl,
};
pub use validate::IrError;

use packets::Signal;
use serde::{Deserialize, Serialize};

/// Offset of the scan header (right after the packets).
pub const HEADER_OFFSET: usize = packets::PACKETS_LEN;
/// Length of the scan header.
pub const HEADER_LEN: usize = 16;
/// Image offset of the u32 index of the next SLOW slice.
pub const HDR_NEXT_SLICE: usize = HEADER_OFFSET;
/// Image offset of the u32 fault flags.
pub const HDR_FAULTS: usize = HEADER_OFFSET + 4;
/// Fault flag: an integer division or MOD by zero happened.
pub const FAULT_DIV_ZERO: u32 = 1;
/// Canonical quiet NaN of REAL.
pub const CANON_NAN_F32: u32 = 0x7FC0_0000;
/// Canonical quiet NaN of LREAL.
pub const CANON_NAN_F64: u64 = 0x7FF8_0000_0000_0000;
/// Length of one timer's state.
pub const TIMER_LEN: usize = 8;
/// Length of one counter's state.
pub const COUNTER_LEN: usize = 8;
/// Flag bit of a timer's Q.
pub const FLAG_Q: u8 = 1;
/// Flag bit of the previous input (timers, counters, pulses).
pub const FLAG_PREV: u8 = 2;
/// Flag bit of a running timer, or of a counter's stored R/LD input.
pub const FLAG_RUN: u8 = 4;

/// An elementary type of the language.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Ty {
    /// Boolean, one bit in a signal or one byte 0/1 in a variable.
    Bool,
    /// u8.
    Byte,
    /// u16.
    Word,
    /// u32.
    Dword,
    /// i16.
    Int,
    /// i32.
    Dint,
    /// f32.
    Real,
    /// f64.
    Lreal,
}

impl Ty {
    /// Size in bytes in the image.
    pub const fn size(self) -> usize {
        match self {
            Ty::Bool | Ty::Byte => 1,
            Ty::Word | Ty::Int => 2,
            Ty::Dword | Ty::Dint | Ty::Real => 4,
            Ty::Lreal => 8,
        }
    }
    /// Width in bits of the value (1 for BOOL).
    pub const fn bits(self) -> u32 {
        match self {
            Ty::Bool => 1,
            _ => self.size() as u32 * 8,
        }
    }
    /// True for BYTE, WORD, DWORD, INT, DINT.
    pub const fn is_int(self) -> bool {
        matches!(self, Ty::Byte | Ty::Word | Ty::Dword | Ty::Int | Ty::Dint)
    }
    /// True for INT and DINT.
    pub const fn is_signed(self) -> bool {
        matches!(self, Ty::Int | Ty::Dint)
    }
    /// True for REAL and LREAL.
    pub const fn is_float(self) -> bool {
        matches!(self, Ty::Real | Ty::Lreal)
    }
    /// The keyword, as the source writes it.
    pub const fn name(self) -> &'static str {
        match self {
            Ty::Bool => "BOOL",
            Ty::Byte => "BYTE",
            Ty::Word => "WORD",
            Ty::Dword => "DWORD",
            Ty::Int => "INT",
            Ty::Dint => "DINT",
            Ty::Real => "REAL",
            Ty::Lreal => "LREAL",
        }
    }
}

/// A typed constant.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Value {
    /// BOOL.
    Bool(bool),
    /// BYTE.
    Byte(u8),
    /// WORD.
    Word(u16),
    /// DWORD.
    Dword(u32),
    /// INT.
    Int(i16),
    /// DINT.
    Dint(i32),
    /// REAL.
    Real(f32),
    /// LREAL.
    Lreal(f64),
}

impl Value {
    /// The constant's type.
    pub const fn ty(self) -> Ty {
        match self {
            Value::Bool(_) => Ty::Bool,
            Value::Byte(_) => Ty::Byte,
            Value::Word(_) => Ty::Word,
            Value::Dword(_) => Ty::Dword,
            Value::Int(_) => Ty::Int,
            Value::Dint(_) => Ty::Dint,
            Value::Real(_) => Ty::Real,
            Value::Lreal(_) => Ty::Lreal,
        }
    }
    /// The little-endian bytes as stored in the image (BOOL: one byte 0/1), zero-padded to 8.
    pub fn to_bits(self) -> u64 {
        match self {
            Value::Bool(b) => u64::from(b),
            Value::Byte(v) => u64::from(v),
            Value::Word(v) => u64::from(v),
            Value::Dword(v) => u64::from(v),
            Value::Int(v) => u64::from(v as u16),
            Value::Dint(v) => u64::from(v as u32),
            Value::Real(v) => u64::from(v.to_bits()),
            Value::Lreal(v) => v.to_bits(),
        }
    }
    /// The zero of a type.
    pub const fn zero(ty: Ty) -> Value {
        match ty {
            Ty::Bool => Value::Bool(false),
            Ty::Byte => Value::Byte(0),
            Ty::Word => Value::Word(0),
            Ty::Dword => Value::Dword(0),
            Ty::Int => Value::Int(0),
            Ty::Dint => Value::Dint(0),
            Ty::Real => Value::Real(0.0),
            Ty::Lreal => Value::Lreal(0.0),
        }
    }
}

/// Index of a variable in [`Program::vars`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct VarId(pub u32);
/// Index of a timer in [`Program::timers`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct TimerId(pub u32);
/// Index of a counter in [`Program::counters`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct CounterId(pub u32);
/// Index of a pulse in [`Program::pulses`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct PulseId(pub u32);

/// Something an assignment writes and a load reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Place {
    /// A packet signal: a bit (`I…`/`U…`, type BOOL) or a byte (`W…`/`S…`, type BYTE).
    Signal(Signal),
    /// A typed view `AT` a byte signal: `ty.size()` consecutive bytes of the same connector,
    /// little-endian, starting at `at` (must be a [`Signal::Byte`]; not BOOL).
    View {
        /// The first (least significant) byte.
        at: Signal,
        /// The view's type.
        ty: Ty,
    },
    /// An internal variable.
    Var(VarId),
    /// Bit `bit` of an integer variable (`x.n`, type BOOL; `bit` < the variable's width).
    VarBit {
        /// The variable.
        var: VarId,
        /// Bit number, 0 = least significant.
        bit: u8,
    },
}

/// Unary operators on numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum UnOp {
    /// Arithmetic negation (wraps).
    Neg,
    /// Bitwise complement `~` (integers only).
    BitNot,
    /// Absolute value (wraps).
    Abs,
}

/// Binary operators; both operands and the result have the operator's type.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum BinOp {
    /// `+` on numbers.
    Add,
    /// `-`.
    Sub,
    /// `*` on numbers.
    Mul,
    /// `/` (integer: guarded, see module docs).
    Div,
    /// `MOD` (integers only).
    Mod,
    /// `&` (integers).
    BitAnd,
    /// `|` (integers).
    BitOr,
    /// `^` (integers).
    BitXor,
    /// `<<` (integers).
    Shl,
    /// `>>` (integers; arithmetic for signed).
    Shr,
    /// `MIN(a, b)` on numbers.
    Min,
    /// `MAX(a, b)` on numbers.
    Max,
    /// BOOL AND (`*`).
    And,
    /// BOOL OR (`+`).
    Or,
    /// BOOL XOR.
    Xor,
}

/// Comparison operators (result BOOL).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum CmpOp {
    /// `=`.
    Eq,
    /// `<>` (true for NaN).
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

/// A typed expression. Evaluation has no side effects (inline timers are lowered to a
/// [`Stmt::Timer`] before the statement plus an [`Expr::TimerQ`] read).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Expr {
    /// A constant.
    Const(Value),
    /// Reads a place.
    Load(Place),
    /// Bit `bit` of an integer expression of type `ty` (BOOL).
    BitOf {
        /// The integer type of `value`.
        ty: Ty,
        /// The integer.
        value: Box<Expr>,
        /// Bit number < `ty.bits()`.
        bit: u8,
    },
    /// BOOL negation (`/`, `NOT`).
    Not(Box<Expr>),
    /// A unary operator on a number of type `ty`.
    Unary {
        /// The operator.
        op: UnOp,
        /// Operand and result type.
        ty: Ty,
        /// The operand.
        arg: Box<Expr>,
    },
    /// A binary operator; both operands and the result have type `ty`.
    Binary {
        /// The operator.
        op: BinOp,
        /// Operand and result type.
        ty: Ty,
        /// Left operand.
        lhs: Box<Expr>,
        /// Right operand.
        rhs: Box<Expr>,
    },
    /// A comparison of two operands of type `ty` (BOOL result).
    Cmp {
        /// The comparison.
        op: CmpOp,
        /// Operand type.
        ty: Ty,
        /// Left operand.
        lhs: Box<Expr>,
        /// Right operand.
        rhs: Box<Expr>,
    },
    /// A conversion `to(arg)` from `from`.
    Convert {
        /// Source type.
        from: Ty,
        /// Target type.
        to: Ty,
        /// The operand.
        arg: Box<Expr>,
    },
    /// `BCD(x)`: binary to packed BCD in integer type `ty`.
    Bcd {
        /// Operand and result type.
        ty: Ty,
        /// The operand.
        arg: Box<Expr>,
    },
    /// `BIN(x)`: packed BCD to binary in integer type `ty`.
    Bin {
        /// Operand and result type.
        ty: Ty,
        /// The operand.
        arg: Box<Expr>,
    },
    /// `LIMIT(lo, x, hi)` = `MIN(MAX(x, lo), hi)` on numbers of type `ty`.
    Limit {
        /// Operand and result type.
        ty: Ty,
        /// Lower bound.
        lo: Box<Expr>,
        /// The value.
        x: Box<Expr>,
        /// Upper bound.
        hi: Box<Expr>,
    },
    /// The current value of pulse `P<n>` (BOOL).
    Pulse(PulseId),
    /// A timer's Q (BOOL).
    TimerQ(TimerId),
    /// A timer's ET in ms (DINT).
    TimerEt(TimerId),
    /// A counter's Q (BOOL): `CV >= PV` for CTU, `CV <= 0` for CTD.
    CounterQ(CounterId),
    /// A counter's CV (DINT).
    CounterCv(CounterId),
}

impl Expr {
    /// The expression's type (meaningful for validated programs).
    pub fn ty(&self, p: &Program) -> Ty {
        match self {
            Expr::Const(v) => v.ty(),
            Expr::Load(place) => p.place_ty(place),
            Expr::BitOf { .. } | Expr::Not(_) | Expr::Cmp { .. } | Expr::Pulse(_) => Ty::Bool,
            Expr::TimerQ(_) | Expr::CounterQ(_) => Ty::Bool,
            Expr::TimerEt(_) | Expr::CounterCv(_) => Ty::Dint,
            Expr::Unary { ty, .. }
            | Expr::Binary { ty, .. }
            | Expr::Bcd { ty, .. }
            | Expr::Bin { ty, .. }
            | Expr::Limit { ty, .. } => *ty,
            Expr::Convert { to, .. } => *to,
        }
    }
    /// Number of nodes (the cost model's unit).
    pub fn nodes(&self) -> u32 {
        match self {
            Expr::Const(_)
            | Expr::Load(_)
            | Expr::Pulse(_)
            | Expr::TimerQ(_)
            | Expr::TimerEt(_)
            | Expr::CounterQ(_)
            | Expr::CounterCv(_) => 1,
            Expr::BitOf { value: a, .. }
            | Expr::Not(a)
            | Expr::Unary { arg: a, .. }
            | Expr::Convert { arg: a, .. } => 1 + a.nodes(),
            Expr::Bcd { arg, .. } | Expr::Bin { arg, .. } => 8 + arg.nodes(),
            Expr::Binary { lhs, rhs, .. } | Expr::Cmp { lhs, rhs, .. } => {
                1 + lhs.nodes() + rhs.nodes()
            }
            Expr::Limit { lo, x, hi, .. } => 2 + lo.nodes() + x.nodes() + hi.nodes(),
        }
    }
}

/// A statement.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Stmt {
    /// `place = value` (a coil); `value` has the place's type.
    Assign {
        /// The target.
        place: Place,
        /// The value.
        value: Expr,
    },
    /// `SET place = cond`: if cond, the BOOL place := 1.
    Set {
        /// The BOOL target.
        place: Place,
        /// The condition.
        cond: Expr,
    },
    /// `RES place = cond`: if cond, the BOOL place := 0.
    Res {
        /// The BOOL target.
        place: Place,
        /// The condition.
        cond: Expr,
    },
    /// `P<n> = input`: value := input AND NOT prev; prev := input.
    Pulse {
        /// The pulse.
        pulse: PulseId,
        /// The BOOL input.
        input: Expr,
    },
    /// Drives a timer's IN. With `tick` = [`Program::tick_ms`] and PT the rounded preset:
    /// - TON: `ET := IN ? (prev ? min(ET + tick, PT) : 0) : 0; Q := IN AND ET >= PT`.
    /// - TOF: if IN: `Q := 1, ET := 0, running := 0`; else if prev: `running := 1, ET := 0`; else
    ///   if running: `ET := ET + tick`; then (IN = 0) if running and `ET >= PT`: `running := 0`;
    ///   `Q := IN OR running`.
    /// - TP: if running: `ET := ET + tick`, and if `ET >= PT`: stop; else if IN rose and PT > 0:
    ///   start, `ET := 0`; else if not IN: `ET := 0`. `Q := running`.
    ///
    /// In every case prev := IN afterwards.
    Timer {
        /// The timer.
        timer: TimerId,
        /// The BOOL input.
        input: Expr,
    },
    /// A counter's count input: CTU: if not R and the input rose, `CV := CV + 1` (saturating);
    /// CTD: if not LD and the input rose, `CV := CV - 1` (saturating). prev := input.
    CounterCount {
        /// The counter.
        counter: CounterId,
        /// The BOOL input.
        input: Expr,
    },
    /// A counter's second input: CTU `c.R = x` (R := x; if x, CV := 0), CTD `c.LD = x`
    /// (LD := x; if x, CV := PV).
    CounterReset {
        /// The counter.
        counter: CounterId,
        /// The BOOL input.
        input: Expr,
    },
    /// `IF cond THEN … ELSE … END_IF`: a master-control zone.
    If {
        /// The BOOL condition.
        cond: Expr,
        /// Statements run when cond holds.
        then_: Vec<Stmt>,
        /// Statements run otherwise.
        else_: Vec<Stmt>,
    },
}

impl Stmt {
    /// The cost estimate used to cut the SLOW part into slices (expression nodes, +4 per
    /// stateful element, IF zones count both branches).
    pub fn cost(&self) -> u32 {
        match self {
            Stmt::Assign { value: e, .. }
            | Stmt::Set { cond: e, .. }
            | Stmt::Res { cond: e, .. } => 1 + e.nodes(),
            Stmt::Pulse { input, .. }
            | Stmt::CounterCount { input, .. }
            | Stmt::CounterReset { input, .. } => 3 + input.nodes(),
            Stmt::Timer { input, .. } => 5 + input.nodes(),
            Stmt::If { cond, then_, else_ } => {
                let body: u32 = then_
                    .iter()
                    .chain(else_)
                    .map(Stmt::cost)
                    .fold(0, u32::saturating_add);
                (1 + cond.nodes()).saturating_add(body)
            }
        }
    }
}
