//! Expression checking: resolves names, types every operand and builds the typed IR expression.
//!
//! Literals stay untyped ([`Val::Lit`]) until an operand or the target gives them a type
//! ("a literal takes the type of the other operand or of the target"). The meaning of `+`, `*`,
//! `OR`, `AND`, `XOR`, `&`, `|`, `^` follows the operand type: logic on BOOL, arithmetic or bitwise
//! on numbers. Inline timers become a [`ir::Stmt::Timer`] in `pending` (emitted before the
//! statement) plus a read of their Q.

use super::memo;
use super::signals::{Access, check_signal};
use super::symbols::{FUNCTIONS, const_lit};
use super::types::{Lit, LitError, common, lit_value, type_by_name, widens};
use super::{Checker, SymKind, codes};
use crate::ast::{BinOp, CmpOp, Expr, ExprKind, Name, Span, UnOp};
use crate::ir::{self, Ty};

/// A checked operand: an untyped literal or a typed IR expression.
#[derive(Debug, Clone)]
pub(crate) enum Val {
    /// A constant whose type is not decided yet.
    Lit(Lit),
    /// A typed expression.
    Typed(ir::Expr, Ty),
}

pub(crate) fn bx(e: ir::Expr) -> Box<ir::Expr> {
    Box::new(e)
}

impl Checker<'_> {
    /// Checks `e` and converts it to `ty` (implicit widening only).
    pub(crate) fn expr_to(&mut self, e: &Expr, ty: Ty) -> Option<ir::Expr> {
        let v = self.infer(e)?;
        self.coerce(v, ty, &e.span)
    }

    /// Converts a checked operand to `ty`, reporting literals out of range and narrowing.
    pub(crate) fn coerce(&mut self, v: Val, ty: Ty, span: &Span) -> Option<ir::Expr> {
        match v {
            Val::Lit(l) => match lit_value(l, ty) {
                Ok(v) => Some(ir::Expr::Const(v)),
                Err(LitError::Range(r)) => {
                    self.error(
                        codes::LITERAL_RANGE,
                        span,
                        format!("{} does not fit {}", l.describe(), ty.name()),
                        format!("{} holds {r}", ty.name()),
                    );
                    None
                }
                Err(LitError::Kind) => {
                    let hint = match (l, ty) {
                        (Lit::Real(_), t) if t.is_int() => {
                            format!("write a whole number, or convert: {}(…)", t.name())
                        }
                        (_, Ty::Bool) => "a BOOL takes TRUE, FALSE, 1 or 0".to_string(),
                        _ => format!("write a {} constant", ty.name()),
                    };
                    self.error(
                        codes::TYPE_MISMATCH,
                        span,
                        format!(
                            "expected {}, found the constant {}",
                            ty.name(),
                            l.describe()
                        ),
                        hint,
                    );
                    None
                }
            },
            Val::Typed(e, t) if t == ty => Some(e),
            Val::Typed(e, t) if widens(t, ty) && t != Ty::Bool => Some(ir::Expr::Convert {
                from: t,
                to: ty,
                arg: bx(e),
            }),
            Val::Typed(_, t) if t != Ty::Bool && ty != Ty::Bool => {
                self.error(
                    codes::NARROWING,
                    span,
                    format!(
                        "a {} value does not fit {} without a conversion",
                        t.name(),
                        ty.name()
                    ),
                    format!("convert explicitly: {}(…) keeps the low bits", ty.name()),
                );
                None
            }
            Val::Typed(_, t) => {
                let hint = if ty == Ty::Bool {
                    "compare it in brackets, e.g. [x <> 0], or convert with BOOL(x)".to_string()
                } else {
                    format!("convert explicitly: {}(x) gives 0 or 1", ty.name())
                };
                self.error(
                    codes::TYPE_MISMATCH,
                    span,
                    format!("expected {}, found {}", ty.name(), t.name()),
                    hint,
                );
                None
            }
        }
    }

    /// Gives a literal its default type.
    pub(crate) fn typed(&mut self, v: Val, span: &Span) -> Option<(ir::Expr, Ty)> {
        match v {
            Val::Typed(e, t) => Some((e, t)),
            Val::Lit(l) => {
                let t = l.default_ty();
                self.coerce(Val::Lit(l), t, span).map(|e| (e, t))
            }
        }
    }

    /// Checks an expression.
    pub(crate) fn infer(&mut self, e: &Expr) -> Option<Val> {
        if let Some(l) = const_lit(e) {
            return Some(Val::Lit(l));
        }
        match &e.kind {
            ExprKind::Bool(_) | ExprKind::Int(_) | ExprKind::Real(_) | ExprKind::Duration(_) => {
                None
            }
            ExprKind::Error => None,
            ExprKind::Signal(raw) => {
                let mut d = Vec::new();
                let sig = check_signal(raw, &e.span, Access::Read, self.ctx, self.file, &mut d);
                self.diags.append(&mut d);
                let sig = sig?;
                let ty = if sig.bit().is_some() {
                    Ty::Bool
                } else {
                    Ty::Byte
                };
                Some(Val::Typed(ir::Expr::Load(ir::Place::Signal(sig)), ty))
            }
            ExprKind::Pulse(n) => {
                let n = self.pulse_number(*n, &e.span)?;
                self.pulses_read.entry(n).or_insert_with(|| e.span.clone());
                if let Some(r) = &mut self.rec {
                    r.events.push(memo::Event::PulseRead(n, e.span.clone()));
                }
                Some(Val::Typed(ir::Expr::Pulse(self.builder.pulse(n)), Ty::Bool))
            }
            ExprKind::Name(n) => self.name_value(n, &e.span),
            ExprKind::Member(base, member) => self.member(base, member),
            ExprKind::BitOf(base, bit, bit_span) => {
                let v = self.infer(base)?;
                let (value, ty) = match v {
                    Val::Typed(x, t) if t.is_int() => (x, t),
                    Val::Typed(_, t) => {
                        self.error(
                            codes::BAD_OPERATOR,
                            &base.span,
                            format!("`.{bit}` needs an integer, found {}", t.name()),
                            "bits can be taken of BYTE, WORD, DWORD, INT, DINT",
                        );
                        return None;
                    }
                    Val::Lit(_) => {
                        self.error(
                            codes::BAD_OPERATOR,
                            &base.span,
                            "`.n` of a constant",
                            "take bits of a signal or variable",
                        );
                        return None;
                    }
                };
                if *bit >= ty.bits() {
                    self.error(
                        codes::BIT_RANGE,
                        bit_span,
                        format!("{} has no bit {bit}", ty.name()),
                        format!("bits of a {} are 0..{}", ty.name(), ty.bits() - 1),
                    );
                    return None;
                }
                Some(Val::Typed(
                    ir::Expr::BitOf {
                        ty,
                        value: bx(value),
                        bit: *bit as u8,
                    },
                    Ty::Bool,
                ))
            }
            ExprKind::Unary(op, arg) => self.unary(*op, arg, &e.span),
            ExprKind::Binary(op, a, b) => self.binary(*op, a, b, &e.span),
            ExprKind::Compare(op, a, b) => self.compare(*op, a, b),
            ExprKind::Call(name, args) => self.call(name, args, &e.span),
        }
    }

    /// Checks a one-shot number (0..1023).
    pub(crate) fn pulse_number(&mut self, n: u32, span: &Span) -> Option<u16> {
        if n > 1023 {
            self.error(
                codes::PULSE_RANGE,
                span,
                format!("one-shot P{n} does not exist"),
                "one-shots are P0..P1023",
            );
            return None;
        }
        Some(n as u16)
    }

    fn name_value(&mut self, n: &str, span: &Span) -> Option<Val> {
        let Some(i) = self.lookup(n) else {
            if type_by_name(n).is_some() || FUNCTIONS.contains(&n) {
                self.error(
                    codes::NOT_A_VALUE,
                    span,
                    format!("`{n}` is a type or function, not a value"),
                    format!("call it: {n}(…)"),
                );
            } else if !self.failed.contains(n) {
                let hint = self.suggest_name(n, format!("define it (`DEF {n} = <signal>` or `DEF {n} : <type>`) or use a predeclared interface name"));
                self.error(
                    codes::UNDEFINED,
                    span,
                    format!("`{n}` is not defined"),
                    hint,
                );
            }
            return None;
        };
        self.mark_read(i);
        Some(match self.syms[i].kind {
            SymKind::Place { place, ty, .. } => Val::Typed(ir::Expr::Load(place), ty),
            SymKind::Var { id, ty } => Val::Typed(ir::Expr::Load(ir::Place::Var(id)), ty),
            SymKind::Timer { id, .. } => Val::Typed(ir::Expr::TimerQ(id), Ty::Bool),
            SymKind::Counter { id, .. } => Val::Typed(ir::Expr::CounterQ(id), Ty::Bool),
        })
    }

    fn member(&mut self, base: &Expr, member: &Name) -> Option<Val> {
        let m = member.text.as_str();
        let kind = match &base.kind {
            ExprKind::Name(n) => match self.lookup(n) {
                Some(i) => {
                    self.mark_read(i);
                    Some(self.syms[i].kind.clone())
                }
                None => return self.name_value(n, &base.span),
            },
            _ => None,
        };
        match (kind, m) {
            (Some(SymKind::Timer { id, .. }), "ET") => {
                Some(Val::Typed(ir::Expr::TimerEt(id), Ty::Dint))
            }
            (Some(SymKind::Timer { id, .. }), "Q") => {
                Some(Val::Typed(ir::Expr::TimerQ(id), Ty::Bool))
            }
            (Some(SymKind::Counter { id, .. }), "CV") => {
                Some(Val::Typed(ir::Expr::CounterCv(id), Ty::Dint))
            }
            (Some(SymKind::Counter { id, .. }), "Q") => {
                Some(Val::Typed(ir::Expr::CounterQ(id), Ty::Bool))
            }
            (Some(SymKind::Timer { .. }), _) => {
                self.error(
                    codes::BAD_MEMBER,
                    &member.span,
                    format!("a timer has no readable `.{m}`"),
                    "a timer reads as its Q; `.Q` and `.ET` (elapsed ms) can be read",
                );
                None
            }
            (Some(SymKind::Counter { .. }), _) => {
                self.error(
                    codes::BAD_MEMBER,
                    &member.span,
                    format!("a counter has no readable `.{m}`"),
                    "a counter reads as its Q; `.Q` and `.CV` (the count) can be read",
                );
                None
            }
            _ => {
                self.error(codes::BAD_MEMBER, &member.span, format!("`.{m}` needs a timer or counter"), "members exist on timers (`.ET`, `.Q`) and counters (`.CV`, `.Q`); `x.n` takes bit n");
                None
            }
        }
    }

    fn unary(&mut self, op: UnOp, arg: &Expr, span: &Span) -> Option<Val> {
        let v = self.infer(arg)?;
        match op {
            UnOp::Slash | UnOp::Not => match v {
                Val::Lit(Lit::Bool(b)) => Some(Val::Lit(Lit::Bool(!b))),
                Val::Typed(e, Ty::Bool) => Some(Val::Typed(ir::Expr::Not(bx(e)), Ty::Bool)),
                Val::Typed(e, t) if t.is_int() && op == UnOp::Not => Some(Val::Typed(
                    ir::Expr::Unary {
                        op: ir::UnOp::BitNot,
                        ty: t,
                        arg: bx(e),
                    },
                    t,
                )),
                other => {
                    let found = match other {
                        Val::Typed(_, t) => t.name().to_string(),
                        Val::Lit(l) => format!("the constant {}", l.describe()),
                    };
                    self.error(
                        codes::TYPE_MISMATCH,
                        span,
                        format!("`/` negates a BOOL, found {found}"),
                        "use `~` (or NOT) for the bitwise complement of an integer",
                    );
                    None
                }
            },
            UnOp::Neg => {
                let (e, t) = self.typed(v, &arg.span)?;
                if t == Ty::Bool {
                    self.error(
                        codes::BAD_OPERATOR,
                        span,
                        "unary `-` on a BOOL",
                        "use `/` or NOT to negate a BOOL",
                    );
                    return None;
                }
                Some(Val::Typed(
                    ir::Expr::Unary {
                        op: ir::UnOp::Neg,
                        ty: t,
                        arg: bx(e),
                    },
                    t,
                ))
            }
            UnOp::BitNot => {
                let (e, t) = self.typed(v, &arg.span)?;
                if !t.is_int() {
                    let hint = if t == Ty::Bool {
                        "use `/` or NOT to negate a BOOL"
                    } else {
                        "`~` works on BYTE, WORD, DWORD, INT, DINT"
                    };
                    self.error(
                        codes::BAD_OPERATOR,
                        span,
                        format!("`~` on {}", t.name()),
                        hint,
                    );
                    return None;
                }
                Some(Val::Typed(
                    ir::Expr::Unary {
                        op: ir::UnOp::BitNot,
                        ty: t,
                        arg: bx(e),
                    },
                    t,
                ))
            }
        }
    }

    /// Checks two operands and brings them to one type; literals follow the other side.
    pub(crate) fn operands(&mut self, a: &Expr, b: &Expr) -> Option<(ir::Expr, ir::Expr, Ty)> {
        let va = self.infer(a);
        let vb = self.infer(b);
        self.unify(va?, vb?, a, b)
    }

    /// Brings two checked operands to one type; literals follow the other side.
    fn unify(&mut self, va: Val, vb: Val, a: &Expr, b: &Expr) -> Option<(ir::Expr, ir::Expr, Ty)> {
        let (ea, ta) = match (&va, &vb) {
            (Val::Lit(_), Val::Typed(_, tb)) => {
                let tb = *tb;
                (self.coerce(va, tb, &a.span)?, tb)
            }
            _ => self.typed(va, &a.span)?,
        };
        let (eb, tb) = match vb {
            Val::Lit(_) => (self.coerce(vb, ta, &b.span)?, ta),
            v => self.typed(v, &b.span)?,
        };
        let Some(t) = common(ta, tb) else {
            let span = a.span.start..b.span.end;
            self.error(
                codes::TYPE_MISMATCH,
                &span,
                format!(
                    "operands of different kinds: {} and {}",
                    ta.name(),
                    tb.name()
                ),
                "convert one side (BOOL(x), BYTE(x), DINT(x), …) or compare in brackets",
            );
            return None;
        };
        let widen = |e: ir::Expr, from: Ty| {
            if from == t {
                e
            } else {
                ir::Expr::Convert {
                    from,
                    to: t,
                    arg: bx(e),
                }
            }
        };
        Some((widen(ea, ta), widen(eb, tb), t))
    }

    fn binary(&mut self, op: BinOp, a: &Expr, b: &Expr, span: &Span) -> Option<Val> {
        let va = self.infer(a);
        let vb = self.infer(b);
        let (va, vb) = (va?, vb?);
        // Two literals make a literal, so that the target decides the type (`W3K0 = 0 + 1`).
        if let (Val::Lit(x), Val::Lit(y)) = (&va, &vb)
            && let Some(folded) = fold(op, *x, *y)
        {
            return Some(Val::Lit(folded));
        }
        let (ea, eb, t) = self.unify(va, vb, a, b)?;
        let sym = match op {
            BinOp::Plus => "+",
            BinOp::Minus => "-",
            BinOp::Star => "*",
            BinOp::Slash => "/",
            BinOp::Mod => "MOD",
            BinOp::OrKw => "OR",
            BinOp::AndKw => "AND",
            BinOp::XorKw => "XOR",
            BinOp::Amp => "&",
            BinOp::Pipe => "|",
            BinOp::Caret => "^",
            BinOp::Shl => "<<",
            BinOp::Shr => ">>",
        };
        use ir::BinOp as I;
        let irop = if t == Ty::Bool {
            match op {
                BinOp::Plus | BinOp::OrKw | BinOp::Pipe => Some(I::Or),
                BinOp::Star | BinOp::AndKw | BinOp::Amp => Some(I::And),
                BinOp::XorKw | BinOp::Caret => Some(I::Xor),
                BinOp::Slash => {
                    self.error(
                        codes::BOOL_DIVISION,
                        span,
                        "`/` between BOOLs",
                        "for AND NOT write `*/` (e.g. A*/B); `/` alone only negates",
                    );
                    return None;
                }
                _ => None,
            }
        } else {
            match op {
                BinOp::Plus => Some(I::Add),
                BinOp::Minus => Some(I::Sub),
                BinOp::Star => Some(I::Mul),
                BinOp::Slash => Some(I::Div),
                BinOp::Mod if t.is_int() => Some(I::Mod),
                BinOp::AndKw | BinOp::Amp if t.is_int() => Some(I::BitAnd),
                BinOp::OrKw | BinOp::Pipe if t.is_int() => Some(I::BitOr),
                BinOp::XorKw | BinOp::Caret if t.is_int() => Some(I::BitXor),
                BinOp::Shl if t.is_int() => Some(I::Shl),
                BinOp::Shr if t.is_int() => Some(I::Shr),
                _ => None,
            }
        };
        let Some(irop) = irop else {
            let hint = if t == Ty::Bool {
                "BOOL operators: + (OR), * (AND), XOR, / (NOT)"
            } else {
                "MOD, bitwise and shift operators need integers"
            };
            self.error(
                codes::BAD_OPERATOR,
                span,
                format!("`{sym}` is not defined for {}", t.name()),
                hint,
            );
            return None;
        };
        Some(Val::Typed(
            ir::Expr::Binary {
                op: irop,
                ty: t,
                lhs: bx(ea),
                rhs: bx(eb),
            },
            t,
        ))
    }

    fn compare(&mut self, op: CmpOp, a: &Expr, b: &Expr) -> Option<Val> {
        let (lhs, rhs, ty) = self.operands(a, b)?;
        let op = match op {
            CmpOp::Eq => ir::CmpOp::Eq,
            CmpOp::Ne => ir::CmpOp::Ne,
            CmpOp::Lt => ir::CmpOp::Lt,
            CmpOp::Le => ir::CmpOp::Le,
            CmpOp::Gt => ir::CmpOp::Gt,
            CmpOp::Ge => ir::CmpOp::Ge,
        };
        Some(Val::Typed(
            ir::Expr::Cmp {
                op,
                ty,
                lhs: bx(lhs),
                rhs: bx(rhs),
            },
            Ty::Bool,
        ))
    }
}

/// Folds an operation on two untyped literals, when the result is exact whatever type it later
/// takes: integers with checked arithmetic (no overflow, no division by zero) and BOOL logic.
/// Reals are left to typed arithmetic, so that REAL and LREAL round as they do at run time.
fn fold(op: BinOp, a: Lit, b: Lit) -> Option<Lit> {
    match (a, b) {
        (Lit::Int(x), Lit::Int(y)) => {
            let v = match op {
                BinOp::Plus => x.checked_add(y),
                BinOp::Minus => x.checked_sub(y),
                BinOp::Star => x.checked_mul(y),
                BinOp::Slash => x.checked_div(y),
                BinOp::Mod => x.checked_rem(y),
                BinOp::Amp | BinOp::AndKw if x >= 0 && y >= 0 => Some(x & y),
                BinOp::Pipe | BinOp::OrKw if x >= 0 && y >= 0 => Some(x | y),
                BinOp::Caret | BinOp::XorKw if x >= 0 && y >= 0 => Some(x ^ y),
                BinOp::Shl if x >= 0 && (0..32).contains(&y) => {
                    x.checked_shl(y as u32).filter(|v| *v <= u32::MAX as i64)
                }
                BinOp::Shr if x >= 0 && (0..64).contains(&y) => Some(x >> y),
                _ => None,
            }?;
            Some(Lit::Int(v))
        }
        (Lit::Bool(x), Lit::Bool(y)) => match op {
            BinOp::Plus | BinOp::OrKw | BinOp::Pipe => Some(Lit::Bool(x || y)),
            BinOp::Star | BinOp::AndKw | BinOp::Amp => Some(Lit::Bool(x && y)),
            BinOp::XorKw | BinOp::Caret => Some(Lit::Bool(x != y)),
            _ => None,
        },
        _ => None,
    }
}
