//! The IR type checker: a program that passes [`Program::validate`] can be run by every engine
//! without any check at run time besides the image length.

use packets::Signal;

use super::{BinOp, Expr, Place, Program, Stmt, Ty, UnOp};

/// An IR rule the front end broke (a front-end bug, never a user error).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum IrError {
    /// An expression or place has the wrong type.
    #[error("IR type error: {0}")]
    Type(String),
    /// An id points past its table.
    #[error("IR reference error: {0}")]
    Reference(String),
    /// A place lies outside the image or a view crosses its connector.
    #[error("IR place error: {0}")]
    Place(String),
}

fn ty_err(what: impl Into<String>) -> IrError {
    IrError::Type(what.into())
}

fn expect(got: Ty, want: Ty, what: &str) -> Result<(), IrError> {
    if got == want {
        Ok(())
    } else {
        Err(ty_err(format!(
            "{what}: expected {}, found {}",
            want.name(),
            got.name()
        )))
    }
}

impl Program {
    /// Checks every type rule and reference (see the module docs of [`crate::ir`]).
    pub fn validate(&self) -> Result<(), IrError> {
        for v in &self.vars {
            expect(v.init.ty(), v.ty, &format!("initial value of `{}`", v.name))?;
            if v.offset + v.ty.size() > self.image_len {
                return Err(IrError::Place(format!(
                    "variable `{}` lies outside the image",
                    v.name
                )));
            }
        }
        for t in &self.timers {
            if t.preset_ms < 0 || t.offset + super::TIMER_LEN > self.image_len {
                return Err(IrError::Place(format!("timer `{}` is malformed", t.name)));
            }
        }
        for c in &self.counters {
            if c.offset + super::COUNTER_LEN > self.image_len {
                return Err(IrError::Place(format!(
                    "counter `{}` lies outside the image",
                    c.name
                )));
            }
        }
        for p in &self.pulses {
            if p.n > 1023 || p.offset >= self.image_len {
                return Err(IrError::Place(format!("pulse P{} is malformed", p.n)));
            }
        }
        if self.retain.0 > self.retain.1
            || self.retain.1 > self.image_len
            || self.image_len > u32::MAX as usize
        {
            return Err(IrError::Place(
                "retain area or image length out of range".into(),
            ));
        }
        self.check_block(&self.fast)?;
        for s in &self.slow {
            self.check_block(s)?;
        }
        Ok(())
    }

    fn check_block(&self, stmts: &[Stmt]) -> Result<(), IrError> {
        stmts.iter().try_for_each(|s| self.check_stmt(s))
    }

    fn check_stmt(&self, s: &Stmt) -> Result<(), IrError> {
        match s {
            Stmt::Assign { place, value } => {
                let pt = self.check_place(place)?;
                expect(self.check_expr(value)?, pt, "assignment")
            }
            Stmt::Set { place, cond } | Stmt::Res { place, cond } => {
                expect(self.check_place(place)?, Ty::Bool, "SET/RES target")?;
                expect(self.check_expr(cond)?, Ty::Bool, "SET/RES condition")
            }
            Stmt::Pulse { pulse, input } => {
                self.pulses
                    .get(pulse.0 as usize)
                    .ok_or_else(|| IrError::Reference(format!("{pulse:?}")))?;
                expect(self.check_expr(input)?, Ty::Bool, "pulse input")
            }
            Stmt::Timer { timer, input } => {
                self.timers
                    .get(timer.0 as usize)
                    .ok_or_else(|| IrError::Reference(format!("{timer:?}")))?;
                expect(self.check_expr(input)?, Ty::Bool, "timer input")
            }
            Stmt::CounterCount { counter, input } | Stmt::CounterReset { counter, input } => {
                self.counters
                    .get(counter.0 as usize)
                    .ok_or_else(|| IrError::Reference(format!("{counter:?}")))?;
                expect(self.check_expr(input)?, Ty::Bool, "counter input")
            }
            Stmt::If { cond, then_, else_ } => {
                expect(self.check_expr(cond)?, Ty::Bool, "IF condition")?;
                self.check_block(then_)?;
                self.check_block(else_)
            }
        }
    }

    /// Checks a place and returns its type.
    fn check_place(&self, place: &Place) -> Result<Ty, IrError> {
        match *place {
            Place::Signal(_) => Ok(self.place_ty(place)),
            Place::View { at, ty } => match at {
                Signal::Byte { index, .. } if ty != Ty::Bool && index as usize + ty.size() <= 4 => {
                    if at.image_byte() + ty.size() > packets::PACKETS_LEN {
                        return Err(IrError::Place(format!("view at {at} leaves the packets")));
                    }
                    Ok(ty)
                }
                _ => Err(IrError::Place(format!(
                    "{} view at {at} is not within one connector",
                    ty.name()
                ))),
            },
            Place::Var(v) => self
                .vars
                .get(v.0 as usize)
                .map(|d| d.ty)
                .ok_or_else(|| IrError::Reference(format!("{v:?}"))),
            Place::VarBit { var, bit } => {
                let d = self
                    .vars
                    .get(var.0 as usize)
                    .ok_or_else(|| IrError::Reference(format!("{var:?}")))?;
                if !d.ty.is_int() || u32::from(bit) >= d.ty.bits() {
                    return Err(ty_err(format!(
                        "bit {bit} of `{}` ({})",
                        d.name,
                        d.ty.name()
                    )));
                }
                Ok(Ty::Bool)
            }
        }
    }

    /// Checks an expression and returns its type.
    fn check_expr(&self, e: &Expr) -> Result<Ty, IrError> {
        let reference = |what: String| IrError::Reference(what);
        match e {
            Expr::Const(v) => Ok(v.ty()),
            Expr::Load(place) => self.check_place(place),
            Expr::BitOf { ty, value, bit } => {
                expect(self.check_expr(value)?, *ty, "bit-of operand")?;
                if !ty.is_int() || u32::from(*bit) >= ty.bits() {
                    return Err(ty_err(format!("bit {bit} of a {}", ty.name())));
                }
                Ok(Ty::Bool)
            }
            Expr::Not(a) => {
                expect(self.check_expr(a)?, Ty::Bool, "NOT operand")?;
                Ok(Ty::Bool)
            }
            Expr::Unary { op, ty, arg } => {
                expect(self.check_expr(arg)?, *ty, "unary operand")?;
                let ok = match op {
                    UnOp::Neg | UnOp::Abs => ty.is_int() || ty.is_float(),
                    UnOp::BitNot => ty.is_int(),
                };
                if !ok {
                    return Err(ty_err(format!("{op:?} on {}", ty.name())));
                }
                Ok(*ty)
            }
            Expr::Binary { op, ty, lhs, rhs } => {
                expect(self.check_expr(lhs)?, *ty, "left operand")?;
                expect(self.check_expr(rhs)?, *ty, "right operand")?;
                let ok = match op {
                    BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Div | BinOp::Min | BinOp::Max => {
                        ty.is_int() || ty.is_float()
                    }
                    BinOp::Mod
                    | BinOp::BitAnd
                    | BinOp::BitOr
                    | BinOp::BitXor
                    | BinOp::Shl
                    | BinOp::Shr => ty.is_int(),
                    BinOp::And | BinOp::Or | BinOp::Xor => *ty == Ty::Bool,
                };
                if !ok {
                    return Err(ty_err(format!("{op:?} on {}", ty.name())));
                }
                Ok(*ty)
            }
            Expr::Cmp { ty, lhs, rhs, .. } => {
                expect(self.check_expr(lhs)?, *ty, "left comparand")?;
                expect(self.check_expr(rhs)?, *ty, "right comparand")?;
                Ok(Ty::Bool)
            }
            Expr::Convert { from, to, arg } => {
                expect(self.check_expr(arg)?, *from, "conversion operand")?;
                Ok(*to)
            }
            Expr::Bcd { ty, arg } | Expr::Bin { ty, arg } => {
                expect(self.check_expr(arg)?, *ty, "BCD/BIN operand")?;
                if !ty.is_int() {
                    return Err(ty_err(format!("BCD/BIN on {}", ty.name())));
                }
                Ok(*ty)
            }
            Expr::Limit { ty, lo, x, hi } => {
                for a in [lo, x, hi] {
                    expect(self.check_expr(a)?, *ty, "LIMIT operand")?;
                }
                if !(ty.is_int() || ty.is_float()) {
                    return Err(ty_err(format!("LIMIT on {}", ty.name())));
                }
                Ok(*ty)
            }
            Expr::Pulse(p) => self
                .pulses
                .get(p.0 as usize)
                .map(|_| Ty::Bool)
                .ok_or_else(|| reference(format!("{p:?}"))),
            Expr::TimerQ(t) | Expr::TimerEt(t) => {
                self.timers
                    .get(t.0 as usize)
                    .ok_or_else(|| reference(format!("{t:?}")))?;
                Ok(if matches!(e, Expr::TimerQ(_)) {
                    Ty::Bool
                } else {
                    Ty::Dint
                })
            }
            Expr::CounterQ(c) | Expr::CounterCv(c) => {
                self.counters
                    .get(c.0 as usize)
                    .ok_or_else(|| reference(format!("{c:?}")))?;
                Ok(if matches!(e, Expr::CounterQ(_)) {
                    Ty::Bool
                } else {
                    Ty::Dint
                })
            }
        }
    }
}
