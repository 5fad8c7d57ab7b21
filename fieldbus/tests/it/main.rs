//! The integration tests of crate `fieldbus`, one test binary: each module was a separate
//! `tests/*.rs` binary before (issue 24: one link instead of one per file).

mod canopen;
mod cia402;
mod drives_map;
mod hmi;
mod machines;
mod map;
mod modbus_client;
mod modbus_direct;
mod python_canopen;
