//! The end-to-end tests of the workspace, one test binary (`cargo test -p ncplc --test e2e`;
//! one module with `cargo test -p ncplc --test e2e part::`): each module drives the `ncplc`
//! binary on the bundled machines and was a binary of its own before issue 24.
//!
//! Invariants of sharing one process: no test changes the process's environment variables or
//! current directory (children get theirs through `Command`); the real-time runs with simulated
//! devices (`io`, `modbus_peer`) hold `e2e_common::serial()` so that at most one of them runs at a
//! time, as when they were separate binaries. `e2e_common` (the workspace root, the `ncplc` runner
//! and its `run` builder, machine copies) and `hmi_common` (a running `ncplc run --hmi` and its
//! HTTP client) are the shared test kit.

mod build;
mod cdp;
mod check;
mod check_run_files;
mod cli;
mod docs;
mod drives;
mod drives_homing;
mod drives_parts;
mod drives_peer;
mod e2e_common;
mod generated_parsers;
mod hmi;
mod hmi_browser;
mod hmi_cnc;
mod hmi_common;
mod hmi_flow;
mod hmi_security;
mod io;
mod ionode;
mod lsp;
mod macro_vars;
mod manual_limits;
mod modbus_peer;
mod nc;
mod nc_run;
mod opcua;
mod opcua_methods;
mod opcua_variables;
mod part;
mod part_contour;
mod part_prop;
mod part_replay;
mod part_spindle;
mod plc_messages;
mod plot;
mod process2;
mod record_crash;
mod replay;
mod retain;
mod run;
mod servo;
mod test_cmd;
mod trace;
