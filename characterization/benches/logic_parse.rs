//! Decoding speed of PGCFIL and IOCFIL: the manual's examples, read and decoded.

use characterization::reader::{Grammar, read, read_with};
use characterization::{iocfil, pgcfil};
use criterion::{Criterion, criterion_group, criterion_main};

fn bench(c: &mut Criterion) {
    let pg = include_bytes!("../tests/fixtures/pgcfil_nc110.txt");
    let io = include_bytes!("../tests/fixtures/iocfil_example.txt");
    c.bench_function("pgcfil_nc110_read_and_parse", |b| {
        b.iter(|| {
            let (f, _) = read_with("PGCFIL", std::hint::black_box(pg), Grammar::PGCFIL);
            pgcfil::parse(&f)
        })
    });
    c.bench_function("iocfil_example_read_and_parse", |b| {
        b.iter(|| {
            let (f, _) = read("IOCFIL", std::hint::black_box(io));
            iocfil::parse(&f)
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
