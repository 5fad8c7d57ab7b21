//! Native code for parameter arithmetic (placeholder, filled in below).

use crate::arith::ArithState;
use crate::program::Program;

/// Native functions of one program.
#[derive(Debug, Default)]
pub struct NativeCode {
    /// (block index, function index).
    pub block_fn: Vec<(usize, usize)>,
}

impl NativeCode {
    /// Calls function `fi`.
    pub fn call(&self, _fi: usize, _st: &mut ArithState) -> i32 {
        0
    }
}

/// Compiles the arithmetic blocks of `prog`.
pub fn compile_program(_prog: &Program) -> Result<NativeCode, String> {
    Ok(NativeCode::default())
}
