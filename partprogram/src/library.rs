//! The machine's macro folder as a library of its own: which of its files a dialect's compile
//! reads (MEFI `L<n>` and `$PC` cycle files, Fanuc `O<n>`), and checking them without a part.
//!
//! Every compile of a part or of MDI text loads the whole library, so an error in any library
//! file refuses every program; `ncplc check` reports them with the machine ([`check_library`]),
//! and names the folder's files that no compile reads ([`unread_files`]).

use std::path::Path;

use diag::{Diagnostic, Hidden};

use crate::machine::{Dialect, MachineSpec};
use crate::program::{SourceFile, compile_capped, macro_folder_files, text_of};

/// Whether a macro-folder file with upper-case `stem` (its name before the first `.`) and
/// `text` is a MEFI library file: a subprogram `L<n>` or a cycle file starting with `$PC`.
pub(crate) fn is_mefi_library(stem: &str, text: &str) -> bool {
    let is_l =
        stem.len() > 1 && stem.starts_with('L') && stem[1..].bytes().all(|c| c.is_ascii_digit());
    is_l || text.trim_start().starts_with("$PC")
}

/// The program number of a macro-folder file with upper-case `stem` when it is a Fanuc library
/// file `O<n>`.
pub(crate) fn fanuc_library_number(stem: &str) -> Option<u32> {
    stem.strip_prefix('O').and_then(|d| d.parse::<u32>().ok())
}

/// The folder part of the name diagnostics give a macro-folder file.
const FOLDER: &str = "macros/";

/// The name diagnostics give a macro-folder file.
pub(crate) fn file_name(fname: &str) -> String {
    format!("{FOLDER}{fname}")
}

/// The macro library of `machine` checked on its own: its files' diagnostics as a compile of any
/// program reports them (syntax, units, links, recursion; at most `max` per file, 0: all).
#[derive(Debug, Default)]
pub struct LibraryCheck {
    /// The library files the dialect reads, with their texts (for rendering).
    pub files: Vec<SourceFile>,
    /// Diagnostics of the library files, in file order.
    pub diagnostics: Vec<Diagnostic>,
    /// What the cap hid, per library file.
    pub hidden: Vec<Hidden>,
}

/// The main program compiled beside the library: it calls nothing, so every diagnostic the
/// compile gives is the library's.
const MAIN: &str = "<library check>";

/// The text of the main program in `dialect`: a program end and nothing else.
fn main_text(dialect: Dialect) -> &'static str {
    match dialect {
        Dialect::Mefi => "%1\nN1 M30\n",
        Dialect::Fanuc => "M30\n",
    }
}

/// Checks the macro library of `machine` (`machine.macro_dir`) as a compile in its dialect loads
/// it: beside an empty main program, keeping the diagnostics of the library files. The texts are
/// those the compile read: every library file's when it compiled, else (a rejected compile keeps
/// none) those of the files its diagnostics name, read again for rendering.
pub fn check_library(machine: &MachineSpec, max: usize) -> LibraryCheck {
    let (prog, diagnostics, hidden) =
        compile_capped(machine, MAIN, main_text(machine.dialect), max);
    let diagnostics: Vec<Diagnostic> = diagnostics.into_iter().filter(|d| d.file != MAIN).collect();
    let files = match prog {
        Some(p) => p.files.into_iter().filter(|f| f.name != MAIN).collect(),
        None => {
            let mut names: Vec<&str> = diagnostics.iter().map(|d| d.file.as_str()).collect();
            names.dedup();
            names
                .into_iter()
                .filter_map(|name| {
                    let fname = name.strip_prefix(FOLDER)?;
                    let text = std::fs::read(machine.macro_dir.join(fname)).ok()?;
                    Some(SourceFile {
                        name: name.to_string(),
                        text: text_of(text),
                    })
                })
                .collect()
        }
    };
    LibraryCheck {
        files,
        diagnostics,
        hidden: hidden.into_iter().filter(|h| h.file != MAIN).collect(),
    }
}

/// The files of the macro folder `dir` that a compile in none of `dialects` reads (their names
/// as diagnostics give them), e.g. a `README` or, for a Fanuc-only machine, MEFI `L<n>` files,
/// and its subfolders (a compile reads none), in name order.
pub fn unread_files(dir: &Path, dialects: &[Dialect]) -> Vec<String> {
    let mut out: Vec<String> = std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .filter_map(|e| e.ok())
        .filter(|e| e.path().is_dir())
        .map(|e| file_name(&e.file_name().to_string_lossy()))
        .collect();
    for (path, fname, stem) in macro_folder_files(dir) {
        let read = dialects.iter().any(|d| match d {
            Dialect::Fanuc => fanuc_library_number(&stem).is_some(),
            // An unreadable file is reported by the compile (2031), not here.
            Dialect::Mefi => std::fs::read(&path)
                .map(|b| is_mefi_library(&stem, &String::from_utf8_lossy(&b)))
                .unwrap_or(true),
        });
        if !read {
            out.push(file_name(&fname));
        }
    }
    out.sort();
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The main program compiled beside the library gives no diagnostic of its own in either
    /// dialect, so dropping the main's diagnostics drops nothing a library could cause.
    #[test]
    fn the_empty_main_compiles_clean_in_both_dialects() {
        for dialect in [Dialect::Mefi, Dialect::Fanuc] {
            let spec = MachineSpec::new(dialect, &['X', 'Z']);
            let checked = check_library(&spec, 0);
            assert!(checked.files.is_empty() && checked.diagnostics.is_empty());
            let (prog, diags, hidden) = compile_capped(&spec, MAIN, main_text(dialect), 0);
            assert!(prog.is_some(), "{dialect:?}");
            assert_eq!(
                (diags.len(), hidden.len()),
                (0, 0),
                "{dialect:?}: {diags:?}"
            );
        }
    }
}
