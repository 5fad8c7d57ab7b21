//! Macro B compiled with cranelift: runs of macro-only blocks as native functions.
//!
//! A block belongs to a run when it is a macro statement without block skip (`#i = …`, `IF … THEN`,
//! `IF … GOTO`, `GOTO`, `WHILE … DO`, `DO`, `END`) whose jumps were resolved at compile time
//! ([`super::flow`]) and whose variables are plain (`#0`, #1–#33, #100–#199, #500–#999), computed
//! (`#[…]`) or system variables the executor serves ([`SysVars`]; not `#3000`). Consecutive such
//! blocks of one unit form a run; its function `fn(*mut MacroCtx, entry) -> i64` (built by [`emit`]
//! through [`crate::jit::Jit`], the module builder of the MEFI regions) starts at any block of the
//! run, follows fall-through, loops and jumps inside it, counts every block against the
//! executed-block limit before running it, and returns the index of the first block outside the run
//! (or of a block it hands back to the interpreter: a computed number outside the plain table, a
//! system variable the host refuses), or a negative [`MacroError::code`] (the failing block in
//! [`MacroCtx::fail`]). Arithmetic, null handling, comparisons and the exact functions are inline
//! and follow [`super::eval`] operation by operation; the transcendental functions call the same
//! `extern "C"` functions the interpreter calls, so both back ends give the same bits.

mod emit;

use cranelift_codegen::ir::types;
use cranelift_jit::JITModule;

use super::eval::MacroError;
use super::{Expr, Stmt, Target, is_plain};
use crate::fanuc_exec::macros::is_system;
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
    /// The system-variable host: a `*mut &mut dyn SysVars`, or null.
    pub host: *mut std::ffi::c_void,
}

/// The system variables native code reads and writes through the executor.
pub trait SysVars {
    /// System variable `n` (never null), or None to hand the block to the interpreter.
    fn read_sys(&self, n: u32) -> Option<f64>;
    /// Writes system variable `n` (raw value); false hands the block to the interpreter (nothing
    /// was written).
    fn write_sys(&mut self, n: u32, v: f64) -> bool;
}

/// System variable `n` for native code; NaN: hand the block to the interpreter.
extern "C" fn sys_read(ctx: *mut MacroCtx, n: i64) -> f64 {
    // SAFETY: native code passes the `MacroCtx` `MacroCode::run` built; `host` is null or points
    // to a `&mut dyn SysVars` that outlives the call.
    let host = unsafe { (*ctx).host } as *mut &mut dyn SysVars;
    if host.is_null() {
        return f64::NAN;
    }
    // SAFETY: as above; no other reference to the host is alive while native code runs.
    let host = unsafe { &*host };
    u32::try_from(n)
        .ok()
        .and_then(|n| host.read_sys(n))
        .unwrap_or(f64::NAN)
}

/// Writes system variable `n` for native code; 0 when written, 1: hand the block to the interpreter.
extern "C" fn sys_write(ctx: *mut MacroCtx, n: i64, v: f64) -> i64 {
    // SAFETY: as in `sys_read`.
    let host = unsafe { (*ctx).host } as *mut &mut dyn SysVars;
    if host.is_null() {
        return 1;
    }
    // SAFETY: as in `sys_read`.
    let host = unsafe { &mut *host };
    match u32::try_from(n) {
        Ok(n) if host.write_sys(n, v) => 0,
        _ => 1,
    }
}

/// Error code of the executed-block limit.
const LIMIT_CODE: i64 = 9000;
/// Return code of a block handed to the interpreter.
const INTERPRET_CODE: i64 = 9001;

/// How a macro function ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MacroExit {
    /// Continue with this block index (not yet counted).
    Next(usize),
    /// Block `.0` failed.
    Error(usize, MacroError),
    /// Block `.0` exceeded the executed-block limit.
    Limit(usize),
    /// Block `.0` (not yet counted) must run in the interpreter: a computed variable number outside
    /// the plain table or a system variable the host refused.
    Interpret(usize),
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

    /// Runs run `ri` from block `entry` on `vars`, advancing `executed` up to `max_blocks`; system
    /// variables go through `host` (without one, their blocks return to the interpreter).
    pub fn run(
        &self,
        ri: usize,
        entry: usize,
        vars: &mut [f64],
        executed: &mut u64,
        max_blocks: u64,
        host: Option<&mut dyn SysVars>,
    ) -> MacroExit {
        let Some(f) = self.fns.get(ri) else {
            return MacroExit::Next(entry);
        };
        if vars.len() < super::SLOTS {
            return MacroExit::Next(entry);
        }
        let mut host = host;
        let hp: *mut std::ffi::c_void = match host.as_mut() {
            Some(h) => (h as *mut &mut dyn SysVars).cast(),
            None => std::ptr::null_mut(),
        };
        let mut ctx = MacroCtx {
            vars: vars.as_mut_ptr(),
            executed: *executed,
            max_blocks,
            fail: 0,
            host: hp,
        };
        // SAFETY: compiled for `MacroCtx` (repr(C)); it reads and writes `vars[0..SLOTS]` only
        // (checked above; computed numbers are checked against the plain ranges), calls the pure
        // host functions of `eval` and `sys_read`/`sys_write` on `host`, borrowed for this call.
        let rv = unsafe { f(&mut ctx, entry as i64) };
        *executed = ctx.executed;
        let at = ctx.fail as usize;
        match rv {
            n if n >= 0 => MacroExit::Next(n as usize),
            n if n == -LIMIT_CODE => MacroExit::Limit(at),
            n if n == -INTERPRET_CODE => MacroExit::Interpret(at),
            n => MacroExit::Error(at, MacroError::from_code(-n)),
        }
    }
}

/// A variable number native code handles: null, plain, or a system variable other than `#3000`.
fn native_var(n: u32) -> bool {
    n == 0 || is_plain(n) || (is_system(n) && n != 3000)
}

fn plain_expr(e: &Expr) -> bool {
    match e {
        Expr::Num(_) => true,
        Expr::Var(n) => native_var(*n),
        Expr::VarAt(x) | Expr::Neg(x) | Expr::Call(_, x) => plain_expr(x),
        Expr::Bin(_, a, b) | Expr::Atan2(a, b) => plain_expr(a) && plain_expr(b),
    }
}

fn plain_target(t: &Target) -> bool {
    match t {
        Target::Var(n) => *n != 0 && native_var(*n),
        Target::At(e) => plain_expr(e),
    }
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
    let f1sig = jit.signature(&[types::I64, types::F64], types::F64);
    let f2sig = jit.signature(&[types::F64, types::F64], types::F64);
    let rdsig = jit.signature(&[ptr, types::I64], types::F64);
    let wrsig = jit.signature(&[ptr, types::I64, types::F64], types::I64);
    let mut ids = Vec::new();
    for &(s, e) in &runs {
        let sigs = [&f1sig, &f2sig, &rdsig, &wrsig].map(|s| s.clone());
        ids.push(jit.define(sig.clone(), |b, _| {
            let [f1, f2, rd, wr] = sigs.map(|s| b.import_signature(s));
            emit::build(b, ptr, emit::Sigs { f1, f2, rd, wr }, prog, s, e);
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
