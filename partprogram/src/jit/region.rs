//! Native regions: runs of consecutive blocks of one program unit that touch nothing but the parameter
//! state, compiled into one function each, control flow included.
//!
//! A block belongs to a region when its words are only literal `G26`–`G29` with control words declared
//! in the block ([`super::static_words`]), literal `G73`/`G78`, one `GR<n>` (a computed G that must
//! be 73 or 78), a literal `L` that names a block of the unit when the block can jump, and a literal or
//! `R<n>` `Q`; plus any declarations `R<n>=…` and the block-skip mark. Such a block has no effect
//! outside the parameters, the G-group table and the jump counters, so its whole execution — the
//! order of parameters-cycles §10 (substitution, declarations, arithmetic, G groups, jump at the end of
//! the block) and the executor's count of executed blocks with its `max_blocks` limit — can run
//! natively. A region function `fn(*mut RegionCtx, entry) -> i64` starts at any block of its run
//! (`br_table`), follows fall-through and jumps inside the run (loops included), and returns the
//! index of the first block it does not handle: a block outside the run, or a `GR<n>` block whose
//! parameter is not 73 or 78 (returned before it is counted, so the interpreter runs it with the
//! same result). Failures return a negative code with the failing block in [`RegionCtx::fail`].
//!
//! Jump counters follow `exec::flow` exactly: per frame, one slot per block of the unit, [`IDLE`] when
//! no count is active; reaching the block with no count loads Q−1 and jumps when Q > 0, with a count
//! of 0 clears it and falls through, with a count k > 0 stores k−1 and jumps.

use cranelift_codegen::ir::condcodes::IntCC;
use cranelift_codegen::ir::{Block, BlockArg, InstBuilder, SigRef, Type, Value, types};
use cranelift_frontend::{FunctionBuilder, Variable};

use super::ops::{FL, Gen};
use crate::arith::{ArithError, ArithState, NPARAM};
use crate::ast::Val;
use crate::machine::DoublePrecision;
use crate::program::{Program, lit_int};

/// Counter slot value when no count is active.
pub const IDLE: i64 = -1;

/// Longest run compiled into one function (longer runs are split; crossing the split returns to the
/// executor once).
const MAX_RUN: usize = 512;

/// Error code of the executed-block limit (distinct from every [`ArithError::code`]).
const LIMIT_CODE: i64 = 9000;

/// What a region function hands to the executor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RegionExit {
    /// Continue with this block index (it has not been executed or counted).
    Next(usize),
    /// Parameter arithmetic of block `.0` failed (the block was counted).
    Arith(usize, ArithError),
    /// Block `.0` exceeded `max_blocks` (it was counted, not executed).
    Limit(usize),
}

/// The executed-block count a region advances, with the options that govern it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RegionCount {
    /// Blocks executed so far (in and out).
    pub executed: u64,
    /// `PlanOptions::max_blocks`.
    pub max_blocks: u64,
    /// `PlanOptions::block_skip`.
    pub block_skip: bool,
}

/// The state a region function works on. `repr(C)`: native code addresses the fields by offset.
#[derive(Debug)]
#[repr(C)]
pub struct RegionCtx {
    /// The parameter state.
    pub st: *mut ArithState,
    /// Jump counters of the current frame, indexed by block index − unit start.
    pub counters: *mut i64,
    /// Executed-block count (in and out).
    pub executed: u64,
    /// Limit of the executed-block count.
    pub max_blocks: u64,
    /// 1 when block skip `/` is selected.
    pub block_skip: u64,
    /// The block that failed (out).
    pub fail: u64,
}

pub(super) fn decode_exit(rv: i64, fail: usize) -> RegionExit {
    match rv {
        n if n >= 0 => RegionExit::Next(n as usize),
        n if n == -LIMIT_CODE => RegionExit::Limit(fail),
        n => RegionExit::Arith(fail, ArithError::from_code(i32::try_from(-n).unwrap_or(0))),
    }
}

/// The G word of group 7 a region block may hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum G7 {
    /// Literal G73 or G78.
    Lit(i64),
    /// `GR<n>`: parameter n.
    Param(u8),
}

/// A literal or parameter `Q`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Count {
    Lit(i64),
    Param(u8),
}

/// One block of a region, decoded at compile time.
#[derive(Debug, Clone)]
pub(super) struct PBlock {
    /// Block index.
    pub bi: usize,
    skip: bool,
    decls: Vec<(u8, i64)>,
    arith: Option<(i64, Vec<i64>)>,
    g7: Option<G7>,
    /// Resolved jump target when the block can jump.
    target: Option<usize>,
    q: Count,
}

/// A run of region blocks with the unit it is in.
#[derive(Debug, Clone)]
pub(super) struct Run {
    /// The blocks, consecutive indices.
    pub blocks: Vec<PBlock>,
    /// First block of the unit (counter slot 0).
    pub unit_start: usize,
    /// Number of blocks of the unit.
    pub unit_len: usize,
}

/// The parameter a `<addr>R<n>` word reads, as the executor's substitution clamps it.
fn param(p: &crate::lexer::Lit) -> u8 {
    usize::try_from(p.int).map_or(NPARAM - 1, |v| v.min(NPARAM - 1)) as u8
}

/// Decodes block `bi` as a region block, or None when it does anything else.
fn classify(prog: &Program, bi: usize) -> Option<PBlock> {
    let b = &prog.blocks[bi];
    let (mut arith, mut g7, mut l, mut q) = (None, None, None, None);
    for w in &b.words {
        match (w.addr, w.val) {
            ('G', Val::Lit(x)) => match lit_int(&x)? {
                g @ 26..=29 if arith.is_none() => arith = Some(g),
                g @ (73 | 78) if g7.is_none() => g7 = Some(G7::Lit(g)),
                _ => return None,
            },
            ('G', Val::Param(p)) if g7.is_none() => g7 = Some(G7::Param(param(&p))),
            ('L', Val::Lit(x)) if l.is_none() => l = Some(lit_int(&x)?),
            ('Q', Val::Lit(x)) if q.is_none() => q = Some(Count::Lit(x.milli() / 1000)),
            ('Q', Val::Param(p)) if q.is_none() => q = Some(Count::Param(param(&p))),
            _ => return None,
        }
    }
    // L or Q without a jump means nothing: the interpreter refuses the block (2530).
    if g7.is_none() && (l.is_some() || q.is_some()) {
        return None;
    }
    let arith = match arith {
        Some(g) if i64::from(b.arith_ops) == g - 25 => Some((g, super::static_words(prog, bi)?)),
        Some(_) => return None,
        None => None,
    };
    let target = match g7 {
        Some(G7::Lit(73)) | Some(G7::Param(_)) => {
            let lv = u32::try_from(l?).ok()?;
            prog.units[b.unit].index.get(lv)
        }
        _ => None,
    };
    Some(PBlock {
        bi,
        skip: b.skip,
        decls: b.decls.iter().map(|d| (d.param, d.r)).collect(),
        arith,
        g7,
        target,
        q: q.unwrap_or(Count::Lit(1)),
    })
}

/// Every run worth compiling: maximal runs of region blocks per unit, split at [`MAX_RUN`]; a run of
/// one block is kept only when it can jump (a self-loop).
pub(super) fn find_runs(prog: &Program) -> Vec<Run> {
    let mut runs = Vec::new();
    for unit in &prog.units {
        let mut cur: Vec<PBlock> = Vec::new();
        let mut flush = |cur: &mut Vec<PBlock>| {
            if cur.len() > 1 || cur.iter().any(|p| p.target.is_some()) {
                runs.push(Run {
                    blocks: std::mem::take(cur),
                    unit_start: unit.start,
                    unit_len: unit.end - unit.start,
                });
            }
            cur.clear();
        };
        for bi in unit.start..unit.end {
            match classify(prog, bi) {
                Some(pb) => {
                    if cur.len() == MAX_RUN {
                        flush(&mut cur);
                    }
                    cur.push(pb);
                }
                None => flush(&mut cur),
            }
        }
        flush(&mut cur);
    }
    runs
}

/// Field offsets of [`RegionCtx`] and [`ArithState`].
const OFF_ST: i32 = std::mem::offset_of!(RegionCtx, st) as i32;
const OFF_COUNTERS: i32 = std::mem::offset_of!(RegionCtx, counters) as i32;
const OFF_EXECUTED: i32 = std::mem::offset_of!(RegionCtx, executed) as i32;
const OFF_MAX: i32 = std::mem::offset_of!(RegionCtx, max_blocks) as i32;
const OFF_SKIP: i32 = std::mem::offset_of!(RegionCtx, block_skip) as i32;
const OFF_FAIL: i32 = std::mem::offset_of!(RegionCtx, fail) as i32;
const OFF_GGROUPS: i32 = std::mem::offset_of!(ArithState, g_groups) as i32;

/// Shared values of the function being built.
struct Frame {
    ctx: Value,
    st: Value,
    counters: Value,
    executed: Variable,
    exit: Block,
    fail: Block,
    heads: Vec<Block>,
    first: usize,
}

impl Frame {
    /// Continues at block index `to`: inside the run a branch, else a return to the executor.
    fn goto(&self, b: &mut FunctionBuilder, to: usize) {
        match to.checked_sub(self.first).filter(|&k| k < self.heads.len()) {
            Some(k) => {
                b.ins().jump(self.heads[k], &[]);
            }
            None => {
                let v = b.ins().iconst(types::I64, to as i64);
                b.ins().jump(self.exit, &[BlockArg::from(v)]);
            }
        }
    }
}

/// Builds the function of `run`.
pub(super) fn build(
    b: &mut FunctionBuilder,
    host_ref: SigRef,
    ptr: Type,
    mode: DoublePrecision,
    run: &Run,
) {
    let entry = b.create_block();
    b.append_block_params_for_function_params(entry);
    b.switch_to_block(entry);
    let ctx = b.block_params(entry)[0];
    let at = b.block_params(entry)[1];
    let st = b.ins().load(ptr, FL, ctx, OFF_ST);
    let counters = b.ins().load(ptr, FL, ctx, OFF_COUNTERS);
    let max = b.ins().load(types::I64, FL, ctx, OFF_MAX);
    let skip_on = b.ins().load(types::I64, FL, ctx, OFF_SKIP);
    let executed = b.declare_var(types::I64);
    let e0 = b.ins().load(types::I64, FL, ctx, OFF_EXECUTED);
    b.def_var(executed, e0);
    let exit = b.create_block();
    b.append_block_param(exit, types::I64);
    let fail = b.create_block();
    b.append_block_param(fail, types::I32);
    b.append_block_param(fail, types::I64);
    let first = run.blocks.first().map_or(0, |p| p.bi);
    let fr = Frame {
        ctx,
        st,
        counters,
        executed,
        exit,
        fail,
        heads: run.blocks.iter().map(|_| b.create_block()).collect(),
        first,
    };
    super::dispatch::entry_dispatch(b, at, first, &fr.heads, exit);
    for (k, pb) in run.blocks.iter().enumerate() {
        b.switch_to_block(fr.heads[k]);
        block(
            b,
            &fr,
            host_ref,
            ptr,
            mode,
            max,
            skip_on,
            pb,
            run.unit_start,
        );
    }
    // Exits write the count back.
    b.switch_to_block(exit);
    let next = b.block_params(exit)[0];
    let e = b.use_var(executed);
    b.ins().store(FL, e, fr.ctx, OFF_EXECUTED);
    b.ins().return_(&[next]);
    b.switch_to_block(fail);
    let (code, bi) = (b.block_params(fail)[0], b.block_params(fail)[1]);
    let e = b.use_var(executed);
    b.ins().store(FL, e, fr.ctx, OFF_EXECUTED);
    b.ins().store(FL, bi, fr.ctx, OFF_FAIL);
    let wide = b.ins().sextend(types::I64, code);
    let neg = b.ins().ineg(wide);
    b.ins().return_(&[neg]);
}

/// Emits one block at the current position (its head).
#[allow(clippy::too_many_arguments)]
fn block(
    b: &mut FunctionBuilder,
    fr: &Frame,
    host_ref: SigRef,
    ptr: Type,
    mode: DoublePrecision,
    max: Value,
    skip_on: Value,
    pb: &PBlock,
    unit_start: usize,
) {
    let load =
        |b: &mut FunctionBuilder, p: u8| b.ins().load(types::I64, FL, fr.st, i32::from(p) * 8);
    let next = pb.bi + 1;
    // 1. Substitution with the values from before the block; a G other than 73/78 leaves the region.
    let gval = match pb.g7 {
        Some(G7::Param(p)) => {
            let v = load(b, p);
            let is73 = b.ins().icmp_imm_s(IntCC::Equal, v, 73);
            let is78 = b.ins().icmp_imm_s(IntCC::Equal, v, 78);
            let ok = b.ins().bor(is73, is78);
            let (cont, out) = (b.create_block(), b.create_block());
            b.ins().brif(ok, cont, &[], out, &[]);
            b.switch_to_block(out);
            let here = b.ins().iconst(types::I64, pb.bi as i64);
            b.ins().jump(fr.exit, &[BlockArg::from(here)]);
            b.switch_to_block(cont);
            Some((v, is73))
        }
        _ => None,
    };
    let q = pb.target.map(|_| match pb.q {
        Count::Lit(v) => b.ins().iconst(types::I64, v),
        Count::Param(p) => load(b, p),
    });
    // 2. Count the block; beyond the limit fail before it has any effect.
    let e = b.use_var(fr.executed);
    let e = b.ins().iadd_imm_s(e, 1);
    b.def_var(fr.executed, e);
    let over = b.ins().icmp(IntCC::UnsignedGreaterThan, e, max);
    let (cont, limit) = (b.create_block(), b.create_block());
    b.ins().brif(over, limit, &[], cont, &[]);
    b.switch_to_block(limit);
    let code = b.ins().iconst(types::I32, LIMIT_CODE);
    let here = b.ins().iconst(types::I64, pb.bi as i64);
    b.ins()
        .jump(fr.fail, &[BlockArg::from(code), BlockArg::from(here)]);
    b.switch_to_block(cont);
    // 3. A skipped block does nothing else.
    if pb.skip {
        let (run_it, skipped) = (b.create_block(), b.create_block());
        b.ins().brif(skip_on, skipped, &[], run_it, &[]);
        b.switch_to_block(skipped);
        fr.goto(b, next);
        b.switch_to_block(run_it);
    }
    // 4. Declarations.
    for &(p, r) in &pb.decls {
        let v = b.ins().iconst(types::I64, r);
        b.ins().store(FL, v, fr.st, i32::from(p) * 8);
    }
    // 5. Arithmetic.
    if let Some((_, words)) = &pb.arith {
        let done = b.create_block();
        Gen {
            b: &mut *b,
            st: fr.st,
            host_ref,
            ptr,
            mode,
            fail: fr.fail,
            cur: pb.bi as i64,
        }
        .seq(words, done);
        b.switch_to_block(done);
    }
    // 6. G-group table (after the arithmetic, as `Exec::sync_groups`).
    if let Some((g, _)) = pb.arith {
        let v = b.ins().iconst(types::I64, g);
        b.ins().istore16(FL, v, fr.st, OFF_GGROUPS + 2 * 4);
    }
    match (pb.g7, gval) {
        (Some(G7::Lit(g)), _) => {
            let v = b.ins().iconst(types::I64, g);
            b.ins().istore16(FL, v, fr.st, OFF_GGROUPS + 2 * 7);
        }
        (Some(G7::Param(_)), Some((v, _))) => {
            b.ins().istore16(FL, v, fr.st, OFF_GGROUPS + 2 * 7);
        }
        _ => {}
    }
    // 7. Jump at the end of the block.
    let (Some(target), Some(q)) = (pb.target, q) else {
        fr.goto(b, next);
        return;
    };
    if let Some((_, is73)) = gval {
        let (jump, no) = (b.create_block(), b.create_block());
        b.ins().brif(is73, jump, &[], no, &[]);
        b.switch_to_block(no);
        fr.goto(b, next);
        b.switch_to_block(jump);
    }
    let off = ((pb.bi - unit_start) * 8) as i32;
    let c = b.ins().load(types::I64, FL, fr.counters, off);
    let idle = b.ins().icmp_imm_s(IntCC::Equal, c, IDLE);
    let [arm, armed, arm_take, zero, count] = [(); 5].map(|_| b.create_block());
    let no_arm = b.create_block();
    b.ins().brif(idle, arm, &[], armed, &[]);
    // No count: load Q−1 and jump when Q > 0.
    b.switch_to_block(arm);
    let pos = b.ins().icmp_imm_s(IntCC::SignedGreaterThan, q, 0);
    b.ins().brif(pos, arm_take, &[], no_arm, &[]);
    b.switch_to_block(no_arm);
    fr.goto(b, next);
    b.switch_to_block(arm_take);
    let k = b.ins().iadd_imm_s(q, -1);
    b.ins().store(FL, k, fr.counters, off);
    fr.goto(b, target);
    // A count: 0 clears it and falls through, k > 0 stores k−1 and jumps.
    b.switch_to_block(armed);
    let is0 = b.ins().icmp_imm_s(IntCC::Equal, c, 0);
    b.ins().brif(is0, zero, &[], count, &[]);
    b.switch_to_block(zero);
    let idle_v = b.ins().iconst(types::I64, IDLE);
    b.ins().store(FL, idle_v, fr.counters, off);
    fr.goto(b, next);
    b.switch_to_block(count);
    let k = b.ins().iadd_imm_s(c, -1);
    b.ins().store(FL, k, fr.counters, off);
    fr.goto(b, target);
}
