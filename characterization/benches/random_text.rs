//! 50 MB of random text as an AXCFIL through the reader and, when it reads on, the validator
//! (issue 12: bounded work on any input; target ≤ 2 s release).

use characterization::axcfil;
use characterization::reader::read;
use criterion::{Criterion, criterion_group, criterion_main};

fn bench(c: &mut Criterion) {
    let text = diag::random_text(50_000_000, 12);
    let mut g = c.benchmark_group("random_text");
    g.sample_size(10);
    g.bench_function("axcfil_50mb", |b| {
        b.iter(|| {
            let (f, d) = read("AXCFIL", std::hint::black_box(&text));
            if f.abandoned {
                d.len()
            } else {
                d.len() + axcfil::validate(&f).1.len()
            }
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
