//! 50 MB of random text as a PLC program through the front end (issue 12: bounded work on any
//! input; target ≤ 2 s release).

use compiler::{MachineContext, compile};
use criterion::{Criterion, criterion_group, criterion_main};

fn bench(c: &mut Criterion) {
    let text = diag::random_text(50_000_000, 12);
    let ctx = MachineContext::lathe_like();
    let mut g = c.benchmark_group("random_text");
    g.sample_size(10);
    g.bench_function("plc_50mb", |b| {
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
