//! The cranelift back end: the FAST part and each SLOW slice become `extern "C" fn(*mut u8)`
//! functions over the image (long parts are split into several functions of bounded size to keep
//! compile time linear). One [`JITModule`] per program version; dropping the [`JitProgram`] frees
//! its code.
//!
//! Compile time is about linear in the number of CLIF instructions, so the translation keeps it
//! low: BOOL rungs work on bits in place (`bits`), loads are cached and stores to one place merged
//! within a block (`memory`), small IF zones are if-converted (`translate`), timers and counters
//! are branch-free (`stateful`). [`clif_stats`] counts what a program compiles to; functions are
//! compiled on [`JitOptions::threads`] threads.

mod bits;
mod cache;
mod code_cache;
pub mod disk_cache;
mod memory;
mod stateful;
mod translate;

use cranelift_codegen::ir::{AbiParam, Function, InstBuilder, Signature, UserFuncName};
use cranelift_codegen::isa::{CallConv, OwnedTargetIsa};
use cranelift_codegen::settings::{self, Configurable};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_jit::{JITBuilder, JITModule};
use cranelift_module::{Linkage, Module};

use crate::engine::Engine;
use crate::ir::{self, Program, Stmt};
use cache::Caches;
pub use code_cache::CodeCache;
use translate::Translator;

/// Why JIT compilation failed.
#[derive(Debug, thiserror::Error)]
pub enum JitError {
    /// The program breaks an IR rule.
    #[error(transparent)]
    Ir(#[from] ir::IrError),
    /// The host ISA or a setting is not available.
    #[error("cranelift setup: {0}")]
    Setup(String),
    /// Cranelift rejected a function.
    #[error("cranelift: {0}")]
    Codegen(String),
}

/// Code generation options (the defaults are what [`compile`] uses: `none`, `single_pass`,
/// chunks of 2000 cost units, one thread so that compiling never competes with the scan thread,
/// IF zones up to 24 cost units if-converted).
#[derive(Debug, Clone)]
pub struct JitOptions {
    /// Cranelift `opt_level`: `none`, `speed` or `speed_and_size`.
    pub opt_level: &'static str,
    /// Cranelift `regalloc_algorithm`: `backtracking` or `single_pass`.
    pub regalloc: &'static str,
    /// Largest cost ([`ir::Stmt::cost`]) of top-level statements put into one function.
    pub chunk_cost: u32,
    /// Threads compiling functions in parallel (0: the available cores, at most 4).
    pub threads: usize,
    /// IF zones whose [`ir::Stmt::cost`] is at most this run branch-free (both branches with
    /// guarded stores) instead of branching; 0 never, `u32::MAX` always.
    pub if_convert_cost: u32,
    /// A value loaded from or stored to the image, or a constant, is reused by the statements up
    /// to this many after the one that made it, and loaded or made again after that (short live
    /// ranges: fewer spills).
    pub cache_window: u32,
}

impl Default for JitOptions {
    fn default() -> Self {
        JitOptions {
            opt_level: "none",
            regalloc: "single_pass",
            chunk_cost: 2000,
            threads: 1,
            if_convert_cost: 24,
            cache_window: 1,
        }
    }
}

type ScanFn = unsafe extern "C" fn(*mut u8);

/// A compiled program: owns its executable memory.
pub struct JitProgram {
    module: Option<JITModule>,
    fast: Vec<ScanFn>,
    slow: Vec<Vec<ScanFn>>,
    image_len: usize,
    /// Address and length of the finalized text (all functions, see `link`).
    text: (usize, usize),
}

fn isa(opts: &JitOptions) -> Result<OwnedTargetIsa, JitError> {
    let setup = |e: &dyn std::fmt::Display| JitError::Setup(e.to_string());
    let mut fb = settings::builder();
    fb.set("opt_level", opts.opt_level).map_err(|e| setup(&e))?;
    fb.set("regalloc_algorithm", opts.regalloc)
        .map_err(|e| setup(&e))?;
    fb.set("is_pic", "false").map_err(|e| setup(&e))?;
    // The IR verifier re-checks every function we emit. Debug builds (all tests) keep it on so an
    // ill-formed function fails loudly; release builds skip it: it costs compile time on every
    // online change, and the differential tests guard what it would catch.
    let verify = if cfg!(debug_assertions) {
        "true"
    } else {
        "false"
    };
    fb.set("enable_verifier", verify).map_err(|e| setup(&e))?;
    fb.set("use_colocated_libcalls", "false")
        .map_err(|e| setup(&e))?;
    let builder = cranelift_native::builder().map_err(|e| setup(&e))?;
    builder
        .finish(settings::Flags::new(fb))
        .map_err(|e| setup(&e))
}

/// Groups top-level statements into chunks of at most `budget` cost (at least one statement each).
/// Past three quarters of the budget a chunk also ends where [`cut_here`] says so: the cut then
/// depends on the statements around it, not on their position, so an edit that adds or removes
/// statements moves the chunk boundaries after it only up to the next such cut, and the chunks
/// behind keep their code (see [`CodeCache`]).
fn chunks(stmts: &[Stmt], budget: u32) -> Vec<&[Stmt]> {
    let mut out = Vec::new();
    let soft = budget - budget / 4;
    let (mut start, mut cost, mut prev) = (0, 0u32, 0u32);
    for (i, s) in stmts.iter().enumerate() {
        let c = s.cost();
        let full = cost.saturating_add(c) > budget;
        let seam = cost >= soft && cut_here(prev, c);
        prev = c;
        if i > start && (full || seam) {
            out.push(&stmts[start..i]);
            start = i;
            cost = 0;
        }
        cost = cost.saturating_add(c);
    }
    if start < stmts.len() {
        out.push(&stmts[start..]);
    }
    out
}

/// A content-defined chunk boundary between statements of costs `prev` and `next` (one pair in
/// eight, by a multiplicative hash).
fn cut_here(prev: u32, next: u32) -> bool {
    let h = (prev.wrapping_mul(0x9E37_79B9) ^ next).wrapping_mul(0x85EB_CA6B);
    h >> 29 == 0
}

/// Fills `func` with the body for `stmts`.
/// What one compiling thread reuses from function to function (allocations only; no function
/// depends on what was compiled before it).
struct Scratch {
    fctx: FunctionBuilderContext,
    ctx: cranelift_codegen::Context,
    caches: Caches,
}

impl Default for Scratch {
    fn default() -> Self {
        Scratch {
            fctx: FunctionBuilderContext::new(),
            ctx: cranelift_codegen::Context::new(),
            caches: Caches::default(),
        }
    }
}

fn build(
    func: &mut Function,
    s: &mut Scratch,
    p: &Program,
    stmts: &[Stmt],
    isa: &OwnedTargetIsa,
    opts: &JitOptions,
) {
    let (fctx, caches) = (&mut s.fctx, &mut s.caches);
    caches.clear();
    caches.window = opts.cache_window;
    let mut b = FunctionBuilder::new(func, fctx);
    let entry = b.create_block();
    b.append_block_params_for_function_params(entry);
    b.switch_to_block(entry);
    let mem = b.block_params(entry)[0];
    {
        let mut t = Translator {
            b: &mut b,
            p,
            mem,
            c: caches,
            guard: None,
            if_convert_cost: opts.if_convert_cost,
            stamp: 0,
        };
        t.stmts(stmts);
        t.flush_all();
    }
    b.ins().return_(&[]);
    b.seal_all_blocks();
    b.finalize(isa.frontend_config());
}

fn signature(isa: &OwnedTargetIsa, call_conv: CallConv) -> Signature {
    let mut sig = Signature::new(call_conv);
    sig.params.push(AbiParam::new(isa.pointer_type()));
    sig
}

fn check_len(p: &Program) -> Result<(), JitError> {
    p.validate()?;
    if p.image_len > i32::MAX as usize {
        return Err(JitError::Codegen("image longer than 2 GiB".into()));
    }
    Ok(())
}

/// Compiles a program with the default options.
pub fn compile(p: &Program) -> Result<JitProgram, JitError> {
    compile_with(p, &JitOptions::default())
}

/// Machine code of one function: bytes and required alignment.
type Code = (Vec<u8>, u64);

/// One compiled function: its code and, when compiling through a [`CodeCache`], its keys and
/// whether the code came from the cache.
type Compiled = (Code, Option<(code_cache::Keys, bool)>);

/// Builds and compiles one function for `stmts` (position-independent, no relocations); with a
/// cache, a function whose IR the cache holds is not compiled again.
fn machine_code(
    p: &Program,
    stmts: &[Stmt],
    target: (&OwnedTargetIsa, &Signature),
    opts: &JitOptions,
    s: &mut Scratch,
    cache: Option<(&CodeCache, &[u8])>,
) -> Result<Compiled, JitError> {
    let (isa, sig) = target;
    let mut keys = code_cache::Keys {
        stmts: cache.and_then(|_| code_cache::stmts_key(stmts)),
        ir: None,
    };
    if let (Some((cache, facts)), Some(k)) = (cache, &keys.stmts)
        && let Some(code) = cache.get_by_stmts(opts, facts, k)
    {
        return Ok((code.clone(), Some((keys, true))));
    }
    let mut ctx = std::mem::replace(&mut s.ctx, cranelift_codegen::Context::new());
    ctx.clear();
    ctx.func.signature = sig.clone();
    build(&mut ctx.func, s, p, stmts, isa, opts);
    keys.ir = cache.and_then(|_| code_cache::key(&mut ctx.func));
    if let (Some((cache, _)), Some(ir)) = (cache, &keys.ir)
        && let Some(code) = cache.get(opts, ir)
    {
        s.ctx = ctx;
        return Ok((code.clone(), Some((keys, true))));
    }
    let mut ctrl = cranelift_codegen::control::ControlPlane::default();
    let result = machine_code_of(&mut ctx, isa, &mut ctrl);
    s.ctx = ctx;
    Ok((result?, cache.map(|_| (keys, false))))
}

/// Compiles the function in `ctx` and copies out its code.
fn machine_code_of(
    ctx: &mut cranelift_codegen::Context,
    isa: &OwnedTargetIsa,
    ctrl: &mut cranelift_codegen::control::ControlPlane,
) -> Result<Code, JitError> {
    let code = ctx
        .compile(&**isa, ctrl)
        .map_err(|e| JitError::Codegen(format!("{:?}", e.inner)))?;
    if !code.buffer.relocs().is_empty() {
        return Err(JitError::Codegen("scan code needs relocations".into()));
    }
    Ok((
        code.code_buffer().to_vec(),
        u64::from(code.buffer.alignment),
    ))
}

/// Lays the functions' code end to end, each at an offset aligned as it needs (at least
/// `min_align`), padding with `int3`. The code is position-independent (no relocations), so it
/// runs wherever it lands. Returns the text, each function's offset and the text's alignment.
fn link(codes: &[Code], min_align: u64) -> (Vec<u8>, Vec<usize>, u64) {
    let align = codes
        .iter()
        .map(|(_, a)| *a)
        .fold(min_align.max(1), u64::max);
    let mut text = Vec::with_capacity(codes.iter().map(|(b, _)| b.len() + align as usize).sum());
    let mut offsets = Vec::with_capacity(codes.len());
    for (bytes, a) in codes {
        let a = (*a).max(min_align).max(1) as usize;
        text.resize(text.len().div_ceil(a) * a, 0xCC);
        offsets.push(text.len());
        text.extend_from_slice(bytes);
    }
    (text, offsets, align)
}

/// Compiles every chunk, on several threads when there is more than one chunk: each thread takes
/// the next chunk not yet taken (so uneven chunks still share the work evenly); results keep the
/// order of `chunks`, and the code does not depend on the thread that made it.
fn compile_chunks(
    p: &Program,
    chunks: &[&[Stmt]],
    target: (&OwnedTargetIsa, &Signature),
    opts: &JitOptions,
    cache: Option<(&CodeCache, &[u8])>,
) -> Result<Vec<Compiled>, JitError> {
    let auto = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(4);
    let threads = if opts.threads == 0 {
        auto
    } else {
        opts.threads
    };
    let threads = threads.min(chunks.len()).max(1);
    if threads == 1 {
        let mut scratch = Scratch::default();
        return chunks
            .iter()
            .map(|stmts| machine_code(p, stmts, target, opts, &mut scratch, cache))
            .collect();
    }
    let next = std::sync::atomic::AtomicUsize::new(0);
    let work = || -> Result<Vec<(usize, Compiled)>, JitError> {
        let mut scratch = Scratch::default();
        let mut out = Vec::new();
        loop {
            let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            let Some(stmts) = chunks.get(i) else {
                return Ok(out);
            };
            out.push((
                i,
                machine_code(p, stmts, target, opts, &mut scratch, cache)?,
            ));
        }
    };
    std::thread::scope(|scope| {
        let handles: Vec<_> = (1..threads).map(|_| scope.spawn(work)).collect();
        let mine = work();
        // Join every thread before looking at any result (a thread left running would keep its
        // panic for the end of the scope).
        let theirs: Vec<_> = handles.into_iter().map(|h| h.join()).collect();
        let mut all = mine?;
        for codes in theirs {
            all.extend(codes.map_err(|_| JitError::Codegen("a compile thread panicked".into()))??);
        }
        all.sort_unstable_by_key(|(i, _)| *i);
        Ok(all.into_iter().map(|(_, code)| code).collect())
    })
}

/// Compiles a program with explicit options.
pub fn compile_with(p: &Program, opts: &JitOptions) -> Result<JitProgram, JitError> {
    compile_program(p, opts, None)
}

/// [`compile_with`] reusing the machine code of every function whose cranelift IR is unchanged
/// since the last program compiled through `cache` (an online change of a few statements
/// recompiles a few functions); afterwards `cache` holds this program's functions. The program
/// behaves exactly as compiled by [`compile_with`].
pub fn compile_cached(
    p: &Program,
    opts: &JitOptions,
    cache: &mut CodeCache,
) -> Result<JitProgram, JitError> {
    compile_program(p, opts, Some(cache))
}

fn compile_program(
    p: &Program,
    opts: &JitOptions,
    cache: Option<&mut CodeCache>,
) -> Result<JitProgram, JitError> {
    compile_program_to(p, opts, cache, None)
}

/// The statements of each function: the chunks of the FAST part, then of each SLOW slice.
fn program_chunks<'p>(p: &'p Program, opts: &JitOptions) -> Vec<Vec<&'p [Stmt]>> {
    std::iter::once(&p.fast[..])
        .chain(p.slow.iter().map(Vec::as_slice))
        .map(|stmts| chunks(stmts, opts.chunk_cost))
        .collect()
}

/// [`compile_program`]; the linked text is also left in `disk` (see [`disk_cache`]).
fn compile_program_to(
    p: &Program,
    opts: &JitOptions,
    cache: Option<&mut CodeCache>,
    disk: Option<&disk_cache::Entry>,
) -> Result<JitProgram, JitError> {
    check_len(p)?;
    let isa = isa(opts)?;
    let sig = signature(&isa, isa.default_call_conv());
    let parts = program_chunks(p, opts);
    let flat: Vec<&[Stmt]> = parts.iter().flatten().copied().collect();
    let facts = cache.as_ref().and_then(|_| code_cache::facts(p, opts));
    let lookup = cache.as_deref().zip(facts.as_deref());
    let compiled = compile_chunks(p, &flat, (&isa, &sig), opts, lookup)?;
    let mut codes = Vec::with_capacity(compiled.len());
    let mut keys = Vec::new();
    for (code, key) in compiled {
        if let Some((k, reused)) = key {
            keys.push((k, code.clone(), reused));
        }
        codes.push(code);
    }
    if let Some(cache) = cache {
        cache.replace(opts, facts, keys);
    }
    let (text, offsets, align) = link(&codes, isa.function_alignment().minimum.into());
    let text = Text {
        bytes: text,
        offsets,
        align,
        counts: parts.iter().map(Vec::len).collect(),
        codes: codes.iter().map(|(b, a)| (b.len(), *a)).collect(),
    };
    let program = load_text(isa, &text, p.image_len)?;
    if let Some(disk) = disk {
        disk.store(&text);
    }
    Ok(program)
}

/// A program's linked machine code: every function laid end to end (see `link`), where each
/// starts, and how many functions the FAST part and each SLOW slice have.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub(crate) struct Text {
    bytes: Vec<u8>,
    offsets: Vec<usize>,
    align: u64,
    /// Functions of the FAST part, then of each SLOW slice.
    counts: Vec<usize>,
    /// Each function's code length (without the padding after it) and alignment, so that the
    /// functions of a mapped text can fill a [`CodeCache`] (see [`disk_cache::lookup_cached`]).
    codes: Vec<(usize, u64)>,
}

impl Text {
    /// Each function's machine code as compiled (`None` when the layout is inconsistent).
    fn functions(&self) -> Option<Vec<Code>> {
        if self.codes.len() != self.offsets.len() {
            return None;
        }
        self.offsets
            .iter()
            .zip(&self.codes)
            .map(|(&at, &(len, align))| {
                Some((self.bytes.get(at..at.checked_add(len)?)?.to_vec(), align))
            })
            .collect()
    }
}

/// Maps `text` executable and wraps it as a program over images of `image_len` bytes.
fn load_text(isa: OwnedTargetIsa, text: &Text, image_len: usize) -> Result<JitProgram, JitError> {
    let codegen = |e: &dyn std::fmt::Display| JitError::Codegen(e.to_string());
    let total: usize = text.counts.iter().sum();
    if text.offsets.len() != total
        || text.counts.is_empty()
        || text.offsets.iter().any(|&at| at >= text.bytes.len())
    {
        return Err(codegen(&"inconsistent machine code layout"));
    }
    let sig = signature(&isa, isa.default_call_conv());
    let mut module = JITModule::new(JITBuilder::with_isa(
        isa,
        cranelift_module::default_libcall_names(),
    ));
    // One definition holding every function: one mapping and one `mprotect` for the program
    // instead of one per function.
    let id = module
        .declare_function("text", Linkage::Local, &sig)
        .map_err(|e| codegen(&e))?;
    module
        .define_function_bytes(id, text.align, &text.bytes, &[])
        .map_err(|e| codegen(&e))?;
    module.finalize_definitions().map_err(|e| codegen(&e))?;
    let base = module.get_finalized_function(id);
    let mut fns = text.offsets.iter().map(|&at| {
        // SAFETY: `at` is the start of one function inside the finalized text (see `link`, or a
        // disk cache entry whose key matched in full); every function was compiled with signature
        // `fn(*mut u8)` and the system calling convention.
        unsafe { std::mem::transmute::<*const u8, ScanFn>(base.wrapping_add(at)) }
    });
    let mut take = |n: usize| fns.by_ref().take(n).collect::<Vec<ScanFn>>();
    let fast = take(text.counts[0]);
    let slow = text.counts[1..].iter().map(|&n| take(n)).collect();
    Ok(JitProgram {
        module: Some(module),
        fast,
        slow,
        image_len,
        text: (base as usize, text.bytes.len()),
    })
}

/// The cranelift IR of every function the program compiles to (for `ncplc build --emit clif`).
pub fn emit_clif(p: &Program) -> Result<String, JitError> {
    check_len(p)?;
    let opts = JitOptions::default();
    let isa = isa(&opts)?;
    let sig = signature(&isa, isa.default_call_conv());
    let mut s = Scratch::default();
    let mut out = String::new();
    let mut n = 0u32;
    let lists = std::iter::once(("FAST", &p.fast[..]))
        .chain(p.slow.iter().map(|s| ("SLOW slice", s.as_slice())));
    for (i, (what, stmts)) in lists.enumerate() {
        for chunk in chunks(stmts, opts.chunk_cost) {
            let mut func = Function::with_name_signature(UserFuncName::user(0, n), sig.clone());
            build(&mut func, &mut s, p, chunk, &isa, &opts);
            let label = if i == 0 {
                what.to_string()
            } else {
                format!("{what} {}", i - 1)
            };
            out.push_str(&format!(
                "; {label}, function part{n}\n{}\n",
                func.display()
            ));
            n += 1;
        }
    }
    Ok(out)
}

/// Size of the cranelift IR a program compiles to (the JIT's compile time is about linear in it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ClifStats {
    /// Functions (FAST chunks plus SLOW slice chunks).
    pub functions: usize,
    /// Basic blocks over all functions.
    pub blocks: usize,
    /// CLIF instructions over all functions.
    pub insts: usize,
}

/// Builds (without compiling) the cranelift IR of every function and counts it.
pub fn clif_stats(p: &Program, opts: &JitOptions) -> Result<ClifStats, JitError> {
    check_len(p)?;
    let isa = isa(opts)?;
    let sig = signature(&isa, isa.default_call_conv());
    let mut s = Scratch::default();
    let mut st = ClifStats::default();
    let lists = std::iter::once(&p.fast[..]).chain(p.slow.iter().map(Vec::as_slice));
    for stmts in lists {
        for chunk in chunks(stmts, opts.chunk_cost) {
            let mut func = Function::with_name_signature(UserFuncName::default(), sig.clone());
            build(&mut func, &mut s, p, chunk, &isa, opts);
            st.functions += 1;
            for block in func.layout.blocks() {
                st.blocks += 1;
                st.insts += func.layout.block_insts(block).count();
            }
        }
    }
    Ok(st)
}

impl JitProgram {
    /// Number of machine-code functions (FAST chunks plus SLOW slice chunks).
    pub fn function_count(&self) -> usize {
        self.fast.len() + self.slow.iter().map(Vec::len).sum::<usize>()
    }

    /// The program's machine code: every function laid end to end. Code generation is
    /// deterministic, so two compiles of one program give equal bytes, with or without a
    /// [`CodeCache`] (what the cache's tests check).
    pub fn machine_code(&self) -> &[u8] {
        let (addr, len) = self.text;
        if self.module.is_none() || len == 0 {
            return &[];
        }
        // SAFETY: the text was finalized by `module`, which lives (and keeps it mapped, readable
        // and executable) as long as `self`; `len` is the length defined.
        unsafe { std::slice::from_raw_parts(addr as *const u8, len) }
    }
}

impl Engine for JitProgram {
    fn tick(&mut self, image: &mut [u8]) {
        if image.len() < self.image_len {
            return;
        }
        let mem = image.as_mut_ptr();
        for f in &self.fast {
            // SAFETY: every access the code makes lies below `image_len` (checked at compile
            // time by `Program::validate`), and the image is at least that long.
            unsafe { f(mem) };
        }
        if !self.slow.is_empty() {
            let at = ir::HDR_NEXT_SLICE;
            let next = u32::from_le_bytes([image[at], image[at + 1], image[at + 2], image[at + 3]])
                as usize;
            let i = if next < self.slow.len() { next } else { 0 };
            let mem = image.as_mut_ptr();
            for f in &self.slow[i] {
                // SAFETY: as above.
                unsafe { f(mem) };
            }
            let n = if i + 1 == self.slow.len() { 0 } else { i + 1 } as u32;
            image[at..at + 4].copy_from_slice(&n.to_le_bytes());
        }
    }

    fn name(&self) -> &'static str {
        "jit"
    }
}

impl Drop for JitProgram {
    fn drop(&mut self) {
        self.fast.clear();
        self.slow.clear();
        if let Some(module) = self.module.take() {
            // SAFETY: the function pointers into this module were dropped above and no other
            // copy of them escapes the JitProgram.
            unsafe { module.free_memory() };
        }
    }
}
