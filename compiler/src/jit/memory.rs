//! Image accesses: loads served from the block's cache when the place was loaded or stored
//! before, and stores held back for one statement so that the next statement's store to the same
//! place replaces them (coils of one byte become one store). All offsets are constants, so
//! aliasing is known exactly; a load that misses the cache first emits the held stores it overlaps.

use cranelift_codegen::ir::{InstBuilder, Type, Value, types};

use super::cache::Pending;
use super::translate::{FL, Translator};

impl Translator<'_, '_> {
    pub(super) fn load8(&mut self, at: usize) -> Value {
        self.load(types::I8, at)
    }

    /// Loads a value of type `ty` at image offset `at`, reusing the value last loaded from or
    /// stored to exactly that place in this block (all offsets are constants, so aliasing is
    /// known exactly).
    pub(super) fn load(&mut self, ty: Type, at: usize) -> Value {
        if let Some(v) = self.c.get(at, ty) {
            return v;
        }
        self.flush_overlapping(at, ty.bytes() as usize);
        let v = self.b.ins().load(ty, FL, self.mem, Self::off(at));
        self.c.remember(at, ty, v);
        v
    }

    pub(super) fn load32(&mut self, at: usize) -> Value {
        self.load(types::I32, at)
    }

    /// Stores `v` at image offset `at`; cached values overlapping the written bytes are dropped
    /// and the stored value is remembered for later loads. Inside an if-converted zone the store
    /// writes `guard ? v : old`.
    ///
    /// The store itself is held back until the end of the next statement: if that statement
    /// stores to the same place again, the held store is dead and is dropped (later reads of
    /// the place are served from the cache, and a load of overlapping bytes that misses the cache
    /// first emits the held stores it overlaps).
    pub(super) fn store(&mut self, v: Value, at: usize) {
        let ty = self.b.func.dfg.value_type(v);
        let v = match self.guard {
            Some(g) => {
                let old = self.load(ty, at);
                self.b.ins().select(g, v, old)
            }
            None => v,
        };
        self.c.stored(at, ty, v);
        let len = ty.bytes() as usize;
        let stamp = self.stamp;
        if let Some(p) = self
            .c
            .pending
            .iter_mut()
            .find(|p| p.at == at && p.len == len)
        {
            p.v = v;
            p.stamp = stamp;
            return;
        }
        self.flush_overlapping(at, len);
        self.c.pending.push(Pending { at, v, len, stamp });
    }

    fn emit_store(&mut self, p: Pending) {
        self.b.ins().store(FL, p.v, self.mem, Self::off(p.at));
    }

    /// Emits the held stores that overlap `at..at + len`.
    fn flush_overlapping(&mut self, at: usize, len: usize) {
        let mut i = 0;
        while i < self.c.pending.len() {
            let p = self.c.pending[i];
            if p.at < at + len && at < p.at + p.len {
                self.c.pending.remove(i);
                self.emit_store(p);
            } else {
                i += 1;
            }
        }
    }

    /// Emits the held stores the current statement did not write.
    pub(super) fn flush_stale(&mut self) {
        let stamp = self.stamp;
        let mut i = 0;
        while i < self.c.pending.len() {
            let p = self.c.pending[i];
            if p.stamp != stamp {
                self.c.pending.remove(i);
                self.emit_store(p);
            } else {
                i += 1;
            }
        }
    }

    /// Emits every held store (before a branch, a jump or the return).
    pub(super) fn flush_all(&mut self) {
        for p in std::mem::take(&mut self.c.pending) {
            self.emit_store(p);
        }
    }
}
