//! The integration tests of crate `partprogram`, one test binary: each module was a separate
//! `tests/*.rs` binary before (issue 24: one link instead of one per file).

/// Counts the live bytes of the threads that ask (`peak_alloc::peak_during`), for the memory tests.
#[global_allocator]
static ALLOC: peak_alloc::Counting = peak_alloc::Counting;

mod arith_ops;
mod bounded_memory;
mod common;
mod conformance;
mod corrections;
mod diagnostics;
mod differential;
mod examples;
mod fanuc_classes;
mod fanuc_golden;
mod fanuc_programs;
mod gouge;
mod lathe_cycles;
mod macro_b;
mod mefi_programs;
mod modal_record;
mod native_regions;
mod path_control;
mod peak_alloc;
mod planes;
mod radius;
mod rs274_diff;
mod spindle_modes;
mod threads;
