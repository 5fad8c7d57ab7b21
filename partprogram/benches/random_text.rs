//! 50 MB of random text as a MEFI partprogram through `compile` (issue 12: bounded work on any
//! input; target ≤ 2 s release).

use criterion::{Criterion, criterion_group, criterion_main};
use partprogram::machine::{Dialect, MachineSpec};

fn bench(c: &mut Criterion) {
    let bytes = diag::random_text(50_000_000, 12);
    let text = String::from_utf8_lossy(&bytes).into_owned();
    let spec = MachineSpec::new(Dialect::Mefi, &['X', 'Y', 'Z']);
    let mut g = c.benchmark_group("random_text");
    g.sample_size(10);
    g.bench_function("partprogram_50mb", |b| {
        b.iter(|| {
            partprogram::compile(&spec, "nc/R", std::hint::black_box(&text))
                .1
                .len()
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
