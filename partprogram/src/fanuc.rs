//! Fanuc/HAAS dialect (placeholder).

use diag::Diagnostic;

use crate::ast::ParsedFile;
use crate::program::Program;

/// Builds the units of a Fanuc file.
pub fn build_units(_prog: &mut Program, _parsed: ParsedFile, _diags: &mut Vec<Diagnostic>) {}

/// Static checks of a Fanuc program.
pub fn check(_prog: &mut Program, _diags: &mut Vec<Diagnostic>) {}

/// Plans a Fanuc program.
pub fn plan(prog: &Program, opts: crate::exec::PlanOptions) -> Result<crate::exec::Plan, (Vec<crate::canon::Canon>, crate::exec::RunError)> {
    crate::exec::plan(prog, opts)
}
