//! The per-file cap on printed diagnostics: the first `max` of each file, then one line saying how
//! many more there are, so that one broken file cannot flood the output (issue 12: 21,012 errors
//! for 8.6 MB of random text). `ncplc check|build|nc check|nc plan --max-errors N` sets `max`.

use std::collections::BTreeMap;

use crate::{Diagnostic, Sources};

/// Diagnostics printed per file when the user does not say otherwise.
pub const DEFAULT_MAX_PER_FILE: usize = 100;

/// What the cap left out of one file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Hidden {
    /// The file, as in [`Diagnostic::file`].
    pub file: String,
    /// Errors not shown.
    pub errors: usize,
    /// Warnings not shown.
    pub warnings: usize,
}

impl Hidden {
    /// The one line that replaces the hidden diagnostics:
    /// `note: 20912 more errors and 1 more warning in MP0/AXCFIL (--max-errors 0 shows all)`.
    pub fn line(&self) -> String {
        let mut what = Vec::new();
        if self.errors > 0 {
            what.push(count(self.errors, "error"));
        }
        if self.warnings > 0 {
            what.push(count(self.warnings, "warning"));
        }
        format!(
            "note: {} in {} (--max-errors 0 shows all)",
            what.join(" and "),
            self.file
        )
    }

    /// The JSON line of the same note: `{"file":…,"more_errors":…,"more_warnings":…}`.
    pub fn to_json_line(&self) -> String {
        serde_json::json!({
            "file": self.file,
            "more_errors": self.errors,
            "more_warnings": self.warnings,
        })
        .to_string()
    }
}

fn count(n: usize, word: &str) -> String {
    if n == 1 {
        format!("1 more {word}")
    } else {
        format!("{n} more {word}s")
    }
}

/// Splits `diagnostics` into the first `max` of every file (in their order; `max == 0` keeps all)
/// and, per file in order of first appearance, what was left out.
pub fn cap_per_file(diagnostics: &[Diagnostic], max: usize) -> (Vec<&Diagnostic>, Vec<Hidden>) {
    if max == 0 {
        return (diagnostics.iter().collect(), Vec::new());
    }
    let mut seen: BTreeMap<&str, usize> = BTreeMap::new();
    let mut order: Vec<&str> = Vec::new();
    let mut hidden: BTreeMap<&str, Hidden> = BTreeMap::new();
    let mut shown = Vec::new();
    for d in diagnostics {
        let n = seen.entry(d.file.as_str()).or_insert_with(|| {
            order.push(d.file.as_str());
            0
        });
        *n += 1;
        if *n <= max {
            shown.push(d);
            continue;
        }
        let h = hidden.entry(d.file.as_str()).or_insert_with(|| Hidden {
            file: d.file.clone(),
            errors: 0,
            warnings: 0,
        });
        if d.is_error() {
            h.errors += 1;
        } else {
            h.warnings += 1;
        }
    }
    let hidden = order.iter().filter_map(|f| hidden.remove(f)).collect();
    (shown, hidden)
}

/// [`crate::render_human`] of at most `max` diagnostics per file (0: all), each file's overflow as
/// one [`Hidden::line`]; the summary line still counts every diagnostic.
pub fn render_human_capped(diagnostics: &[Diagnostic], sources: &Sources, max: usize) -> String {
    render_human_capped_with(diagnostics, &[], sources, max)
}

/// [`render_human_capped`] of the diagnostics a [`crate::Sink`] stored, with `dropped`, what it
/// only counted, added to the note lines and to the summary.
pub fn render_human_capped_with(
    diagnostics: &[Diagnostic],
    dropped: &[Hidden],
    sources: &Sources,
    max: usize,
) -> String {
    let (shown, mut hidden) = cap_per_file(diagnostics, max);
    crate::sink::merge_hidden(&mut hidden, dropped);
    let shown: Vec<Diagnostic> = shown.into_iter().cloned().collect();
    let mut text = crate::render_body(&shown, sources);
    for h in &hidden {
        text.push_str(&h.line());
        text.push('\n');
    }
    let errors = diagnostics.iter().filter(|d| d.is_error()).count();
    let warnings = diagnostics.len() - errors;
    let (more_e, more_w) = dropped
        .iter()
        .fold((0, 0), |(e, w), h| (e + h.errors, w + h.warnings));
    text.push_str(&crate::summary_counts(errors + more_e, warnings + more_w));
    text
}

/// One JSON line per shown diagnostic, then one [`Hidden::to_json_line`] per capped file.
pub fn json_lines_capped(diagnostics: &[Diagnostic], max: usize) -> String {
    json_lines_capped_with(diagnostics, &[], max)
}

/// [`json_lines_capped`] with `dropped`, what a [`crate::Sink`] only counted, in the notes.
pub fn json_lines_capped_with(
    diagnostics: &[Diagnostic],
    dropped: &[Hidden],
    max: usize,
) -> String {
    let (shown, mut hidden) = cap_per_file(diagnostics, max);
    crate::sink::merge_hidden(&mut hidden, dropped);
    let mut text = String::new();
    for d in shown {
        text.push_str(&d.to_json_line());
        text.push('\n');
    }
    for h in &hidden {
        text.push_str(&h.to_json_line());
        text.push('\n');
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    fn errors(file: &str, n: usize) -> Vec<Diagnostic> {
        (0..n)
            .map(|i| Diagnostic::error(7, file, i..i + 1, format!("bad {i}")))
            .collect()
    }

    #[test]
    fn cap_keeps_the_first_of_each_file_and_counts_the_rest() {
        let mut all = errors("AXCFIL", 5);
        all.push(Diagnostic::warning(9, "AXCFIL", 0..1, "w"));
        all.extend(errors("IOCFIL", 2));
        let (shown, hidden) = cap_per_file(&all, 3);
        let files: Vec<&str> = shown.iter().map(|d| d.file.as_str()).collect();
        assert_eq!(files, ["AXCFIL", "AXCFIL", "AXCFIL", "IOCFIL", "IOCFIL"]);
        assert_eq!(
            hidden,
            [Hidden {
                file: "AXCFIL".into(),
                errors: 2,
                warnings: 1
            }]
        );
        assert_eq!(
            hidden[0].line(),
            "note: 2 more errors and 1 more warning in AXCFIL (--max-errors 0 shows all)"
        );
        assert_eq!(
            hidden[0].to_json_line(),
            r#"{"file":"AXCFIL","more_errors":2,"more_warnings":1}"#
        );
        assert_eq!(cap_per_file(&all, 0).0.len(), 8);
    }

    #[test]
    fn capped_rendering_ends_with_the_note_and_the_full_count() {
        let all = errors("PLCPRG", 4);
        let text = render_human_capped(&all, &Sources::new(), 1);
        assert!(text.contains("bad 0"), "{text}");
        assert!(!text.contains("bad 1"), "{text}");
        assert!(
            text.ends_with(
                "note: 3 more errors in PLCPRG (--max-errors 0 shows all)\n4 errors, 0 warnings\n"
            ),
            "{text}"
        );
    }
}
