//! Per-keystroke cost of the language server's analysis layer: diagnostics after a
//! one-character edit (the incremental parse, check and lowering) of the 10,000-statement
//! synthetic program and of the example lathe's program; hover and completion on the large one.
//! Targets (issue 26): ≤ 30 ms p95, ≤ 3 ms, and ≤ 10 ms p95. Besides criterion's means, the
//! bench prints the p50 and p95 of 200 timed runs of each kind (criterion reports no
//! percentiles), in wall-clock time and in the thread's CPU time (which a busy shared machine
//! inflates much less). Hover and completion run on a built index; the index is built by the
//! first request after an edit, measured as "edit, then hover".

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
        self.change();
        self.doc.lsp_diagnostics().len()
    }

    /// One edit of one character.
    fn change(&mut self) {
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
    }
}

/// The calling thread's CPU time: on a shared machine it leaves out the time the thread waited
/// for a core, which wall-clock time does not.
fn thread_cpu() -> Duration {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid timespec for the call to write.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID)");
    Duration::new(ts.tv_sec as u64, ts.tv_nsec as u32)
}

/// Runs `f` 200 times; prints the p50 and p95 of wall-clock and of thread CPU time.
fn percentiles(what: &str, mut f: impl FnMut()) {
    let (mut wall, mut cpu): (Vec<Duration>, Vec<Duration>) = (0..200)
        .map(|_| {
            let (s, c) = (Instant::now(), thread_cpu());
            f();
            (s.elapsed(), thread_cpu().saturating_sub(c))
        })
        .unzip();
    wall.sort();
    cpu.sort();
    eprintln!(
        "{what}: wall p50 {:?} p95 {:?}; thread CPU p50 {:?} p95 {:?} (200 runs)",
        wall[99], wall[189], cpu[99], cpu[189]
    );
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
    large.edit();
    let (reused, parsed) = large.doc.parse_counts();
    let (replayed, checked) = large.doc.check_counts();
    eprintln!(
        "10k program: a one-character edit reuses {reused} parsed segments and parses {parsed}; \
         replays {replayed} statement checks and checks {checked}"
    );
    percentiles(
        "diagnostics after a one-character edit, 10k statements",
        || {
            black_box(large.edit());
        },
    );
    percentiles(
        "diagnostics after a one-character edit, lathe program",
        || {
            black_box(small.edit());
        },
    );
    let hover_at = large.at;
    percentiles("hover, 10k statements", || {
        let (a, text, m) = large.doc.parts();
        black_box(plc_lsp::hover::hover(a, m, text, text.offset(hover_at)));
    });
    percentiles("completion, 10k statements", || {
        let (a, text, m) = large.doc.parts();
        black_box(plc_lsp::complete::complete(a, m, text, text.offset(hover_at)).len());
    });
    percentiles(
        "a one-character edit, then hover (compile and index), 10k statements",
        || {
            large.change();
            let (a, text, m) = large.doc.parts();
            black_box(plc_lsp::hover::hover(a, m, text, text.offset(hover_at)));
        },
    );

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
