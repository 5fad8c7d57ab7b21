//! The reference interpreter of macro expressions and the arithmetic rules both back ends share.
//!
//! Values are `f64`; the null value (an undefined variable, `#0`) is a NaN. Null rules (Fanuc Macro B):
//! a variable read as such keeps null (`#2 = #1` copies it, `X#1` drops the word); every operation and
//! function reads null as 0; `EQ`/`NE` compare null only equal to null; `GT GE LT LE` read it as 0.
//! Every operation's result must be finite: a NaN or infinity (SQRT of a negative, LN of 0, ASIN of
//! 2, an overflow) is error [`MacroError::Range`], a zero divisor of `/` or `MOD` [`MacroError::DivZero`].
//! Functions run through the `extern "C"` functions of this module, which the native code calls too,
//! so both back ends compute the same bits.

use super::{BinOp, Expr, Func};
use detmath::Det as _;

/// Why a macro expression or statement failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum MacroError {
    /// A zero divisor of `/` or `MOD`.
    #[error("division by zero")]
    DivZero,
    /// A result that is not a finite number.
    #[error("value out of range (SQRT, LN, ASIN, ACOS, BIN, BCD argument or overflow)")]
    Range,
    /// A variable number that does not exist.
    #[error("variable #{0} does not exist")]
    NoVar(i64),
    /// A variable that cannot be written.
    #[error("variable #{0} cannot be written")]
    ReadOnly(i64),
}

impl MacroError {
    /// The code native functions return for this error (never 0).
    pub fn code(self) -> i64 {
        match self {
            MacroError::DivZero => 1,
            MacroError::Range => 2,
            MacroError::NoVar(_) => 3,
            MacroError::ReadOnly(_) => 4,
        }
    }

    /// The error of native code `c` (variable numbers are not carried: native code never fails on them).
    pub fn from_code(c: i64) -> MacroError {
        match c {
            1 => MacroError::DivZero,
            2 => MacroError::Range,
            3 => MacroError::NoVar(-1),
            _ => MacroError::ReadOnly(-1),
        }
    }
}

/// Where expression evaluation reads variables.
pub trait Vars {
    /// The value of variable `n` (NaN: null), or why it cannot be read.
    fn get(&self, n: i64) -> Result<f64, MacroError>;
}

/// Null read as a number: 0.
#[inline]
pub fn z(x: f64) -> f64 {
    if x.is_nan() { 0.0 } else { x }
}

/// True when `x` is the null value.
#[inline]
pub fn is_null(x: f64) -> bool {
    x.is_nan()
}

/// A finite result or [`MacroError::Range`].
#[inline]
fn fin(x: f64) -> Result<f64, MacroError> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(MacroError::Range)
    }
}

/// Code of `f` passed to [`host_func`].
pub fn func_code(f: Func) -> i64 {
    f as i64
}

fn func_of(code: i64) -> Option<Func> {
    use Func::*;
    [
        Sin, Cos, Tan, Asin, Acos, Atan, Sqrt, Abs, Round, Fix, Fup, Ln, Exp, Bin, Bcd,
    ]
    .into_iter()
    .find(|f| *f as i64 == code)
}

/// Degrees to radians as both back ends compute it.
fn rad(x: f64) -> f64 {
    x * (std::f64::consts::PI / 180.0)
}

/// Radians to degrees.
fn deg(x: f64) -> f64 {
    x * (180.0 / std::f64::consts::PI)
}

/// BCD to binary: each 4-bit digit of the integer part of `x` (0..=9) weighs a power of ten.
fn bin(x: f64) -> f64 {
    if !(0.0..=4_294_967_295.0).contains(&x) {
        return f64::NAN;
    }
    let mut v = x as u64;
    let (mut out, mut w) = (0u64, 1u64);
    while v > 0 {
        let d = v & 15;
        if d > 9 {
            return f64::NAN;
        }
        out += d * w;
        w *= 10;
        v >>= 4;
    }
    out as f64
}

/// Binary to BCD: the decimal digits of the integer part of `x` (0..=99999999) as 4-bit digits.
fn bcd(x: f64) -> f64 {
    if !(0.0..=99_999_999.0).contains(&x) {
        return f64::NAN;
    }
    let mut v = x as u64;
    let (mut out, mut sh) = (0u64, 0);
    while v > 0 {
        out |= (v % 10) << sh;
        sh += 4;
        v /= 10;
    }
    out as f64
}

/// Function `code` ([`func_code`]) of `x` (null already read as 0); NaN when undefined there.
pub extern "C" fn host_func(code: i64, x: f64) -> f64 {
    let Some(f) = func_of(code) else {
        return f64::NAN;
    };
    match f {
        Func::Sin => rad(x).dsin(),
        Func::Cos => rad(x).dcos(),
        Func::Tan => rad(x).dtan(),
        Func::Asin => deg(x.dasin()),
        Func::Acos => deg(x.dacos()),
        Func::Atan => deg(x.datan()),
        Func::Sqrt => x.sqrt(),
        Func::Abs => x.abs(),
        Func::Round => x.round(),
        Func::Fix => x.trunc(),
        Func::Fup => {
            let t = x.trunc();
            if t == x {
                x
            } else if x > 0.0 {
                t + 1.0
            } else {
                t - 1.0
            }
        }
        Func::Ln => {
            if x > 0.0 {
                x.dln()
            } else {
                f64::NAN
            }
        }
        Func::Exp => x.dexp(),
        Func::Bin => bin(x),
        Func::Bcd => bcd(x),
    }
}

/// `ATAN[a]/[b]`: the angle of (b, a) in degrees, 0 ≤ angle < 360 (Fanuc's range).
pub extern "C" fn host_atan2(a: f64, b: f64) -> f64 {
    let d = deg(a.datan2(b));
    if d < 0.0 { d + 360.0 } else { d }
}

/// `a MOD b` for operands already rounded to integers, `b` ≠ 0: the remainder with the sign of `a`.
pub extern "C" fn host_mod(a: f64, b: f64) -> f64 {
    a % b
}

/// The variable number of `#[v]`: `v` rounded to an integer (null reads as #0).
pub fn var_number(v: f64) -> i64 {
    let r = z(v).round();
    if r.abs() > 1e9 { -1 } else { r as i64 }
}

/// Applies `op` to raw operand values (null as NaN) by the rules above.
pub fn binop(op: BinOp, a: f64, b: f64) -> Result<f64, MacroError> {
    let bool_f = |c: bool| if c { 1.0 } else { 0.0 };
    match op {
        BinOp::Eq => Ok(bool_f(eq(a, b))),
        BinOp::Ne => Ok(bool_f(!eq(a, b))),
        _ => {
            let (a, b) = (z(a), z(b));
            match op {
                BinOp::Add => fin(a + b),
                BinOp::Sub => fin(a - b),
                BinOp::Mul => fin(a * b),
                BinOp::Div => {
                    if b == 0.0 {
                        Err(MacroError::DivZero)
                    } else {
                        fin(a / b)
                    }
                }
                BinOp::Mod => {
                    let (a, b) = (
                        host_func(Func::Round as i64, a),
                        host_func(Func::Round as i64, b),
                    );
                    if b == 0.0 {
                        Err(MacroError::DivZero)
                    } else {
                        fin(host_mod(a, b))
                    }
                }
                BinOp::And => Ok(((a as i64) & (b as i64)) as f64),
                BinOp::Or => Ok(((a as i64) | (b as i64)) as f64),
                BinOp::Xor => Ok(((a as i64) ^ (b as i64)) as f64),
                BinOp::Gt => Ok(bool_f(a > b)),
                BinOp::Ge => Ok(bool_f(a >= b)),
                BinOp::Lt => Ok(bool_f(a < b)),
                BinOp::Le => Ok(bool_f(a <= b)),
                BinOp::Eq | BinOp::Ne => Ok(0.0),
            }
        }
    }
}

/// `EQ`: null equals only null; numbers compare as numbers.
fn eq(a: f64, b: f64) -> bool {
    match (a.is_nan(), b.is_nan()) {
        (true, true) => true,
        (false, false) => a == b,
        _ => false,
    }
}

/// Evaluates `e`; the result is raw (null when `e` is a variable that is null).
pub fn eval(e: &Expr, vars: &dyn Vars) -> Result<f64, MacroError> {
    match e {
        Expr::Num(v) => Ok(*v),
        Expr::Var(n) => vars.get(i64::from(*n)),
        Expr::VarAt(x) => {
            let n = var_number(eval(x, vars)?);
            vars.get(n)
        }
        Expr::Neg(x) => fin(-z(eval(x, vars)?)),
        Expr::Bin(op, a, b) => {
            let a = eval(a, vars)?;
            let b = eval(b, vars)?;
            binop(*op, a, b)
        }
        Expr::Call(f, x) => fin(host_func(*f as i64, z(eval(x, vars)?))),
        Expr::Atan2(a, b) => {
            let a = z(eval(a, vars)?);
            let b = z(eval(b, vars)?);
            fin(host_atan2(a, b))
        }
    }
}

/// A condition: true when the value (null read as 0) is not zero.
pub fn truth(v: f64) -> bool {
    z(v) != 0.0
}
