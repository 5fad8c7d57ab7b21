//! The integration tests of crate `motion`, one test binary: each module was a separate
//! `tests/*.rs` binary before (issue 24: one link instead of one per file).

mod cam;
mod common;
mod golden;
mod override_stall;
mod props;
mod ruckig_peer;
mod thread;
