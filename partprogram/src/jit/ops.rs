//! Code generation of G26–G29 control-word sequences: [`Gen`] emits one sequence of operations into
//! the function being built, inline where the operation is simple and through a host call into the
//! reference interpreter otherwise. Both the per-block functions and the region functions use it.
//!
//! Every failure branches to the function's fail block with two arguments: the [`ArithError::code`]
//! and the index of the block being executed ([`Gen::cur`]), so a region function can report where it
//! failed.

use cranelift_codegen::ir::condcodes::IntCC;
use cranelift_codegen::ir::{Block, InstBuilder, MemFlagsData, SigRef, Type, Value, types};
use cranelift_frontend::FunctionBuilder;

use crate::arith::{ArithError, ArithState, Step, Word};
use crate::machine::DoublePrecision;

/// Memory flags of parameter-table accesses: in bounds by construction, never trapping.
pub(super) const FL: MemFlagsData = MemFlagsData::new().with_notrap();

/// The host callback: executes one control word in the interpreter; 0 or an error code.
pub(super) extern "C" fn host_op(st: *mut ArithState, word: i64) -> i32 {
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

/// Host callback for conditions: 0 continue, 1 skip, other: error code.
pub(super) extern "C" fn host_op_cond(st: *mut ArithState, word: i64) -> i32 {
    let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        // SAFETY: native code passes the exclusive pointer it was called with.
        let st = unsafe { &mut *st };
        match Word::decode(word).map(|w| st.exec_word(w, 0)) {
            Some(Ok(Step::Next)) => 0,
            Some(Ok(Step::Skip)) => 1,
            Some(Err(e)) => e.code(),
            None => ArithError::BadOp(99).code(),
        }
    }));
    r.unwrap_or(ArithError::Overflow.code())
}

/// True when field `f` can be read or written inline (a single parameter, not a pair).
fn inline_field(f: u8, mode: DoublePrecision) -> bool {
    f < 50 || (mode == DoublePrecision::Disabled && f < 96)
}

/// Emits control-word sequences into one function.
pub(super) struct Gen<'a, 'b> {
    /// The builder of the function.
    pub b: &'a mut FunctionBuilder<'b>,
    /// The `*mut ArithState` value.
    pub st: Value,
    /// Signature of the host callbacks.
    pub host_ref: SigRef,
    /// Pointer type.
    pub ptr: Type,
    /// Double-precision mode of the machine.
    pub mode: DoublePrecision,
    /// Fail block with parameters (i32 error code, i64 block index).
    pub fail: Block,
    /// Index of the block whose operations are being emitted.
    pub cur: i64,
}

impl Gen<'_, '_> {
    /// An i64 constant.
    pub fn c(&mut self, v: i64) -> Value {
        self.b.ins().iconst(types::I64, v)
    }

    /// Loads R`f`.
    pub fn load(&mut self, f: u8) -> Value {
        self.b.ins().load(types::I64, FL, self.st, i32::from(f) * 8)
    }

    /// Branches to the fail block with `code` (and the current block).
    pub fn fail_with(&mut self, code: Value) {
        let bi = self.c(self.cur);
        self.b.ins().jump(self.fail, &[code.into(), bi.into()]);
    }

    /// Checks that `v` fits 32 bits (else fails with the overflow code) and stores it into R`f`.
    fn store_fit(&mut self, f: u8, v: Value) {
        let ok = self.fits32(v);
        self.guard(ok, ArithError::Overflow.code());
        self.b.ins().store(FL, v, self.st, i32::from(f) * 8);
    }

    /// Continues when `ok` is true, else fails with `code`.
    pub fn guard(&mut self, ok: Value, code: i32) {
        let cont = self.b.create_block();
        let bad = self.b.create_block();
        self.b.ins().brif(ok, cont, &[], bad, &[]);
        self.b.switch_to_block(bad);
        let rc = self.b.ins().iconst(types::I32, i64::from(code));
        self.fail_with(rc);
        self.b.switch_to_block(cont);
    }

    fn call_host(&mut self, f: extern "C" fn(*mut ArithState, i64) -> i32, word: i64) -> Value {
        let w = self.c(word);
        let fp = self
            .b
            .ins()
            .iconst(self.ptr, f as *const () as usize as i64);
        let call = self.b.ins().call_indirect(self.host_ref, fp, &[self.st, w]);
        self.b.inst_results(call)[0]
    }

    fn host(&mut self, word: i64) {
        let rc = self.call_host(host_op, word);
        let zero = self.b.ins().iconst(types::I32, 0);
        let ok = self.b.ins().icmp(IntCC::Equal, rc, zero);
        let cont = self.b.create_block();
        let bad = self.b.create_block();
        self.b.ins().brif(ok, cont, &[], bad, &[]);
        self.b.switch_to_block(bad);
        self.fail_with(rc);
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

    /// `x / y` (y ≠ 0, x ≠ i64::MIN) truncated toward zero: a 32-bit division when both fit 32 bits
    /// and y ≠ −1 (several times faster than the 64-bit one on x86-64), else the 64-bit one.
    fn sdiv(&mut self, x: Value, y: Value) -> Value {
        let fx = self.fits32(x);
        let fy = self.fits32(y);
        let not_m1 = self.b.ins().icmp_imm_s(IntCC::NotEqual, y, -1);
        let both = self.b.ins().band(fx, fy);
        let narrow = self.b.ins().band(both, not_m1);
        let (short, long, join) = (
            self.b.create_block(),
            self.b.create_block(),
            self.b.create_block(),
        );
        self.b.append_block_param(join, types::I64);
        self.b.ins().brif(narrow, short, &[], long, &[]);
        self.b.switch_to_block(short);
        let x32 = self.b.ins().ireduce(types::I32, x);
        let y32 = self.b.ins().ireduce(types::I32, y);
        let q32 = self.b.ins().sdiv(x32, y32);
        let q = self.b.ins().sextend(types::I64, q32);
        self.b.ins().jump(join, &[q.into()]);
        self.b.switch_to_block(long);
        let q = self.b.ins().sdiv(x, y);
        self.b.ins().jump(join, &[q.into()]);
        self.b.switch_to_block(join);
        self.b.block_params(join)[0]
    }

    fn fits32(&mut self, v: Value) -> Value {
        let narrow = self.b.ins().ireduce(types::I32, v);
        let wide = self.b.ins().sextend(types::I64, narrow);
        self.b.ins().icmp(IntCC::Equal, wide, v)
    }

    /// Emits the operations `words` (IF…ENDIF skips and code 33 included) at the current position
    /// and continues at `done` when they have run.
    pub fn seq(&mut self, words: &[i64], done: Block) {
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
                // The target is a single 32-bit parameter, so a product beyond i64 (possible with
                // pair halves as operands) cannot fit it either: overflow, as in the interpreter.
                let p = self.b.ins().imul(x, y);
                let hi = self.b.ins().smulhi(x, y);
                let sign = self.b.ins().sshr_imm_u(p, 63);
                let ok = self.b.ins().icmp(IntCC::Equal, hi, sign);
                self.guard(ok, ArithError::Overflow.code());
                let v = if w.raw { p } else { self.div1000(p) };
                self.store_fit(w.c, v);
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
                let v = self.sdiv(x, y);
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
                let rc = self.call_host(host_op_cond, r);
                let one = self.b.ins().iconst(types::I32, 1);
                let zero = self.b.ins().iconst(types::I32, 0);
                let is_skip = self.b.ins().icmp(IntCC::Equal, rc, one);
                let is_ok = self.b.ins().icmp(IntCC::Equal, rc, zero);
                let (cont, check, bad) = (
                    self.b.create_block(),
                    self.b.create_block(),
                    self.b.create_block(),
                );
                self.b.ins().brif(is_skip, skip, &[], check, &[]);
                self.b.switch_to_block(check);
                self.b.ins().brif(is_ok, cont, &[], bad, &[]);
                self.b.switch_to_block(bad);
                self.fail_with(rc);
                self.b.switch_to_block(cont);
            }
            _ => self.host(r),
        }
    }
}
