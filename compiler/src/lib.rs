//! The PLC-interface language: logos/lalrpop front end, typed IR, reference interpreter, cranelift JIT.

pub mod engine;
pub mod interp;
pub mod ir;

pub use engine::Engine;
pub use interp::Interpreter;
pub mod jit;

pub use jit::{JitError, JitProgram};
pub mod migrate;

pub use migrate::migrate_state;
