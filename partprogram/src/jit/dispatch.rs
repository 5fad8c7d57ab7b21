//! The entry dispatch shared by the native MEFI regions and Macro B runs: a run's function is
//! entered at any of its blocks, so it first jumps through a table to the head of block `at`, and
//! leaves through `exit(at)` when `at` is not one of its blocks.

use cranelift_codegen::ir::{
    Block, BlockArg, InstBuilder, JumpTableData, Value, condcodes::IntCC, types,
};
use cranelift_frontend::FunctionBuilder;

/// Emits the jump from the entry (block index `at`, I64) to `heads[at - first]`, or to
/// `exit(at)` when `at` lies outside `first..first + heads.len()`.
pub(crate) fn entry_dispatch(
    b: &mut FunctionBuilder,
    at: Value,
    first: usize,
    heads: &[Block],
    exit: Block,
) {
    let idx = b.ins().iadd_imm_s(at, -(first as i64));
    let len = b.ins().iconst(types::I64, heads.len() as i64);
    let inside = b.ins().icmp(IntCC::UnsignedLessThan, idx, len);
    let (dispatch, outside) = (b.create_block(), b.create_block());
    b.ins().brif(inside, dispatch, &[], outside, &[]);
    b.switch_to_block(outside);
    b.ins().jump(exit, &[BlockArg::from(at)]);
    b.switch_to_block(dispatch);
    let idx32 = b.ins().ireduce(types::I32, idx);
    let def = b.func.dfg.block_call(outside, &[]);
    let table: Vec<_> = heads
        .iter()
        .map(|&h| b.func.dfg.block_call(h, &[]))
        .collect();
    let jt = b.create_jump_table(JumpTableData::new(def, &table));
    b.ins().br_table(idx32, jt);
}
