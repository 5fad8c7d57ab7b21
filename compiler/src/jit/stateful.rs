//! Timers, counters and pulses emitted inline and branch-free (cranelift cannot inline Rust
//! helpers): every update is a handful of loads, selects and stores over the element's state.

use cranelift_codegen::ir::condcodes::IntCC;
use cranelift_codegen::ir::{InstBuilder, Value};

use super::translate::Translator;
use crate::ir::{CounterKind, FLAG_PREV, FLAG_RUN, TimerKind};

impl Translator<'_, '_> {
    /// `P<n> = x`: value := x AND NOT prev; prev := x (`x` is I8 0/1, so `x & !(f >> 1)` has
    /// no other bit set).
    pub(super) fn pulse(&mut self, x: Value, at: usize) {
        let f = self.load8(at);
        let prev = self.ushr_k(f, 1);
        let np = self.b.ins().bnot(prev);
        let v = self.b.ins().band(x, np);
        let x2 = self.ishl_k(x, 1);
        let n = self.b.ins().bor(v, x2);
        self.store(n, at);
    }

    /// Flags byte `q | x << 1 | run << 2` (I8 0/1 inputs).
    fn flags(&mut self, q: Value, x: Value, run: Option<Value>) -> Value {
        let x2 = self.ishl_k(x, 1);
        let f = self.b.ins().bor(q, x2);
        match run {
            Some(r) => {
                let r4 = self.ishl_k(r, 2);
                self.b.ins().bor(f, r4)
            }
            None => f,
        }
    }

    /// One timer execution (the rules on [`crate::ir::Stmt::Timer`]).
    pub(super) fn timer(&mut self, kind: TimerKind, pt: i32, x: Value, at: usize) {
        let tick = i64::from(self.p.tick_ms as i32);
        let pt64 = i64::from(pt);
        let f = self.load8(at + 4);
        let et = self.load32(at);
        let zero = self.k(cranelift_codegen::ir::types::I32, 0);
        let eta = self.iadd_k(et, tick);
        if kind == TimerKind::Ton {
            // x and prev without normalizing prev: (x << 1) & f is nonzero exactly when both hold
            // (FLAG_PREV is bit 1), and x << 1 is the new flags' prev bit as well.
            let x2 = self.ishl_k(x, 1);
            let xp = self.b.ins().band(x2, f);
            let ptv = self.k(cranelift_codegen::ir::types::I32, pt64);
            let m = self.b.ins().smin(eta, ptv);
            let et2 = self.b.ins().select(xp, m, zero);
            let reached = self.icmp_k(IntCC::SignedGreaterThanOrEqual, et2, pt64);
            let q = self.b.ins().band(x, reached);
            self.store(et2, at);
            let fl = self.b.ins().bor(q, x2);
            self.store(fl, at + 4);
            return;
        }
        let prev = self.band_k(f, i64::from(FLAG_PREV));
        let prev = self.icmp_k(IntCC::NotEqual, prev, 0);
        let running = self.band_k(f, i64::from(FLAG_RUN));
        let running = self.icmp_k(IntCC::NotEqual, running, 0);
        let (et2, q, run) = match kind {
            TimerKind::Tof => {
                let nx = self.bxor_k(x, 1);
                let e1 = self.b.ins().select(running, eta, et);
                let e1 = self.b.ins().select(prev, zero, e1);
                let et2 = self.b.ins().select(x, zero, e1);
                let pr = self.b.ins().bor(prev, running);
                let run1 = self.b.ins().band(nx, pr);
                let lt = self.icmp_k(IntCC::SignedLessThan, et2, pt64);
                let run2 = self.b.ins().band(run1, lt);
                let q = self.b.ins().bor(x, run2);
                (et2, q, Some(run2))
            }
            // TP (TON returned above).
            _ => {
                let np = self.bxor_k(prev, 1);
                let rising = self.b.ins().band(x, np);
                let nw = self.bxor_k(running, 1);
                let start = if pt > 0 {
                    self.b.ins().band(nw, rising)
                } else {
                    self.i8c(0)
                };
                let cont = self.icmp_k(IntCC::SignedLessThan, eta, pt64);
                let e1 = self.b.ins().select(x, et, zero);
                let e1 = self.b.ins().select(start, zero, e1);
                let et2 = self.b.ins().select(running, eta, e1);
                let run = self.b.ins().select(running, cont, start);
                (et2, run, Some(run))
            }
        };
        self.store(et2, at);
        let fl = self.flags(q, x, run);
        self.store(fl, at + 4);
    }

    /// A counter's count input: count a rising edge unless R/LD is set (saturating).
    pub(super) fn counter_count(&mut self, kind: CounterKind, x: Value, at: usize) {
        let f = self.load8(at + 4);
        let cv = self.load32(at);
        let busy = self.band_k(f, i64::from(FLAG_PREV | FLAG_RUN));
        let idle = self.icmp_k(IntCC::Equal, busy, 0);
        let go = self.b.ins().band(x, idle);
        let (limit, step) = match kind {
            CounterKind::Ctu => (i64::from(i32::MAX), 1),
            CounterKind::Ctd => (i64::from(i32::MIN), -1),
        };
        let at_limit = self.icmp_k(IntCC::Equal, cv, limit);
        let stepped = self.iadd_k(cv, step);
        let n = self.b.ins().select(at_limit, cv, stepped);
        let n = self.b.ins().select(go, n, cv);
        self.store(n, at);
        let kept = self.band_k(f, i64::from(!FLAG_PREV));
        let x2 = self.ishl_k(x, 1);
        let nf = self.b.ins().bor(kept, x2);
        self.store(nf, at + 4);
    }

    /// A counter's R (CTU, `value` 0) or LD (CTD, `value` PV) input.
    pub(super) fn counter_reset(&mut self, value: i32, x: Value, at: usize) {
        let f = self.load8(at + 4);
        let cv = self.load32(at);
        let k = self.k(cranelift_codegen::ir::types::I32, i64::from(value as u32));
        let n = self.b.ins().select(x, k, cv);
        self.store(n, at);
        let kept = self.band_k(f, i64::from(!FLAG_RUN));
        let x4 = self.ishl_k(x, 2);
        let nf = self.b.ins().bor(kept, x4);
        self.store(nf, at + 4);
    }
}
