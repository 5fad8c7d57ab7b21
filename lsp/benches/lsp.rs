//! Per-keystroke cost of the language server's analysis layer: diagnostics after a
//! one-character edit (the incremental parse, check and lowering) of the 10,000-statement
//! synthetic program and of the example lathe's program; hover and completion on the large one.
//! Targets (issue 26): ≤ 30 ms p95, ≤ 3 ms, and ≤ 10 ms p95. Besides criterion's means, the
//! bench prints the p95 of 200 timed edits of each kind (criterion reports no percentiles).

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

use std::hint::black_box;
use std::sync::Arc;
use std::time::{Duration, Instant};

use compiler::MachineContext;
use criterion::{Criterion, criterion_group, criterion_main};
use lsp_types::{Position, Range, TextDocumentContentChangeEvent};
use plc_lsp::analysis::Document;
use plc_lsp::machine::Machine;

fn machine(ctx: MachineContext) -> Arc<Machine> {
    Arc::new(Machine {
        dir: None,
        ctx,
        plc_source: None,
        iocfil: None,
        note: None,
    })
}

/// A document and the position of one character that toggles between two valid values.
struct Case {
    doc: Document,
    at: Position,
    flip: bool,
}

impl Case {
    fn new(text: String, needle: &str, ctx: MachineContext) -> Case {
        let mid = text.len() / 2;
        let found = text[mid..]
            .find(needle)
            .map(|i| mid + i)
            .or_else(|| text.find(needle));
        let i = found.expect("needle") + needle.len() - 1;
        let mut doc = Document::new("bench".into(), text, 0, machine(ctx));
        let at = doc.text.position(i);
        assert!(
            doc.lsp_diagnostics()
                .iter()
                .all(|d| d.severity != Some(lsp_types::DiagnosticSeverity::ERROR))
        );
        Case {
            doc,
            at,
            flip: false,
        }
    }

    /// One edit of one character, then the diagnostics.
    fn edit(&mut self) -> usize {
        self.flip = !self.flip;
        let c = if self.flip { "4" } else { "3" };
        let change = TextDocumentContentChangeEvent {
            range: Some(Range::new(
                self.at,
                Position::new(self.at.line, self.at.character + 1),
            )),
            range_length: None,
            text: c.to_string(),
        };
        self.doc.edit(1, &[change]);
        self.doc.lsp_diagnostics().len()
    }
}

fn p95(mut f: impl FnMut()) -> Duration {
    let mut t: Vec<Duration> = (0..200)
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed()
        })
        .collect();
    t.sort();
    t[189]
}

fn big_ctx() -> MachineContext {
    MachineContext {
        spl: 5000,
        ..MachineContext::lathe_like()
    }
}

fn lathe() -> String {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../plc-programs/lathe/MP0/PLCPRG"
    ))
    .expect("the lathe program")
}

fn bench(c: &mut Criterion) {
    let big = compiler::synth::synthetic_program(10_000);
    let mut large = Case::new(big.clone(), ") * 3", big_ctx());
    let mut small = Case::new(lathe(), "FOV = 10", lathe_ctx());
    let (reused, parsed) = {
        large.edit();
        large.doc.parse_counts()
    };
    eprintln!(
        "10k program: a one-character edit reuses {reused} parsed segments and parses {parsed}"
    );
    eprintln!(
        "p95 of 200: diagnostics after a one-character edit, 10k statements: {:?}",
        p95(|| {
            black_box(large.edit());
        })
    );
    eprintln!(
        "p95 of 200: diagnostics after a one-character edit, lathe program: {:?}",
        p95(|| {
            black_box(small.edit());
        })
    );
    let hover_at = large.at;
    let p = p95(|| {
        let (a, text, m) = large.doc.parts();
        black_box(plc_lsp::hover::hover(a, m, text, text.offset(hover_at)));
    });
    eprintln!("p95 of 200: hover, 10k statements: {p:?}");
    let p = p95(|| {
        let (a, text, m) = large.doc.parts();
        black_box(plc_lsp::complete::complete(a, m, text, text.offset(hover_at)).len());
    });
    eprintln!("p95 of 200: completion, 10k statements: {p:?}");

    let mut g = c.benchmark_group("lsp");
    g.sample_size(20);
    g.bench_function("diagnostics_after_edit_10k", |b| b.iter(|| large.edit()));
    g.bench_function("diagnostics_after_edit_lathe", |b| b.iter(|| small.edit()));
    g.bench_function("hover_10k", |b| {
        b.iter(|| {
            let (a, text, m) = large.doc.parts();
            plc_lsp::hover::hover(a, m, text, text.offset(hover_at))
        })
    });
    g.bench_function("completion_10k", |b| {
        b.iter(|| {
            let (a, text, m) = large.doc.parts();
            plc_lsp::complete::complete(a, m, text, text.offset(hover_at)).len()
        })
    });
    g.finish();
}

fn lathe_ctx() -> MachineContext {
    Machine::for_file(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../plc-programs/lathe/MP0/PLCPRG"
    )))
    .ctx
}

criterion_group!(benches, bench);
criterion_main!(benches);
