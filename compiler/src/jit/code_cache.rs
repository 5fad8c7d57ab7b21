//! Machine code kept from one program version to the next, so that an online change recompiles
//! only the functions whose cranelift IR changed.
//!
//! The key of a function is its complete cranelift IR, written out byte for byte by [`key`]
//! (signature, memory flags, every block with its parameters and their types, every instruction
//! with its operands, immediates, branch targets and result types): code generation is
//! deterministic, so equal IR under equal settings gives equal machine code. Keys are compared in
//! full, never by hash alone; a function using IR the key does not spell out (constants pools,
//! jump tables, stack slots, calls, global values) gets no key and is always compiled. The code
//! is position-independent (the JIT refuses relocations), so the bytes can be laid anywhere in
//! the next program's text. After each compile the cache holds exactly the functions of that
//! program.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hash, Hasher};

use cranelift_codegen::ir::Function;

use super::{Code, JitOptions};

/// A [`Hasher`] that keeps every byte written to it: `Hash` implementations then serialize.
struct Recorder(Vec<u8>);

impl Hasher for Recorder {
    fn write(&mut self, bytes: &[u8]) {
        self.0.extend_from_slice(bytes);
    }
    fn finish(&self) -> u64 {
        0
    }
}

/// Hashes the long keys a word at a time (FxHash mixing); equal hashes are compared in full.
#[derive(Default)]
struct WordHasher(u64);

impl WordHasher {
    fn add(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}

impl Hasher for WordHasher {
    fn write(&mut self, bytes: &[u8]) {
        let mut words = bytes.chunks_exact(8);
        for w in &mut words {
            let mut b = [0u8; 8];
            b.copy_from_slice(w);
            self.add(u64::from_le_bytes(b));
        }
        for &b in words.remainder() {
            self.add(u64::from(b));
        }
    }
    fn write_usize(&mut self, i: usize) {
        self.add(i as u64);
    }
    fn finish(&self) -> u64 {
        self.0
    }
}

/// The complete IR of `func` as bytes (aliases resolved first), or `None` when it uses IR
/// outside what the key spells out.
pub(super) fn key(func: &mut Function) -> Option<Vec<u8>> {
    let dfg = &func.dfg;
    if dfg.constants.len() != 0
        || !dfg.immediates.is_empty()
        || !dfg.jump_tables.is_empty()
        || !dfg.exception_tables.is_empty()
        || !dfg.signatures.is_empty()
        || !dfg.ext_funcs.is_empty()
        || !func.sized_stack_slots.is_empty()
        || !func.dynamic_stack_slots.is_empty()
        || !func.global_values.is_empty()
    {
        return None;
    }
    func.dfg.resolve_all_aliases();
    let (dfg, layout) = (&func.dfg, &func.layout);
    let mut r = Recorder(Vec::with_capacity(dfg.num_insts() * 64));
    func.signature.hash(&mut r);
    dfg.mem_flags.hash(&mut r);
    for block in layout.blocks() {
        block.hash(&mut r);
        dfg.block_params(block).len().hash(&mut r);
        for &v in dfg.block_params(block) {
            (v, dfg.value_type(v)).hash(&mut r);
        }
        for inst in layout.block_insts(block) {
            dfg.insts[inst].hash(&mut r, &dfg.value_lists);
            dfg.inst_results(inst).len().hash(&mut r);
            for &v in dfg.inst_results(inst) {
                (v, dfg.value_type(v)).hash(&mut r);
            }
        }
        // Ends the block's instruction list (no instruction data starts with these bytes).
        u64::MAX.hash(&mut r);
    }
    Some(r.0)
}

/// Machine code of the last program compiled through [`super::compile_cached`], by cranelift IR.
#[derive(Debug, Default)]
pub struct CodeCache {
    /// The code-generation settings the entries were made with (`opt_level`, `regalloc`).
    settings: Option<(&'static str, &'static str)>,
    by_ir: HashMap<Vec<u8>, Code, BuildHasherDefault<WordHasher>>,
    reused: usize,
    compiled: usize,
}

impl CodeCache {
    /// An empty cache.
    pub fn new() -> CodeCache {
        CodeCache::default()
    }

    /// Functions of the last compile whose code came from the cache.
    pub fn reused(&self) -> usize {
        self.reused
    }

    /// Functions of the last compile that cranelift compiled.
    pub fn compiled(&self) -> usize {
        self.compiled
    }

    /// Distinct functions held (those of the last program).
    pub fn len(&self) -> usize {
        self.by_ir.len()
    }

    /// True when nothing is held.
    pub fn is_empty(&self) -> bool {
        self.by_ir.is_empty()
    }

    /// The code of a function with IR [`key`] `ir` compiled under `opts`, if held.
    pub(super) fn get(&self, opts: &JitOptions, ir: &[u8]) -> Option<&Code> {
        if self.settings != Some(settings(opts)) {
            return None;
        }
        self.by_ir.get(ir)
    }

    /// Replaces the content with the functions of the program just compiled under `opts`.
    pub(super) fn replace(
        &mut self,
        opts: &JitOptions,
        functions: impl IntoIterator<Item = (Vec<u8>, Code, bool)>,
    ) {
        self.by_ir.clear();
        self.settings = Some(settings(opts));
        self.reused = 0;
        self.compiled = 0;
        for (ir, code, reused) in functions {
            if reused {
                self.reused += 1;
            } else {
                self.compiled += 1;
            }
            self.by_ir.insert(ir, code);
        }
    }
}

/// The settings besides the IR that decide the machine code.
fn settings(opts: &JitOptions) -> (&'static str, &'static str) {
    (opts.opt_level, opts.regalloc)
}
