//! Calls: conversions `BYTE(x)` …, `BCD`, `BIN`, `ABS`, `MIN`, `MAX`, `LIMIT`, and inline timers
//! `TON(input, preset)`, which become a [`ir::Stmt::Timer`] in `pending` plus a read of their Q
//! (one instance per place in the text, named `TON@line:column`).

use super::expr::{Val, bx};
use super::symbols::const_lit;
use super::types::{Lit, common, type_by_name};
use super::{Checker, codes};
use crate::ast::{Expr, Name, Span};
use crate::ir::{self, TimerKind, Ty};

impl Checker<'_> {
    fn arity(&mut self, name: &Name, args: &[Expr], n: usize, span: &Span, form: &str) -> bool {
        if args.len() == n {
            return true;
        }
        self.error(
            codes::ARITY,
            span,
            format!(
                "{} takes {n} argument{}, found {}",
                name.text,
                if n == 1 { "" } else { "s" },
                args.len()
            ),
            format!("write {form}"),
        );
        false
    }

    fn number(&mut self, v: Val, span: &Span, what: &str) -> Option<(ir::Expr, Ty)> {
        let (e, t) = self.typed(v, span)?;
        if t == Ty::Bool {
            self.error(
                codes::TYPE_MISMATCH,
                span,
                format!("{what} needs a number, found BOOL"),
                "convert with BYTE(x), DINT(x), …",
            );
            return None;
        }
        Some((e, t))
    }

    pub(crate) fn call(&mut self, name: &Name, args: &[Expr], span: &Span) -> Option<Val> {
        let f = name.text.as_str();
        if let Some(to) = type_by_name(f) {
            if !self.arity(name, args, 1, span, &format!("{f}(x)")) {
                return None;
            }
            let v = self.infer(&args[0])?;
            let (e, from) = self.typed(v, &args[0].span)?;
            if from == to {
                return Some(Val::Typed(e, to));
            }
            return Some(Val::Typed(
                ir::Expr::Convert {
                    from,
                    to,
                    arg: bx(e),
                },
                to,
            ));
        }
        match f {
            "BCD" | "BIN" | "ABS" => {
                if !self.arity(name, args, 1, span, &format!("{f}(x)")) {
                    return None;
                }
                let v = self.infer(&args[0])?;
                let (e, t) = self.number(v, &args[0].span, f)?;
                if f != "ABS" && !t.is_int() {
                    self.error(
                        codes::BAD_OPERATOR,
                        &args[0].span,
                        format!("{f} needs an integer, found {}", t.name()),
                        "convert first: DINT(x)",
                    );
                    return None;
                }
                let out = match f {
                    "BCD" => ir::Expr::Bcd { ty: t, arg: bx(e) },
                    "BIN" => ir::Expr::Bin { ty: t, arg: bx(e) },
                    _ => ir::Expr::Unary {
                        op: ir::UnOp::Abs,
                        ty: t,
                        arg: bx(e),
                    },
                };
                Some(Val::Typed(out, t))
            }
            "MIN" | "MAX" => {
                if !self.arity(name, args, 2, span, &format!("{f}(a, b)")) {
                    return None;
                }
                let (a, b, t) = self.operands(&args[0], &args[1])?;
                if t == Ty::Bool {
                    self.error(
                        codes::TYPE_MISMATCH,
                        span,
                        format!("{f} needs numbers, found BOOL"),
                        "use + (OR) or * (AND) for BOOLs",
                    );
                    return None;
                }
                let op = if f == "MIN" {
                    ir::BinOp::Min
                } else {
                    ir::BinOp::Max
                };
                Some(Val::Typed(
                    ir::Expr::Binary {
                        op,
                        ty: t,
                        lhs: bx(a),
                        rhs: bx(b),
                    },
                    t,
                ))
            }
            "LIMIT" => {
                if !self.arity(name, args, 3, span, "LIMIT(lo, x, hi)") {
                    return None;
                }
                let vals: Vec<Option<Val>> = args.iter().map(|a| self.infer(a)).collect();
                let vals: Vec<Val> = vals.into_iter().collect::<Option<_>>()?;
                let mut t: Option<Ty> = None;
                for v in &vals {
                    if let Val::Typed(_, vt) = v {
                        t = match t {
                            None => Some(*vt),
                            Some(t0) => common(t0, *vt),
                        };
                        if t.is_none() {
                            break;
                        }
                    }
                }
                let all_lit = vals.iter().all(|v| matches!(v, Val::Lit(_)));
                let t = match (t, &vals[0]) {
                    (Some(t), _) => Some(t),
                    (None, Val::Lit(l)) if all_lit => Some(l.default_ty()),
                    _ => None,
                };
                let Some(t) = t.filter(|t| *t != Ty::Bool) else {
                    self.error(
                        codes::TYPE_MISMATCH,
                        span,
                        "LIMIT needs three numbers of compatible types",
                        "convert the operands to one type",
                    );
                    return None;
                };
                let mut it = vals.into_iter().zip(args);
                let mut next = |c: &mut Self| it.next().and_then(|(v, a)| c.coerce(v, t, &a.span));
                let lo = next(self);
                let x = next(self);
                let hi = next(self);
                let (lo, x, hi) = (lo?, x?, hi?);
                Some(Val::Typed(
                    ir::Expr::Limit {
                        ty: t,
                        lo: bx(lo),
                        x: bx(x),
                        hi: bx(hi),
                    },
                    t,
                ))
            }
            "TON" | "TOF" | "TP" => {
                if !self.arity(
                    name,
                    args,
                    2,
                    span,
                    &format!("{f}(input, preset) e.g. {f}(I0A5, 2s)"),
                ) {
                    return None;
                }
                let input = self.expr_to(&args[0], Ty::Bool);
                let preset = match const_lit(&args[1]) {
                    Some(Lit::Int(v)) if v >= 0 => Some(v as u64),
                    Some(Lit::Real(r)) if (0.0..2.0e9).contains(&r) => Some(r.ceil() as u64),
                    _ => {
                        self.error(
                            codes::BAD_PRESET,
                            &args[1].span,
                            format!("invalid preset for {f}"),
                            "the preset is a constant time such as 500ms, 2s or 1.5s",
                        );
                        None
                    }
                };
                let (input, preset) = (input?, preset?);
                let kind = match f {
                    "TON" => TimerKind::Ton,
                    "TOF" => TimerKind::Tof,
                    _ => TimerKind::Tp,
                };
                let label = format!("{f}@{}", self.position(span.start));
                let id = self.builder.timer(&label, kind, preset);
                self.pending.push(ir::Stmt::Timer { timer: id, input });
                Some(Val::Typed(ir::Expr::TimerQ(id), Ty::Bool))
            }
            "CTU" | "CTD" => {
                self.error(
                    codes::BAD_STATEFUL_USE,
                    span,
                    format!("{f} cannot be used inline"),
                    format!("declare it: `DEF c : {f}(preset)`, then `c = input`"),
                );
                None
            }
            _ => {
                self.error(
                    codes::UNKNOWN_FUNCTION,
                    &name.span,
                    format!("unknown function `{f}`"),
                    "functions: BCD BIN MIN MAX LIMIT ABS, conversions BOOL BYTE WORD DWORD INT DINT REAL LREAL, timers TON TOF TP",
                );
                None
            }
        }
    }
}
