//! The PLC program `ncplc check` reads: the source `run` loads (FCRSYS `PLCSRC`, else
//! `MP0/PLCPRG`), through the compiler's front end exactly as `build` runs it (codes 1000–1999),
//! without generating native code. `check` reads every file `run` reads, so a program `run`
//! would refuse is an error of `check` too.
//!
//! Work and memory stay bounded on any source: the front end stops after 50 bad statement lines
//! (1011) and the report prints `--max-errors` diagnostics per file.

use std::path::Path;

use diag::{Diagnostic, Sources};

/// The diagnostics of the PLC program of the machine in `dir` (`machine` loaded without errors,
/// with an IOCFIL), compiled against `interface` (the valid map `check` loaded), its text added
/// to `sources` under its name relative to `dir`. Nothing when the source does not exist
/// (FCRSYS's warning 916 says so).
pub fn check(
    dir: &Path,
    machine: &characterization::Machine,
    interface: compiler::InterfaceMap,
    sources: &mut Sources,
) -> Vec<Diagnostic> {
    let Some(io) = machine.iocfil.as_ref() else {
        return Vec::new();
    };
    let ctx = runtime::machine_facts::compiler_context_with(io, interface);
    let path = &machine.paths.plc_source;
    let name = path.strip_prefix(dir).unwrap_or(path).display().to_string();
    let bytes = match compiler::read_source(path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Vec::new(),
        Err(e) => {
            return vec![Diagnostic::error(
                super::check_files::codes::IO,
                name.as_str(),
                0..0,
                format!("cannot read {name}: {e}"),
            )];
        }
    };
    let c = compiler::compile(&name, &bytes, &ctx);
    sources.add(name, c.text.clone());
    c.diagnostics
}
