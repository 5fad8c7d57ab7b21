//! The front-end driver: bytes → decoded text → AST → checked program → [`ir::Program`].
//!
//! [`compile`] is what the runtime and the CLI call. It never panics on input: whatever the
//! bytes, it returns a [`Compilation`] with either a program or at least one located error.

use std::io::Read;
use std::path::Path;
use std::time::Instant;

use diag::Diagnostic;

use crate::context::MachineContext;
use crate::parse_cache::ParseCache;
use crate::sema::memo::CheckCache;
use crate::{ast, ir, lexer, lower, parser, sema};

/// Numbers for the one-line build summary.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CompileStats {
    /// Executable statements (assignments and `IF`s, nested ones included).
    pub statements: usize,
    /// Symbolic names the program defines (counted against IOCFIL SPL).
    pub symbolic_names: usize,
    /// Length in bytes of the image the program needs (0 when it did not compile).
    pub image_size: usize,
    /// Number of SLOW slices.
    pub slow_slices: usize,
    /// Time spent in decode + parse + check + lowering, in microseconds.
    pub front_end_micros: u64,
}

/// The result of compiling one PLC source.
#[derive(Debug, Clone)]
pub struct Compilation {
    /// The program, when there are no errors.
    pub program: Option<ir::Program>,
    /// Every error and warning, located, in source order.
    pub diagnostics: Vec<Diagnostic>,
    /// Summary numbers.
    pub stats: CompileStats,
    /// The decoded source text the diagnostics' spans refer to (for rendering).
    pub text: String,
}

/// The largest PLC source compiled, in bytes (2 MiB). A program addresses a bounded set of
/// signals (packets A, K, N and T, at most 5,000 symbolic names by IOCFIL SPL) and the bundled
/// ones are a few kilobytes; 2 MiB is about 60,000 statement lines. A parsed source takes about 40
/// times its size, so without the limit a 50 MB file took 2 GB to reject (issue 23); with it any
/// source is checked in about 100 MB.
pub const MAX_SOURCE_BYTES: usize = 2 << 20;

/// The bytes of the PLC source `path`: all of them up to [`MAX_SOURCE_BYTES`], and for a larger
/// file only the limit plus one byte, which [`compile`] refuses (1012). Every reader of a PLC
/// source (`check`, `build`, `run`, online change, the language server) reads through this, so a
/// file of any size is rejected in constant memory.
pub fn read_source(path: &Path) -> std::io::Result<Vec<u8>> {
    let file = std::fs::File::open(path)?;
    let size = file.metadata().map(|m| m.len()).unwrap_or(0);
    let cap = MAX_SOURCE_BYTES as u64 + 1;
    let mut bytes = Vec::with_capacity(usize::try_from(size.min(cap)).unwrap_or(0));
    file.take(cap).read_to_end(&mut bytes)?;
    Ok(bytes)
}

/// The error for a source over [`MAX_SOURCE_BYTES`] (the length is not named: [`read_source`]
/// stops reading one byte past the limit), at the start of the file.
fn too_large(file_name: &str) -> Diagnostic {
    Diagnostic::error(
        sema::codes::TOO_LARGE,
        file_name,
        0..0,
        format!("the PLC program has more than {MAX_SOURCE_BYTES} bytes (2 MiB), the most a PLC source may have"),
    )
    .with_hint("a PLC program of this machine is a few thousand lines: split generated logic or generate less of it")
    .locate("")
}

/// Compiles `source` (the bytes of `file_name`) for the machine `ctx`.
pub fn compile(file_name: &str, source: &[u8], ctx: &MachineContext) -> Compilation {
    compile_with_threads(file_name, source, ctx, 1)
}

/// [`compile`] parsing on up to `threads` threads (0: the available cores; see
/// [`parser::parse_with_threads`]); the result is the same.
pub fn compile_with_threads(
    file_name: &str,
    source: &[u8],
    ctx: &MachineContext,
    threads: usize,
) -> Compilation {
    let start = Instant::now();
    if source.len() > MAX_SOURCE_BYTES {
        return Compilation {
            program: None,
            diagnostics: vec![too_large(file_name)],
            stats: CompileStats::default(),
            text: String::new(),
        };
    }
    let text = lexer::decode_source(source);
    let (ast, diagnostics) = parser::parse_with_threads(file_name, &text, threads);
    check_parsed(file_name, text, &ast, diagnostics, ctx, start)
}

/// The diagnostics of [`compile`] for an editor's text, without building the program: reuses
/// the parsed segments `parse` holds ([`parser::parse_cached`]) and the checks of unchanged
/// statements `check` holds ([`sema::memo`]). Exactly [`compile`]'s diagnostics, except that the
/// lowering's own error ([`sema::codes::LOWERING`], an internal compiler error for a program
/// that passed every check) cannot appear: no program is lowered. Also returns the syntax tree.
pub fn diagnose_incremental(
    file_name: &str,
    text: &str,
    ctx: &MachineContext,
    parse: &mut ParseCache,
    check: &mut CheckCache,
) -> (Vec<Diagnostic>, ast::Program) {
    let text = text.strip_prefix('\u{FEFF}').unwrap_or(text);
    if text.len() > MAX_SOURCE_BYTES {
        return (vec![too_large(file_name)], ast::Program::default());
    }
    let (ast, mut diagnostics) = parser::parse_cached(file_name, text, parse);
    if parser::stopped_early(&diagnostics) {
        stop_first(&mut diagnostics);
        return (diagnostics, ast);
    }
    let (counts, sema_diags) = sema::memo::check_incremental(file_name, text, &ast, ctx, check);
    add_sema(&mut diagnostics, sema_diags);
    if let Some(c) = counts.filter(|_| !diag::has_errors(&diagnostics))
        && c.statements == 0
        && c.symbolic_names == 0
    {
        diagnostics.push(empty_program(file_name, text));
    }
    diagnostics.sort_by_key(|d| (d.line, d.column));
    (diagnostics, ast)
}

/// Puts the reason a file was read only in part first.
fn stop_first(diagnostics: &mut [Diagnostic]) {
    // The stop comes first: it is the cause, and the per-file cap of the CLI would hide it
    // behind the errors of the lines read (random text has several per line).
    diagnostics.sort_by_key(|d| {
        (
            !matches!(d.code, sema::codes::NOT_TEXT | sema::codes::GAVE_UP),
            d.line,
            d.column,
        )
    });
}

/// Appends sema's diagnostics to the parser's.
fn add_sema(diagnostics: &mut Vec<Diagnostic>, mut sema_diags: Vec<Diagnostic>) {
    if diag::has_errors(diagnostics) {
        // Usage is not known after a syntax error: the lines that would use or write a name may
        // be the ones the parser could not read, so "never used/written" would mislead.
        sema_diags.retain(|d| !sema::codes::is_usage_warning(d.code));
    }
    diagnostics.append(&mut sema_diags);
}

/// The warning for a program without statements or names.
fn empty_program(file_name: &str, text: &str) -> Diagnostic {
    let what = if text.trim().is_empty() {
        "is empty"
    } else {
        "has no statements"
    };
    diag::Diagnostic::warning(
        sema::codes::EMPTY_PROGRAM,
        file_name,
        0..0,
        format!("the PLC program {what}: every output stays 0"),
    )
    .with_hint("write statements such as `U4A0 = I0A0 * I0A1`; plc-programs/mill/MP0/PLCPRG is a complete example")
    .locate(text)
}

/// Checks and lowers a parsed program (the part of a compile after the parser).
fn check_parsed(
    file_name: &str,
    text: String,
    ast: &ast::Program,
    mut diagnostics: Vec<Diagnostic>,
    ctx: &MachineContext,
    start: Instant,
) -> Compilation {
    if parser::stopped_early(&diagnostics) {
        stop_first(&mut diagnostics);
        // A file read only in part (not text, or not a PLC program) is not checked further:
        // its names and signals would only add follow-on errors.
        let stats = CompileStats {
            front_end_micros: u64::try_from(start.elapsed().as_micros()).unwrap_or(u64::MAX),
            ..CompileStats::default()
        };
        return Compilation {
            program: None,
            diagnostics,
            stats,
            text,
        };
    }
    let (checked, sema_diags) = sema::check(file_name, &text, ast, ctx);
    add_sema(&mut diagnostics, sema_diags);
    let mut stats = CompileStats::default();
    let mut program = None;
    // A program with syntax errors is never handed out, even if the recovered lines check.
    if let Some(checked) = checked.filter(|_| !diag::has_errors(&diagnostics)) {
        if checked.statements == 0 && checked.symbolic_names == 0 {
            diagnostics.push(empty_program(file_name, &text));
        }
        stats.statements = checked.statements;
        stats.symbolic_names = checked.symbolic_names;
        match lower::lower(file_name, checked) {
            Ok(p) => {
                stats.image_size = p.image_len();
                stats.slow_slices = p.slow.len();
                program = Some(p);
            }
            Err(d) => diagnostics.push(d.locate(&text)),
        }
    }
    diagnostics.sort_by_key(|d| (d.line, d.column));
    stats.front_end_micros = u64::try_from(start.elapsed().as_micros()).unwrap_or(u64::MAX);
    Compilation {
        program,
        diagnostics,
        stats,
        text,
    }
}
