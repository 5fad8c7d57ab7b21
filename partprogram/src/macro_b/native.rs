//! Macro B compiled with cranelift: runs of macro-only blocks as native functions.
//!
//! A block belongs to a run when it is a macro statement without block skip (`#i = …`, `IF … THEN`,
//! `IF … GOTO`, `GOTO`, `WHILE … DO`, `DO`, `END`) whose jumps were resolved at compile time
//! ([`super::flow`]) and which reads and writes only plain variables (`#0`, #1–#33, #100–#199,
//! #500–#999 with literal numbers). Consecutive such blocks of one unit form a run; its function
//! `fn(*mut MacroCtx, entry) -> i64` (built through [`crate::jit::Jit`], the module builder of the
//! MEFI regions) starts at any block of the run, follows fall-through, loops and jumps inside it,
//! counts every block against the executed-block limit before running it, and returns the index of the
//! first block outside the run, or a negative [`MacroError::code`] (the failing block in
//! [`MacroCtx::fail`]). Arithmetic, null handling and comparisons are inline and follow
//! [`super::eval`] operation by operation; functions, `MOD` and `ROUND` call the same `extern "C"`
//! functions the interpreter calls, so both back ends give the same bits.

use cranelift_codegen::ir::condcodes::{FloatCC, IntCC};
use cranelift_codegen::ir::immediates::Ieee64;
use cranelift_codegen::ir::{
    Block, BlockArg, InstBuilder, JumpTableData, MemFlagsData, SigRef, Type, Value, types,
};
use cranelift_frontend::{FunctionBuilder, Variable};
use cranelift_jit::JITModule;

use super::eval::{MacroError, host_atan2, host_func, host_mod};
use super::{BinOp, Expr, Func, Stmt, Target, is_plain};
use crate::jit::{Jit, NativeError};
use crate::program::Program;

/// The state a macro function works on. `repr(C)`: native code addresses the fields by offset.
#[derive(Debug)]
#[repr(C)]
pub struct MacroCtx {
    /// The variable table ([`super::SLOTS`] values).
    pub vars: *mut f64,
    /// Executed-block count (in and out).
    pub executed: u64,
    /// Limit of the executed-block count.
    pub max_blocks: u64,
    /// The block that failed (out).
    pub fail: u64,
}

/// Error code of the executed-block limit.
const LIMIT_CODE: i64 = 9000;
const FL: MemFlagsData = MemFlagsData::new().with_notrap();
const OFF_VARS: i32 = std::mem::offset_of!(MacroCtx, vars) as i32;
const OFF_EXECUTED: i32 = std::mem::offset_of!(MacroCtx, executed) as i32;
const OFF_MAX: i32 = std::mem::offset_of!(MacroCtx, max_blocks) as i32;
const OFF_FAIL: i32 = std::mem::offset_of!(MacroCtx, fail) as i32;

/// How a macro function ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MacroExit {
    /// Continue with this block index (not yet counted).
    Next(usize),
    /// Block `.0` failed.
    Error(usize, MacroError),
    /// Block `.0` exceeded the executed-block limit.
    Limit(usize),
}

type MacroFn = unsafe extern "C" fn(*mut MacroCtx, i64) -> i64;

/// The compiled macro runs of a program.
pub struct MacroCode {
    fns: Vec<MacroFn>,
    region_of: Vec<u32>,
    module: Option<JITModule>,
}

impl std::fmt::Debug for MacroCode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "MacroCode({} runs)", self.fns.len())
    }
}

// SAFETY: the module owns immutable finalized code; the pointers are plain code addresses.
unsafe impl Send for MacroCode {}
// SAFETY: as above; calling a function needs an exclusive `&mut [f64]`.
unsafe impl Sync for MacroCode {}

impl Drop for MacroCode {
    fn drop(&mut self) {
        self.fns.clear();
        if let Some(m) = self.module.take() {
            // SAFETY: the function pointers were dropped above and never escape this value.
            unsafe { m.free_memory() };
        }
    }
}

impl MacroCode {
    /// The run that can start at block `bi`, if any.
    pub fn run_at(&self, bi: usize) -> Option<usize> {
        self.region_of
            .get(bi)
            .filter(|&&r| r != u32::MAX)
            .map(|&r| r as usize)
    }

    /// Number of compiled runs.
    pub fn run_count(&self) -> usize {
        self.fns.len()
    }

    /// Runs run `ri` from block `entry` on `vars`, advancing `executed` up to `max_blocks`.
    pub fn run(
        &self,
        ri: usize,
        entry: usize,
        vars: &mut [f64],
        executed: &mut u64,
        max_blocks: u64,
    ) -> MacroExit {
        let Some(f) = self.fns.get(ri) else {
            return MacroExit::Next(entry);
        };
        if vars.len() < super::SLOTS {
            return MacroExit::Next(entry);
        }
        let mut ctx = MacroCtx {
            vars: vars.as_mut_ptr(),
            executed: *executed,
            max_blocks,
            fail: 0,
        };
        // SAFETY: compiled for `MacroCtx` (repr(C)); it reads and writes `vars[0..SLOTS]` only
        // (checked above) and calls the pure host functions of `eval`.
        let rv = unsafe { f(&mut ctx, entry as i64) };
        *executed = ctx.executed;
        let at = ctx.fail as usize;
        match rv {
            n if n >= 0 => MacroExit::Next(n as usize),
            n if n == -LIMIT_CODE => MacroExit::Limit(at),
            n => MacroExit::Error(at, MacroError::from_code(-n)),
        }
    }
}

fn plain_expr(e: &Expr) -> bool {
    match e {
        Expr::Num(_) => true,
        Expr::Var(n) => *n == 0 || is_plain(*n),
        Expr::VarAt(_) => false,
        Expr::Neg(x) | Expr::Call(_, x) => plain_expr(x),
        Expr::Bin(_, a, b) | Expr::Atan2(a, b) => plain_expr(a) && plain_expr(b),
    }
}

fn plain_target(t: &Target) -> bool {
    matches!(t, Target::Var(n) if is_plain(*n))
}

/// True when block `bi` can run natively.
fn nativable(prog: &Program, bi: usize) -> bool {
    let b = &prog.blocks[bi];
    if b.skip {
        return false;
    }
    let Some(stmt) = b.mac.as_ref().and_then(|m| m.stmt.as_ref()) else {
        return false;
    };
    match stmt {
        Stmt::Assign(t, e) => plain_target(t) && plain_expr(e),
        Stmt::IfThen(c, t, e) => plain_expr(c) && plain_target(t) && plain_expr(e),
        Stmt::IfGoto(c, _) => b.jump.is_some() && plain_expr(c),
        Stmt::Goto(_) | Stmt::End(_) => b.jump.is_some(),
        Stmt::While(c, _) => b.jump.is_some() && c.as_ref().is_none_or(plain_expr),
        Stmt::Call { .. } => false,
    }
}

/// The runs of `prog`: (first block, one past the last).
fn find_runs(prog: &Program) -> Vec<(usize, usize)> {
    let mut runs = Vec::new();
    for u in &prog.units {
        let mut bi = u.start;
        while bi < u.end {
            if !nativable(prog, bi) {
                bi += 1;
                continue;
            }
            let s = bi;
            while bi < u.end && nativable(prog, bi) && bi - s < 1024 {
                bi += 1;
            }
            runs.push((s, bi));
        }
    }
    runs
}

/// Compiles the macro runs of `prog` (None when it has none).
pub fn compile(prog: &Program) -> Result<Option<MacroCode>, NativeError> {
    let runs = find_runs(prog);
    if runs.is_empty() {
        return Ok(None);
    }
    let mut jit = Jit::new(prog.machine.double_precision)?;
    let ptr = jit.pointer_type();
    let sig = jit.region_signature();
    let fsig = jit.signature(&[types::I64, types::F64], types::F64);
    let f2sig = jit.signature(&[types::F64, types::F64], types::F64);
    let mut ids = Vec::new();
    for &(s, e) in &runs {
        let (fsig, f2sig) = (fsig.clone(), f2sig.clone());
        ids.push(jit.define(sig.clone(), |b, _| {
            let f1 = b.import_signature(fsig);
            let f2 = b.import_signature(f2sig);
            build(b, ptr, f1, f2, prog, s, e);
        })?);
    }
    let (module, ptrs) = jit.finish_raw(&ids)?;
    let fns = ptrs
        .into_iter()
        // SAFETY: defined with signature `fn(*mut MacroCtx, i64) -> i64` in the default call conv.
        .map(|p| unsafe { std::mem::transmute::<*const u8, MacroFn>(p) })
        .collect();
    let mut region_of = vec![u32::MAX; prog.blocks.len()];
    for (ri, &(s, e)) in runs.iter().enumerate() {
        for r in &mut region_of[s..e] {
            *r = ri as u32;
        }
    }
    Ok(Some(MacroCode {
        fns,
        region_of,
        module: Some(module),
    }))
}

struct G<'a, 'b> {
    b: &'a mut FunctionBuilder<'b>,
    ptr: Type,
    vars: Value,
    f1: SigRef,
    f2: SigRef,
    fail: Block,
    exit: Block,
    heads: Vec<Block>,
    first: usize,
    bi: usize,
    executed: Variable,
    max: Value,
}

impl G<'_, '_> {
    fn f(&mut self, v: f64) -> Value {
        self.b.ins().f64const(Ieee64::with_bits(v.to_bits()))
    }

    /// Null read as 0.
    fn z(&mut self, x: Value) -> Value {
        let nan = self.b.ins().fcmp(FloatCC::Unordered, x, x);
        let zero = self.f(0.0);
        self.b.ins().select(nan, zero, x)
    }

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

    /// `x` when finite, else the Range error.
    fn fin(&mut self, x: Value) -> Value {
        let a = self.b.ins().fabs(x);
        let inf = self.f(f64::INFINITY);
        let ok = self.b.ins().fcmp(FloatCC::LessThan, a, inf);
        self.guard(ok, MacroError::Range.code());
        x
    }

    fn call1(&mut self, f: Func, x: Value) -> Value {
        let code = self.b.ins().iconst(types::I64, f as i64);
        let fp = self.b.ins().iconst(
            self.ptr,
            host_func as extern "C" fn(i64, f64) -> f64 as usize as i64,
        );
        let c = self.b.ins().call_indirect(self.f1, fp, &[code, x]);
        self.b.inst_results(c)[0]
    }

    fn call2(&mut self, h: extern "C" fn(f64, f64) -> f64, a: Value, b: Value) -> Value {
        let fp = self.b.ins().iconst(self.ptr, h as usize as i64);
        let c = self.b.ins().call_indirect(self.f2, fp, &[a, b]);
        self.b.inst_results(c)[0]
    }

    fn bool_f(&mut self, c: Value) -> Value {
        let (one, zero) = (self.f(1.0), self.f(0.0));
        self.b.ins().select(c, one, zero)
    }

    /// The raw value of `e` (null possible only from a variable), as [`super::eval::eval`].
    fn expr(&mut self, e: &Expr) -> Value {
        match e {
            Expr::Num(v) => self.f(*v),
            Expr::Var(0) | Expr::VarAt(_) => self.f(f64::NAN),
            Expr::Var(n) => self
                .b
                .ins()
                .load(types::F64, FL, self.vars, (*n as i32) * 8),
            Expr::Neg(x) => {
                let v = self.expr(x);
                let v = self.z(v);
                let n = self.b.ins().fneg(v);
                self.fin(n)
            }
            Expr::Call(f, x) => {
                let v = self.expr(x);
                let v = self.z(v);
                // ABS, FIX and SQRT are exact IEEE operations: inline, the same bits as Rust's.
                let r = match f {
                    Func::Abs => self.b.ins().fabs(v),
                    Func::Fix => self.b.ins().trunc(v),
                    Func::Sqrt => self.b.ins().sqrt(v),
                    _ => self.call1(*f, v),
                };
                self.fin(r)
            }
            Expr::Atan2(a, b) => {
                let a = self.expr(a);
                let a = self.z(a);
                let b = self.expr(b);
                let b = self.z(b);
                let r = self.call2(host_atan2, a, b);
                self.fin(r)
            }
            Expr::Bin(op, a, b) => {
                let a = self.expr(a);
                let b = self.expr(b);
                self.bin(*op, a, b)
            }
        }
    }

    fn bin(&mut self, op: BinOp, a: Value, b: Value) -> Value {
        if matches!(op, BinOp::Eq | BinOp::Ne) {
            let na = self.b.ins().fcmp(FloatCC::Unordered, a, a);
            let nb = self.b.ins().fcmp(FloatCC::Unordered, b, b);
            let both = self.b.ins().band(na, nb);
            let same = self.b.ins().fcmp(FloatCC::Equal, a, b);
            let eq = self.b.ins().bor(both, same);
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
                let zero = self.f(0.0);
                let ok = self.b.ins().fcmp(FloatCC::NotEqual, b, zero);
                self.guard(ok, MacroError::DivZero.code());
                let r = self.b.ins().fdiv(a, b);
                self.fin(r)
            }
            BinOp::Mod => {
                let ra = self.call1(Func::Round, a);
                let rb = self.call1(Func::Round, b);
                let zero = self.f(0.0);
                let ok = self.b.ins().fcmp(FloatCC::NotEqual, rb, zero);
                self.guard(ok, MacroError::DivZero.code());
                let r = self.call2(host_mod, ra, rb);
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

    fn store(&mut self, t: &Target, v: Value) {
        if let Target::Var(n) = t {
            self.b.ins().store(FL, v, self.vars, (*n as i32) * 8);
        }
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
        let Some(stmt) = blk.mac.as_ref().and_then(|m| m.stmt.as_ref()) else {
            return self.goto(bi + 1);
        };
        let jump = blk.jump.unwrap_or(bi + 1);
        match stmt {
            Stmt::Assign(t, x) => {
                let v = self.expr(x);
                self.store(t, v);
                self.goto(bi + 1);
            }
            Stmt::IfThen(c, t, x) => {
                let c = self.truth(c);
                let (yes, next) = (self.b.create_block(), self.b.create_block());
                self.b.ins().brif(c, yes, &[], next, &[]);
                self.b.switch_to_block(yes);
                let v = self.expr(x);
                self.store(t, v);
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
}

/// Builds the function of run `first..end`.
fn build(
    b: &mut FunctionBuilder,
    ptr: Type,
    f1: SigRef,
    f2: SigRef,
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
    let exit = b.create_block();
    b.append_block_param(exit, types::I64);
    let fail = b.create_block();
    b.append_block_param(fail, types::I64);
    b.append_block_param(fail, types::I64);
    let heads: Vec<Block> = (first..end).map(|_| b.create_block()).collect();
    // Dispatch on the entry block.
    let idx = b.ins().iadd_imm_s(at, -(first as i64));
    let len = b.ins().iconst(types::I64, (end - first) as i64);
    let inside = b.ins().icmp(IntCC::UnsignedLessThan, idx, len);
    let (dispatch, outside) = (b.create_block(), b.create_block());
    b.ins().brif(inside, dispatch, &[], outside, &[]);
    b.switch_to_block(outside);
    b.ins().jump(exit, &[BlockArg::from(at)]);
    b.switch_to_block(dispatch);
    let idx32 = b.ins().ireduce(types::I32, idx);
    let def = b.func.dfg.block_call(outside, &[]);
    let table: Vec<_> = heads
        .iter()
        .map(|&h| b.func.dfg.block_call(h, &[]))
        .collect();
    let jt = b.create_jump_table(JumpTableData::new(def, &table));
    b.ins().br_table(idx32, jt);
    let mut g = G {
        b,
        ptr,
        vars,
        f1,
        f2,
        fail,
        exit,
        heads: heads.clone(),
        first,
        bi: first,
        executed,
        max,
    };
    for (k, bi) in (first..end).enumerate() {
        g.b.switch_to_block(heads[k]);
        g.block(prog, bi);
    }
    let b = g.b;
    b.switch_to_block(exit);
    let next = b.block_params(exit)[0];
    let e = b.use_var(executed);
    b.ins().store(FL, e, ctx, OFF_EXECUTED);
    b.ins().return_(&[next]);
    b.switch_to_block(fail);
    let (code, bi) = (b.block_params(fail)[0], b.block_params(fail)[1]);
    let e = b.use_var(executed);
    b.ins().store(FL, e, ctx, OFF_EXECUTED);
    b.ins().store(FL, bi, ctx, OFF_FAIL);
    let neg = b.ins().ineg(code);
    b.ins().return_(&[neg]);
}
