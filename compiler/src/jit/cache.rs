//! Per-thread scratch state of the translator, reused from one function to the next: the block's
//! materialized integer constants (hashed with a small multiplicative hash instead of SipHash) and
//! the value each image byte offset holds in the current block (a flat table indexed by offset,
//! with the list of touched offsets so that clearing costs what was used).

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use cranelift_codegen::ir::{Type, Value};

/// A fast, non-cryptographic hasher (the FxHash mixing step) for small integer keys.
#[derive(Debug, Default, Clone, Copy)]
pub(super) struct FxHasher(u64);

impl FxHasher {
    fn add(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}

impl Hasher for FxHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.add(u64::from(b));
        }
    }
    fn write_u8(&mut self, i: u8) {
        self.add(u64::from(i));
    }
    fn write_u16(&mut self, i: u16) {
        self.add(u64::from(i));
    }
    fn write_u32(&mut self, i: u32) {
        self.add(u64::from(i));
    }
    fn write_u64(&mut self, i: u64) {
        self.add(i);
    }
    fn write_i64(&mut self, i: i64) {
        self.add(i as u64);
    }
    fn write_usize(&mut self, i: usize) {
        self.add(i as u64);
    }
    fn finish(&self) -> u64 {
        self.0
    }
}

/// A store not emitted yet (see [`Caches::pending`]).
#[derive(Debug, Clone, Copy)]
pub(super) struct Pending {
    /// Image offset.
    pub at: usize,
    /// The stored value (its type gives the width).
    pub v: Value,
    /// Width in bytes.
    pub len: usize,
    /// The statement that last wrote it.
    pub stamp: u32,
}

/// What the translator remembers within one basic block.
///
/// Remembered values and constants are reused only within [`Caches::window`] statements of the
/// one that made them: a value kept live across a long stretch of rungs costs a spill and a
/// reload (no cheaper than reloading the image byte) and, worse, makes the register allocator
/// spill around it; reloading keeps live ranges short.
#[derive(Debug, Default)]
pub(super) struct Caches {
    /// Integer constants already materialized in the current block, with the statement that
    /// made them.
    consts: HashMap<(Type, i64), (Value, u32), BuildHasherDefault<FxHasher>>,
    /// `mem[o]`: the value of type `Type` the image holds at offset `o`, as far as this block
    /// loaded or stored it, and the statement that loaded or stored it.
    mem: Vec<Option<(Type, Value, u32)>>,
    /// Offsets with a `Some` in `mem`.
    touched: Vec<usize>,
    /// Stores held back for a statement, in program order: a store to the same place by the
    /// next statement replaces the held one (coils of one byte become one store).
    pub pending: Vec<Pending>,
    /// The statement being translated (see [`Caches::window`]).
    pub now: u32,
    /// How many statements back a remembered value or constant is still reused (0: only within
    /// its own statement).
    pub window: u32,
}

impl Caches {
    /// Forgets everything (a new block starts); keeps the allocations.
    pub fn clear(&mut self) {
        self.consts.clear();
        self.pending.clear();
        for o in self.touched.drain(..) {
            if let Some(slot) = self.mem.get_mut(o) {
                *slot = None;
            }
        }
    }

    /// True when something made by statement `made` may still be reused now.
    fn fresh(&self, made: u32) -> bool {
        self.now.wrapping_sub(made) <= self.window
    }

    /// The constant `(ty, v)` if it was materialized recently in this block.
    pub fn konst(&self, ty: Type, v: i64) -> Option<Value> {
        match self.consts.get(&(ty, v)) {
            Some(&(c, made)) if self.fresh(made) => Some(c),
            _ => None,
        }
    }

    /// Remembers the constant `(ty, v)` as `c`.
    pub fn set_konst(&mut self, ty: Type, v: i64, c: Value) {
        self.consts.insert((ty, v), (c, self.now));
    }

    /// The value known at `at`, if it has type `ty` and was loaded or stored recently.
    pub fn get(&self, at: usize, ty: Type) -> Option<Value> {
        match self.mem.get(at) {
            Some(Some((t, v, made))) if *t == ty && self.fresh(*made) => Some(*v),
            _ => None,
        }
    }

    /// Remembers that `at` holds `v` of type `ty` (after a load).
    pub fn remember(&mut self, at: usize, ty: Type, v: Value) {
        if self.mem.len() <= at {
            self.mem.resize(at + 1, None);
        }
        if self.mem[at].is_none() {
            self.touched.push(at);
        }
        self.mem[at] = Some((ty, v, self.now));
    }

    /// A store of `ty` at `at`: values overlapping the written bytes are dropped, then the stored
    /// value is remembered.
    pub fn stored(&mut self, at: usize, ty: Type, v: Value) {
        let end = (at + ty.bytes() as usize).min(self.mem.len());
        for o in at.saturating_sub(7)..end {
            if let Some((t, _, _)) = self.mem[o]
                && o + t.bytes() as usize > at
            {
                self.mem[o] = None;
            }
        }
        self.remember(at, ty, v);
    }
}
