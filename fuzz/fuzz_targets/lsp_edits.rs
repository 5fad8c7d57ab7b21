#![no_main]
//! Random edit sequences through the language server's document and analysis layer never panic
//! or hang, and after every edit the incremental analysis gives exactly the diagnostics a full
//! compile of the same text gives, and hover, completion, references, definition, rename and
//! symbols at the edited place answer without panicking; on the last text semantic tokens answer,
//! and formatting is idempotent and changes no diagnostic.
//!
//! Input: two bytes choosing the document, a window of the example lathe's or mill's program
//! (first byte: which program, bit 0, and the first line; second byte: 1 to 64 lines), then a
//! sequence of edits, each `line, column, deleted characters, inserted length` (one byte each)
//! followed by that many bytes (lossily UTF-8). Every pass of an edit reads the whole document,
//! so a window keeps an execution cheap (the whole lathe program cost ~0.5 ms per edit) while
//! the windows together still hold every construct of both programs.
use std::sync::Arc;

use lsp_types::{Position, Range, TextDocumentContentChangeEvent};
use plc_lsp::analysis::Document;
use plc_lsp::machine::Machine;

const PROGRAMS: [&str; 2] = [
    include_str!("../../plc-programs/lathe/MP0/PLCPRG"),
    include_str!("../../plc-programs/mill/MP0/PLCPRG"),
];

/// The machine, built once (parsing the built-in interface map per input was most of an
/// execution).
static MACHINE: std::sync::LazyLock<Arc<Machine>> = std::sync::LazyLock::new(|| {
    Arc::new(Machine {
        dir: None,
        ctx: compiler::MachineContext::lathe_like(),
        plc_source: None,
        iocfil: None,
        note: None,
    })
});

/// Lines `first..first + n` of program `which` (clamped), each with its line end.
fn window(which: u8, first: u8, n: u8) -> String {
    let src = PROGRAMS[usize::from(which & 1)];
    let lines: Vec<&str> = src.split_inclusive('\n').collect();
    let start = usize::from(first) * lines.len() / 128;
    let end = (start + 1 + usize::from(n % 64)).min(lines.len());
    lines[start.min(lines.len())..end].concat()
}

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let [head, lines, edits @ ..] = data else {
        return;
    };
    let mut rest = edits;
    let machine = Arc::clone(&MACHINE);
    let base = window(*head, *head >> 1, *lines);
    let mut doc = Document::new("fuzz".into(), base, 0, machine.clone());
    let mut version = 0;
    while let [line, col, del, len, tail @ ..] = rest {
        let n = usize::from(*len).min(tail.len());
        let text = String::from_utf8_lossy(&tail[..n]).into_owned();
        rest = &tail[n..];
        let start = Position::new(u32::from(*line) % 72, u32::from(*col));
        let end = Position::new(start.line, start.character + u32::from(*del));
        version += 1;
        doc.edit(
            version,
            &[TextDocumentContentChangeEvent {
                range: Some(Range::new(start, end)),
                range_length: None,
                text,
            }],
        );
        let got = doc.lsp_diagnostics().len();
        let full = compiler::compile("fuzz", doc.text.as_str().as_bytes(), &machine.ctx);
        assert_eq!(got, full.diagnostics.len());
        let offset = doc.text.offset(start);
        let (a, text, m) = doc.parts();
        assert_eq!(
            a.diagnostics
                .iter()
                .map(|d| (d.code, d.span.clone()))
                .collect::<Vec<_>>(),
            full.diagnostics
                .iter()
                .map(|d| (d.code, d.span.clone()))
                .collect::<Vec<_>>()
        );
        let _ = plc_lsp::hover::hover(a, m, text, offset);
        let _ = plc_lsp::complete::complete(a, m, text, offset);
        let _ = plc_lsp::navigate::references(a, offset, true);
        let _ = plc_lsp::navigate::definition(a, m, offset);
        let _ = plc_lsp::navigate::rename(a, m, offset, "NEW_NAME");
        let _ = plc_lsp::navigate::document_symbols(a, text.as_str().len());
    }
    // The passes over the whole text, on the text the edits end with (each earlier text is the
    // last one of a shorter input).
    let text = doc.text.as_str();
    let _ = plc_lsp::tokens::semantic_tokens(&doc.text);
    let f = plc_lsp::format::format(text);
    assert_eq!(plc_lsp::format::format(&f), f);
    // Layout only: the formatted text has the same diagnostics (columns move).
    let codes = |t: &str| {
        compiler::compile("fuzz", t.as_bytes(), &machine.ctx)
            .diagnostics
            .iter()
            .map(|d| d.code)
            .collect::<Vec<_>>()
    };
    assert_eq!(codes(&f), codes(text), "{f}");
});
