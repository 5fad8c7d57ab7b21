//! 50 MB of random text and of random bytes as a trace through `Trace::from_bytes`, what
//! `ncplc trace dump` and `replay` read (issue 12: bounded work on any input; ≤ 2 s release).

use criterion::{Criterion, criterion_group, criterion_main};
use trace::Trace;

fn bench(c: &mut Criterion) {
    let text = diag::random_text(50_000_000, 12);
    let mut g = c.benchmark_group("random_text");
    g.sample_size(10);
    g.bench_function("trace_50mb", |b| {
        b.iter(|| Trace::from_bytes(std::hint::black_box(&text)).is_err())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
