//! The PLC-interface language: logos/lalrpop front end, typed IR, reference interpreter, cranelift JIT.

pub mod ast;
pub mod cgen;
pub mod context;
pub mod engine;
pub mod front;
pub mod front_cache;
pub mod interface_map;
pub mod interp;
pub mod ir;
pub mod jit;
pub mod lexer;
pub mod lower;
pub mod migrate;
pub mod parse_cache;
pub mod parser;
pub mod sema;
pub mod synth;

pub use context::MachineContext;
pub use engine::Engine;
pub use front::{
    Compilation, CompileStats, MAX_SOURCE_BYTES, compile, compile_with_threads,
    diagnose_incremental, read_source,
};
pub use interface_map::InterfaceMap;
pub use interp::Interpreter;
pub use jit::{JitError, JitProgram};
pub use migrate::migrate_state;
