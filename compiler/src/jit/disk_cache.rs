//! Machine code kept on disk across processes: `ncplc run` or `replay` after an `ncplc build` of
//! the same program maps the code the build made instead of compiling it again.
//!
//! Content-addressed: the key is the exact byte encoding (postcard) of the laid-out program, the
//! code-generation options, the compiler build (package version, size and modification time of
//! the executable) and the host ISA with its CPU features. The file name is a 64-bit FNV-1a hash
//! of the key; the file holds the whole key, compared in full before its code is used, so a hash
//! collision or a damaged file only costs a compile. Writes go to a temporary file renamed into
//! place; at most [`MAX_ENTRIES`] files are kept (the oldest go first). The cache is best-effort:
//! an I/O error never fails a compile.

use std::path::{Path, PathBuf};

use cranelift_codegen::isa::OwnedTargetIsa;
use serde::Serialize;

use super::{
    JitError, JitOptions, JitProgram, Text, check_len, compile_program_to, isa, load_text,
};
use crate::ir::Program;

/// Entries kept in a cache directory.
pub const MAX_ENTRIES: usize = 64;

/// A directory of machine code entries.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DiskCache {
    dir: PathBuf,
}

/// Where one program's code is (or will be) stored, and its full key.
#[derive(Debug)]
pub(super) struct Entry {
    path: PathBuf,
    key: Vec<u8>,
}

/// Everything the machine code depends on.
#[derive(Serialize)]
struct Key<'a> {
    program: &'a Program,
    opt_level: &'a str,
    regalloc: &'a str,
    chunk_cost: u32,
    if_convert_cost: u32,
    cache_window: u32,
    build: String,
    isa: String,
}

impl DiskCache {
    /// A cache in `dir` (created when the first entry is stored).
    pub fn new(dir: impl Into<PathBuf>) -> DiskCache {
        DiskCache { dir: dir.into() }
    }

    /// The cache the CLI uses: `$NCPLC_CODE_CACHE` (`off` or empty: none), else
    /// `$XDG_CACHE_HOME/ncplc/code`, else `$HOME/.cache/ncplc/code`.
    pub fn from_env() -> Option<DiskCache> {
        if let Some(dir) = std::env::var_os("NCPLC_CODE_CACHE") {
            if dir.is_empty() || dir == "off" {
                return None;
            }
            return Some(DiskCache::new(dir));
        }
        let base = std::env::var_os("XDG_CACHE_HOME")
            .filter(|d| !d.is_empty())
            .map(PathBuf::from)
            .or_else(|| std::env::var_os("HOME").map(|h| Path::new(&h).join(".cache")))?;
        Some(DiskCache::new(base.join("ncplc").join("code")))
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    fn entry(&self, p: &Program, opts: &JitOptions, isa: &OwnedTargetIsa) -> Option<Entry> {
        let key = postcard::to_allocvec(&Key {
            program: p,
            opt_level: opts.opt_level,
            regalloc: opts.regalloc,
            chunk_cost: opts.chunk_cost,
            if_convert_cost: opts.if_convert_cost,
            cache_window: opts.cache_window,
            build: build_id(),
            isa: isa_id(isa),
        })
        .ok()?;
        let path = self.path_for(&key, "code");
        Some(Entry { path, key })
    }
}

impl Entry {
    /// The stored text, when the file holds exactly this key.
    fn load(&self) -> Option<Text> {
        let bytes = std::fs::read(&self.path).ok()?;
        let (key, text): (Vec<u8>, Text) = postcard::from_bytes(&bytes).ok()?;
        (key == self.key).then_some(text)
    }

    /// Stores `text` under this key (best-effort; see the module docs).
    pub(super) fn store(&self, text: &Text) {
        if let Ok(bytes) = postcard::to_allocvec(&(&self.key, text)) {
            write_entry(&self.path, &bytes);
        }
    }
}

impl DiskCache {
    /// The file of the entry with `key` and extension `ext` (the key's FNV-1a hash names it).
    pub(crate) fn path_for(&self, key: &[u8], ext: &str) -> PathBuf {
        self.dir.join(format!("{:016x}.{ext}", fnv1a(key)))
    }
}

/// Writes `bytes` to `path` through a temporary file renamed into place, then prunes the
/// directory's entries with `path`'s extension (best-effort: errors are ignored).
pub(crate) fn write_entry(path: &Path, bytes: &[u8]) {
    let (Some(dir), Some(ext)) = (path.parent(), path.extension()) else {
        return;
    };
    if std::fs::create_dir_all(dir).is_err() {
        return;
    }
    let tmp = path.with_extension(format!("tmp{}", std::process::id()));
    if std::fs::write(&tmp, bytes).is_ok() && std::fs::rename(&tmp, path).is_ok() {
        prune(dir, ext);
    } else {
        let _ = std::fs::remove_file(&tmp);
    }
}

/// Compiles `p` like [`super::compile_with`], taking the code from `cache` when it holds this
/// program's code and leaving it there otherwise. Returns the program and whether the code came
/// from the cache.
pub fn compile(
    p: &Program,
    opts: &JitOptions,
    cache: Option<&DiskCache>,
) -> Result<(JitProgram, bool), JitError> {
    let Some(cache) = cache else {
        return Ok((compile_program_to(p, opts, None, None)?, false));
    };
    check_len(p)?;
    let target = isa(opts)?;
    let entry = cache.entry(p, opts, &target);
    if let Some(text) = entry.as_ref().and_then(Entry::load) {
        match load_text(target, &text, p.image_len) {
            Ok(program) => return Ok((program, true)),
            Err(_) => return Ok((compile_program_to(p, opts, None, entry.as_ref())?, false)),
        }
    }
    Ok((compile_program_to(p, opts, None, entry.as_ref())?, false))
}

/// The program's code from `cache`, if it holds it (nothing is compiled or stored).
pub fn lookup(p: &Program, opts: &JitOptions, cache: &DiskCache) -> Option<JitProgram> {
    check_len(p).ok()?;
    let target = isa(opts).ok()?;
    let text = cache.entry(p, opts, &target)?.load()?;
    load_text(target, &text, p.image_len).ok()
}

/// [`lookup`], and on a hit `code_cache` is filled with the program's functions as if it had
/// just compiled them (found by their statements), so that the next online change through it
/// compiles only the functions it changed.
pub fn lookup_cached(
    p: &Program,
    opts: &JitOptions,
    cache: &DiskCache,
    code_cache: &mut super::CodeCache,
) -> Option<JitProgram> {
    check_len(p).ok()?;
    let target = isa(opts).ok()?;
    let text = cache.entry(p, opts, &target)?.load()?;
    let program = load_text(target, &text, p.image_len).ok()?;
    if let Some(codes) = text.functions() {
        super::code_cache::fill(code_cache, p, opts, codes);
    }
    Some(program)
}

/// Removes the oldest entries with extension `ext` beyond [`MAX_ENTRIES`].
fn prune(dir: &Path, ext: &std::ffi::OsStr) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<(std::time::SystemTime, PathBuf)> = rd
        .filter_map(Result::ok)
        .filter(|e| e.path().extension().is_some_and(|x| x == ext))
        .filter_map(|e| Some((e.metadata().ok()?.modified().ok()?, e.path())))
        .collect();
    if entries.len() <= MAX_ENTRIES {
        return;
    }
    entries.sort();
    for (_, path) in &entries[..entries.len() - MAX_ENTRIES] {
        let _ = std::fs::remove_file(path);
    }
}

/// The compiler build: package version, and size and modification time of the executable (a
/// rebuilt compiler never reuses an older build's code).
pub(crate) fn build_id() -> String {
    let exe = std::env::current_exe()
        .and_then(std::fs::metadata)
        .ok()
        .map(|m| {
            let t = m
                .modified()
                .ok()
                .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
                .map_or(0, |d| d.as_nanos());
            format!("{} {t}", m.len())
        })
        .unwrap_or_default();
    format!("{} {exe}", env!("CARGO_PKG_VERSION"))
}

/// The host target and its CPU features as cranelift sees them.
fn isa_id(isa: &OwnedTargetIsa) -> String {
    let flags: Vec<String> = isa.isa_flags().iter().map(|f| f.to_string()).collect();
    format!("{} {}", isa.triple(), flags.join(","))
}

fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}
