//! The conventions every subcommand shares: exit codes, where output goes, colour, SIGPIPE, and
//! how paths are shown.
//!
//! **stdout** carries what a command was asked to produce (the `--dump` model, `--emit` IR, a
//! plan, trace text, `--stats`, diagnostics in `--format json`); **stderr** carries human-readable
//! diagnostics, progress and summaries. Exit codes: [`OK`], [`PROBLEMS`], [`USAGE`].

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::OnceLock;
use std::time::Instant;

/// Exit code: success.
pub const OK: u8 = 0;
/// Exit code: the input has problems (diagnostics with errors, a replay that diverges, a run
/// that tripped its safe state).
pub const PROBLEMS: u8 = 1;
/// Exit code: a usage or environment error (bad arguments, a missing machine directory or file,
/// an unwritable output).
pub const USAGE: u8 = 2;

/// The exit-code table shown at the end of `--help`.
pub const EXIT_CODES_HELP: &str = "Exit codes: 0 ok; 1 problems found in the input (errors, a diverging replay, a tripped run); 2 usage or environment error (bad arguments, missing machine directory or file).\nOutput: results on stdout; diagnostics, progress and summaries on stderr.";

/// When to colour diagnostics.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Color {
    /// Colour when stderr is a terminal (and `NO_COLOR` is not set).
    #[default]
    Auto,
    /// Always colour.
    Always,
    /// Never colour.
    Never,
}

static STARTED: OnceLock<Instant> = OnceLock::new();
static COLOR: OnceLock<Color> = OnceLock::new();

/// Records the process start and the colour choice; called first thing by `cli::main`.
pub fn init(color: Color) {
    STARTED.get_or_init(Instant::now);
    let _ = COLOR.set(color);
}

/// When the command line started being handled (for the start-to-first-tick figure).
pub fn started() -> Instant {
    *STARTED.get_or_init(Instant::now)
}

/// Whether diagnostics on stderr get ANSI colour.
pub fn colored() -> bool {
    use std::io::IsTerminal;
    match COLOR.get().copied().unwrap_or_default() {
        Color::Always => true,
        Color::Never => false,
        Color::Auto => std::env::var_os("NO_COLOR").is_none() && std::io::stderr().is_terminal(),
    }
}

/// Renders human diagnostics, coloured per [`colored`].
pub fn render_diagnostics(diagnostics: &[diag::Diagnostic], sources: &diag::Sources) -> String {
    if colored() {
        diag::render_human_colored(diagnostics, sources)
    } else {
        diag::render_human(diagnostics, sources)
    }
}

/// Lets a write to a closed pipe end the process quietly (as `cat` does: killed by SIGPIPE, exit
/// status 141 in a shell) instead of a panic in `println!`. Not for `run`, whose fieldbus sockets
/// must never kill the controller.
pub fn quiet_sigpipe() {
    // SAFETY: restoring the default disposition of one signal; no handler runs.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// `path` as the user can open it from the current directory: relative to it when inside it,
/// as given otherwise.
pub fn user_path(path: &Path) -> PathBuf {
    let cwd = std::env::current_dir().ok();
    let abs = if path.is_absolute() {
        path.to_path_buf()
    } else if let Some(c) = &cwd {
        c.join(path)
    } else {
        return path.to_path_buf();
    };
    let abs = normalize(&abs);
    match cwd.as_deref().map(normalize) {
        Some(c) => match abs.strip_prefix(&c) {
            Ok(rel) if rel.as_os_str().is_empty() => PathBuf::from("."),
            Ok(rel) => rel.to_path_buf(),
            Err(_) => abs,
        },
        None => abs,
    }
}

/// Removes `.` and resolves `..` lexically.
fn normalize(p: &Path) -> PathBuf {
    use std::path::Component;
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                if !out.pop() {
                    out.push("..");
                }
            }
            other => out.push(other),
        }
    }
    out
}

/// Reports a usage or environment error on stderr and returns [`USAGE`].
pub fn usage_error(message: impl std::fmt::Display) -> ExitCode {
    eprintln!("{message}");
    ExitCode::from(USAGE)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_are_shown_relative_to_the_current_directory() {
        let cwd = std::env::current_dir().expect("cwd");
        assert_eq!(user_path(&cwd.join("a/b/../c")), PathBuf::from("a/c"));
        assert_eq!(user_path(Path::new("./x/./y")), PathBuf::from("x/y"));
        assert_eq!(user_path(&cwd), PathBuf::from("."));
        assert_eq!(user_path(Path::new("/")), PathBuf::from("/"));
    }
}
