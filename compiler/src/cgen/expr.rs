//! Expressions as C: every value is an `int64_t` normalised to its type (as the interpreter's
//! `V::I`), a `float` (REAL) or a `double` (LREAL).

use std::fmt::Write;

use crate::ir::{BinOp, CmpOp, CounterKind, Expr, Place, Program, Ty, UnOp};

/// How a C expression holds its value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kind {
    /// `int64_t`, normalised to the IR type.
    I,
    /// `float`.
    F,
    /// `double`.
    D,
}

/// The C kind of an IR type.
pub(super) fn kind(ty: Ty) -> Kind {
    match ty {
        Ty::Real => Kind::F,
        Ty::Lreal => Kind::D,
        _ => Kind::I,
    }
}

/// The normalising helper of an integer type (`n_byte`, …); REAL/LREAL need none.
fn norm(ty: Ty) -> &'static str {
    match ty {
        Ty::Bool => "n_bool",
        Ty::Byte => "n_byte",
        Ty::Word => "n_word",
        Ty::Dword => "n_dword",
        Ty::Int => "n_int",
        Ty::Dint => "n_dint",
        Ty::Real | Ty::Lreal => "",
    }
}

fn mask(ty: Ty) -> u64 {
    if ty.size() >= 8 {
        u64::MAX
    } else {
        (1u64 << (8 * ty.size())) - 1
    }
}

/// Image byte and bit of a place (`None` for a whole value).
pub(super) fn place_at(p: &Program, place: &Place) -> (usize, Option<u8>) {
    match *place {
        Place::Signal(sig) => (sig.image_byte(), sig.bit()),
        Place::View { at, .. } => (at.image_byte(), None),
        Place::Var(v) => (p.vars[v.0 as usize].offset, None),
        Place::VarBit { var, bit } => (
            p.vars[var.0 as usize].offset + bit as usize / 8,
            Some(bit % 8),
        ),
    }
}

/// The C text of `e` and its kind.
pub(super) fn expr(p: &Program, e: &Expr) -> (String, Kind) {
    let mut s = String::new();
    let k = write_expr(p, e, &mut s);
    (s, k)
}

/// `e` as a C truth value (`e` is BOOL, hence an int).
pub(super) fn cond(p: &Program, e: &Expr) -> String {
    let (s, _) = expr(p, e);
    format!("({s} != 0)")
}

fn write_expr(p: &Program, e: &Expr, s: &mut String) -> Kind {
    match e {
        Expr::Const(v) => {
            let bits = v.to_bits();
            match v.ty() {
                Ty::Real => {
                    let _ = write!(s, "f32b({bits:#x}u)");
                    Kind::F
                }
                Ty::Lreal => {
                    let _ = write!(s, "f64b({bits:#x}ull)");
                    Kind::D
                }
                ty => {
                    let v = match ty {
                        Ty::Int => i64::from(bits as u16 as i16),
                        Ty::Dint => i64::from(bits as u32 as i32),
                        _ => bits as i64,
                    };
                    let _ = write!(s, "INT64_C({v})");
                    Kind::I
                }
            }
        }
        Expr::Load(place) => load(p, place, s),
        Expr::BitOf { value, bit, .. } => {
            let (v, _) = expr(p, value);
            let _ = write!(s, "((({v}) >> {bit}) & 1)");
            Kind::I
        }
        Expr::Not(a) => {
            let (v, _) = expr(p, a);
            let _ = write!(s, "(int64_t)(({v}) == 0)");
            Kind::I
        }
        Expr::Unary { op, ty, arg } => {
            let (v, k) = expr(p, arg);
            let _ = match (op, k) {
                (UnOp::Neg, Kind::F | Kind::D) => write!(s, "(-({v}))"),
                (UnOp::Abs, Kind::F) => write!(s, "fabsf({v})"),
                (UnOp::Abs, Kind::D) => write!(s, "fabs({v})"),
                (UnOp::Neg, Kind::I) => write!(s, "{}(wsub(0, {v}))", norm(*ty)),
                (UnOp::Abs, Kind::I) => write!(s, "{}(iabs({v}))", norm(*ty)),
                (UnOp::BitNot, Kind::I) => write!(s, "{}(~({v}))", norm(*ty)),
                (UnOp::BitNot, _) => write!(s, "({v})"),
            };
            k
        }
        Expr::Binary { op, ty, lhs, rhs } => {
            let (a, k) = expr(p, lhs);
            let (b, _) = expr(p, rhs);
            binary(*op, *ty, k, &a, &b, s);
            k
        }
        Expr::Cmp { op, lhs, rhs, .. } => {
            let (a, _) = expr(p, lhs);
            let (b, _) = expr(p, rhs);
            let o = match op {
                CmpOp::Eq => "==",
                CmpOp::Ne => "!=",
                CmpOp::Lt => "<",
                CmpOp::Le => "<=",
                CmpOp::Gt => ">",
                CmpOp::Ge => ">=",
            };
            let _ = write!(s, "(int64_t)(({a}) {o} ({b}))");
            Kind::I
        }
        Expr::Convert { to, arg, .. } => {
            let (v, k) = expr(p, arg);
            let _ = match (k, to) {
                (Kind::F, Ty::Real) | (Kind::D, Ty::Lreal) => write!(s, "({v})"),
                (Kind::F, Ty::Lreal) => write!(s, "c64((double)({v}))"),
                (Kind::D, Ty::Real) => write!(s, "c32((float)({v}))"),
                (Kind::F | Kind::D, Ty::Bool) => write!(s, "(int64_t)(({v}) != 0)"),
                (Kind::F | Kind::D, _) => write!(s, "{}(sat64({v}))", norm(*to)),
                (Kind::I, Ty::Real) => write!(s, "(float)({v})"),
                (Kind::I, Ty::Lreal) => write!(s, "(double)({v})"),
                (Kind::I, _) => write!(s, "{}({v})", norm(*to)),
            };
            kind(*to)
        }
        Expr::Bcd { ty, arg } | Expr::Bin { ty, arg } => {
            let (v, _) = expr(p, arg);
            let f = if matches!(e, Expr::Bcd { .. }) {
                "bcd"
            } else {
                "bin"
            };
            let _ = write!(
                s,
                "{}((int64_t){f}((uint64_t)({v}) & {:#x}ull, {}))",
                norm(*ty),
                mask(*ty),
                2 * ty.size()
            );
            Kind::I
        }
        Expr::Limit { ty, lo, x, hi } => {
            let (lo, k) = expr(p, lo);
            let (x, _) = expr(p, x);
            let (hi, _) = expr(p, hi);
            let mut inner = String::new();
            binary(BinOp::Max, *ty, k, &x, &lo, &mut inner);
            binary(BinOp::Min, *ty, k, &inner, &hi, s);
            k
        }
        Expr::Pulse(id) => {
            let at = p.pulses[id.0 as usize].offset;
            let _ = write!(s, "(int64_t)(m[{at}] & 1)");
            Kind::I
        }
        Expr::TimerQ(id) => {
            let at = p.timers[id.0 as usize].offset + 4;
            let _ = write!(s, "(int64_t)(m[{at}] & 1)");
            Kind::I
        }
        Expr::TimerEt(id) => {
            let at = p.timers[id.0 as usize].offset;
            let _ = write!(s, "(int64_t)(int32_t)ld(m, {at}, 4)");
            Kind::I
        }
        Expr::CounterQ(id) => {
            let d = &p.counters[id.0 as usize];
            let at = d.offset;
            let _ = match d.kind {
                CounterKind::Ctu => write!(s, "(int64_t)((int32_t)ld(m, {at}, 4) >= {})", d.preset),
                CounterKind::Ctd => write!(s, "(int64_t)((int32_t)ld(m, {at}, 4) <= 0)"),
            };
            Kind::I
        }
        Expr::CounterCv(id) => {
            let at = p.counters[id.0 as usize].offset;
            let _ = write!(s, "(int64_t)(int32_t)ld(m, {at}, 4)");
            Kind::I
        }
    }
}

fn load(p: &Program, place: &Place, s: &mut String) -> Kind {
    let (at, bit) = place_at(p, place);
    if let Some(bit) = bit {
        let _ = write!(s, "(int64_t)((m[{at}] >> {bit}) & 1)");
        return Kind::I;
    }
    let ty = p.place_ty(place);
    let _ = match ty {
        Ty::Real => write!(s, "ldf(m, {at})"),
        Ty::Lreal => write!(s, "ldd(m, {at})"),
        Ty::Bool => write!(s, "(int64_t)(m[{at}] != 0)"),
        Ty::Byte => write!(s, "(int64_t)m[{at}]"),
        Ty::Word => write!(s, "(int64_t)(uint16_t)ld(m, {at}, 2)"),
        Ty::Dword => write!(s, "(int64_t)(uint32_t)ld(m, {at}, 4)"),
        Ty::Int => write!(s, "(int64_t)(int16_t)ld(m, {at}, 2)"),
        Ty::Dint => write!(s, "(int64_t)(int32_t)ld(m, {at}, 4)"),
    };
    kind(ty)
}

fn binary(op: BinOp, ty: Ty, k: Kind, a: &str, b: &str, s: &mut String) {
    let _ = match k {
        Kind::F | Kind::D => {
            let (c, w) = if k == Kind::F {
                ("c32", "32")
            } else {
                ("c64", "64")
            };
            match op {
                BinOp::Add => write!(s, "{c}(({a}) + ({b}))"),
                BinOp::Sub => write!(s, "{c}(({a}) - ({b}))"),
                BinOp::Mul => write!(s, "{c}(({a}) * ({b}))"),
                BinOp::Div => write!(s, "{c}(({a}) / ({b}))"),
                BinOp::Min => write!(s, "fmin{w}({a}, {b})"),
                BinOp::Max => write!(s, "fmax{w}({a}, {b})"),
                _ => write!(s, "({a})"),
            }
        }
        Kind::I => {
            let n = norm(ty);
            let (m, bits) = (mask(ty), ty.bits());
            match op {
                BinOp::Add => write!(s, "{n}(wadd({a}, {b}))"),
                BinOp::Sub => write!(s, "{n}(wsub({a}, {b}))"),
                BinOp::Mul => write!(s, "{n}(wmul({a}, {b}))"),
                BinOp::Div => write!(s, "{n}(idiv(m, {a}, {b}))"),
                BinOp::Mod => write!(s, "{n}(imod(m, {a}, {b}))"),
                BinOp::BitAnd | BinOp::And => write!(s, "(({a}) & ({b}))"),
                BinOp::BitOr | BinOp::Or => write!(s, "(({a}) | ({b}))"),
                BinOp::BitXor | BinOp::Xor => write!(s, "(({a}) ^ ({b}))"),
                BinOp::Shl => write!(s, "{n}(ishl({a}, {b}, {m:#x}ull, {bits}))"),
                BinOp::Shr => write!(s, "{n}(ishr({a}, {b}, {m:#x}ull, {bits}))"),
                BinOp::Min => write!(s, "imin({a}, {b})"),
                BinOp::Max => write!(s, "imax({a}, {b})"),
            }
        }
    };
}
