//! Native code for MEFI parameter programs, compiled with cranelift.
//!
//! Two kinds of functions are generated:
//!
//! * **Block functions** `fn(*mut ArithState) -> i32`: the G26–G29 operations of one block whose control
//!   words are declared in the block itself; the executor calls them for blocks that also do other
//!   things (motion, M functions, calls). They return 0 or the [`ArithError::code`] of the failure.
//! * **Region functions** `fn(*mut RegionCtx, entry) -> i64` ([`region`]): a run of consecutive blocks
//!   of one program unit that touch nothing but the parameters (declarations, static G26–G29, `G73 L Q`
//!   and `GR<n> L Q` jumps with literal targets, empty blocks) runs entirely natively — declarations,
//!   arithmetic, G-group bookkeeping, jump counters, loops formed by backward jumps and the
//!   executed-block count with its limit — and returns the index of the next block the executor
//!   must handle.
//!
//! Control words are decoded at compile time. Copy, add, subtract, multiply, divide, square, abs,
//! negate, comparisons (73/78), IF…ENDIF conditions (as branches), int↔real conversion, increment and
//! decrement and odd/even run inline on the parameter table ([`ops`]); all other operations (and
//! operands that address double-precision pairs) call back into the reference interpreter
//! ([`crate::arith`]) through one host function. Blocks whose control words are computed at run time
//! (self-modifying cycles) stay with the interpreter. Native and interpreted runs agree bit for bit
//! (checked by differential tests).

pub(crate) mod dispatch;
mod ops;
pub mod region;

use cranelift_codegen::ir::{AbiParam, InstBuilder, Signature, Value, types};
use cranelift_codegen::isa::OwnedTargetIsa;
use cranelift_codegen::settings::{self, Configurable};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_jit::{JITBuilder, JITModule};
use cranelift_module::{FuncId, Linkage, Module};

use crate::arith::{ArithError, ArithState, Word};
use crate::machine::DoublePrecision;
use crate::program::Program;
pub use region::{RegionCount, RegionCtx, RegionExit};

type BlockFn = unsafe extern "C" fn(*mut ArithState) -> i32;
type RegionFn = unsafe extern "C" fn(*mut RegionCtx, i64) -> i64;

/// One compiled region: its function and the blocks it covers.
struct RegionCode {
    f: RegionFn,
    /// Number of jump counters the function may address (the length of its unit).
    counters: usize,
}

/// Native functions of one program.
pub struct NativeCode {
    /// (block index, function index) for every block with native arithmetic.
    pub block_fn: Vec<(usize, usize)>,
    fns: Vec<BlockFn>,
    regions: Vec<RegionCode>,
    /// Region index per block (`u32::MAX`: the block is in no region).
    region_of: Vec<u32>,
    module: Option<JITModule>,
}

impl std::fmt::Debug for NativeCode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "NativeCode({} block functions, {} regions)",
            self.fns.len(),
            self.regions.len()
        )
    }
}

// SAFETY: the JIT module owns immutable, finalized code; the function pointers are plain code addresses.
unsafe impl Send for NativeCode {}
// SAFETY: as above; calling the functions requires `&mut ArithState`, so no shared mutable state.
unsafe impl Sync for NativeCode {}

impl NativeCode {
    /// Runs block function `fi` on `st`; returns 0 or an [`ArithError::code`].
    pub fn call(&self, fi: usize, st: &mut ArithState) -> i32 {
        match self.fns.get(fi) {
            // SAFETY: the function was compiled for `ArithState` (repr(C), `r` first) and only
            // touches `r[0..96]` inline; everything else goes through the host callbacks, which take
            // the same exclusive pointer.
            Some(f) => unsafe { f(st as *mut ArithState) },
            None => ArithError::BadOp(99).code(),
        }
    }

    /// The region that can run block `bi` natively, if any.
    pub fn region_at(&self, bi: usize) -> Option<usize> {
        self.region_of
            .get(bi)
            .filter(|&&r| r != u32::MAX)
            .map(|&r| r as usize)
    }

    /// Number of compiled regions.
    pub fn region_count(&self) -> usize {
        self.regions.len()
    }

    /// Runs region `ri` from block `entry`. `counters` are the G73 counters of the current frame
    /// (indexed by block index − unit start, [`region::IDLE`] for none); `count` holds the
    /// executed-block count, advanced by the blocks run here and checked against its limit.
    pub fn run_region(
        &self,
        ri: usize,
        entry: usize,
        st: &mut ArithState,
        counters: &mut [i64],
        count: &mut RegionCount,
    ) -> RegionExit {
        let Some(rc) = self.regions.get(ri) else {
            return RegionExit::Next(entry);
        };
        if counters.len() < rc.counters {
            return RegionExit::Next(entry);
        }
        let mut ctx = RegionCtx {
            st: st as *mut ArithState,
            counters: counters.as_mut_ptr(),
            executed: count.executed,
            max_blocks: count.max_blocks,
            block_skip: u64::from(count.block_skip),
            fail: 0,
        };
        // SAFETY: the function was compiled for `RegionCtx` (repr(C)); it addresses `r`, `g_groups`
        // of `*st` and `counters[0..rc.counters]` (checked above) only, and calls the host callbacks
        // with the same exclusive `st` pointer. Entries outside the region return at once.
        let rv = unsafe { (rc.f)(&mut ctx, entry as i64) };
        count.executed = ctx.executed;
        region::decode_exit(rv, ctx.fail as usize)
    }
}

impl Drop for NativeCode {
    fn drop(&mut self) {
        self.fns.clear();
        self.regions.clear();
        if let Some(m) = self.module.take() {
            // SAFETY: the function pointers were dropped above and never escape this value.
            unsafe { m.free_memory() };
        }
    }
}

/// The statically known control words of block `bi`, or None when any is computed at run time.
pub fn static_words(prog: &Program, bi: usize) -> Option<Vec<i64>> {
    let b = &prog.blocks[bi];
    let n = usize::from(b.arith_ops);
    let mut words = Vec::with_capacity(n);
    let mut dirty = false;
    for k in 0..n {
        let p = (5 + k) as u8;
        if dirty {
            return None;
        }
        let r = b.decls.iter().rev().find(|d| d.param == p)?.r;
        let w = Word::decode(r)?;
        // Any operation that may write R5..R8 makes the following words dynamic.
        let writes_ctl = match w.op {
            33 | 34 | 35 | 45 | 48 | 49 | 25 | 26 => true,
            20 | 21 | 22 | 29..=32 | 44 | 50 | 51 => false,
            _ => (5..=8).contains(&w.c) || w.c >= 50,
        };
        dirty |= writes_ctl;
        words.push(r);
    }
    Some(words)
}

/// Compiles every block of `prog` whose arithmetic is static, and every parameter-only region.
pub fn compile_program(prog: &Program) -> Result<NativeCode, NativeError> {
    let todo: Vec<(usize, Vec<i64>)> = (0..prog.blocks.len())
        .filter(|&bi| prog.blocks[bi].arith_ops > 0)
        .filter_map(|bi| static_words(prog, bi).map(|w| (bi, w)))
        .collect();
    let runs = region::find_runs(prog);
    if todo.is_empty() && runs.is_empty() {
        return Ok(NativeCode {
            block_fn: Vec::new(),
            fns: Vec::new(),
            regions: Vec::new(),
            region_of: Vec::new(),
            module: None,
        });
    }
    let mut jit = Jit::new(prog.machine.double_precision)?;
    let ids = todo
        .iter()
        .map(|(_, w)| jit.block_fn(w))
        .collect::<Result<Vec<_>, _>>()?;
    let rids = runs
        .iter()
        .map(|r| jit.region_fn(r))
        .collect::<Result<Vec<_>, _>>()?;
    let mut region_of = vec![u32::MAX; prog.blocks.len()];
    for (ri, r) in runs.iter().enumerate() {
        for pb in &r.blocks {
            region_of[pb.bi] = ri as u32;
        }
    }
    jit.finish(&todo, &ids, &runs, &rids, region_of)
}

/// Compiles one block function per `(key, words)` entry (used by tests and benchmarks directly).
pub fn compile_words(
    todo: &[(usize, Vec<i64>)],
    mode: DoublePrecision,
) -> Result<NativeCode, NativeError> {
    let mut jit = Jit::new(mode)?;
    let ids = todo
        .iter()
        .map(|(_, w)| jit.block_fn(w))
        .collect::<Result<Vec<_>, _>>()?;
    jit.finish(todo, &ids, &[], &[], Vec::new())
}

/// Why native code could not be generated (the interpreter then runs the program).
#[derive(Debug, thiserror::Error)]
pub enum NativeError {
    /// The host ISA or a cranelift setting is not available.
    #[error("cranelift setup: {0}")]
    Setup(String),
    /// Cranelift rejected a function or the module could not be finalized.
    #[error("cranelift: {0}")]
    Codegen(String),
}

fn setup(x: &dyn std::fmt::Display) -> NativeError {
    NativeError::Setup(x.to_string())
}

fn codegen(x: &dyn std::fmt::Display) -> NativeError {
    NativeError::Codegen(x.to_string())
}

/// A cranelift JIT module being filled with functions (shared with the Macro B compiler,
/// [`crate::macro_b::native`]).
pub(crate) struct Jit {
    isa: OwnedTargetIsa,
    module: JITModule,
    ctx: cranelift_codegen::Context,
    fctx: FunctionBuilderContext,
    block_sig: Signature,
    region_sig: Signature,
    host_sig: Signature,
    mode: DoublePrecision,
    count: usize,
}

impl Jit {
    /// A module for the host ISA (`mode`: the MEFI double-precision rule of the ops).
    pub(crate) fn new(mode: DoublePrecision) -> Result<Jit, NativeError> {
        let mut fb = settings::builder();
        fb.set("opt_level", "speed").map_err(|x| setup(&x))?;
        fb.set("is_pic", "false").map_err(|x| setup(&x))?;
        // As in the PLC JIT: the IR verifier re-checks every function; debug builds (all tests)
        // keep it, release builds skip it (it was 17 % of a part run's start-up).
        let verify = if cfg!(debug_assertions) {
            "true"
        } else {
            "false"
        };
        fb.set("enable_verifier", verify).map_err(|x| setup(&x))?;
        fb.set("use_colocated_libcalls", "false")
            .map_err(|x| setup(&x))?;
        let isa = cranelift_native::builder()
            .map_err(|x| setup(&x))?
            .finish(settings::Flags::new(fb))
            .map_err(|x| setup(&x))?;
        let ptr = isa.pointer_type();
        let module = JITModule::new(JITBuilder::with_isa(
            isa.clone(),
            cranelift_module::default_libcall_names(),
        ));
        let cc = isa.default_call_conv();
        let mut block_sig = Signature::new(cc);
        block_sig.params.push(AbiParam::new(ptr));
        block_sig.returns.push(AbiParam::new(types::I32));
        let mut region_sig = Signature::new(cc);
        region_sig.params.push(AbiParam::new(ptr));
        region_sig.params.push(AbiParam::new(types::I64));
        region_sig.returns.push(AbiParam::new(types::I64));
        let mut host_sig = Signature::new(cc);
        host_sig.params.push(AbiParam::new(ptr));
        host_sig.params.push(AbiParam::new(types::I64));
        host_sig.returns.push(AbiParam::new(types::I32));
        let ctx = module.make_context();
        Ok(Jit {
            isa,
            module,
            ctx,
            fctx: FunctionBuilderContext::new(),
            block_sig,
            region_sig,
            host_sig,
            mode,
            count: 0,
        })
    }

    /// Declares, builds with `body` and defines one function with signature `sig`.
    pub(crate) fn define(
        &mut self,
        sig: Signature,
        body: impl FnOnce(&mut FunctionBuilder, cranelift_codegen::ir::SigRef),
    ) -> Result<FuncId, NativeError> {
        self.count += 1;
        let id = self
            .module
            .declare_function(&format!("pp{}", self.count), Linkage::Local, &sig)
            .map_err(|x| codegen(&x))?;
        self.ctx.func.signature = sig;
        {
            let mut b = FunctionBuilder::new(&mut self.ctx.func, &mut self.fctx);
            let host_ref = b.import_signature(self.host_sig.clone());
            body(&mut b, host_ref);
            b.seal_all_blocks();
            b.finalize(self.isa.frontend_config());
        }
        self.module
            .define_function(id, &mut self.ctx)
            .map_err(|x| NativeError::Codegen(format!("{x:?}")))?;
        self.module.clear_context(&mut self.ctx);
        Ok(id)
    }

    /// The pointer type of the host.
    pub(crate) fn pointer_type(&self) -> types::Type {
        self.isa.pointer_type()
    }

    /// The signature `fn(*mut ctx, i64) -> i64` of region functions.
    pub(crate) fn region_signature(&self) -> Signature {
        self.region_sig.clone()
    }

    /// A signature in the host's call convention.
    pub(crate) fn signature(&self, params: &[types::Type], ret: types::Type) -> Signature {
        let mut s = Signature::new(self.isa.default_call_conv());
        s.params.extend(params.iter().map(|t| AbiParam::new(*t)));
        s.returns.push(AbiParam::new(ret));
        s
    }

    /// Finalizes the module and returns it with the addresses of functions `ids`.
    pub(crate) fn finish_raw(
        mut self,
        ids: &[FuncId],
    ) -> Result<(JITModule, Vec<*const u8>), NativeError> {
        self.module
            .finalize_definitions()
            .map_err(|x| codegen(&x))?;
        let ptrs = ids
            .iter()
            .map(|&id| self.module.get_finalized_function(id))
            .collect();
        Ok((self.module, ptrs))
    }

    fn block_fn(&mut self, words: &[i64]) -> Result<FuncId, NativeError> {
        let (ptr, mode) = (self.isa.pointer_type(), self.mode);
        self.define(self.block_sig.clone(), |b, host_ref| {
            let entry = b.create_block();
            b.append_block_params_for_function_params(entry);
            b.switch_to_block(entry);
            let st = b.block_params(entry)[0];
            let fail = b.create_block();
            b.append_block_param(fail, types::I32);
            b.append_block_param(fail, types::I64);
            let done = b.create_block();
            ops::Gen {
                b: &mut *b,
                st,
                host_ref,
                ptr,
                mode,
                fail,
                cur: 0,
            }
            .seq(words, done);
            b.switch_to_block(done);
            let zero = b.ins().iconst(types::I32, 0);
            b.ins().return_(&[zero]);
            b.switch_to_block(fail);
            let rc: Value = b.block_params(fail)[0];
            b.ins().return_(&[rc]);
        })
    }

    fn region_fn(&mut self, run: &region::Run) -> Result<FuncId, NativeError> {
        let (ptr, mode) = (self.isa.pointer_type(), self.mode);
        self.define(self.region_sig.clone(), |b, host_ref| {
            region::build(b, host_ref, ptr, mode, run);
        })
    }

    fn finish(
        mut self,
        todo: &[(usize, Vec<i64>)],
        ids: &[FuncId],
        runs: &[region::Run],
        rids: &[FuncId],
        region_of: Vec<u32>,
    ) -> Result<NativeCode, NativeError> {
        self.module
            .finalize_definitions()
            .map_err(|x| codegen(&x))?;
        let fns = ids
            .iter()
            .map(|&id| {
                let p = self.module.get_finalized_function(id);
                // SAFETY: defined with signature `fn(*mut ArithState) -> i32` in the default call conv.
                unsafe { std::mem::transmute::<*const u8, BlockFn>(p) }
            })
            .collect();
        let regions = rids
            .iter()
            .zip(runs)
            .map(|(&id, run)| {
                let p = self.module.get_finalized_function(id);
                RegionCode {
                    // SAFETY: defined with signature `fn(*mut RegionCtx, i64) -> i64` in the default
                    // call conv.
                    f: unsafe { std::mem::transmute::<*const u8, RegionFn>(p) },
                    counters: run.unit_len,
                }
            })
            .collect();
        let block_fn = todo
            .iter()
            .enumerate()
            .map(|(i, (bi, _))| (*bi, i))
            .collect();
        Ok(NativeCode {
            block_fn,
            fns,
            regions,
            region_of,
            module: Some(self.module),
        })
    }
}
