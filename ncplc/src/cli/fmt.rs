//! `ncplc fmt FILE [--check]`: the PLC source laid out by the language server's formatter
//! ([`plc_lsp::format::format`]), written back atomically.

use std::path::Path;
use std::process::ExitCode;

/// Rewrites the file formatted (0), or with `check` says whether it is formatted (0) or not (1,
/// nothing written); 2 when it cannot be read or written, is over the PLC source limit (2 MiB) or
/// is not UTF-8. The file is replaced atomically (`runtime::atomic_file`): a crash or a full disk
/// while writing leaves the program as it was, never half of it.
pub fn run(path: &Path, check: bool) -> ExitCode {
    let bytes = match compiler::read_source(path) {
        Ok(b) if b.len() > compiler::MAX_SOURCE_BYTES => {
            eprintln!(
                "ncplc fmt: {} has more than {} bytes (2 MiB), the most a PLC source may have (1012): left unchanged",
                path.display(),
                compiler::MAX_SOURCE_BYTES
            );
            return ExitCode::from(2);
        }
        Ok(b) => b,
        Err(e) => {
            eprintln!("ncplc fmt: cannot read {}: {e}", path.display());
            return ExitCode::from(2);
        }
    };
    let Ok(src) = String::from_utf8(bytes) else {
        eprintln!(
            "ncplc fmt: {} is not UTF-8 (a DOS/Windows CP866 or CP1251 file?): left unchanged, since rewriting it would change the bytes of its comments",
            path.display()
        );
        return ExitCode::from(2);
    };
    let formatted = plc_lsp::format::format(&src);
    if formatted == src {
        if !check {
            eprintln!("ncplc fmt: {} is already formatted", path.display());
        }
        return ExitCode::SUCCESS;
    }
    if check {
        eprintln!(
            "ncplc fmt: {} is not formatted (run `ncplc fmt {}`)",
            path.display(),
            path.display()
        );
        return ExitCode::from(1);
    }
    match runtime::atomic_file::write(path, formatted.as_bytes()) {
        Ok(()) => {
            eprintln!("ncplc fmt: formatted {}", path.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("ncplc fmt: cannot write {}: {e}", path.display());
            ExitCode::from(2)
        }
    }
}
