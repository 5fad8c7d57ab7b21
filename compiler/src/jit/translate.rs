//! IR → cranelift IR for expressions and plain statements. Every operation is branch-free except
//! larger IF zones (small ones are if-converted: both branches run with guarded stores);
//! divisions are guarded so that no emitted instruction can trap.

use cranelift_codegen::ir::condcodes::{FloatCC, IntCC};
use cranelift_codegen::ir::immediates::{Ieee32, Ieee64};
use cranelift_codegen::ir::{InstBuilder, MemFlagsData, Type, Value, types};
use cranelift_frontend::FunctionBuilder;

use super::cache::Caches;
use crate::ir::{self, BinOp, CmpOp, CounterKind, Expr, FLAG_Q, Place, Program, Stmt, Ty, UnOp};

/// Memory flags for image accesses: offsets are checked against the image length at compile time
/// (non-trapping), little-endian, no alignment assumed.
pub(super) const FL: MemFlagsData = MemFlagsData::new()
    .with_notrap()
    .with_endianness(cranelift_codegen::ir::Endianness::Little);

/// The cranelift type of a value of `ty`.
pub(super) fn clty(ty: Ty) -> Type {
    match ty {
        Ty::Bool | Ty::Byte => types::I8,
        Ty::Word | Ty::Int => types::I16,
        Ty::Dword | Ty::Dint => types::I32,
        Ty::Real => types::F32,
        Ty::Lreal => types::F64,
    }
}

/// Translates statements into one function body over the image pointer `mem`.
pub(super) struct Translator<'a, 'b> {
    /// The function under construction.
    pub b: &'a mut FunctionBuilder<'b>,
    /// The program (declarations and offsets).
    pub p: &'a Program,
    /// The image pointer.
    pub mem: Value,
    /// Constants and image values known in the current block.
    pub c: &'a mut Caches,
    /// Inside an if-converted zone: the I8 0/1 condition under which stores take effect.
    pub guard: Option<Value>,
    /// IF zones up to this cost are if-converted ([`super::JitOptions::if_convert_cost`]).
    pub if_convert_cost: u32,
    /// Number of the statement being translated (for held-back stores).
    pub stamp: u32,
}

macro_rules! with_k {
    ($($name:ident => $op:ident),* $(,)?) => {$(
        /// The operation with a constant right operand (shared per block).
        pub(super) fn $name(&mut self, x: Value, v: i64) -> Value {
            let ty = self.b.func.dfg.value_type(x);
            let c = self.k(ty, v);
            self.b.ins().$op(x, c)
        }
    )*};
}

impl Translator<'_, '_> {
    with_k!(band_k => band, bor_k => bor, bxor_k => bxor, ushr_k => ushr, ishl_k => ishl, sshr_k => sshr, iadd_k => iadd);

    /// An integer constant of type `ty` (the low bits of `v`), materialized once per block.
    pub(super) fn k(&mut self, ty: Type, v: i64) -> Value {
        let v = if ty.bits() >= 64 {
            v
        } else {
            v & ((1i64 << ty.bits()) - 1)
        };
        if let Some(c) = self.c.konst(ty, v) {
            return c;
        }
        let c = self.b.ins().iconst(ty, v);
        self.c.set_konst(ty, v, c);
        c
    }

    /// Compares with a constant.
    pub(super) fn icmp_k(&mut self, cc: IntCC, x: Value, v: i64) -> Value {
        let ty = self.b.func.dfg.value_type(x);
        let c = self.k(ty, v);
        self.b.ins().icmp(cc, x, c)
    }

    /// Switches to `block`; constants of the previous block are forgotten.
    fn switch(&mut self, block: cranelift_codegen::ir::Block) {
        self.c.clear();
        self.b.switch_to_block(block);
    }

    pub(super) fn off(o: usize) -> i32 {
        o as i32
    }

    /// An I8 constant 0/1 or any I8 constant.
    pub(super) fn i8c(&mut self, v: i64) -> Value {
        self.k(types::I8, v & 0xFF)
    }

    /// BOOL (I8 0/1) from a nonzero test.
    fn nonzero(&mut self, v: Value) -> Value {
        self.icmp_k(IntCC::NotEqual, v, 0)
    }

    pub(super) fn place_at(&self, place: &Place) -> (usize, Option<u8>) {
        match *place {
            Place::Signal(sig) => (sig.image_byte(), sig.bit()),
            Place::View { at, .. } => (at.image_byte(), None),
            Place::Var(v) => (self.p.vars[v.0 as usize].offset, None),
            Place::VarBit { var, bit } => (
                self.p.vars[var.0 as usize].offset + bit as usize / 8,
                Some(bit % 8),
            ),
        }
    }

    fn load_place(&mut self, place: &Place) -> Value {
        let (at, bit) = self.place_at(place);
        if let Some(bit) = bit {
            let byte = self.load8(at);
            let s = self.ushr_k(byte, i64::from(bit));
            return self.band_k(s, 1);
        }
        let ty = self.p.place_ty(place);
        let v = self.load(clty(ty), at);
        if ty == Ty::Bool { self.nonzero(v) } else { v }
    }

    /// Emits a list of statements.
    pub(super) fn stmts(&mut self, stmts: &[Stmt]) {
        for s in stmts {
            self.stamp += 1;
            self.c.now = self.stamp;
            self.stmt(s);
            self.flush_stale();
        }
    }

    fn stmt(&mut self, s: &Stmt) {
        match s {
            Stmt::Assign { place, value } => self.assign(place, value),
            Stmt::Set { place, cond } => self.set_res(place, cond, true),
            Stmt::Res { place, cond } => self.set_res(place, cond, false),
            Stmt::Pulse { pulse, input } => {
                let x = self.expr(input);
                let at = self.p.pulses[pulse.0 as usize].offset;
                self.pulse(x, at);
            }
            Stmt::Timer { timer, input } => {
                let x = self.expr(input);
                let d = &self.p.timers[timer.0 as usize];
                self.timer(d.kind, d.preset_ms, x, d.offset);
            }
            Stmt::CounterCount { counter, input } => {
                let x = self.expr(input);
                let d = &self.p.counters[counter.0 as usize];
                self.counter_count(d.kind, x, d.offset);
            }
            Stmt::CounterReset { counter, input } => {
                let x = self.expr(input);
                let d = &self.p.counters[counter.0 as usize];
                let value = if d.kind == CounterKind::Ctu {
                    0
                } else {
                    d.preset
                };
                self.counter_reset(value, x, d.offset);
            }
            Stmt::If { cond, then_, else_ } => self.zone(s.cost(), cond, then_, else_),
        }
    }

    /// An IF zone. A small one (or any zone inside an if-converted one) is if-converted: both
    /// branches run straight-line and every store is guarded by the branch's condition, which
    /// keeps the block (and its cached loads and constants) going. A larger one branches; an
    /// empty branch jumps straight to the join block.
    fn zone(&mut self, cost: u32, cond: &Expr, then_: &[Stmt], else_: &[Stmt]) {
        let x = self.bits(cond, 0);
        if self.guard.is_some() || cost <= self.if_convert_cost {
            let c = self.materialize(x);
            let outer = self.guard;
            let g = match outer {
                Some(o) => self.b.ins().band(o, c),
                None => c,
            };
            self.guard = Some(g);
            self.stmts(then_);
            if !else_.is_empty() {
                let nc = self.bxor_k(c, 1);
                let g = match outer {
                    Some(o) => self.b.ins().band(o, nc),
                    None => nc,
                };
                self.guard = Some(g);
                self.stmts(else_);
            }
            self.guard = outer;
            return;
        }
        let c = self.truthy(x);
        self.flush_all();
        let join = self.b.create_block();
        let tb = if then_.is_empty() {
            join
        } else {
            self.b.create_block()
        };
        let eb = if else_.is_empty() {
            join
        } else {
            self.b.create_block()
        };
        self.b.ins().brif(c, tb, &[], eb, &[]);
        for (block, body) in [(tb, then_), (eb, else_)] {
            if block != join {
                self.switch(block);
                self.stmts(body);
                self.flush_all();
                self.b.ins().jump(join, &[]);
            }
        }
        self.switch(join);
    }

    fn canon(&mut self, ty: Ty, v: Value) -> Value {
        let nan = self.b.ins().fcmp(FloatCC::Unordered, v, v);
        let c = if ty == Ty::Real {
            self.b.ins().f32const(Ieee32::with_bits(ir::CANON_NAN_F32))
        } else {
            self.b.ins().f64const(Ieee64::with_bits(ir::CANON_NAN_F64))
        };
        self.b.ins().select(nan, c, v)
    }

    /// Emits an expression; the result has type `clty(e.ty())` (BOOL: I8 0/1).
    pub(super) fn expr(&mut self, e: &Expr) -> Value {
        if self.is_bitwise(e) {
            let x = self.bits(e, 0);
            return self.materialize(x);
        }
        self.expr_plain(e)
    }

    /// [`Translator::expr`] for the kinds [`Translator::is_bitwise`] does not take.
    pub(super) fn expr_plain(&mut self, e: &Expr) -> Value {
        match e {
            Expr::Const(v) => self.constant(*v),
            Expr::Load(place) => self.load_place(place),
            Expr::BitOf { ty, value, bit } => {
                let v = self.expr(value);
                let s = self.ushr_k(v, i64::from(*bit));
                let s = self.band_k(s, 1);
                if clty(*ty) == types::I8 {
                    s
                } else {
                    self.b.ins().ireduce(types::I8, s)
                }
            }
            Expr::Not(a) => {
                let v = self.expr(a);
                self.bxor_k(v, 1)
            }
            Expr::Unary { op, ty, arg } => {
                let v = self.expr(arg);
                match (op, ty.is_float()) {
                    (UnOp::Neg, true) => self.b.ins().fneg(v),
                    (UnOp::Abs, true) => self.b.ins().fabs(v),
                    (UnOp::Neg, false) => self.b.ins().ineg(v),
                    (UnOp::Abs, false) if ty.is_signed() => self.b.ins().iabs(v),
                    (UnOp::Abs, false) => v,
                    (UnOp::BitNot, _) => self.b.ins().bnot(v),
                }
            }
            Expr::Binary { op, ty, lhs, rhs } => {
                let a = self.expr(lhs);
                let c = self.expr(rhs);
                self.binary(*op, *ty, a, c)
            }
            Expr::Cmp { op, ty, lhs, rhs } => {
                let a = self.expr(lhs);
                let c = self.expr(rhs);
                self.compare(*op, *ty, a, c)
            }
            Expr::Convert { from, to, arg } => {
                let v = self.expr(arg);
                self.convert(*from, *to, v)
            }
            Expr::Bcd { ty, arg } => {
                let v = self.expr(arg);
                let mut v = self.ext_u64(*ty, v);
                let ten = self.k(types::I64, 10);
                let mut r = self.k(types::I64, 0);
                for i in 0..2 * ty.size() {
                    let d = self.b.ins().urem(v, ten);
                    let d = self.ishl_k(d, 4 * i as i64);
                    r = self.b.ins().bor(r, d);
                    v = self.b.ins().udiv(v, ten);
                }
                self.b.ins().ireduce(clty(*ty), r)
            }
            Expr::Bin { ty, arg } => {
                let v = self.expr(arg);
                let v = self.ext_u64(*ty, v);
                let mut r = self.k(types::I64, 0);
                let mut scale = 1i64;
                for i in 0..2 * ty.size() {
                    let n = self.ushr_k(v, 4 * i as i64);
                    let n = self.band_k(n, 0xF);
                    let k = self.k(types::I64, scale);
                    let n = self.b.ins().imul(n, k);
                    r = self.b.ins().iadd(r, n);
                    scale = scale.wrapping_mul(10);
                }
                self.b.ins().ireduce(clty(*ty), r)
            }
            Expr::Limit { ty, lo, x, hi } => {
                let lo = self.expr(lo);
                let x = self.expr(x);
                let hi = self.expr(hi);
                let t = self.binary(BinOp::Max, *ty, x, lo);
                self.binary(BinOp::Min, *ty, t, hi)
            }
            Expr::Pulse(id) => {
                let v = self.load8(self.p.pulses[id.0 as usize].offset);
                self.band_k(v, 1)
            }
            Expr::TimerQ(id) => {
                let v = self.load8(self.p.timers[id.0 as usize].offset + 4);
                self.band_k(v, i64::from(FLAG_Q))
            }
            Expr::TimerEt(id) => self.load32(self.p.timers[id.0 as usize].offset),
            Expr::CounterQ(id) => {
                let d = &self.p.counters[id.0 as usize];
                let (kind, preset) = (d.kind, d.preset);
                let cv = self.load32(d.offset);
                match kind {
                    CounterKind::Ctu => {
                        self.icmp_k(IntCC::SignedGreaterThanOrEqual, cv, i64::from(preset))
                    }
                    CounterKind::Ctd => self.icmp_k(IntCC::SignedLessThanOrEqual, cv, 0),
                }
            }
            Expr::CounterCv(id) => self.load32(self.p.counters[id.0 as usize].offset),
        }
    }

    fn constant(&mut self, v: ir::Value) -> Value {
        let bits = v.to_bits();
        match v.ty() {
            Ty::Real => self.b.ins().f32const(Ieee32::with_bits(bits as u32)),
            Ty::Lreal => self.b.ins().f64const(Ieee64::with_bits(bits)),
            ty => self.k(clty(ty), bits as i64),
        }
    }

    /// Zero- or sign-extends an integer/BOOL value of `ty` to I64 (`signed` from the type).
    fn ext_i64(&mut self, ty: Ty, v: Value) -> Value {
        if ty.is_signed() {
            self.b.ins().sextend(types::I64, v)
        } else {
            self.b.ins().uextend(types::I64, v)
        }
    }

    /// The bits of an integer of `ty` read as unsigned, in an I64.
    fn ext_u64(&mut self, _ty: Ty, v: Value) -> Value {
        self.b.ins().uextend(types::I64, v)
    }

    fn binary(&mut self, op: BinOp, ty: Ty, a: Value, c: Value) -> Value {
        if ty.is_float() {
            let r = match op {
                BinOp::Add => self.b.ins().fadd(a, c),
                BinOp::Sub => self.b.ins().fsub(a, c),
                BinOp::Mul => self.b.ins().fmul(a, c),
                BinOp::Div => self.b.ins().fdiv(a, c),
                BinOp::Min | BinOp::Max => {
                    let cc = if op == BinOp::Min {
                        FloatCC::LessThan
                    } else {
                        FloatCC::GreaterThan
                    };
                    let t = self.b.ins().fcmp(cc, c, a);
                    return self.b.ins().select(t, c, a);
                }
                _ => return a,
            };
            return self.canon(ty, r);
        }
        let signed = ty.is_signed();
        match op {
            BinOp::Add => self.b.ins().iadd(a, c),
            BinOp::Sub => self.b.ins().isub(a, c),
            BinOp::Mul => self.b.ins().imul(a, c),
            BinOp::Div | BinOp::Mod => self.division(op, ty, a, c),
            BinOp::BitAnd | BinOp::And => self.b.ins().band(a, c),
            BinOp::BitOr | BinOp::Or => self.b.ins().bor(a, c),
            BinOp::BitXor | BinOp::Xor => self.b.ins().bxor(a, c),
            BinOp::Shl | BinOp::Shr => {
                let over = self.icmp_k(IntCC::UnsignedGreaterThanOrEqual, c, i64::from(ty.bits()));
                let (raw, sat) = if op == BinOp::Shl {
                    (self.b.ins().ishl(a, c), self.k(clty(ty), 0))
                } else if signed {
                    (
                        self.b.ins().sshr(a, c),
                        self.sshr_k(a, i64::from(ty.bits() - 1)),
                    )
                } else {
                    (self.b.ins().ushr(a, c), self.k(clty(ty), 0))
                };
                self.b.ins().select(over, sat, raw)
            }
            BinOp::Min | BinOp::Max => {
                let cc = match (op == BinOp::Min, signed) {
                    (true, true) => IntCC::SignedLessThan,
                    (true, false) => IntCC::UnsignedLessThan,
                    (false, true) => IntCC::SignedGreaterThan,
                    (false, false) => IntCC::UnsignedGreaterThan,
                };
                let t = self.b.ins().icmp(cc, a, c);
                self.b.ins().select(t, a, c)
            }
        }
    }

    /// Guarded integer division/MOD: by 0 gives 0 and sets the fault flag; signed by -1 negates
    /// (MOD gives 0). The divisor reaching the machine instruction is never 0 or -1.
    fn division(&mut self, op: BinOp, ty: Ty, a: Value, c: Value) -> Value {
        let t = clty(ty);
        let zero = self.icmp_k(IntCC::Equal, c, 0);
        let faults = self.load32(ir::HDR_FAULTS);
        let z32 = self.b.ins().uextend(types::I32, zero);
        let f = self.b.ins().bor(faults, z32);
        self.store(f, ir::HDR_FAULTS);
        let one = self.k(t, 1);
        let zv = self.k(t, 0);
        let r = if ty.is_signed() {
            let m1 = self.icmp_k(IntCC::Equal, c, -1);
            let bad = self.b.ins().bor(zero, m1);
            let safe = self.b.ins().select(bad, one, c);
            let (q, special) = if op == BinOp::Div {
                (self.b.ins().sdiv(a, safe), self.b.ins().ineg(a))
            } else {
                (self.b.ins().srem(a, safe), zv)
            };
            self.b.ins().select(m1, special, q)
        } else {
            let safe = self.b.ins().select(zero, one, c);
            if op == BinOp::Div {
                self.b.ins().udiv(a, safe)
            } else {
                self.b.ins().urem(a, safe)
            }
        };
        self.b.ins().select(zero, zv, r)
    }

    fn compare(&mut self, op: CmpOp, ty: Ty, a: Value, c: Value) -> Value {
        if ty.is_float() {
            let cc = match op {
                CmpOp::Eq => FloatCC::Equal,
                CmpOp::Ne => FloatCC::NotEqual,
                CmpOp::Lt => FloatCC::LessThan,
                CmpOp::Le => FloatCC::LessThanOrEqual,
                CmpOp::Gt => FloatCC::GreaterThan,
                CmpOp::Ge => FloatCC::GreaterThanOrEqual,
            };
            return self.b.ins().fcmp(cc, a, c);
        }
        let s = ty.is_signed();
        let cc = match op {
            CmpOp::Eq => IntCC::Equal,
            CmpOp::Ne => IntCC::NotEqual,
            CmpOp::Lt if s => IntCC::SignedLessThan,
            CmpOp::Le if s => IntCC::SignedLessThanOrEqual,
            CmpOp::Gt if s => IntCC::SignedGreaterThan,
            CmpOp::Ge if s => IntCC::SignedGreaterThanOrEqual,
            CmpOp::Lt => IntCC::UnsignedLessThan,
            CmpOp::Le => IntCC::UnsignedLessThanOrEqual,
            CmpOp::Gt => IntCC::UnsignedGreaterThan,
            CmpOp::Ge => IntCC::UnsignedGreaterThanOrEqual,
        };
        self.b.ins().icmp(cc, a, c)
    }

    fn convert(&mut self, from: Ty, to: Ty, v: Value) -> Value {
        match (from.is_float(), to) {
            (true, Ty::Bool) => {
                let z = if from == Ty::Real {
                    self.b.ins().f32const(Ieee32::with_bits(0))
                } else {
                    self.b.ins().f64const(Ieee64::with_bits(0))
                };
                self.b.ins().fcmp(FloatCC::NotEqual, v, z)
            }
            (true, Ty::Real | Ty::Lreal) => {
                if from == to {
                    return v;
                }
                let r = if to == Ty::Lreal {
                    self.b.ins().fpromote(types::F64, v)
                } else {
                    self.b.ins().fdemote(types::F32, v)
                };
                self.canon(to, r)
            }
            (true, _) => {
                let i = self.b.ins().fcvt_to_sint_sat(types::I64, v);
                self.b.ins().ireduce(clty(to), i)
            }
            (false, Ty::Bool) => self.nonzero(v),
            (false, Ty::Real | Ty::Lreal) => {
                let i = self.ext_i64(from, v);
                self.b.ins().fcvt_from_sint(clty(to), i)
            }
            (false, _) => {
                let (fs, ts) = (from.size(), to.size());
                if fs == ts {
                    v
                } else if fs > ts {
                    self.b.ins().ireduce(clty(to), v)
                } else if from.is_signed() {
                    self.b.ins().sextend(clty(to), v)
                } else {
                    self.b.ins().uextend(clty(to), v)
                }
            }
        }
    }
}
