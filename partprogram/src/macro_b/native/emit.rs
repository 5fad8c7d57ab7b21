//! The cranelift code of one macro run: blocks, statements and expressions, operation by operation
//! as [`crate::macro_b::eval`] computes them.
//!
//! Plain variables with literal numbers live in cranelift variables (registers) for the whole run
//! when the run has no computed variable number (`#[…]`): loaded before the entry dispatch, stored
//! back on every exit. Expressions whose every value is an integer ([`integral`]) are not rounded
//! again where `MOD` or a computed number rounds, and a literal `MOD` divisor is rounded at compile
//! time. Null (`#0`, NaN) is tracked statically: only a variable read can be null, so
//! the "null reads as 0" select is emitted for those only. `ROUND`, `FUP`, `FIX`, `ABS`, `SQRT` and
//! `MOD` are inline (`MOD` as an integer remainder when both rounded operands are below 2^53, where
//! it equals the interpreter's `fmod` bit for bit, the sign of a zero included). A computed variable
//! number outside the plain table, or a system variable the host cannot serve, *bails out*: the
//! block's count is taken back and the run returns that block to the interpreter, which executes it
//! (no side effect has happened before: stores come last).

mod arith;

use std::collections::BTreeMap;

use cranelift_codegen::ir::condcodes::{FloatCC, IntCC};
use cranelift_codegen::ir::{
    Block, BlockArg, InstBuilder, MemFlagsData, SigRef, Type, Value, types,
};
use cranelift_frontend::{FunctionBuilder, Variable};

use super::super::eval::host_atan2;
use super::super::{Expr, Func, SEQ_SLOT, Stmt, Target, is_plain};
use super::{INTERPRET_CODE, LIMIT_CODE, MacroCtx, sys_read, sys_write};
use crate::program::Program;

const FL: MemFlagsData = MemFlagsData::new().with_notrap();
const OFF_VARS: i32 = std::mem::offset_of!(MacroCtx, vars) as i32;
const OFF_EXECUTED: i32 = std::mem::offset_of!(MacroCtx, executed) as i32;
const OFF_MAX: i32 = std::mem::offset_of!(MacroCtx, max_blocks) as i32;
const OFF_FAIL: i32 = std::mem::offset_of!(MacroCtx, fail) as i32;

/// Most variables of one run kept in registers (the others stay in memory).
const MAX_REGS: usize = 32;

/// The signatures a run calls.
pub(super) struct Sigs {
    /// `fn(i64, f64) -> f64`: [`host_func`].
    pub f1: SigRef,
    /// `fn(f64, f64) -> f64`: [`host_atan2`], [`host_mod`].
    pub f2: SigRef,
    /// `fn(ptr, i64) -> f64`: [`sys_read`].
    pub rd: SigRef,
    /// `fn(ptr, i64, f64) -> i64`: [`sys_write`].
    pub wr: SigRef,
}

/// An expression value and whether it can be null.
#[derive(Clone, Copy)]
struct V {
    v: Value,
    null: bool,
}

struct G<'a, 'b> {
    b: &'a mut FunctionBuilder<'b>,
    ptr: Type,
    ctx: Value,
    vars: Value,
    s: Sigs,
    fail: Block,
    exit: Block,
    heads: Vec<Block>,
    first: usize,
    bi: usize,
    executed: Variable,
    max: Value,
    regs: BTreeMap<u32, Variable>,
}

/// The plain variables with literal numbers of `e`.
fn expr_vars(e: &Expr, out: &mut Vec<u32>, indexed: &mut bool) {
    match e {
        Expr::Num(_) => {}
        Expr::Var(n) => {
            if is_plain(*n) {
                out.push(*n);
            }
        }
        Expr::VarAt(x) => {
            *indexed = true;
            expr_vars(x, out, indexed);
        }
        Expr::Neg(x) | Expr::Call(_, x) => expr_vars(x, out, indexed),
        Expr::Bin(_, a, b) | Expr::Atan2(a, b) => {
            expr_vars(a, out, indexed);
            expr_vars(b, out, indexed);
        }
    }
}

/// True when every value `e` can have (null read as 0, an operation that is not finite fails) is
/// an integer: rounding it changes no bit (`ROUND` of an integer, `-0` included, is itself).
fn integral(e: &Expr) -> bool {
    use super::super::BinOp;
    match e {
        Expr::Num(v) => v.fract() == 0.0,
        Expr::Var(_) | Expr::VarAt(_) | Expr::Atan2(..) => false,
        Expr::Neg(x) => integral(x),
        Expr::Call(f, x) => match f {
            Func::Round | Func::Fix | Func::Fup => true,
            Func::Abs => integral(x),
            _ => false,
        },
        // A sum, difference or product of integers is one (beyond 2^53 every f64 is an integer).
        Expr::Bin(BinOp::Add | BinOp::Sub | BinOp::Mul, a, b) => integral(a) && integral(b),
        Expr::Bin(BinOp::Div, ..) => false,
        // The remainder of rounded operands, the bitwise operators and the comparisons.
        Expr::Bin(..) => true,
    }
}

/// The variables of run `first..end` kept in registers (none when it computes a variable number).
fn register_vars(prog: &Program, first: usize, end: usize) -> Vec<u32> {
    let (mut vars, mut indexed) = (Vec::new(), false);
    for b in &prog.blocks[first..end] {
        let Some(stmt) = b.mac.as_ref().and_then(|m| m.stmt.as_ref()) else {
            continue;
        };
        let target = |t: &Target, vars: &mut Vec<u32>, indexed: &mut bool| match t {
            Target::Var(n) if is_plain(*n) => vars.push(*n),
            Target::Var(_) => {}
            Target::At(e) => {
                *indexed = true;
                expr_vars(e, vars, indexed);
            }
        };
        match stmt {
            Stmt::Assign(t, e) => {
                target(t, &mut vars, &mut indexed);
                expr_vars(e, &mut vars, &mut indexed);
            }
            Stmt::IfThen(c, t, e) => {
                expr_vars(c, &mut vars, &mut indexed);
                target(t, &mut vars, &mut indexed);
                expr_vars(e, &mut vars, &mut indexed);
            }
            Stmt::IfGoto(c, _) | Stmt::While(Some(c), _) => expr_vars(c, &mut vars, &mut indexed),
            _ => {}
        }
    }
    // A computed number may name any variable: registers would need a comparison with each of
    // them at every `#[…]` (measured: slower than the loads they save).
    if indexed {
        return Vec::new();
    }
    vars.sort_unstable();
    vars.dedup();
    vars.truncate(MAX_REGS);
    vars
}

impl G<'_, '_> {
    /// Fails the current block with `code` unless `ok`.
    fn guard(&mut self, ok: Value, code: i64) {
        let (cont, bad) = (self.b.create_block(), self.b.create_block());
        self.b.ins().brif(ok, cont, &[], bad, &[]);
        self.b.switch_to_block(bad);
        let c = self.b.ins().iconst(types::I64, code);
        let at = self.b.ins().iconst(types::I64, self.bi as i64);
        self.b
            .ins()
            .jump(self.fail, &[BlockArg::from(c), BlockArg::from(at)]);
        self.b.switch_to_block(cont);
    }

    /// Hands the current block to the interpreter unless `ok` (its count taken back).
    fn bail_unless(&mut self, ok: Value) {
        let (cont, bail) = (self.b.create_block(), self.b.create_block());
        self.b.ins().brif(ok, cont, &[], bail, &[]);
        self.b.switch_to_block(bail);
        let e = self.b.use_var(self.executed);
        let e = self.b.ins().iadd_imm_s(e, -1);
        self.b.def_var(self.executed, e);
        let c = self.b.ins().iconst(types::I64, INTERPRET_CODE);
        let at = self.b.ins().iconst(types::I64, self.bi as i64);
        self.b
            .ins()
            .jump(self.fail, &[BlockArg::from(c), BlockArg::from(at)]);
        self.b.switch_to_block(cont);
    }

    /// The variable number of `#[x]` as [`super::super::eval::var_number`] (saturated beyond);
    /// `int`: `x` is an integer already (no rounding).
    fn var_number(&mut self, x: V, int: bool) -> Value {
        let v = self.z(x);
        let r = if int { v } else { self.round(v) };
        self.b.ins().fcvt_to_sint_sat(types::I64, r)
    }

    /// True when `n` is a plain variable number.
    fn is_plain_n(&mut self, n: Value) -> Value {
        let mut ok = None;
        for (lo, hi) in [(1i64, 33i64), (100, 199), (500, 999)] {
            let d = self.b.ins().iadd_imm_s(n, -lo);
            let k = self
                .b
                .ins()
                .icmp_imm_s(IntCC::UnsignedLessThanOrEqual, d, hi - lo);
            ok = Some(match ok {
                None => k,
                Some(o) => self.b.ins().bor(o, k),
            });
        }
        ok.unwrap_or_else(|| self.b.ins().iconst(types::I8, 0))
    }

    fn slot_addr(&mut self, n: Value) -> Value {
        let off = self.b.ins().imul_imm_s(n, 8);
        self.b.ins().iadd(self.vars, off)
    }

    fn read(&mut self, n: u32) -> V {
        if n == 0 {
            return V {
                v: self.f(f64::NAN),
                null: true,
            };
        }
        if let Some(&r) = self.regs.get(&n) {
            return V {
                v: self.b.use_var(r),
                null: true,
            };
        }
        if is_plain(n) {
            let v = self.b.ins().load(types::F64, FL, self.vars, (n as i32) * 8);
            return V { v, null: true };
        }
        if n == 4114 || n == 4314 {
            // The sequence number lives in the table, not in the host.
            let v = self
                .b
                .ins()
                .load(types::F64, FL, self.vars, (SEQ_SLOT as i32) * 8);
            return V { v, null: true };
        }
        // A system variable: the host's value, NaN when the interpreter must run the block.
        let nv = self.b.ins().iconst(types::I64, i64::from(n));
        let fp = self.b.ins().iconst(
            self.ptr,
            sys_read as extern "C" fn(*mut MacroCtx, i64) -> f64 as usize as i64,
        );
        let c = self.b.ins().call_indirect(self.s.rd, fp, &[self.ctx, nv]);
        let v = self.b.inst_results(c)[0];
        let ok = self.b.ins().fcmp(FloatCC::Ordered, v, v);
        self.bail_unless(ok);
        V { v, null: false }
    }

    /// The raw value of `e`, as [`super::super::eval::eval`].
    fn expr(&mut self, e: &Expr) -> V {
        let nn = |v| V { v, null: false };
        match e {
            Expr::Num(v) => nn(self.f(*v)),
            Expr::Var(n) => self.read(*n),
            Expr::VarAt(x) => {
                let int = integral(x);
                let x = self.expr(x);
                let n = self.var_number(x, int);
                let zero = self.b.ins().icmp_imm_s(IntCC::Equal, n, 0);
                let plain = self.is_plain_n(n);
                let ok = self.b.ins().bor(zero, plain);
                self.bail_unless(ok);
                // Slot 0 is #0, always null: the table never stores into it.
                let a = self.slot_addr(n);
                let v = self.b.ins().load(types::F64, FL, a, 0);
                V { v, null: true }
            }
            Expr::Neg(x) => {
                let v = self.expr(x);
                let v = self.z(v);
                let n = self.b.ins().fneg(v);
                nn(self.fin(n))
            }
            Expr::Call(f, x) => {
                let v = self.expr(x);
                let v = self.z(v);
                // Exact IEEE operations, inline: the same bits as the interpreter's.
                let r = match f {
                    Func::Abs => self.b.ins().fabs(v),
                    Func::Fix => self.b.ins().trunc(v),
                    Func::Sqrt => self.b.ins().sqrt(v),
                    Func::Round => self.round(v),
                    Func::Fup => self.fup(v),
                    _ => self.call1(*f, v),
                };
                nn(self.fin(r))
            }
            Expr::Atan2(a, b) => {
                let a = self.expr(a);
                let a = self.z(a);
                let b = self.expr(b);
                let b = self.z(b);
                let r = self.call2(host_atan2, a, b);
                nn(self.fin(r))
            }
            Expr::Bin(op, a, b) => {
                let lit = match **b {
                    Expr::Num(v) => Some(v),
                    _ => None,
                };
                let int_a = integral(a);
                let a = self.expr(a);
                let b = self.expr(b);
                nn(self.bin(*op, a, b, lit, int_a))
            }
        }
    }

    /// A condition as an i8 truth value.
    fn truth(&mut self, e: &Expr) -> Value {
        let v = self.expr(e);
        let v = self.z(v);
        let zero = self.f(0.0);
        self.b.ins().fcmp(FloatCC::NotEqual, v, zero)
    }

    fn goto(&mut self, to: usize) {
        match to.checked_sub(self.first).filter(|&k| k < self.heads.len()) {
            Some(k) => {
                self.b.ins().jump(self.heads[k], &[]);
            }
            None => {
                let v = self.b.ins().iconst(types::I64, to as i64);
                self.b.ins().jump(self.exit, &[BlockArg::from(v)]);
            }
        }
    }

    /// Stores `v` (raw) into target `t`; the variable number of `#[…]` is computed here, after the
    /// value, as the interpreter does.
    fn store(&mut self, t: &Target, v: Value) {
        match t {
            Target::Var(n) => {
                if let Some(&r) = self.regs.get(n) {
                    self.b.def_var(r, v);
                } else if is_plain(*n) {
                    self.b.ins().store(FL, v, self.vars, (*n as i32) * 8);
                } else {
                    let nv = self.b.ins().iconst(types::I64, i64::from(*n));
                    let fp = self.b.ins().iconst(
                        self.ptr,
                        sys_write as extern "C" fn(*mut MacroCtx, i64, f64) -> i64 as usize as i64,
                    );
                    let c = self
                        .b
                        .ins()
                        .call_indirect(self.s.wr, fp, &[self.ctx, nv, v]);
                    let r = self.b.inst_results(c)[0];
                    let ok = self.b.ins().icmp_imm_s(IntCC::Equal, r, 0);
                    self.bail_unless(ok);
                }
            }
            Target::At(e) => {
                let x = self.expr(e);
                let n = self.var_number(x, integral(e));
                let ok = self.is_plain_n(n);
                self.bail_unless(ok);
                let a = self.slot_addr(n);
                self.b.ins().store(FL, v, a, 0);
            }
        }
    }

    /// The register-held variables (empty in a run with computed numbers).
    fn reg_list(&self) -> Vec<(u32, Variable)> {
        self.regs.iter().map(|(n, r)| (*n, *r)).collect()
    }

    /// Emits block `bi` at its head.
    fn block(&mut self, prog: &Program, bi: usize) {
        self.bi = bi;
        let blk = &prog.blocks[bi];
        let e = self.b.use_var(self.executed);
        let e = self.b.ins().iadd_imm_s(e, 1);
        self.b.def_var(self.executed, e);
        let ok = self
            .b
            .ins()
            .icmp(IntCC::UnsignedLessThanOrEqual, e, self.max);
        self.guard(ok, LIMIT_CODE);
        if let Some(n) = blk.n {
            let v = self.f(f64::from(n));
            self.b.ins().store(FL, v, self.vars, (SEQ_SLOT as i32) * 8);
        }
        let Some(stmt) = blk.mac.as_ref().and_then(|m| m.stmt.as_ref()) else {
            return self.goto(bi + 1);
        };
        let jump = blk.jump.unwrap_or(bi + 1);
        match stmt {
            Stmt::Assign(t, x) => {
                let v = self.expr(x);
                self.store(t, v.v);
                self.goto(bi + 1);
            }
            Stmt::IfThen(c, t, x) => {
                let c = self.truth(c);
                let (yes, next) = (self.b.create_block(), self.b.create_block());
                self.b.ins().brif(c, yes, &[], next, &[]);
                self.b.switch_to_block(yes);
                let v = self.expr(x);
                self.store(t, v.v);
                self.b.ins().jump(next, &[]);
                self.b.switch_to_block(next);
                self.goto(bi + 1);
            }
            Stmt::IfGoto(c, _) => {
                let c = self.truth(c);
                let (yes, no) = (self.b.create_block(), self.b.create_block());
                self.b.ins().brif(c, yes, &[], no, &[]);
                self.b.switch_to_block(yes);
                self.goto(jump);
                self.b.switch_to_block(no);
                self.goto(bi + 1);
            }
            Stmt::Goto(_) | Stmt::End(_) => self.goto(jump),
            Stmt::While(Some(c), _) => {
                let c = self.truth(c);
                let (yes, no) = (self.b.create_block(), self.b.create_block());
                self.b.ins().brif(c, yes, &[], no, &[]);
                self.b.switch_to_block(yes);
                self.goto(bi + 1);
                self.b.switch_to_block(no);
                self.goto(jump + 1);
            }
            Stmt::While(None, _) | Stmt::Call { .. } => self.goto(bi + 1),
        }
    }

    /// Stores the register-held variables back into the table.
    fn write_back(&mut self) {
        for (n, r) in self.reg_list() {
            let v = self.b.use_var(r);
            self.b.ins().store(FL, v, self.vars, (n as i32) * 8);
        }
    }
}

/// Builds the function of run `first..end`: `fn(*mut MacroCtx, entry) -> next or -code`.
pub(super) fn build(
    b: &mut FunctionBuilder,
    ptr: Type,
    s: Sigs,
    prog: &Program,
    first: usize,
    end: usize,
) {
    let entry = b.create_block();
    b.append_block_params_for_function_params(entry);
    b.switch_to_block(entry);
    let ctx = b.block_params(entry)[0];
    let at = b.block_params(entry)[1];
    let vars = b.ins().load(ptr, FL, ctx, OFF_VARS);
    let max = b.ins().load(types::I64, FL, ctx, OFF_MAX);
    let executed = b.declare_var(types::I64);
    let e0 = b.ins().load(types::I64, FL, ctx, OFF_EXECUTED);
    b.def_var(executed, e0);
    let mut regs = BTreeMap::new();
    for n in register_vars(prog, first, end) {
        let r = b.declare_var(types::F64);
        let v = b.ins().load(types::F64, FL, vars, (n as i32) * 8);
        b.def_var(r, v);
        regs.insert(n, r);
    }
    let exit = b.create_block();
    b.append_block_param(exit, types::I64);
    let fail = b.create_block();
    b.append_block_param(fail, types::I64);
    b.append_block_param(fail, types::I64);
    let heads: Vec<Block> = (first..end).map(|_| b.create_block()).collect();
    crate::jit::dispatch::entry_dispatch(b, at, first, &heads, exit);
    let mut g = G {
        b,
        ptr,
        ctx,
        vars,
        s,
        fail,
        exit,
        heads: heads.clone(),
        first,
        bi: first,
        executed,
        max,
        regs,
    };
    for (k, bi) in (first..end).enumerate() {
        g.b.switch_to_block(heads[k]);
        g.block(prog, bi);
    }
    g.b.switch_to_block(exit);
    let next = g.b.block_params(exit)[0];
    g.write_back();
    let e = g.b.use_var(executed);
    g.b.ins().store(FL, e, ctx, OFF_EXECUTED);
    g.b.ins().return_(&[next]);
    g.b.switch_to_block(fail);
    let (code, bi) = (g.b.block_params(fail)[0], g.b.block_params(fail)[1]);
    g.write_back();
    let e = g.b.use_var(executed);
    g.b.ins().store(FL, e, ctx, OFF_EXECUTED);
    g.b.ins().store(FL, bi, ctx, OFF_FAIL);
    let neg = g.b.ins().ineg(code);
    g.b.ins().return_(&[neg]);
}
