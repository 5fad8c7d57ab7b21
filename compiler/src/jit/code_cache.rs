//! Machine code kept from one program version to the next, so that an online change recompiles
//! only the functions whose cranelift IR changed.
//!
//! A function is found by its statements first: their exact byte encoding
//! (postcard, see [`stmts_key`]), valid while the program's declarations (offsets, types, presets, tick)
//! and the translation settings are unchanged — then not even its cranelift IR is built.
//! (A function found that way keeps only that key: after a later change of the declarations it is
//! compiled again.) Otherwise the key is its complete cranelift IR, written out byte for byte by [`key`]
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
use crate::ir::{CounterDecl, Program, PulseDecl, Stmt, TimerDecl, VarDecl};

/// The keys of one function: its statements (see [`stmts_key`]) and its IR (see [`key`]).
#[derive(Debug, Clone, Default)]
pub(super) struct Keys {
    pub stmts: Option<Vec<u8>>,
    pub ir: Option<Vec<u8>>,
}

/// Everything besides its statements that the translation of a function reads from the program
/// and the options: while it is equal, equal statements give equal IR. Names are left out (an
/// inline timer is named after its source line, which an edit above it moves); the patterns
/// name every field, so a new field must be decided on here. `None` when it has no exact
/// encoding (never for the IR's types).
pub(super) fn facts(p: &Program, opts: &JitOptions) -> Option<Vec<u8>> {
    let vars: Vec<_> = p
        .vars
        .iter()
        .map(
            |VarDecl {
                 name: _,
                 ty,
                 init,
                 retain,
                 offset,
             }| (ty, init, retain, offset),
        )
        .collect();
    let timers: Vec<_> = p
        .timers
        .iter()
        .map(
            |TimerDecl {
                 name: _,
                 kind,
                 preset_ms,
                 offset,
             }| (kind, preset_ms, offset),
        )
        .collect();
    let counters: Vec<_> = p
        .counters
        .iter()
        .map(
            |CounterDecl {
                 name: _,
                 kind,
                 preset,
                 offset,
             }| (kind, preset, offset),
        )
        .collect();
    let pulses: Vec<_> = p
        .pulses
        .iter()
        .map(|PulseDecl { n, offset }| (n, offset))
        .collect();
    let facts = (
        p.tick_ms,
        vars,
        timers,
        counters,
        pulses,
        p.image_len,
        opts.if_convert_cost,
        opts.cache_window,
    );
    exact_bytes(&facts)
}

/// The statements of a function, encoded exactly.
pub(super) fn stmts_key(stmts: &[Stmt]) -> Option<Vec<u8>> {
    exact_bytes(stmts)
}

/// `value` in postcard, an exact encoding for keys: variants by index, sequences and strings with
/// their length, floats by their bits (distinct NaNs, `0.0` and `-0.0` differ), and decodable, so
/// equal bytes mean equal values of one type. `None` when the value has no such encoding.
fn exact_bytes<T: serde::Serialize + ?Sized>(value: &T) -> Option<Vec<u8>> {
    postcard::to_extend(value, Vec::with_capacity(256)).ok()
}

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
    /// [`facts`] of the program the entries of `by_stmts` belong to.
    facts: Option<Vec<u8>>,
    by_stmts: HashMap<Vec<u8>, Code, BuildHasherDefault<WordHasher>>,
    functions: usize,
    reused: usize,
    by_statements: usize,
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

    /// Functions of the last compile found by their statements, without building their IR (the
    /// rest of [`CodeCache::reused`] was found by the IR).
    pub fn reused_by_statements(&self) -> usize {
        self.by_statements
    }

    /// Functions of the last compile that cranelift compiled.
    pub fn compiled(&self) -> usize {
        self.compiled
    }

    /// Functions of the last program (whose code is held).
    pub fn len(&self) -> usize {
        self.functions
    }

    /// True when nothing is held.
    pub fn is_empty(&self) -> bool {
        self.functions == 0
    }

    /// The code of a function with statements [`stmts_key`] `stmts` in a program with
    /// [`facts`] `facts`, compiled under `opts`, if held.
    pub(super) fn get_by_stmts(
        &self,
        opts: &JitOptions,
        facts: &[u8],
        stmts: &[u8],
    ) -> Option<&Code> {
        if self.settings != Some(settings(opts)) || self.facts.as_deref() != Some(facts) {
            return None;
        }
        self.by_stmts.get(stmts)
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
        facts: Option<Vec<u8>>,
        functions: impl IntoIterator<Item = (Keys, Code, bool)>,
    ) {
        self.by_ir.clear();
        self.by_stmts.clear();
        self.settings = Some(settings(opts));
        self.facts = facts;
        (
            self.functions,
            self.reused,
            self.compiled,
            self.by_statements,
        ) = (0, 0, 0, 0);
        for (keys, code, reused) in functions {
            self.functions += 1;
            if reused {
                self.reused += 1;
                self.by_statements += usize::from(keys.ir.is_none());
            } else {
                self.compiled += 1;
            }
            if let Some(k) = keys.stmts {
                self.by_stmts.insert(k, code.clone());
            }
            if let Some(k) = keys.ir {
                self.by_ir.insert(k, code);
            }
        }
    }
}

/// Fills `cache` with the functions of `p`, whose machine code `codes` (one per function, in
/// the order of [`super::program_chunks`]) was compiled under `opts` earlier (a text mapped from
/// the disk cache): found by their statements, so that the next online change compiles only the
/// functions it changed. Does nothing when the counts disagree or `p` has no exact encoding.
pub(super) fn fill(cache: &mut CodeCache, p: &Program, opts: &JitOptions, codes: Vec<Code>) {
    let flat: Vec<&[Stmt]> = super::program_chunks(p, opts)
        .into_iter()
        .flatten()
        .collect();
    let Some(facts) = facts(p, opts) else {
        return;
    };
    if flat.len() != codes.len() {
        return;
    }
    let functions = flat.iter().zip(codes).map(|(stmts, code)| {
        let keys = Keys {
            stmts: stmts_key(stmts),
            ir: None,
        };
        (keys, code, true)
    });
    cache.replace(opts, Some(facts), functions);
}

/// The settings besides the IR that decide the machine code.
fn settings(opts: &JitOptions) -> (&'static str, &'static str) {
    (opts.opt_level, opts.regalloc)
}
