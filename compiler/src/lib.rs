//! The PLC-interface language: logos/lalrpop front end, typed IR, reference interpreter, cranelift JIT.

pub mod lexer;
pub mod ast;
pub mod parser;
pub mod sema;
pub mod context;
pub mod interface_map;
