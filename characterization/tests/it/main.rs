//! The integration tests of crate `characterization`, one test binary: each module was a separate
//! `tests/*.rs` binary before (issue 24: one link instead of one per file).

mod axcfil_errors;
mod axcfil_examples;
mod axcfil_proptest;
mod bounded_memory;
mod bounded_work;
mod iocfil_errors;
mod iocfil_examples;
mod logic_cross_file;
mod logic_machines;
mod logic_proptest;
mod machine_load;
mod pgcfil_errors;
mod pgcfil_examples;
