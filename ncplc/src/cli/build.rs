//! `ncplc build <machine-dir> [--plc FILE]`: compiles the machine's PLC program.
//!
//! Prints every diagnostic rustc-style (default) or as one JSON object per line (`--format json`,
//! the fields of `ncplc check`), then a one-line summary (statements, image size, compile time),
//! all on stderr. `--emit ir` prints the lowered IR as JSON on stdout, `--emit clif` the cranelift
//! IR of the JIT. Exit code 0 when the program compiles, 1 on errors, 2 when the
//! machine or the source cannot be read.
//!
//! The PLC source is `--plc FILE`, else the file FCRSYS section 2 binds to `PLCSRC`, else
//! `MP0/PLCPRG`.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use compiler::MachineContext;

use runtime::machine_facts::{Facts, MachineError};

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
    #[arg(value_name = "MACHINE")]
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
    /// Diagnostics printed per file; the rest are counted in one `note: N more errors in FILE`
    /// line (0: print all).
    #[arg(long, value_name = "N", default_value_t = diag::DEFAULT_MAX_PER_FILE)]
    pub max_errors: usize,
}

/// The compiler's view of the machine in `dir` and its default PLC source (FCRSYS `PLCSRC`, else
/// `MP0/PLCPRG`), from the validated characterization.
pub fn machine_context(dir: &Path) -> Result<(MachineContext, PathBuf), MachineError> {
    let facts = Facts::load(dir)?;
    Ok((facts.compiler_context()?, facts.plc_source().to_path_buf()))
}

/// The build error for a program the front end accepted but cranelift could not compile.
fn jit_failed(name: &str, e: &impl std::fmt::Display) -> diag::Diagnostic {
    diag::Diagnostic::error(
        compiler::sema::codes::LOWERING,
        name,
        0..0,
        format!("JIT failed: {e}"),
    )
}

/// Runs `ncplc build`.
pub fn run(args: Args) -> ExitCode {
    let started = Instant::now();
    let (ctx, default_source) = match machine_context(&args.machine_dir) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("ncplc build: {e}");
            return ExitCode::from(2);
        }
    };
    let path = args.plc.clone().unwrap_or(default_source);
    let bytes = match compiler::read_source(&path) {
        Ok(b) => b,
        Err(e) => {
            eprintln!("ncplc build: cannot read {}: {e}", path.display());
            return ExitCode::from(2);
        }
    };
    // As the user can open it from the current directory.
    let name = super::output::user_path(&path).display().to_string();
    // A build is not beside a running scan: parse on every core (same result as one thread).
    let front_started = Instant::now();
    // Through the on-disk front-end cache: a rebuild, `run` or `replay` of the same source for
    // the same machine does no front-end work.
    let disk = compiler::jit::disk_cache::DiskCache::from_env();
    let (c, _) = compiler::front_cache::compile_cached(&name, &bytes, &ctx, 0, disk.as_ref());
    let front_ms = front_started.elapsed().as_secs_f64() * 1000.0;
    let mut emitted = None;
    let mut diagnostics = c.diagnostics.clone();
    // The native code `ncplc run` would load, on every core: a program the JIT cannot compile is a
    // build error, and the summary says what the compile costs.
    let mut jit_ms = None;
    if let Some(p) = c
        .program
        .as_ref()
        .filter(|_| !diag::has_errors(&diagnostics))
    {
        let jit_started = Instant::now();
        let opts = compiler::jit::JitOptions {
            threads: 0,
            ..compiler::jit::JitOptions::default()
        };
        // Through the on-disk code cache: a later `ncplc run`/`replay` of it maps this code.
        match compiler::jit::disk_cache::compile(p, &opts, disk.as_ref()) {
            Ok(_) => jit_ms = Some(jit_started.elapsed().as_secs_f64() * 1000.0),
            Err(e) => diagnostics.push(jit_failed(&name, &e)),
        }
    }
    if let (Some(emit), Some(p)) = (args.emit, &c.program) {
        emitted = Some(match emit {
            Emit::Ir => {
                serde_json::to_string_pretty(p).unwrap_or_else(|e| format!("{{\"error\":\"{e}\"}}"))
            }
            Emit::Clif => match compiler::jit::emit_clif(p) {
                Ok(text) => text,
                Err(e) => {
                    diagnostics.push(jit_failed(&name, &e));
                    String::new()
                }
            },
        });
    }
    let mut sources = diag::Sources::new();
    sources.add(name.clone(), c.text.clone());
    let report = match args.format {
        Format::Human => {
            super::output::render_diagnostics_capped(&diagnostics, &sources, args.max_errors)
        }
        Format::Json => diag::json_lines_capped(&diagnostics, args.max_errors),
    };
    let ok = c.program.is_some() && !diag::has_errors(&diagnostics);
    let summary = if ok {
        format!(
            "{name}: {} statements, {} symbolic names, image {} bytes, {} SLOW slices, compiled in {:.1} ms (front end {front_ms:.1} ms, native code {:.1} ms)",
            c.stats.statements,
            c.stats.symbolic_names,
            c.stats.image_size,
            c.stats.slow_slices,
            started.elapsed().as_secs_f64() * 1000.0,
            jit_ms.unwrap_or(0.0)
        )
    } else {
        format!(
            "{name}: not compiled ({} errors)",
            diagnostics.iter().filter(|d| d.is_error()).count()
        )
    };
    // Diagnostics and the summary on stderr; stdout holds only what --emit asked for.
    eprint!("{report}");
    eprintln!("{summary}");
    if let Some(text) = &emitted
        && writeln!(std::io::stdout().lock(), "{text}").is_err()
    {
        return ExitCode::from(2);
    }
    if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
