//! Partprograms: MEFI CNC8x6 and Fanuc/HAAS dialects, parameter macros compiled with cranelift, canonical
//! block plans.
//!
//! [`compile`] parses and checks a partprogram together with the machine's macro folder and returns a
//! [`Program`]; [`plan`] runs it and returns the canonical blocks ([`Canon`]). In MEFI programs, runs of
//! blocks that only touch the parameters (declarations, G26–G29 arithmetic, `G73 L Q` and `GR<n> L`
//! jumps, loops among them) run as cranelift-compiled native code ([`jit::region`]), and the
//! arithmetic of every other block with declared control words runs natively too ([`jit`]); the
//! reference interpreter ([`arith`], [`exec`]) stands beside it. [`PlanOptions::backend`] selects
//! which one; both give the same plan bit for bit.
//! The machine's correction table (`TAB0.KOR`, read by [`parse_kor`]) is
//! [`MachineSpec::corrections`]; tool length correction ([`length`]) and thread run-in/run-out
//! ([`thread`]) use it and the machine constants of the spec.

pub mod arith;
pub mod ast;
pub mod canon;
mod check;
pub mod codes;
pub mod exec;
pub mod fanuc;
pub mod fanuc_exec;
mod fanuc_units;
pub mod geom;
mod group;
pub mod groups;
pub mod jit;
pub mod kor;
pub mod length;
pub mod lexer;
pub mod library;
mod link;
pub mod machine;
pub mod macro_b;
pub mod parse;
pub mod pos;
mod process_words;
pub mod program;
pub mod radius;
pub mod run;
pub mod thread;
mod unit_table;
mod units;

pub use canon::{BlockModal, Canon, Css, Kind, Plane};
pub use exec::{Backend, Plan, PlanOptions, RunError};
pub use kor::{CorrectionTable, KorEntry, parse_kor};
pub use machine::{Dialect, DoublePrecision, LengthMethod, MTiming, MachineSpec, ProcessSpec};
pub use pos::{ZeroOffsets, parse_pos};
pub use program::{Program, compile, compile_capped, text_of};

/// Plans a compiled program: runs it and returns its canonical blocks, or the blocks emitted before a
/// run-time error together with the located error.
// The error carries the blocks planned before it by design (the CLI prints them before the error).
#[allow(clippy::result_large_err)]
pub fn plan(prog: &Program, opts: PlanOptions) -> Result<Plan, (Vec<Canon>, diag::Diagnostic)> {
    match prog.dialect {
        Dialect::Mefi => exec::plan(prog, opts).map_err(|(b, e)| (b, e.to_diagnostic(prog))),
        Dialect::Fanuc => fanuc::plan(prog, opts).map_err(|(b, e)| (b, e.to_diagnostic(prog))),
    }
}

/// Runs a compiled program as [`plan`] does without keeping its canonical blocks (the executor
/// empties them after each block; the radius compensation holds only its look-ahead): the number
/// of blocks executed, or the run-time error [`plan`] would give. `ncplc nc check` finds the
/// geometric errors this way in memory that does not grow with the plan.
pub fn check_plan(prog: &Program, opts: PlanOptions) -> Result<u64, diag::Diagnostic> {
    match prog.dialect {
        Dialect::Mefi => exec::check(prog, opts).map_err(|e| e.to_diagnostic(prog)),
        Dialect::Fanuc => fanuc_exec::check(prog, opts).map_err(|e| e.to_diagnostic(prog)),
    }
}
