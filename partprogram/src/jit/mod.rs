//! Native code for parameter arithmetic: every block whose G26–G29 control words are declared in the
//! block itself becomes one cranelift function `fn(*mut ArithState) -> i32`.
//!
//! Control words are decoded at compile time. Copy, add, subtract, multiply, divide, square, abs,
//! negate, comparisons (73/78), IF…ENDIF conditions (as branches), int↔real conversion, increment and
//! decrement and odd/even run inline on the parameter table; all other operations (and operands that
//! address double-precision pairs) call back into the reference interpreter ([`crate::arith`]) through
//! one host function. Blocks whose control words are computed at run time (self-modifying cycles)
//! stay with the interpreter. The function returns 0 or the [`ArithError::code`] of the failure, so
//! native and interpreted runs agree bit for bit (checked by differential tests).

use cranelift_codegen::ir::condcodes::IntCC;
use cranelift_codegen::ir::{AbiParam, Block, InstBuilder, MemFlagsData, Signature, Value, types};
use cranelift_codegen::settings::{self, Configurable};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_jit::{JITBuilder, JITModule};
use cranelift_module::{Linkage, Module};

use crate::arith::{ArithError, ArithState, Word};
use crate::machine::DoublePrecision;
use crate::program::Program;

type BlockFn = unsafe extern "C" fn(*mut ArithState) -> i32;

const FL: MemFlagsData = MemFlagsData::new().with_notrap();

/// Native functions of one program.
pub struct NativeCode {
    /// (block index, function index) for every block with native arithmetic.
    pub block_fn: Vec<(usize, usize)>,
    fns: Vec<BlockFn>,
    module: Option<JITModule>,
}

impl std::fmt::Debug for NativeCode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "NativeCode({} functions)", self.fns.len())
    }
}

// SAFETY: the JIT module owns immutable, finalized code; the function pointers are plain code addresses.
unsafe impl Send for NativeCode {}
// SAFETY: as above; calling the functions requires `&mut ArithState`, so no shared mutable state.
unsafe impl Sync for NativeCode {}

impl NativeCode {
    /// Runs function `fi` on `st`; returns 0 or an [`ArithError::code`].
    pub fn call(&self, fi: usize, st: &mut ArithState) -> i32 {
        match self.fns.get(fi) {
            // SAFETY: the function was compiled for `ArithState` (repr(C), `r` first) and only
            // touches `r[0..96]` inline; everything else goes through `host_op`, which takes the
            // same exclusive pointer.
            Some(f) => unsafe { f(st as *mut ArithState) },
            None => ArithError::BadOp(99).code(),
        }
    }
}

impl Drop for NativeCode {
    fn drop(&mut self) {
        self.fns.clear();
        if let Some(m) = self.module.take() {
            // SAFETY: the function pointers were dropped above and never escape this value.
            unsafe { m.free_memory() };
        }
    }
}

/// The host callback: executes one control word in the interpreter.
extern "C" fn host_op(st: *mut ArithState, word: i64) -> i32 {
    let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        // SAFETY: native code passes the exclusive pointer it was called with.
        let st = unsafe { &mut *st };
        match Word::decode(word) {
            Some(w) => match st.exec_word(w, 0) {
                Ok(_) => 0,
                Err(e) => e.code(),
            },
            None => ArithError::BadOp(99).code(),
        }
    }));
    r.unwrap_or(ArithError::Overflow.code())
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

fn inline_field(f: u8, mode: DoublePrecision) -> bool {
    f < 50 || (mode == DoublePrecision::Disabled && f < 96)
}

/// Compiles every block of `prog` whose arithmetic is static.
pub fn compile_program(prog: &Program) -> Result<NativeCode, String> {
    let todo: Vec<(usize, Vec<i64>)> = (0..prog.blocks.len())
        .filter(|&bi| prog.blocks[bi].arith_ops > 0)
        .filter_map(|bi| static_words(prog, bi).map(|w| (bi, w)))
        .collect();
    if todo.is_empty() {
        return Ok(NativeCode {
            block_fn: Vec::new(),
            fns: Vec::new(),
            module: None,
        });
    }
    compile_words(&todo, prog.machine.double_precision)
}

/// Compiles one function per `(key, words)` entry (used by tests and benchmarks directly).
pub fn compile_words(
    todo: &[(usize, Vec<i64>)],
    mode: DoublePrecision,
) -> Result<NativeCode, String> {
    let e = |x: &dyn std::fmt::Display| x.to_string();
    let mut fb = settings::builder();
    fb.set("opt_level", "speed").map_err(|x| e(&x))?;
    fb.set("is_pic", "false").map_err(|x| e(&x))?;
    fb.set("use_colocated_libcalls", "false")
        .map_err(|x| e(&x))?;
    let isa = cranelift_native::builder()
        .map_err(|x| e(&x))?
        .finish(settings::Flags::new(fb))
        .map_err(|x| e(&x))?;
    let ptr = isa.pointer_type();
    let mut module = JITModule::new(JITBuilder::with_isa(
        isa.clone(),
        cranelift_module::default_libcall_names(),
    ));
    let mut sig = Signature::new(isa.default_call_conv());
    sig.params.push(AbiParam::new(ptr));
    sig.returns.push(AbiParam::new(types::I32));
    let mut host_sig = Signature::new(isa.default_call_conv());
    host_sig.params.push(AbiParam::new(ptr));
    host_sig.params.push(AbiParam::new(types::I64));
    host_sig.returns.push(AbiParam::new(types::I32));
    let mut ctx = module.make_context();
    let mut fctx = FunctionBuilderContext::new();
    let mut ids = Vec::with_capacity(todo.len());
    for (i, (_, words)) in todo.iter().enumerate() {
        let id = module
            .declare_function(&format!("arith{i}"), Linkage::Local, &sig)
            .map_err(|x| e(&x))?;
        ctx.func.signature = sig.clone();
        {
            let mut b = FunctionBuilder::new(&mut ctx.func, &mut fctx);
            let host_ref = b.import_signature(host_sig.clone());
            let mut g = Gen {
                b: &mut b,
                st: Value::from_u32(0),
                host_ref,
                ptr,
                mode,
                fail: Block::from_u32(0),
            };
            g.build(words);
            b.seal_all_blocks();
            b.finalize(isa.frontend_config());
        }
        module
            .define_function(id, &mut ctx)
            .map_err(|x| format!("{x:?}"))?;
        module.clear_context(&mut ctx);
        ids.push(id);
    }
    module.finalize_definitions().map_err(|x| e(&x))?;
    let fns = ids
        .iter()
        .map(|&id| {
            let p = module.get_finalized_function(id);
            // SAFETY: defined above with signature `fn(*mut ArithState) -> i32` in the default call conv.
            unsafe { std::mem::transmute::<*const u8, BlockFn>(p) }
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
        module: Some(module),
    })
}

struct Gen<'a, 'b> {
    b: &'a mut FunctionBuilder<'b>,
    st: Value,
    host_ref: cranelift_codegen::ir::SigRef,
    ptr: cranelift_codegen::ir::Type,
    mode: DoublePrecision,
    fail: Block,
}

impl Gen<'_, '_> {
    fn c(&mut self, v: i64) -> Value {
        self.b.ins().iconst(types::I64, v)
    }

    fn load(&mut self, f: u8) -> Value {
        self.b.ins().load(types::I64, FL, self.st, i32::from(f) * 8)
    }

    /// Checks that `v` fits 32 bits (else returns the overflow code) and stores it into R`f`.
    fn store_fit(&mut self, f: u8, v: Value) {
        let narrow = self.b.ins().ireduce(types::I32, v);
        let wide = self.b.ins().sextend(types::I64, narrow);
        let ok = self.b.ins().icmp(IntCC::Equal, wide, v);
        self.guard(ok, ArithError::Overflow.code());
        self.b.ins().store(FL, v, self.st, i32::from(f) * 8);
    }

    /// Continues when `ok` is true, else returns `code`.
    fn guard(&mut self, ok: Value, code: i32) {
        let cont = self.b.create_block();
        let bad = self.b.create_block();
        self.b.ins().brif(ok, cont, &[], bad, &[]);
        self.b.switch_to_block(bad);
        let rc = self.b.ins().iconst(types::I32, i64::from(code));
        self.b.ins().return_(&[rc]);
        self.b.switch_to_block(cont);
    }

    fn host(&mut self, word: i64) {
        let w = self.c(word);
        let fp = self
            .b
            .ins()
            .iconst(self.ptr, host_op as *const () as usize as i64);
        let call = self.b.ins().call_indirect(self.host_ref, fp, &[self.st, w]);
        let rc = self.b.inst_results(call)[0];
        let zero = self.b.ins().iconst(types::I32, 0);
        let ok = self.b.ins().icmp(IntCC::Equal, rc, zero);
        let cont = self.b.create_block();
        self.b.ins().brif(ok, cont, &[], self.fail, &[rc.into()]);
        self.b.switch_to_block(cont);
    }

    /// `x / 1000` truncated toward zero without a division instruction: the high half of
    /// `x · ⌈2^71 / 1000⌉`, shifted right by 7, plus one for negative `x` (exact for every i64).
    fn div1000(&mut self, x: Value) -> Value {
        let m = self.c(0x20C4_9BA5_E353_F7CF);
        let hi = self.b.ins().smulhi(x, m);
        let seven = self.c(7);
        let q = self.b.ins().sshr(hi, seven);
        let sixty_three = self.c(63);
        let sign = self.b.ins().ushr(x, sixty_three);
        self.b.ins().iadd(q, sign)
    }

    fn fits32(&mut self, v: Value) -> Value {
        let narrow = self.b.ins().ireduce(types::I32, v);
        let wide = self.b.ins().sextend(types::I64, narrow);
        self.b.ins().icmp(IntCC::Equal, wide, v)
    }

    fn build(&mut self, words: &[i64]) {
        let entry = self.b.create_block();
        self.b.append_block_params_for_function_params(entry);
        self.b.switch_to_block(entry);
        self.st = self.b.block_params(entry)[0];
        self.fail = self.b.create_block();
        self.b.append_block_param(self.fail, types::I32);
        let done = self.b.create_block();
        let decoded: Vec<Option<Word>> = words.iter().map(|&r| Word::decode(r)).collect();
        // start[k] is the first instruction of operation k; start[len] is the end of the sequence.
        let start: Vec<Block> = (0..=words.len()).map(|_| self.b.create_block()).collect();
        self.b.ins().jump(start[0], &[]);
        for (i, (&r, w)) in words.iter().zip(&decoded).enumerate() {
            self.b.switch_to_block(start[i]);
            let Some(w) = *w else {
                self.host(r);
                self.b.ins().jump(start[i + 1], &[]);
                continue;
            };
            // A false condition skips up to and including the next code 22.
            let skip_to = (i + 1..words.len())
                .find(|&j| decoded[j].is_some_and(|x| x.op == 22))
                .map_or(words.len(), |j| j + 1);
            self.op(w, r, start[skip_to]);
            if w.op == 33 {
                self.b.ins().jump(done, &[]);
            } else {
                self.b.ins().jump(start[i + 1], &[]);
            }
        }
        self.b.switch_to_block(start[words.len()]);
        self.b.ins().jump(done, &[]);
        self.b.switch_to_block(done);
        let zero = self.b.ins().iconst(types::I32, 0);
        self.b.ins().return_(&[zero]);
        self.b.switch_to_block(self.fail);
        let rc = self.b.block_params(self.fail)[0];
        self.b.ins().return_(&[rc]);
    }

    fn op(&mut self, w: Word, r: i64, skip: Block) {
        let m = self.mode;
        let ok2 = inline_field(w.a, m) && inline_field(w.c, m);
        let ok3 = ok2 && inline_field(w.b, m);
        match w.op {
            0 | 7 | 8 | 23 | 24 | 41 | 42 | 46 | 47 if ok2 => {
                let x = self.load(w.a);
                let v = match w.op {
                    0 => x,
                    7 => self.b.ins().iabs(x),
                    8 => self.b.ins().ineg(x),
                    23 => {
                        let k = self.c(1000);
                        self.b.ins().imul(x, k)
                    }
                    24 => self.div1000(x),
                    41 | 42 => {
                        let step = i64::from(if w.b == 0 { 1 } else { w.b });
                        let k = self.c(if w.raw { step } else { step * 1000 });
                        if w.op == 41 {
                            self.b.ins().iadd(x, k)
                        } else {
                            self.b.ins().isub(x, k)
                        }
                    }
                    _ => {
                        // x % 2 != 0 ⟺ the lowest bit is set (two's complement).
                        let one = self.c(1);
                        let rem = self.b.ins().band(x, one);
                        let zero = self.c(0);
                        let cc = if w.op == 46 {
                            IntCC::NotEqual
                        } else {
                            IntCC::Equal
                        };
                        let want = self.b.ins().icmp(cc, rem, zero);
                        let (t, f) = (self.c(73), self.c(78));
                        self.b.ins().select(want, t, f)
                    }
                };
                self.store_fit(w.c, v);
            }
            1 | 2 if ok3 => {
                let (x, y) = (self.load(w.a), self.load(w.b));
                let v = if w.op == 1 {
                    self.b.ins().iadd(x, y)
                } else {
                    self.b.ins().isub(x, y)
                };
                self.store_fit(w.c, v);
            }
            3 | 5 if ok3 || (w.op == 5 && ok2) => {
                let x = self.load(w.a);
                let y = if w.op == 5 { x } else { self.load(w.b) };
                // Operands beyond 32 bits (pair halves) could overflow i64: use the interpreter then.
                let fx = self.fits32(x);
                let fy = self.fits32(y);
                let both = self.b.ins().band(fx, fy);
                let fast = self.b.create_block();
                let slow = self.b.create_block();
                let join = self.b.create_block();
                self.b.ins().brif(both, fast, &[], slow, &[]);
                self.b.switch_to_block(slow);
                self.host(r);
                self.b.ins().jump(join, &[]);
                self.b.switch_to_block(fast);
                let p = self.b.ins().imul(x, y);
                let v = if w.raw { p } else { self.div1000(p) };
                self.store_fit(w.c, v);
                self.b.ins().jump(join, &[]);
                self.b.switch_to_block(join);
            }
            4 if ok3 => {
                let (x, y) = (self.load(w.a), self.load(w.b));
                let zero = self.c(0);
                let nz = self.b.ins().icmp(IntCC::NotEqual, y, zero);
                self.guard(nz, ArithError::DivZero.code());
                let x = if w.raw {
                    x
                } else {
                    let k = self.c(1000);
                    self.b.ins().imul(x, k)
                };
                let v = self.b.ins().sdiv(x, y);
                self.store_fit(w.c, v);
            }
            15..=19 if ok3 => {
                let (x, y) = (self.load(w.a), self.load(w.b));
                let cc = match w.op {
                    15 => IntCC::SignedGreaterThan,
                    16 => IntCC::SignedGreaterThanOrEqual,
                    17 => IntCC::SignedLessThan,
                    18 => IntCC::SignedLessThanOrEqual,
                    _ => IntCC::Equal,
                };
                let t = self.b.ins().icmp(cc, x, y);
                let (a, b) = (self.c(73), self.c(78));
                let v = self.b.ins().select(t, a, b);
                self.b.ins().store(FL, v, self.st, i32::from(w.c) * 8);
            }
            20 | 21 | 29..=32 if inline_field(w.a, m) && inline_field(w.b, m) => {
                let (x, y) = (self.load(w.a), self.load(w.b));
                let cc = match w.op {
                    20 => IntCC::Equal,
                    21 => IntCC::NotEqual,
                    29 => IntCC::SignedGreaterThan,
                    30 => IntCC::SignedGreaterThanOrEqual,
                    31 => IntCC::SignedLessThan,
                    _ => IntCC::SignedLessThanOrEqual,
                };
                let t = self.b.ins().icmp(cc, x, y);
                let cont = self.b.create_block();
                self.b.ins().brif(t, cont, &[], skip, &[]);
                self.b.switch_to_block(cont);
            }
            22 => {}
            20 | 21 | 29..=32 => {
                // Conditions on pairs: evaluate through the interpreter, which reports a skip as 1.
                let wv = self.c(r);
                let fp = self
                    .b
                    .ins()
                    .iconst(self.ptr, host_op_cond as *const () as usize as i64);
                let call = self
                    .b
                    .ins()
                    .call_indirect(self.host_ref, fp, &[self.st, wv]);
                let rc = self.b.inst_results(call)[0];
                let one = self.b.ins().iconst(types::I32, 1);
                let is_skip = self.b.ins().icmp(IntCC::Equal, rc, one);
                let cont = self.b.create_block();
                self.b.ins().brif(is_skip, skip, &[], cont, &[]);
                self.b.switch_to_block(cont);
            }
            _ => self.host(r),
        }
    }
}

/// Host callback for conditions: 0 continue, 1 skip, other: error code.
extern "C" fn host_op_cond(st: *mut ArithState, word: i64) -> i32 {
    let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        // SAFETY: native code passes the exclusive pointer it was called with.
        let st = unsafe { &mut *st };
        match Word::decode(word).map(|w| st.exec_word(w, 0)) {
            Some(Ok(crate::arith::Step::Next)) => 0,
            Some(Ok(crate::arith::Step::Skip)) => 1,
            Some(Err(e)) => e.code(),
            None => ArithError::BadOp(99).code(),
        }
    }));
    r.unwrap_or(ArithError::Overflow.code())
}
