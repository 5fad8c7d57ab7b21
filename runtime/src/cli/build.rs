//! `ncplc build <machine-dir> [--plc FILE]`: compiles the machine's PLC program.
//!
//! Prints every diagnostic rustc-style (default) or as one JSON object per line (`--format json`,
//! the fields of `ncplc check`), then a one-line summary (statements, image size, compile time).
//! With `--format json` the summary goes to stderr, so that stdout holds only JSON lines.
//! `--emit ir` prints the lowered IR as JSON, `--emit clif` the cranelift IR of the JIT; the
//! diagnostics and the summary then go to stderr. Exit code 0 when the program compiles, 1 on errors, 2 when the
//! machine or the source cannot be read.
//!
//! The PLC source is `--plc FILE`, else the file FCRSYS section 2 binds to `PLCSRC`, else
//! `MP0/PLCPRG`.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use compiler::{InterfaceMap, MachineContext};

/// Output format of the diagnostics.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// rustc-style with the source line and the span marked.
    Human,
    /// One JSON object per line per diagnostic.
    Json,
}

/// What `--emit` prints.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Emit {
    /// The lowered IR program as JSON.
    Ir,
    /// The cranelift IR of the JIT-compiled scan functions.
    Clif,
}

/// Arguments of `ncplc build`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The machine directory (holding FCRSYS and MP0/).
    pub machine_dir: PathBuf,
    /// The PLC source (default: FCRSYS `PLCSRC`, else MP0/PLCPRG).
    #[arg(long)]
    pub plc: Option<PathBuf>,
    /// How to print diagnostics.
    #[arg(long, value_enum, default_value_t = Format::Human)]
    pub format: Format,
    /// Print the IR or the cranelift IR instead of only checking.
    #[arg(long, value_enum)]
    pub emit: Option<Emit>,
}

/// Why the machine's facts could not be read.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// A file could not be read.
    #[error("cannot read {path}: {source}")]
    Read {
        /// The file.
        path: String,
        /// The OS error.
        source: std::io::Error,
    },
    /// The interface map override is invalid.
    #[error(transparent)]
    Interface(#[from] compiler::interface_map::InterfaceMapError),
}

/// FCRSYS section 2: logical name → file (as `name/MPx` or a DOS path), mapped into `dir`.
// TEMPORARY (until characterization::load_machine is glued in by the lead): a minimal reader of
// FCRSYS section 2 that only resolves one logical name.
fn fcrsys_file(dir: &Path, logical: &str) -> Option<PathBuf> {
    let text = std::fs::read(dir.join("FCRSYS")).ok()?;
    let text = String::from_utf8_lossy(&text);
    let mut section = 0;
    for line in text.lines() {
        let line = line.split(';').next().unwrap_or("").trim();
        if let Some(s) = line.strip_prefix('*') {
            section = s.trim().parse().unwrap_or(0);
            continue;
        }
        if section != 2 {
            continue;
        }
        let mut parts = line.splitn(2, ',');
        let (Some(name), Some(file)) = (parts.next(), parts.next()) else {
            continue;
        };
        if !name.trim().eq_ignore_ascii_case(logical) {
            continue;
        }
        let file = file.trim();
        // `PLCPRG/MP0` (file/directory) or a DOS path `C:\CNC32\MP0\PLCPRG` (…\directory\file).
        let path = match file.split_once('/') {
            Some((f, d)) => dir.join(d.trim()).join(f.trim()),
            None => {
                let comps: Vec<&str> = file
                    .split(['\\', '/'])
                    .filter(|c| !c.is_empty() && !c.ends_with(':'))
                    .collect();
                match comps.as_slice() {
                    [.., d, f] => dir.join(d).join(f),
                    [f] => dir.join(f),
                    [] => return None,
                }
            }
        };
        return Some(path);
    }
    None
}

/// The PLC source of a machine: FCRSYS `PLCSRC`, else `MP0/PLCPRG`.
pub fn default_plc_source(dir: &Path) -> PathBuf {
    fcrsys_file(dir, "PLCSRC").unwrap_or_else(|| dir.join("MP0").join("PLCPRG"))
}

/// The compiler's view of the machine in `dir`.
// TEMPORARY: reads only the `INx=`, `OUx=`, `CLO=` and `SPL=` lines of section 1 of the IOCFIL
// that FCRSYS binds to IOCONF (else MP0/IOCFIL). The lead replaces this with
// characterization::load_machine. Missing values take the manual's defaults (SPL 1, CLO 10,2).
pub fn machine_context(dir: &Path) -> Result<MachineContext, BuildError> {
    let iocfil = fcrsys_file(dir, "IOCONF").unwrap_or_else(|| dir.join("MP0").join("IOCFIL"));
    let bytes = std::fs::read(&iocfil).map_err(|source| BuildError::Read {
        path: iocfil.display().to_string(),
        source,
    })?;
    let text = String::from_utf8_lossy(&bytes);
    let mut ctx = MachineContext {
        a_inputs: Vec::new(),
        a_outputs: Vec::new(),
        spl: 1,
        tick_ms: 10,
        time_slow_ms: 2,
        interface: InterfaceMap::load_for_machine(dir)?,
    };
    let mut section = 1;
    for line in text.lines() {
        let line: String = line
            .split(';')
            .next()
            .unwrap_or("")
            .chars()
            .filter(|c| !c.is_whitespace())
            .collect::<String>()
            .to_ascii_uppercase();
        if let Some(s) = line.strip_prefix('*') {
            section = s.parse().unwrap_or(0);
            continue;
        }
        let Some((key, value)) = line.split_once('=') else {
            continue;
        };
        if section != 1 {
            continue;
        }
        let numbers = || {
            value
                .split(',')
                .filter_map(|v| v.parse::<u32>().ok())
                .collect::<Vec<_>>()
        };
        if key.len() == 3 && key.starts_with("IN") {
            ctx.a_inputs
                .extend(numbers().into_iter().filter_map(|n| u16::try_from(n).ok()));
        } else if key.len() == 3 && key.starts_with("OU") {
            ctx.a_outputs
                .extend(numbers().into_iter().filter_map(|n| u16::try_from(n).ok()));
        } else if key == "SPL" {
            ctx.spl = numbers().first().copied().unwrap_or(1);
        } else if key == "CLO" {
            let n = numbers();
            ctx.tick_ms = n.first().copied().unwrap_or(10);
            ctx.time_slow_ms = n.get(1).copied().unwrap_or(2);
        }
    }
    Ok(ctx)
}

/// Runs `ncplc build`.
pub fn run(args: Args) -> ExitCode {
    let started = Instant::now();
    let ctx = match machine_context(&args.machine_dir) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("ncplc build: {e}");
            return ExitCode::from(2);
        }
    };
    let path = args
        .plc
        .clone()
        .unwrap_or_else(|| default_plc_source(&args.machine_dir));
    let bytes = match std::fs::read(&path) {
        Ok(b) => b,
        Err(e) => {
            eprintln!("ncplc build: cannot read {}: {e}", path.display());
            return ExitCode::from(2);
        }
    };
    let name = path
        .strip_prefix(&args.machine_dir)
        .unwrap_or(&path)
        .display()
        .to_string();
    let c = compiler::compile(&name, &bytes, &ctx);
    let mut emitted = None;
    let mut diagnostics = c.diagnostics.clone();
    if let (Some(emit), Some(p)) = (args.emit, &c.program) {
        emitted = Some(match emit {
            Emit::Ir => {
                serde_json::to_string_pretty(p).unwrap_or_else(|e| format!("{{\"error\":\"{e}\"}}"))
            }
            Emit::Clif => match compiler::jit::emit_clif(p) {
                Ok(text) => text,
                Err(e) => {
                    diagnostics.push(diag::Diagnostic::error(
                        compiler::sema::codes::LOWERING,
                        &name,
                        0..0,
                        format!("JIT failed: {e}"),
                    ));
                    String::new()
                }
            },
        });
    }
    let mut sources = diag::Sources::new();
    sources.add(name.clone(), c.text.clone());
    let report = match args.format {
        Format::Human => diag::render_human(&diagnostics, &sources),
        Format::Json => diagnostics
            .iter()
            .map(|d| d.to_json_line() + "\n")
            .collect(),
    };
    let ok = c.program.is_some() && !diag::has_errors(&diagnostics);
    let summary = if ok {
        format!(
            "{name}: {} statements, {} symbolic names, image {} bytes, {} SLOW slices, compiled in {:.1} ms",
            c.stats.statements,
            c.stats.symbolic_names,
            c.stats.image_size,
            c.stats.slow_slices,
            started.elapsed().as_secs_f64() * 1000.0
        )
    } else {
        format!(
            "{name}: not compiled ({} errors)",
            diagnostics.iter().filter(|d| d.is_error()).count()
        )
    };
    let mut out = std::io::stdout().lock();
    let written = match (&emitted, args.format) {
        (Some(text), _) => {
            eprint!("{report}");
            eprintln!("{summary}");
            writeln!(out, "{text}")
        }
        (None, Format::Human) => write!(out, "{report}").and_then(|_| writeln!(out, "{summary}")),
        (None, Format::Json) => {
            eprintln!("{summary}");
            write!(out, "{report}")
        }
    };
    if written.is_err() {
        return ExitCode::from(2);
    }
    if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fcrsys_names_and_iocfil_lines_are_read() {
        let dir = tempfile::tempdir().expect("temp dir");
        std::fs::create_dir(dir.path().join("MP0")).expect("mkdir");
        std::fs::write(
            dir.path().join("FCRSYS"),
            "*1\nMP0=C:\\CNC32\\MP0\n*2\nIOCONF, IOCFIL/MP0\nPLCSRC,C:\\CNC32\\MP0\\LOGIC\n*\n",
        )
        .expect("write");
        std::fs::write(
            dir.path().join("MP0/IOCFIL"),
            "*1\nIN0=0,1,,,,,,\nOU0 = 4,5\nCLO=20,4 ; tick\nSPL=400\n*2\nIN1=9\n",
        )
        .expect("write");
        let ctx = machine_context(dir.path()).expect("context");
        assert_eq!(
            (
                ctx.a_inputs,
                ctx.a_outputs,
                ctx.spl,
                ctx.tick_ms,
                ctx.time_slow_ms
            ),
            (vec![0, 1], vec![4, 5], 400, 20, 4)
        );
        let bare = tempfile::tempdir().expect("temp dir");
        assert_eq!(
            default_plc_source(bare.path()),
            bare.path().join("MP0").join("PLCPRG")
        );
        assert_eq!(
            default_plc_source(dir.path()),
            dir.path().join("MP0").join("LOGIC")
        );
    }
}
