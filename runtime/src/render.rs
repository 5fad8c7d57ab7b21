//! How the controller shows what it reports: diagnostics rendered (and coloured as the command line
//! chose) and paths as the user can open them from the current directory.
//!
//! The `ncplc` binary sets the colour once at start ([`set_color`]); every layer below renders its
//! diagnostics through [`render_diagnostics`], so a compile error from an online change looks like one
//! from `ncplc build`. **Invariant:** nothing here prints; it only formats.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

static COLOR: OnceLock<Color> = OnceLock::new();

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

/// Sets the colour choice (once, first thing in `ncplc`; later calls are ignored).
pub fn set_color(color: Color) {
    let _ = COLOR.set(color);
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
    render_diagnostics_capped(diagnostics, sources, diag::DEFAULT_MAX_PER_FILE)
}

/// [`render_diagnostics`] showing at most `max` diagnostics per file (0: all; `--max-errors`).
pub fn render_diagnostics_capped(
    diagnostics: &[diag::Diagnostic],
    sources: &diag::Sources,
    max: usize,
) -> String {
    render_diagnostics_capped_with(diagnostics, &[], sources, max)
}

/// [`render_diagnostics_capped`] with `hidden`, what a capped load only counted, in the notes
/// and the summary.
pub fn render_diagnostics_capped_with(
    diagnostics: &[diag::Diagnostic],
    hidden: &[diag::Hidden],
    sources: &diag::Sources,
    max: usize,
) -> String {
    let text = diag::render_human_capped_with(diagnostics, hidden, sources, max);
    if colored() { colorize(&text) } else { text }
}

const RED: &str = "\x1b[1;31m";
const YELLOW: &str = "\x1b[1;33m";
const BLUE: &str = "\x1b[1;34m";
const BOLD: &str = "\x1b[1m";
const RESET: &str = "\x1b[0m";

/// Adds ANSI colours to rustc-style diagnostics, as rustc colours them: the severity and code of
/// each header (red errors, yellow warnings) with a bold message, the gutter and notes in blue, the
/// span markers in the header's colour. Applied to the rendered text so that the renderer (in the
/// `diag` crate) stays one plain-text function.
pub fn colorize(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + text.len() / 4);
    let mut marker = RED;
    for line in text.split_inclusive('\n') {
        let (body, nl) = match line.strip_suffix('\n') {
            Some(b) => (b, "\n"),
            None => (line, ""),
        };
        let header = [("error", RED), ("warning", YELLOW)]
            .into_iter()
            .find(|(w, _)| body.starts_with(w) && body[w.len()..].starts_with(['[', ':']));
        if let Some((_, color)) = header {
            marker = color;
            let (head, msg) = body.split_once(": ").unwrap_or((body, ""));
            out.push_str(&format!("{color}{head}{RESET}"));
            if !msg.is_empty() || body.contains(": ") {
                out.push_str(&format!("{BOLD}: {msg}{RESET}"));
            }
        } else if let Some(bar) = body
            .find('│')
            .or_else(|| body.find('|'))
            .filter(|&i| body[..i].trim().chars().all(|c| c.is_ascii_digit()))
        {
            let (gutter, rest) = body.split_at(bar);
            let bar_len = rest.chars().next().map_or(1, char::len_utf8);
            let (bar, rest) = rest.split_at(bar_len);
            out.push_str(&format!("{BLUE}{gutter}{bar}{RESET}"));
            if rest.contains('^') && rest.chars().all(|c| c == '^' || c == ' ' || c == '-') {
                out.push_str(&format!("{marker}{rest}{RESET}"));
            } else {
                out.push_str(rest);
            }
        } else if body.trim_start().starts_with("┌─")
            || body.trim_start().starts_with("-->")
            || body.trim_start().starts_with('=')
        {
            let indent = body.len() - body.trim_start().len();
            out.push_str(&format!(
                "{}{BLUE}{}{RESET}",
                &body[..indent],
                &body[indent..]
            ));
        } else {
            out.push_str(body);
        }
        out.push_str(nl);
    }
    out
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

/// Renames the machine's files (named relative to the machine directory by the reader) as the
/// user can open them from the current directory, in the diagnostics and the sources.
pub fn relocate(load: &mut characterization::MachineLoad, dir: &std::path::Path) {
    let shown = |name: &str| user_path(&dir.join(name)).display().to_string();
    // A handful of files, up to millions of diagnostics: each name is worked out once (a
    // `getcwd` per diagnostic was 14 % of `check` on an error-dense 5 MB AXCFIL).
    let mut renamed: std::collections::BTreeMap<String, String> = std::collections::BTreeMap::new();
    for d in &mut load.diagnostics {
        let new = renamed
            .entry(std::mem::take(&mut d.file))
            .or_insert_with_key(|old| shown(old));
        d.file.clone_from(new);
    }
    for h in &mut load.hidden {
        h.file = shown(&h.file);
    }
    let mut sources = diag::Sources::new();
    for name in load.sources.names() {
        if let Some(text) = load.sources.get(name) {
            sources.add(shown(name), text);
        }
    }
    load.sources = sources;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colour_marks_headers_gutters_and_spans() {
        let plain =
            "error[E0101]: unknown signal\n  ┌─ MP0/PLCPRG:3:5\n  │\n3 │ LD I9A3\n  │    ^^^^\n";
        assert_eq!(
            colorize(plain),
            "\x1b[1;31merror[E0101]\x1b[0m\x1b[1m: unknown signal\x1b[0m\n  \x1b[1;34m┌─ MP0/PLCPRG:3:5\x1b[0m\n\x1b[1;34m  │\x1b[0m\n\x1b[1;34m3 │\x1b[0m LD I9A3\n\x1b[1;34m  │\x1b[0m\x1b[1;31m    ^^^^\x1b[0m\n"
        );
        assert_eq!(colorize("1 error, 0 warnings\n"), "1 error, 0 warnings\n");
    }

    #[test]
    fn paths_are_shown_relative_to_the_current_directory() {
        let cwd = std::env::current_dir().expect("cwd");
        assert_eq!(user_path(&cwd.join("a/b/../c")), PathBuf::from("a/c"));
        assert_eq!(user_path(Path::new("./x/./y")), PathBuf::from("x/y"));
        assert_eq!(user_path(&cwd), PathBuf::from("."));
        assert_eq!(user_path(Path::new("/")), PathBuf::from("/"));
    }
}
