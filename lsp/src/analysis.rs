//! One open document and its analysis: the text as the editor has it, the compile of it against
//! its machine (the same [`compiler::compile_incremental`] path that gives `ncplc build`'s
//! diagnostics, reusing the parsed segments of the previous version) and the [`Index`] of names.
//!
//! Invariant: [`Document::analysis`] always describes the current text; an edit only marks it
//! stale, and it is recomputed on the next use (the server's debounce decides when that is for
//! diagnostics; a hover or completion after an edit recomputes at once). No text can make any of
//! this panic or loop: the compiler's front end is total and bounded, and every offset is clamped.

use std::sync::Arc;

use compiler::parse_cache::ParseCache;
use lsp_types::{DiagnosticSeverity, NumberOrString, TextDocumentContentChangeEvent};

use crate::index::Index;
use crate::machine::Machine;
use crate::text::Text;

/// The result of checking one version of a document.
#[derive(Debug, Clone)]
pub struct Analysis {
    /// Every error and warning, as `ncplc build` gives them (spans in [`Analysis::base`]-shifted text).
    pub diagnostics: Vec<diag::Diagnostic>,
    /// Names and places.
    pub index: Index,
    /// Bytes of a leading byte-order mark the compiler does not see (0 or 3): add to its spans.
    pub base: usize,
}

impl Analysis {
    /// A span of the compiler's text as a span of the document.
    pub fn to_doc(&self, s: &std::ops::Range<usize>) -> std::ops::Range<usize> {
        s.start + self.base..s.end + self.base
    }

    /// A document offset as an offset of the compiler's text.
    pub fn from_doc(&self, offset: usize) -> usize {
        offset.saturating_sub(self.base)
    }
}

/// An open PLC source.
#[derive(Debug)]
pub struct Document {
    /// The name diagnostics carry (the file's path).
    pub file_name: String,
    /// The text and its line index.
    pub text: Text,
    /// The editor's version number.
    pub version: i32,
    /// The machine it is checked against.
    pub machine: Arc<Machine>,
    cache: ParseCache,
    analysis: Option<Analysis>,
}

impl Document {
    /// A document with `text`, not yet analysed.
    pub fn new(file_name: String, text: String, version: i32, machine: Arc<Machine>) -> Self {
        Document {
            file_name,
            text: Text::new(text),
            version,
            machine,
            cache: ParseCache::new(),
            analysis: None,
        }
    }

    /// Applies the editor's changes (in order) and marks the analysis stale.
    pub fn edit(&mut self, version: i32, changes: &[TextDocumentContentChangeEvent]) {
        for c in changes {
            self.text.apply(c);
        }
        self.version = version;
        self.analysis = None;
    }

    /// True when the analysis is not of the current text.
    pub fn is_stale(&self) -> bool {
        self.analysis.is_none()
    }

    /// The analysis of the current text (computed now when stale).
    pub fn analysis(&mut self) -> &Analysis {
        let analysis = match self.analysis.take() {
            Some(a) => a,
            None => self.analyse(),
        };
        self.analysis.insert(analysis)
    }

    /// The current analysis with the text and machine it is of.
    pub fn parts(&mut self) -> (&Analysis, &Text, &Machine) {
        let analysis = match self.analysis.take() {
            Some(a) => a,
            None => self.analyse(),
        };
        let a = self.analysis.insert(analysis);
        (a, &self.text, &self.machine)
    }

    fn analyse(&mut self) -> Analysis {
        let text = self.text.as_str();
        let base = if text.starts_with('\u{FEFF}') { 3 } else { 0 };
        let (c, ast) = compiler::compile_incremental(
            &self.file_name,
            text,
            &self.machine.ctx,
            &mut self.cache,
        );
        Analysis {
            diagnostics: c.diagnostics,
            index: Index::new(&ast, &self.machine.ctx),
            base,
        }
    }

    /// The analysis's diagnostics for `textDocument/publishDiagnostics`.
    pub fn lsp_diagnostics(&mut self) -> Vec<lsp_types::Diagnostic> {
        self.analysis();
        let Some(a) = self.analysis.as_ref() else {
            return Vec::new();
        };
        a.diagnostics
            .iter()
            .map(|d| to_lsp(d, &self.text, a))
            .collect()
    }

    /// Segments of the last parse reused and parsed (for tests and benchmarks).
    pub fn parse_counts(&self) -> (usize, usize) {
        (self.cache.reused, self.cache.parsed)
    }
}

/// One compiler diagnostic as an LSP diagnostic: the code as a number, the hint after the message
/// as `ncplc build` prints it (`help: …`).
pub fn to_lsp(d: &diag::Diagnostic, text: &Text, a: &Analysis) -> lsp_types::Diagnostic {
    let message = if d.hint.is_empty() {
        d.message.clone()
    } else {
        format!("{}\nhelp: {}", d.message, d.hint)
    };
    lsp_types::Diagnostic {
        range: text.range(a.to_doc(&d.span)),
        severity: Some(if d.is_error() {
            DiagnosticSeverity::ERROR
        } else {
            DiagnosticSeverity::WARNING
        }),
        code: Some(NumberOrString::Number(
            i32::try_from(d.code).unwrap_or(i32::MAX),
        )),
        source: Some("ncplc".to_string()),
        message,
        ..lsp_types::Diagnostic::default()
    }
}
