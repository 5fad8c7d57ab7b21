//! 50 MB of random text as an io.toml through the I/O-map validation (issue 12: bounded work on
//! any input; target ≤ 2 s release).

use criterion::{Criterion, criterion_group, criterion_main};
use fieldbus::{DeclaredConnectors, parse_map};

fn bench(c: &mut Criterion) {
    let bytes = diag::random_text(50_000_000, 12);
    let text = String::from_utf8_lossy(&bytes).into_owned();
    let declared = DeclaredConnectors::default();
    let mut g = c.benchmark_group("random_text");
    g.sample_size(10);
    g.bench_function("io_toml_50mb", |b| {
        b.iter(|| {
            parse_map(std::hint::black_box(&text), "io.toml", &declared)
                .1
                .len()
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
