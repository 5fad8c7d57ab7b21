//! Located diagnostics shared by every ncplc front end.
//!
//! The characterization reader, the PLC-language compiler, the partprogram compiler and the I/O map
//! all report problems as [`Diagnostic`] values: a stable numeric code, a severity, the file, the
//! 1-based line and column, the byte span, an English message and a hint saying what would be valid.
//! This crate renders them two ways: rustc-style with the source line and the span marked
//! ([`render_human`]) and one JSON object per line ([`Diagnostic::to_json_line`]).
//!
//! # Code ranges
//! Codes are numbers so that the JSON form stays machine-friendly and the manual's numbers can be
//! used as they are. The ranges never overlap:
//!
//! | range | owner |
//! |---|---|
//! | 0–299 | characterization errors with the number the manual (chapter 7) gives them |
//! | 900–999 | characterization rules the manual states without a number (project numbers) |
//! | 1000–1999 | PLC-language compiler (`compiler`) |
//! | 2000–2999 | partprogram compiler (`partprogram`) |
//! | 3000–3499 | I/O map and fieldbus configuration (`fieldbus`) |
//! | 3500–3999 | runtime: 3600–3619 `sim.toml` (`runtime::sim::validate`), 3620–3629 the other machine files `check` reads (`nc/DIALECT`, `nc/CONSTANTS`, `retain.bin`) |
//!
//! Broken input is data, not a panic: front ends return their result together with a
//! `Vec<Diagnostic>`, and the command-line tool decides the exit code with [`has_errors`].

use std::collections::BTreeMap;
use std::fmt;
use std::ops::Range;

use serde::{Deserialize, Serialize};

mod cap;
mod config_file;
mod lines;
mod random_text;
mod sink;
mod suggest;
pub mod toml_keys;

pub use cap::{
    DEFAULT_MAX_PER_FILE, Hidden, cap_per_file, json_lines_capped, json_lines_capped_with,
    render_human_capped, render_human_capped_with,
};
pub use config_file::{CONFIG_MAX_BYTES, read_config, read_config_bytes};
pub use lines::{Indexed, LineIndex, line_columns};
pub use random_text::random_text;
pub use sink::{Sink, merge_hidden};
pub use suggest::{did_you_mean, nearest};

/// How serious a diagnostic is: errors fail a check or a build, warnings do not.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    /// Something that must be fixed before the file or program can be used.
    Error,
    /// Something suspicious that does not stop the file or program from being used.
    Warning,
}

impl fmt::Display for Severity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Severity::Error => f.write_str("error"),
            Severity::Warning => f.write_str("warning"),
        }
    }
}

/// One located problem in one source file.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Diagnostic {
    /// Stable numeric code (see the crate docs for the ranges).
    pub code: u32,
    /// Error or warning.
    pub severity: Severity,
    /// The file as the user named it (a path relative to the machine directory where possible).
    pub file: String,
    /// Section number of a characterization file, when the file has sections.
    pub section: Option<u32>,
    /// Process number (1..5) the problem belongs to, when it belongs to one.
    pub process: Option<u32>,
    /// 1-based line of the start of the span (0 when the problem concerns the whole file).
    pub line: u32,
    /// 1-based column (in characters) of the start of the span (0 for the whole file).
    pub column: u32,
    /// Byte range of the offending text in the file, used to mark it under the source line.
    pub span: Range<usize>,
    /// What is wrong, in English.
    pub message: String,
    /// What would be valid instead; empty when there is nothing useful to say.
    pub hint: String,
}

impl Diagnostic {
    /// An error with `code` at byte `span` of `file`; line and column are filled in by [`Diagnostic::locate`].
    pub fn error(
        code: u32,
        file: impl Into<String>,
        span: Range<usize>,
        message: impl Into<String>,
    ) -> Self {
        Self::new(Severity::Error, code, file, span, message)
    }

    /// A warning with `code` at byte `span` of `file`.
    pub fn warning(
        code: u32,
        file: impl Into<String>,
        span: Range<usize>,
        message: impl Into<String>,
    ) -> Self {
        Self::new(Severity::Warning, code, file, span, message)
    }

    fn new(
        severity: Severity,
        code: u32,
        file: impl Into<String>,
        span: Range<usize>,
        message: impl Into<String>,
    ) -> Self {
        Diagnostic {
            code,
            severity,
            file: file.into(),
            section: None,
            process: None,
            line: 0,
            column: 0,
            span,
            message: message.into(),
            hint: String::new(),
        }
    }

    /// Adds the hint saying what would be valid.
    pub fn with_hint(mut self, hint: impl Into<String>) -> Self {
        self.hint = hint.into();
        self
    }

    /// Records the characterization section the problem is in.
    pub fn with_section(mut self, section: u32) -> Self {
        self.section = Some(section);
        self
    }

    /// Records the process the problem belongs to.
    pub fn with_process(mut self, process: u32) -> Self {
        self.process = Some(process);
        self
    }

    /// Fills `line` and `column` from `span.start` in `source` (the text of `self.file`).
    pub fn locate(mut self, source: &str) -> Self {
        let (line, column) = line_column(source, self.span.start);
        self.line = line;
        self.column = column;
        self
    }

    /// Fills `line` and `column` from `span.start` with the prebuilt `index` of `source`; the same
    /// result as [`Diagnostic::locate`] without scanning the text.
    pub fn locate_in(mut self, source: &str, index: &LineIndex) -> Self {
        (self.line, self.column) = index.line_column(source, self.span.start);
        self
    }

    /// True for errors.
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }

    /// The one-line JSON form: `{"file":…,"section":…,"process":…,"line":…,"column":…,"code":…,
    /// "severity":…,"message":…,"hint":…}`.
    pub fn to_json_line(&self) -> String {
        let value = serde_json::json!({
            "file": self.file,
            "section": self.section,
            "process": self.process,
            "line": self.line,
            "column": self.column,
            "code": self.code,
            "severity": self.severity,
            "message": self.message,
            "hint": self.hint,
        });
        value.to_string()
    }
}

impl fmt::Display for Diagnostic {
    /// `file:line:column: error[E0012]: message`, the compact one-line form.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}:{}: {}[E{:04}]: {}",
            self.file, self.line, self.column, self.severity, self.code, self.message
        )
    }
}

/// 1-based line and column (in characters) of byte `offset` in `source`; offsets past the end or
/// inside a character are clamped to the nearest earlier character boundary. Scans `source` up to
/// `offset` unless a live [`Indexed`] guard holds `source`: use one (or a [`LineIndex`]) for more
/// than a few lookups in one text.
pub fn line_column(source: &str, offset: usize) -> (u32, u32) {
    if let Some(index) = lines::active(source) {
        return index.line_column(source, offset);
    }
    scan_line_column(source, offset)
}

/// [`line_column`] by scanning `source` from its start.
fn scan_line_column(source: &str, offset: usize) -> (u32, u32) {
    let mut offset = offset.min(source.len());
    while !source.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &source[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = source[line_start..offset].chars().count() + 1;
    (
        u32::try_from(line).unwrap_or(u32::MAX),
        u32::try_from(column).unwrap_or(u32::MAX),
    )
}

/// True when any diagnostic is an error.
pub fn has_errors(diagnostics: &[Diagnostic]) -> bool {
    diagnostics.iter().any(Diagnostic::is_error)
}

/// Source texts by file name, for rendering diagnostics with their source lines.
#[derive(Debug, Default, Clone)]
pub struct Sources {
    files: BTreeMap<String, String>,
}

impl Sources {
    /// An empty set of sources.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds (or replaces) the text of `name`.
    pub fn add(&mut self, name: impl Into<String>, text: impl Into<String>) {
        self.files.insert(name.into(), text.into());
    }

    /// The names of the files held, in sorted order.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.files.keys().map(String::as_str)
    }

    /// The text of `name`, if known.
    pub fn get(&self, name: &str) -> Option<&str> {
        self.files.get(name).map(String::as_str)
    }
}

/// Renders diagnostics rustc-style, each with its source line and the span marked, followed by a
/// summary line (`2 errors, 1 warning`). Files missing from `sources` are rendered without a snippet.
pub fn render_human(diagnostics: &[Diagnostic], sources: &Sources) -> String {
    let mut text = render_body(diagnostics, sources);
    text.push_str(&summary(diagnostics));
    text
}

/// The summary line `2 errors, 1 warning` (empty when there are no diagnostics).
fn summary(diagnostics: &[Diagnostic]) -> String {
    let errors = diagnostics.iter().filter(|d| d.is_error()).count();
    summary_counts(errors, diagnostics.len() - errors)
}

/// The summary line for `errors` and `warnings` (empty when both are 0).
fn summary_counts(errors: usize, warnings: usize) -> String {
    if errors + warnings == 0 {
        return String::new();
    }
    format!(
        "{}, {}\n",
        plural(errors, "error"),
        plural(warnings, "warning")
    )
}

/// The rustc-style blocks of `diagnostics`, without the summary line.
fn render_body(diagnostics: &[Diagnostic], sources: &Sources) -> String {
    use codespan_reporting::diagnostic::{Diagnostic as CsDiagnostic, Label};
    use codespan_reporting::files::SimpleFiles;
    use codespan_reporting::term::{self, termcolor::Buffer};
    use std::io::Write as _;

    let mut files = SimpleFiles::new();
    let mut ids = BTreeMap::new();
    for (name, text) in &sources.files {
        // Only the files diagnostics point into, and of each only the lines up to the last one a
        // diagnostic points at: the renderer computes the start of every line it is given (8
        // bytes per line: 36 MB for a 50 MB file of short lines, whose first 100 errors are on
        // its first 40 lines).
        let last = diagnostics
            .iter()
            .filter(|d| d.file == *name)
            .map(|d| d.span.end.max(d.span.start))
            .max();
        if let Some(last) = last {
            let from = last.min(text.len());
            let cut = text.as_bytes()[from..]
                .iter()
                .position(|&b| b == b'\n')
                .map_or(text.len(), |i| from + i + 1);
            let shown = text.get(..cut).unwrap_or(text.as_str());
            ids.insert(name.as_str(), files.add(name.as_str(), shown));
        }
    }
    let config = term::Config::default();
    let mut out = Buffer::no_color();
    for d in diagnostics {
        let mut cs = match d.severity {
            Severity::Error => CsDiagnostic::error(),
            Severity::Warning => CsDiagnostic::warning(),
        }
        .with_code(format!("E{:04}", d.code))
        .with_message(&d.message);
        let mut notes = Vec::new();
        if let Some(section) = d.section {
            let mut where_ = format!("in section {section}");
            if let Some(process) = d.process {
                where_.push_str(&format!(", process {process}"));
            }
            notes.push(where_);
        } else if let Some(process) = d.process {
            notes.push(format!("in process {process}"));
        }
        if !d.hint.is_empty() {
            notes.push(format!("help: {}", d.hint));
        }
        let mut excerpt = None;
        let mut shortened = false;
        let snippet = ids.get(d.file.as_str()).and_then(|&id| {
            let text = files.get(id).ok()?.source();
            if let Some(e) = long_line_excerpt(text, d.span.start) {
                // Printing a line of megabytes for each diagnostic would flood the output.
                excerpt = Some(e);
                return None;
            }
            (d.line > 0 && d.span.start <= text.len()).then(|| {
                let end = d.span.end.clamp(d.span.start, text.len());
                let mut start = d.span.start;
                while !text.is_char_boundary(start) {
                    start -= 1;
                }
                let mut end = end.max(start);
                while !text.is_char_boundary(end) {
                    end += 1;
                }
                if let Some(cut) = span_cut(text, start, end) {
                    // A span over thousands of lines (text after the end of a program) would
                    // print them all, and the renderer's work grows with them.
                    end = cut;
                    shortened = true;
                }
                Label::primary(id, start..end)
            })
        });
        match snippet {
            Some(label) => cs = cs.with_labels(vec![label]),
            None => {
                let mut at = format!("in {}:{}:{}", d.file, d.line, d.column);
                if let Some(e) = excerpt {
                    at.push_str(&format!(" (a long line): {e}"));
                }
                notes.insert(0, at);
            }
        }
        if shortened {
            notes.push(format!(
                "the marked text goes on beyond the {MAX_SNIPPET_LINES} lines shown"
            ));
        }
        cs = cs.with_notes(notes);
        if term::emit_to_write_style(&mut out, &config, &files, &cs).is_err() {
            // Rendering into memory only fails on a bad span; fall back to the one-line form.
            let _ = writeln!(out, "{d}");
        }
    }
    String::from_utf8_lossy(&out.into_inner()).into_owned()
}

/// A diagnostic's marked text is printed over at most this many lines.
pub const MAX_SNIPPET_LINES: usize = 8;

/// Where to cut the span `start..end` of `text` so that it covers at most [`MAX_SNIPPET_LINES`]
/// lines (the end of the last of them), or `None` when it already does. Looks at no more than
/// those lines, whatever the span's length.
fn span_cut(text: &str, start: usize, end: usize) -> Option<usize> {
    let mut newlines = text.as_bytes()[start..end]
        .iter()
        .enumerate()
        .filter(|&(_, &b)| b == b'\n')
        .map(|(i, _)| start + i);
    let last = newlines.nth(MAX_SNIPPET_LINES - 1)?;
    // More text after the last shown line's end: cut there (a span ending with that newline
    // itself is left alone).
    (last + 1 < end).then_some(last)
}

/// Source lines longer than this (in bytes) are not printed under a diagnostic; an excerpt
/// around the offending text is given instead.
pub const MAX_SNIPPET_LINE: usize = 300;

/// `…text around offset…` when the line holding `offset` is longer than [`MAX_SNIPPET_LINE`].
fn long_line_excerpt(text: &str, offset: usize) -> Option<String> {
    let offset = offset.min(text.len());
    let bytes = text.as_bytes();
    let start = bytes[..offset]
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1);
    let end = bytes[offset..]
        .iter()
        .position(|&b| b == b'\n')
        .map_or(text.len(), |i| offset + i);
    if end - start <= MAX_SNIPPET_LINE {
        return None;
    }
    let mut from = offset.saturating_sub(30).max(start);
    while !text.is_char_boundary(from) {
        from -= 1;
    }
    let mut to = (offset + 30).min(end);
    while !text.is_char_boundary(to) {
        to += 1;
    }
    let lead = if from > start { "…" } else { "" };
    let tail = if to < end { "…" } else { "" };
    Some(format!("`{lead}{}{tail}`", &text[from..to]))
}

fn plural(n: usize, word: &str) -> String {
    if n == 1 {
        format!("1 {word}")
    } else {
        format!("{n} {word}s")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_column_are_one_based_and_count_characters() {
        let src = "abc\nдве строки\nxyz";
        assert_eq!(line_column(src, 0), (1, 1));
        assert_eq!(line_column(src, 4), (2, 1));
        let x = src.find('x').expect("x is in the text");
        assert_eq!(line_column(src, x), (3, 1));
        let s = src.find('с').expect("с is in the text");
        assert_eq!(line_column(src, s), (2, 5));
        assert_eq!(line_column(src, 10_000), (3, 4));
    }

    #[test]
    fn json_line_has_exactly_the_documented_fields() {
        let d = Diagnostic::error(61, "IOCFIL", 6..9, "connector out of range")
            .with_section(1)
            .with_hint("use 0..31")
            .locate("*1\nIN0=40\n");
        let v: serde_json::Value = serde_json::from_str(&d.to_json_line()).expect("valid JSON");
        assert_eq!(v["file"], "IOCFIL");
        assert_eq!(v["section"], 1);
        assert_eq!(v["process"], serde_json::Value::Null);
        assert_eq!(v["line"], 2);
        assert_eq!(v["column"], 4);
        assert_eq!(v["code"], 61);
        assert_eq!(v["severity"], "error");
        assert_eq!(v["message"], "connector out of range");
    }

    #[test]
    fn a_span_over_many_lines_is_shown_over_its_first_eight() {
        // Lines "L1".."L20"; the span runs from the start of L3 to the end of the text.
        let src: String = (1..=20).map(|i| format!("L{i}\n")).collect();
        let start = src.find("L3").expect("L3");
        let mut sources = Sources::new();
        sources.add("P", src.as_str());
        let d = Diagnostic::error(1005, "P", start..src.len(), "text after the end").locate(&src);
        let text = render_human(&[d], &sources);
        assert!(text.contains("L10"), "{text}");
        assert!(!text.contains("L11"), "{text}");
        assert!(
            text.contains("the marked text goes on beyond the 8 lines shown"),
            "{text}"
        );
        // Eight lines exactly (ending with the eighth line's newline): shown whole, no note.
        let end = src.find("L11").expect("L11");
        assert_eq!(span_cut(&src, start, end), None);
        assert_eq!(span_cut(&src, start, end + 1), Some(end - 1));
    }

    #[test]
    fn a_long_line_is_shown_as_an_excerpt() {
        let src = format!("N1{}Q9{}\n", " X1".repeat(100), " X1".repeat(100));
        let at = src.find('Q').expect("Q is in the text");
        // 30 bytes either side of `Q`: ten ` X1` before; `Q9`, nine ` X1` and a blank after.
        let mut sources = Sources::new();
        sources.add("P", src.as_str());
        let d = Diagnostic::error(2001, "P", at..at + 2, "unknown address `Q`").locate(&src);
        let text = render_human(&[d], &sources);
        assert!(
            text.contains(
                "= in P:1:303 (a long line): `… X1 X1 X1 X1 X1 X1 X1 X1 X1 X1Q9 X1 X1 X1 X1 X1 X1 X1 X1 X1 …`"
            ),
            "{text}"
        );
        assert!(!text.contains("N1 X1"), "{text}");
    }

    #[test]
    fn human_rendering_marks_the_span_and_counts() {
        let src = "U10K5=I0K2\nU999K0=I0K2\n";
        let mut sources = Sources::new();
        sources.add("PLCPRG", src);
        let d = Diagnostic::error(1003, "PLCPRG", 12..15, "connector 999 is out of range")
            .with_hint("K connectors are 0..255")
            .locate(src);
        let text = render_human(&[d], &sources);
        assert!(
            text.contains("error[E1003]: connector 999 is out of range"),
            "{text}"
        );
        assert!(text.contains("PLCPRG:2:2"), "{text}");
        assert!(text.contains("U999K0=I0K2"), "{text}");
        assert!(text.contains("^^^"), "{text}");
        assert!(text.contains("help: K connectors are 0..255"), "{text}");
        assert!(text.ends_with("1 error, 0 warnings\n"), "{text}");
    }
}
