//! The front end's result kept on disk beside the machine code ([`crate::jit::disk_cache`]), so
//! that `ncplc run` or `replay` after an `ncplc build` of the same source does no front-end work
//! either (decode only: the diagnostics' text).
//!
//! Keyed like the code cache: the exact bytes (postcard) of the file name, the source bytes, the
//! machine context (its fields, the interface map's entries in file order, as `Debug` text) and the compiler build; the
//! entry (`<hash>.front`) holds the whole key, compared in full before its program is used. Only
//! results without errors are stored (a program and its warnings); anything unreadable only
//! costs a compile.

use crate::front::{Compilation, CompileStats, compile_with_threads};
use crate::ir::Program;
use crate::jit::disk_cache::{self, DiskCache};
use crate::{MachineContext, lexer};

/// What an entry holds besides its key: the program, its warnings and the summary numbers
/// (statements, symbolic names, image size, SLOW slices).
type Stored = (Program, Vec<diag::Diagnostic>, [u64; 4]);

/// The full key of `source` compiled as `file_name` for `ctx` by this compiler build.
fn key(file_name: &str, source: &[u8], ctx: &MachineContext) -> Option<Vec<u8>> {
    // Every field (a new one must be decided on here); the interface map by its entries in file
    // order (its lookup tables are hash maps, whose order differs from process to process).
    let MachineContext {
        a_inputs,
        a_outputs,
        spl,
        tick_ms,
        time_slow_ms,
        interface,
    } = ctx;
    let entries: Vec<_> = interface.iter().collect();
    let ctx = format!("{a_inputs:?} {a_outputs:?} {spl} {tick_ms} {time_slow_ms} {entries:?}");
    postcard::to_allocvec(&(
        "front 1",
        file_name,
        source,
        ctx.as_str(),
        disk_cache::build_id(),
    ))
    .ok()
}

/// [`compile_with_threads`] through `cache`: the stored result when it holds this source for
/// this machine and compiler build (then `stats.front_end_micros` is the time the lookup took),
/// otherwise a compile whose result is stored when it has no errors. Returns the compilation and
/// whether it came from the cache.
pub fn compile_cached(
    file_name: &str,
    source: &[u8],
    ctx: &MachineContext,
    threads: usize,
    cache: Option<&DiskCache>,
) -> (Compilation, bool) {
    let start = std::time::Instant::now();
    let Some((cache, key)) = cache.and_then(|c| Some((c, key(file_name, source, ctx)?))) else {
        return (compile_with_threads(file_name, source, ctx, threads), false);
    };
    let path = cache.path_for(&key, "front");
    if let Some(bytes) = std::fs::read(&path).ok()
        && let Ok((stored_key, (program, diagnostics, n))) =
            postcard::from_bytes::<(Vec<u8>, Stored)>(&bytes)
        && stored_key == key
    {
        let stats = CompileStats {
            statements: n[0] as usize,
            symbolic_names: n[1] as usize,
            image_size: n[2] as usize,
            slow_slices: n[3] as usize,
            front_end_micros: u64::try_from(start.elapsed().as_micros()).unwrap_or(u64::MAX),
        };
        let text = lexer::decode_source(source);
        let c = Compilation {
            program: Some(program),
            diagnostics,
            stats,
            text,
        };
        return (c, true);
    }
    let c = compile_with_threads(file_name, source, ctx, threads);
    if let Some(p) = c
        .program
        .as_ref()
        .filter(|_| !diag::has_errors(&c.diagnostics))
    {
        let s = &c.stats;
        let n = [s.statements, s.symbolic_names, s.image_size, s.slow_slices].map(|x| x as u64);
        if let Ok(bytes) = postcard::to_allocvec(&(&key, (p, &c.diagnostics, n))) {
            disk_cache::write_entry(&path, &bytes);
        }
    }
    (c, false)
}
