//! Adapting the PLC compiler (front end, interpreter, JIT) to the runtime's program traits.

use crate::config::RunConfig;
use crate::program::Loaded;

/// Which engine runs the program.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum EngineKind {
    /// Native code (cranelift).
    Jit,
    /// The reference interpreter.
    Interp,
}

/// Compiles `source` (named `file_name` in diagnostics) for the machine `cfg` with tick `tick_ms`.
/// `Err` holds the rendered diagnostics.
pub fn compile(
    _file_name: &str,
    _source: &[u8],
    _cfg: &RunConfig,
    _tick_ms: u32,
    _engine: EngineKind,
) -> Result<Loaded, String> {
    Err("error: the PLC compiler is not merged into the runtime yet".into())
}
