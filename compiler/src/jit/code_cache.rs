//! Machine code kept from one program version to the next, so that an online change recompiles
//! only the functions whose cranelift IR changed.
//!
//! The key of a function is the complete text of its cranelift IR (what `ncplc build --emit clif`
//! prints): code generation is deterministic, so equal IR under equal settings gives equal
//! machine code, and the text holds every offset, constant and type the code depends on. Keys
//! are compared in full, never by hash alone. The code is position-independent (the JIT refuses
//! relocations), so the bytes can be laid anywhere in the next program's text. After each
//! compile the cache holds exactly the functions of that program.

use std::collections::HashMap;

use super::{Code, JitOptions};

/// Machine code of the last program compiled through [`super::compile_cached`], by cranelift IR.
#[derive(Debug, Default)]
pub struct CodeCache {
    /// The code-generation settings the entries were made with (`opt_level`, `regalloc`).
    settings: Option<(&'static str, &'static str)>,
    by_clif: HashMap<String, Code>,
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
        self.by_clif.len()
    }

    /// True when nothing is held.
    pub fn is_empty(&self) -> bool {
        self.by_clif.is_empty()
    }

    /// The code of a function with IR text `clif` compiled under `opts`, if held.
    pub(super) fn get(&self, opts: &JitOptions, clif: &str) -> Option<&Code> {
        if self.settings != Some(settings(opts)) {
            return None;
        }
        self.by_clif.get(clif)
    }

    /// Replaces the content with the functions of the program just compiled under `opts`.
    pub(super) fn replace(
        &mut self,
        opts: &JitOptions,
        functions: impl IntoIterator<Item = (String, Code, bool)>,
    ) {
        self.by_clif.clear();
        self.settings = Some(settings(opts));
        self.reused = 0;
        self.compiled = 0;
        for (clif, code, reused) in functions {
            if reused {
                self.reused += 1;
            } else {
                self.compiled += 1;
            }
            self.by_clif.insert(clif, code);
        }
    }
}

/// The settings besides the IR that decide the machine code.
fn settings(opts: &JitOptions) -> (&'static str, &'static str) {
    (opts.opt_level, opts.regalloc)
}
