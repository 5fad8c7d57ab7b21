//! Reading and validating AXCFIL (the manual's two-process example FX-46) and loading a whole
//! example machine directory (FCRSYS, AXCFIL, PGCFIL, IOCFIL) with `load_machine`.

use characterization::reader::read;
use characterization::{axcfil, load_machine};
use criterion::{Criterion, criterion_group, criterion_main};

fn bench(c: &mut Criterion) {
    let fx46 = include_bytes!("../tests/fixtures/FX-46.txt");
    c.bench_function("axcfil_fx46_read_and_validate", |b| {
        b.iter(|| {
            let (f, _) = read("AXCFIL", std::hint::black_box(fx46));
            axcfil::validate(&f)
        })
    });
    let lathe = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../plc-programs/lathe");
    c.bench_function("load_machine_lathe", |b| {
        b.iter(|| load_machine(std::hint::black_box(&lathe)))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
