//! Random text as a PLC program through the front end (issue 12: bounded work on any input;
//! target ≤ 2 s release): 2 MiB, the largest source the front end reads
//! ([`compiler::MAX_SOURCE_BYTES`]; 50 MB until the limit, whose refusal costs nothing).

use compiler::{MachineContext, compile};
use criterion::{Criterion, criterion_group, criterion_main};

fn bench(c: &mut Criterion) {
    let text = diag::random_text(compiler::MAX_SOURCE_BYTES, 12);
    let ctx = MachineContext::lathe_like();
    let mut g = c.benchmark_group("random_text");
    g.sample_size(10);
    g.bench_function("plc_2mib", |b| {
        b.iter(|| {
            compile("PLCPRG", std::hint::black_box(&text), &ctx)
                .diagnostics
                .len()
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
