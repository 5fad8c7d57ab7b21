//! The integration tests of crate `compiler`, one test binary: each module was a separate
//! `tests/*.rs` binary before (issue 24: one link instead of one per file).

mod differential;
mod differential_bits;
mod differential_source;
mod front_bounded;
mod front_cache;
mod front_fuzz;
mod front_incremental;
mod front_lowering;
mod front_parallel;
mod front_programs;
mod front_seeds;
mod front_sema;
mod golden_ir;
mod golden_source;
mod jit_code_cache;
mod jit_disk_cache;
