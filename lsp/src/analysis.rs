//! One open document and its analysis: the text as the editor has it, its diagnostics against
//! its machine ([`compiler::diagnose_incremental`]: `ncplc build`'s front end reusing the parsed
//! segments and the statement checks of the previous version) and the [`Index`] of names.
//!
//! Invariant: [`Document::analysis`] always describes the current text; an edit only marks it
//! stale, and it is recomputed on the next use (the server's debounce decides when that is for
//! diagnostics; a hover or completion after an edit recomputes at once). No text can make any of
//! this panic or loop: the compiler's front end is total and bounded, and every offset is clamped.
//!
//! Per keystroke only the compile runs: the diagnostics of an edit need no [`Index`], so it is
//! built from the kept syntax tree when a request first needs it, and a large document's
//! superseded syntax tree and index are dropped on a helper thread ([`drop_elsewhere`]), not on
//! the path of the next diagnostics.

use std::sync::{Arc, Mutex, OnceLock, mpsc};

use compiler::parse_cache::ParseCache;
use compiler::sema::memo::CheckCache;
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
    checks: CheckCache,
    /// The compile of the current text, before its index is built.
    checked: Option<Checked>,
    analysis: Option<Analysis>,
}

/// The compile of one version: diagnostics and the syntax tree the [`Index`] is built from.
#[derive(Debug)]
struct Checked {
    diagnostics: Vec<diag::Diagnostic>,
    ast: compiler::ast::Program,
    base: usize,
}

/// The text size from which a document's trees are dropped on the helper thread: below it,
/// freeing them takes less than the hand-over (a wake-up of that thread per edit).
const DROP_ELSEWHERE_BYTES: usize = 32 * 1024;

/// Drops `value` on the one helper thread kept for this (inline when it cannot be started):
/// freeing the 10,000-statement program's syntax tree takes milliseconds nobody waits for.
pub fn drop_elsewhere<T: Send + 'static>(value: T) {
    type Garbage = Box<dyn Send>;
    static BIN: OnceLock<Option<Mutex<mpsc::Sender<Garbage>>>> = OnceLock::new();
    let bin = BIN.get_or_init(|| {
        let (tx, rx) = mpsc::channel::<Garbage>();
        std::thread::Builder::new()
            .name("plc-lsp-drop".into())
            .spawn(move || rx.into_iter().for_each(drop))
            .ok()
            .map(|_| Mutex::new(tx))
    });
    // A failed send hands the value back inside the error, which drops it here.
    if let Some(tx) = bin.as_ref().and_then(|m| m.lock().ok()) {
        let _ = tx.send(Box::new(value));
    }
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
            checks: CheckCache::new(),
            checked: None,
            analysis: None,
        }
    }

    /// Applies the editor's changes (in order) and marks the analysis stale.
    pub fn edit(&mut self, version: i32, changes: &[TextDocumentContentChangeEvent]) {
        for c in changes {
            self.text.apply(c);
        }
        self.version = version;
        let old = (self.checked.take(), self.analysis.take());
        if old.0.is_some() || old.1.is_some() {
            self.discard(old);
        }
    }

    /// Drops `value`, a syntax tree or index of this document: on the helper thread when the text
    /// is large, at once when it is small (handing it over would cost more than freeing it).
    fn discard<T: Send + 'static>(&self, value: T) {
        if self.text.as_str().len() >= DROP_ELSEWHERE_BYTES {
            drop_elsewhere(value);
        } else {
            drop(value);
        }
    }

    /// True when neither the diagnostics nor the analysis are of the current text.
    pub fn is_stale(&self) -> bool {
        self.analysis.is_none() && self.checked.is_none()
    }

    /// True when the index of the current text has been built (a request needed it).
    pub fn has_index(&self) -> bool {
        self.analysis.is_some()
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

    /// The analysis of the current text: its compile (done now unless the diagnostics already
    /// did it) and the index of its syntax tree.
    fn analyse(&mut self) -> Analysis {
        let c = match self.checked.take() {
            Some(c) => c,
            None => self.check(),
        };
        let index = Index::new(&c.ast, &self.machine.ctx);
        self.discard(c.ast);
        Analysis {
            diagnostics: c.diagnostics,
            index,
            base: c.base,
        }
    }

    /// Checks the current text (reusing the parse and check caches).
    fn check(&mut self) -> Checked {
        let text = self.text.as_str();
        let base = if text.starts_with('\u{FEFF}') { 3 } else { 0 };
        let (diagnostics, ast) = compiler::diagnose_incremental(
            &self.file_name,
            text,
            &self.machine.ctx,
            &mut self.cache,
            &mut self.checks,
        );
        Checked {
            diagnostics,
            ast,
            base,
        }
    }

    /// The current text's diagnostics for `textDocument/publishDiagnostics` (compiles it when
    /// stale, without building the index).
    pub fn lsp_diagnostics(&mut self) -> Vec<lsp_types::Diagnostic> {
        if self.analysis.is_none() && self.checked.is_none() {
            self.checked = Some(self.check());
        }
        let (diagnostics, base) = match (&self.analysis, &self.checked) {
            (Some(a), _) => (&a.diagnostics, a.base),
            (None, Some(c)) => (&c.diagnostics, c.base),
            (None, None) => return Vec::new(),
        };
        diagnostics
            .iter()
            .map(|d| to_lsp(d, &self.text, base))
            .collect()
    }

    /// Segments of the last parse reused and parsed (for tests and benchmarks).
    pub fn parse_counts(&self) -> (usize, usize) {
        (self.cache.reused, self.cache.parsed)
    }

    /// Statements of the last check replayed and checked (for tests and benchmarks).
    pub fn check_counts(&self) -> (usize, usize) {
        (self.checks.reused, self.checks.checked)
    }
}

/// One compiler diagnostic as an LSP diagnostic: the code as a number, the hint after the message
/// as `ncplc build` prints it (`help: …`).
/// `base` is [`Analysis::base`].
pub fn to_lsp(d: &diag::Diagnostic, text: &Text, base: usize) -> lsp_types::Diagnostic {
    let message = if d.hint.is_empty() {
        d.message.clone()
    } else {
        format!("{}\nhelp: {}", d.message, d.hint)
    };
    lsp_types::Diagnostic {
        range: text.range(d.span.start + base..d.span.end + base),
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

#[cfg(test)]
mod tests {
    use super::*;
    use lsp_types::{Position, Range};

    fn doc(text: &str) -> Document {
        let machine = Arc::new(Machine {
            dir: None,
            ctx: crate::machine::language_only(),
            plc_source: None,
            iocfil: None,
            note: None,
        });
        Document::new("PLCPRG".into(), text.into(), 0, machine)
    }

    #[test]
    fn diagnostics_need_no_index_and_requests_build_it_once() {
        let mut d = doc("DEF A = I0A1\nU4A0 = A * B\n");
        let diags = d.lsp_diagnostics();
        // `B` is undefined at line 2, column 12 (0-based 1:11 in LSP terms).
        assert_eq!(diags.len(), 1);
        assert_eq!(
            diags[0].range,
            Range::new(Position::new(1, 11), Position::new(1, 12))
        );
        assert!(!d.has_index() && !d.is_stale());
        let refs = d.analysis().index.refs.len();
        assert!(d.has_index());
        // A, I0A1 on line 1; U4A0, A, B on line 2.
        assert_eq!(refs, 5);
        // The diagnostics now come from the analysis, unchanged.
        assert_eq!(d.lsp_diagnostics(), diags);
        d.edit(
            1,
            &[TextDocumentContentChangeEvent {
                range: Some(Range::new(Position::new(1, 11), Position::new(1, 12))),
                range_length: None,
                text: "A".into(),
            }],
        );
        assert!(d.is_stale() && !d.has_index());
        assert_eq!(d.lsp_diagnostics(), Vec::new());
        assert!(!d.has_index());
    }
}
