//! The arithmetic of a macro run: constants, the null select, the finite check, host calls, the
//! inline `ROUND`/`FUP`/`MOD` and the binary operators, each as [`crate::macro_b::eval`] computes it.

use cranelift_codegen::ir::condcodes::FloatCC;
use cranelift_codegen::ir::immediates::Ieee64;
use cranelift_codegen::ir::{BlockArg, InstBuilder, Value, types};
use cranelift_frontend::FunctionBuilder;

use super::{G, V};

/// 2^53: below it every integer is an `f64`, and the integer remainder equals `fmod`.
const LIM: f64 = 9_007_199_254_740_992.0;
use crate::macro_b::eval::{MacroError, host_func, host_mod};
use crate::macro_b::{BinOp, Func};

impl G<'_, '_> {
    pub(super) fn f(&mut self, v: f64) -> Value {
        self.b.ins().f64const(Ieee64::with_bits(v.to_bits()))
    }

    /// Null read as 0 (nothing to do for a value that cannot be null).
    pub(super) fn z(&mut self, x: V) -> Value {
        if !x.null {
            return x.v;
        }
        let nan = self.b.ins().fcmp(FloatCC::Unordered, x.v, x.v);
        let zero = self.f(0.0);
        self.b.ins().select(nan, zero, x.v)
    }

    /// `x` when finite, else the Range error (`x − x` is NaN exactly for an infinity or a NaN: two
    /// instructions, no constants).
    pub(super) fn fin(&mut self, x: Value) -> Value {
        let d = self.b.ins().fsub(x, x);
        let ok = self.b.ins().fcmp(FloatCC::Ordered, d, d);
        self.guard(ok, MacroError::Range.code());
        x
    }

    pub(super) fn call1(&mut self, f: Func, x: Value) -> Value {
        let code = self.b.ins().iconst(types::I64, f as i64);
        let fp = self.b.ins().iconst(
            self.ptr,
            host_func as extern "C" fn(i64, f64) -> f64 as usize as i64,
        );
        let c = self.b.ins().call_indirect(self.s.f1, fp, &[code, x]);
        self.b.inst_results(c)[0]
    }

    pub(super) fn call2(&mut self, h: extern "C" fn(f64, f64) -> f64, a: Value, b: Value) -> Value {
        let fp = self.b.ins().iconst(self.ptr, h as usize as i64);
        let c = self.b.ins().call_indirect(self.s.f2, fp, &[a, b]);
        self.b.inst_results(c)[0]
    }

    /// `ROUND`: half away from zero, as `f64::round`: `trunc(x ± h)` with `h` the largest double
    /// below 0.5 (with 0.5 itself, 0.49999999999999994 and the odd integers above 2^52 would round
    /// up once more; with `h` the sum rounds to the right side of every half, `-0` and the
    /// values below 0.5 in magnitude keep their sign, as `f64::round` gives them).
    pub(super) fn round(&mut self, x: Value) -> Value {
        let h = self.f(0.499_999_999_999_999_94);
        let h = self.b.ins().fcopysign(h, x);
        let s = self.b.ins().fadd(x, h);
        self.b.ins().trunc(s)
    }

    /// `FUP`: away from zero, as the interpreter's `host_func`.
    pub(super) fn fup(&mut self, x: Value) -> Value {
        let t = self.b.ins().trunc(x);
        let whole = self.b.ins().fcmp(FloatCC::Equal, t, x);
        let one = self.f(1.0);
        let one = self.b.ins().fcopysign(one, x);
        let t1 = self.b.ins().fadd(t, one);
        self.b.ins().select(whole, x, t1)
    }

    /// `a MOD b` of rounded operands, `b` ≠ 0: an integer remainder below 2^53, else `host_mod`;
    /// `k`: `b` is this constant (below 2^53).
    pub(super) fn rem(&mut self, a: Value, b: Value, k: Option<f64>) -> Value {
        let lim = self.f(LIM);
        let aa = self.b.ins().fabs(a);
        let oka = self.b.ins().fcmp(FloatCC::LessThan, aa, lim);
        let ok = match k {
            Some(_) => oka,
            None => {
                let ab = self.b.ins().fabs(b);
                let okb = self.b.ins().fcmp(FloatCC::LessThan, ab, lim);
                self.b.ins().band(oka, okb)
            }
        };
        let (fast, slow, done) = (
            self.b.create_block(),
            self.b.create_block(),
            self.b.create_block(),
        );
        self.b.append_block_param(done, types::F64);
        self.b.ins().brif(ok, fast, &[], slow, &[]);
        self.b.switch_to_block(fast);
        let x = self.b.ins().fcvt_to_sint_sat(types::I64, a);
        let y = match k {
            Some(k) => self.b.ins().iconst(types::I64, k as i64),
            None => self.b.ins().fcvt_to_sint_sat(types::I64, b),
        };
        let r = self.b.ins().srem(x, y);
        let r = self.b.ins().fcvt_from_sint(types::F64, r);
        let r = self.b.ins().fcopysign(r, a);
        self.b.ins().jump(done, &[BlockArg::from(r)]);
        self.b.switch_to_block(slow);
        let r = self.call2(host_mod, a, b);
        self.b.ins().jump(done, &[BlockArg::from(r)]);
        self.b.switch_to_block(done);
        self.b.block_params(done)[0]
    }

    pub(super) fn bool_f(&mut self, c: Value) -> Value {
        let (one, zero) = (self.f(1.0), self.f(0.0));
        self.b.ins().select(c, one, zero)
    }

    /// `a op b`; `lit`: the right operand when it is a number literal (no zero-divisor check then,
    /// and `MOD` uses it rounded at compile time); `int_a`: `a` is an integer (`MOD` does not round
    /// it).
    pub(super) fn bin(&mut self, op: BinOp, a: V, b: V, lit: Option<f64>, int_a: bool) -> Value {
        if matches!(op, BinOp::Eq | BinOp::Ne) {
            let same = self.b.ins().fcmp(FloatCC::Equal, a.v, b.v);
            let eq = if a.null && b.null {
                let na = self.b.ins().fcmp(FloatCC::Unordered, a.v, a.v);
                let nb = self.b.ins().fcmp(FloatCC::Unordered, b.v, b.v);
                let both = self.b.ins().band(na, nb);
                self.b.ins().bor(both, same)
            } else {
                same
            };
            let c = if op == BinOp::Eq {
                eq
            } else {
                self.b.ins().bxor_imm_s(eq, 1)
            };
            return self.bool_f(c);
        }
        let a = self.z(a);
        let b = self.z(b);
        let cmp = |g: &mut Self, cc: FloatCC| {
            let c = g.b.ins().fcmp(cc, a, b);
            g.bool_f(c)
        };
        let int = |g: &mut Self, f: fn(&mut FunctionBuilder, Value, Value) -> Value| {
            let x = g.b.ins().fcvt_to_sint_sat(types::I64, a);
            let y = g.b.ins().fcvt_to_sint_sat(types::I64, b);
            let r = f(g.b, x, y);
            g.b.ins().fcvt_from_sint(types::F64, r)
        };
        match op {
            BinOp::Add => {
                let r = self.b.ins().fadd(a, b);
                self.fin(r)
            }
            BinOp::Sub => {
                let r = self.b.ins().fsub(a, b);
                self.fin(r)
            }
            BinOp::Mul => {
                let r = self.b.ins().fmul(a, b);
                self.fin(r)
            }
            BinOp::Div => {
                if lit.is_none_or(|v| v == 0.0) {
                    let zero = self.f(0.0);
                    let ok = self.b.ins().fcmp(FloatCC::NotEqual, b, zero);
                    self.guard(ok, MacroError::DivZero.code());
                }
                let r = self.b.ins().fdiv(a, b);
                self.fin(r)
            }
            BinOp::Mod => {
                let ra = if int_a { a } else { self.round(a) };
                // A literal divisor below 2^53 is rounded here, and its range needs no check.
                let k = lit.map(f64::round).filter(|k| *k != 0.0 && k.abs() < LIM);
                let rb = match k {
                    Some(k) => self.f(k),
                    None => self.round(b),
                };
                if k.is_none() {
                    let zero = self.f(0.0);
                    let ok = self.b.ins().fcmp(FloatCC::NotEqual, rb, zero);
                    self.guard(ok, MacroError::DivZero.code());
                }
                let r = self.rem(ra, rb, k);
                self.fin(r)
            }
            BinOp::And => int(self, |b, x, y| b.ins().band(x, y)),
            BinOp::Or => int(self, |b, x, y| b.ins().bor(x, y)),
            BinOp::Xor => int(self, |b, x, y| b.ins().bxor(x, y)),
            BinOp::Gt => cmp(self, FloatCC::GreaterThan),
            BinOp::Ge => cmp(self, FloatCC::GreaterThanOrEqual),
            BinOp::Lt => cmp(self, FloatCC::LessThan),
            BinOp::Le => cmp(self, FloatCC::LessThanOrEqual),
            BinOp::Eq | BinOp::Ne => self.f(0.0),
        }
    }
}
