//! Lowering: the checked program becomes an [`ir::Program`]. Sema already built typed IR
//! statements and declared the state; here the [`ir::ProgramBuilder`] lays out the image, cuts
//! the SLOW part into slices and validates the result. A validation failure is a compiler bug,
//! reported as diagnostic [`codes::LOWERING`] rather than a panic.

use diag::Diagnostic;

use crate::ir;
use crate::sema::{Checked, codes};

/// Finishes a checked program; an IR error becomes a located diagnostic at the start of `file`.
pub fn lower(file: &str, checked: Checked) -> Result<ir::Program, Diagnostic> {
    let lines = checked.lines;
    let mut program = checked
        .builder
        .finish(checked.fast, checked.slow)
        .map_err(|e| {
            Diagnostic::error(
                codes::LOWERING,
                file,
                0..0,
                format!("internal compiler error while lowering: {e}"),
            )
            .with_hint("please report this program; it passed all checks but the IR rejected it")
        })?;
    program.lines = lines;
    Ok(program)
}
