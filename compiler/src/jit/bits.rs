//! BOOL expressions evaluated in place, on bit positions.
//!
//! A boolean is kept as [`Bits`]: bit `pos` of an I8 value, the other bits either known zero
//! (`clean`) or garbage. Reading `I12K5` is then just the (cached) load of its byte, `/x` is one
//! `bnot`, `AND`/`OR`/`XOR` one instruction after at most one shift that lines the operands up,
//! and a coil writes the result into its byte without ever normalizing it to 0/1. Operands are
//! lined up on the bit the statement finally writes when they can be, so most rungs need no
//! shift at all for the target's own bits. Where a real 0/1 is needed (timers, BOOL variables,
//! conversions) [`Translator::materialize`] makes one. The coils, SET and RES of bit places
//! (also here) merge the result into the target byte in two or three instructions.

use cranelift_codegen::ir::{InstBuilder, Value, types};

use super::translate::{Translator, clty};
use crate::ir::{BinOp, Expr, FLAG_Q, Place, Ty};

/// A boolean held as bit `pos` of an I8 value.
#[derive(Debug, Clone, Copy)]
pub(super) struct Bits {
    /// The I8 value holding the bit.
    pub v: Value,
    /// Bit position 0..=7.
    pub pos: u8,
    /// The other bits of `v` are zero.
    pub clean: bool,
}

impl Translator<'_, '_> {
    /// True when [`Translator::bits`] evaluates `e` without first making a 0/1 (these kinds then
    /// go through it from [`Translator::expr`], too).
    pub(super) fn is_bitwise(&self, e: &Expr) -> bool {
        match e {
            Expr::Const(v) => v.ty() == Ty::Bool,
            Expr::Load(place) => {
                matches!(place, Place::Signal(s) if s.bit().is_some())
                    || matches!(place, Place::VarBit { .. })
            }
            Expr::Not(_) | Expr::Pulse(_) | Expr::TimerQ(_) | Expr::BitOf { .. } => true,
            Expr::Binary { ty, .. } => *ty == Ty::Bool,
            _ => false,
        }
    }

    /// Evaluates the BOOL expression `e`, preferring its result on bit `want`.
    pub(super) fn bits(&mut self, e: &Expr, want: u8) -> Bits {
        match e {
            Expr::Const(crate::ir::Value::Bool(b)) => Bits {
                v: self.i8c(i64::from(*b) << want),
                pos: want,
                clean: true,
            },
            Expr::Load(place) => match self.place_at(place) {
                (at, Some(bit)) => Bits {
                    v: self.load8(at),
                    pos: bit,
                    clean: false,
                },
                _ => self.clean01(e),
            },
            Expr::Not(a) => {
                let x = self.bits(a, want);
                let v = if x.clean {
                    self.bxor_k(x.v, 1 << x.pos)
                } else {
                    self.b.ins().bnot(x.v)
                };
                Bits { v, ..x }
            }
            Expr::Binary {
                op: op @ (BinOp::And | BinOp::Or | BinOp::Xor),
                ty: Ty::Bool,
                lhs,
                rhs,
            } => {
                let a = self.bits(lhs, want);
                let c = self.bits(rhs, a.pos);
                let to = if a.pos != want && c.pos == want {
                    want
                } else {
                    a.pos
                };
                let (a, c) = (self.align(a, to), self.align(c, to));
                let (v, clean) = match op {
                    BinOp::And => (self.b.ins().band(a.v, c.v), a.clean || c.clean),
                    BinOp::Or => (self.b.ins().bor(a.v, c.v), a.clean && c.clean),
                    _ => (self.b.ins().bxor(a.v, c.v), a.clean && c.clean),
                };
                Bits { v, pos: to, clean }
            }
            Expr::Pulse(id) => Bits {
                v: self.load8(self.p.pulses[id.0 as usize].offset),
                pos: 0,
                clean: false,
            },
            Expr::TimerQ(id) => Bits {
                v: self.load8(self.p.timers[id.0 as usize].offset + 4),
                pos: FLAG_Q.trailing_zeros() as u8,
                clean: false,
            },
            Expr::BitOf { ty, value, bit } => {
                let v = self.expr(value);
                if clty(*ty) == types::I8 {
                    return Bits {
                        v,
                        pos: *bit,
                        clean: false,
                    };
                }
                let byte = *bit / 8;
                let v = if byte > 0 {
                    self.ushr_k(v, i64::from(byte) * 8)
                } else {
                    v
                };
                Bits {
                    v: self.b.ins().ireduce(types::I8, v),
                    pos: *bit % 8,
                    clean: false,
                }
            }
            _ => self.clean01(e),
        }
    }

    fn clean01(&mut self, e: &Expr) -> Bits {
        Bits {
            v: self.expr_plain(e),
            pos: 0,
            clean: true,
        }
    }

    /// Moves the bit to position `to`.
    pub(super) fn align(&mut self, x: Bits, to: u8) -> Bits {
        let v = match x.pos.cmp(&to) {
            std::cmp::Ordering::Equal => return x,
            std::cmp::Ordering::Less => self.ishl_k(x.v, i64::from(to - x.pos)),
            std::cmp::Ordering::Greater => self.ushr_k(x.v, i64::from(x.pos - to)),
        };
        Bits { v, pos: to, ..x }
    }

    /// The boolean as I8 0/1.
    pub(super) fn materialize(&mut self, x: Bits) -> Value {
        match x.pos {
            0 if x.clean => x.v,
            0 => self.band_k(x.v, 1),
            // A logical shift by 7 leaves nothing but the bit.
            7 => self.ushr_k(x.v, 7),
            p => {
                let s = self.ushr_k(x.v, i64::from(p));
                if x.clean { s } else { self.band_k(s, 1) }
            }
        }
    }

    /// An I8 that is nonzero exactly when the boolean is true (for `brif` and `select`).
    pub(super) fn truthy(&mut self, x: Bits) -> Value {
        if x.clean {
            x.v
        } else {
            self.band_k(x.v, 1 << x.pos)
        }
    }

    /// Writes bit `bit` of the byte at `at` to the boolean `x`.
    fn store_bit(&mut self, at: usize, bit: u8, x: Bits) {
        let byte = self.load8(at);
        let x = self.align(x, bit);
        let m = 1i64 << bit;
        let n = if x.clean {
            let cleared = self.band_k(byte, !m);
            self.b.ins().bor(cleared, x.v)
        } else {
            // byte ^ ((byte ^ x) & m): the bit of x, the other bits of byte.
            let d = self.b.ins().bxor(byte, x.v);
            let d = self.band_k(d, m);
            self.b.ins().bxor(byte, d)
        };
        self.store(n, at);
    }

    pub(super) fn assign(&mut self, place: &Place, value: &Expr) {
        match self.place_at(place) {
            (at, Some(bit)) => {
                let x = self.bits(value, bit);
                self.store_bit(at, bit, x);
            }
            (at, None) => {
                let v = self.expr(value);
                self.store(v, at);
            }
        }
    }

    /// SET (`set`) or RES of a BOOL place when `cond`.
    pub(super) fn set_res(&mut self, place: &Place, cond: &Expr, set: bool) {
        match self.place_at(place) {
            (at, Some(bit)) => {
                let x = self.bits(cond, bit);
                let byte = self.load8(at);
                let x = self.align(x, bit);
                let m = 1i64 << bit;
                let n = match (set, x.clean) {
                    (true, true) => self.b.ins().bor(byte, x.v),
                    (true, false) => {
                        let xm = self.band_k(x.v, m);
                        self.b.ins().bor(byte, xm)
                    }
                    (false, clean) => {
                        let nx = self.b.ins().bnot(x.v);
                        let nx = if clean { nx } else { self.bor_k(nx, !m) };
                        self.b.ins().band(byte, nx)
                    }
                };
                self.store(n, at);
            }
            (at, None) => {
                let x = self.bits(cond, 0);
                let c = self.truthy(x);
                let old = self.load8(at);
                let k = self.i8c(i64::from(set));
                let n = self.b.ins().select(c, k, old);
                self.store(n, at);
            }
        }
    }
}
