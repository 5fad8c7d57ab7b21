//! Options, results and errors of a planning run (shared by both dialects).

use diag::Diagnostic;

use crate::arith::NPARAM;
use crate::canon::Canon;
use crate::codes;
use crate::program::Program;

/// Which engine runs parameter arithmetic.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Backend {
    /// Cranelift-compiled native code where available: parameter-only regions (arithmetic and jumps)
    /// and the arithmetic of other blocks; the interpreter for computed control words.
    #[default]
    Native,
    /// The reference interpreter only.
    Interpreter,
}

/// Options of a planning run.
#[derive(Debug, Clone, Copy)]
pub struct PlanOptions {
    /// Arithmetic engine.
    pub backend: Backend,
    /// Block-skip mode `/` selected (skip blocks marked with `/`).
    pub block_skip: bool,
    /// Stop with an error after this many executed blocks (endless loops).
    pub max_blocks: u64,
    /// Record canonical blocks (false: only run, for benchmarks of arithmetic; radius compensation
    /// then does not run either).
    pub record: bool,
    /// Tool radius compensation settings (G41/G42 corners, arc feed).
    pub radius: crate::radius::RadiusOptions,
    /// Machine position of each axis (machine axis order) at the start: MDI blocks are planned
    /// from where the axes stand, a program from zero.
    pub start: [f64; 6],
}

impl Default for PlanOptions {
    fn default() -> Self {
        PlanOptions {
            backend: Backend::Native,
            block_skip: false,
            max_blocks: 20_000_000,
            record: true,
            radius: crate::radius::RadiusOptions::default(),
            start: [0.0; 6],
        }
    }
}

/// A run-time error with the block it happened in.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{message}")]
pub struct RunError {
    /// Diagnostic code (2500…).
    pub code: u32,
    /// What went wrong.
    pub message: String,
    /// File index.
    pub file: usize,
    /// Byte range of the block.
    pub span: (usize, usize),
}

impl RunError {
    /// The located diagnostic for this error.
    pub fn to_diagnostic(&self, prog: &Program) -> Diagnostic {
        let f = &prog.files[self.file.min(prog.files.len().saturating_sub(1))];
        Diagnostic::error(
            self.code,
            f.name.clone(),
            self.span.0..self.span.1,
            self.message.clone(),
        )
        .with_hint(self.hint(prog))
        .locate(&f.text)
    }

    /// What would be valid instead, for the errors where something useful can be said.
    fn hint(&self, prog: &Program) -> String {
        match self.code {
            codes::RUN_CIRCLE => format!(
                "the end point must be as far from the centre (I, J, K, relative to the start point) as \
                 the start point is, within {} mm; correct the end point or the centre",
                prog.machine.circle_tolerance
            ),
            _ => String::new(),
        }
    }
}

/// The room a plan of `prog` starts with: one canonical block per compiled block (a program
/// without loops plans at most that many), so that planning a large program does not double its
/// vector, and copy it, a dozen times (a 50 MB program's plan is hundreds of megabytes).
pub(crate) fn plan_capacity(prog: &crate::program::Program, opts: &PlanOptions) -> usize {
    prog.blocks
        .len()
        .min(usize::try_from(opts.max_blocks).unwrap_or(usize::MAX))
}

/// The result of a planning run.
#[derive(Debug, Clone)]
pub struct Plan {
    /// Canonical blocks in execution order.
    pub blocks: Vec<Canon>,
    /// The parameters at the end.
    pub params: [i64; NPARAM],
    /// Number of executed blocks.
    pub executed: u64,
    /// Messages of arithmetic operation 51.
    pub messages: Vec<crate::arith::Message>,
    /// Fanuc Macro B variables at the end (slot n is #n; NaN is null; empty for MEFI).
    pub macro_vars: Vec<f64>,
}
