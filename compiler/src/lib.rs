//! The PLC-interface language: logos/lalrpop front end, typed IR, reference interpreter, cranelift JIT.

pub mod lexer;
pub mod ast;
pub mod parser;
pub mod sema;
pub mod context;
pub mod interface_map;
pub mod front;
pub mod lower;

pub use context::MachineContext;
pub use front::{Compilation, CompileStats, compile};
pub use interface_map::InterfaceMap;
