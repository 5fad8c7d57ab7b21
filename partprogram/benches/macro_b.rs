//! Benchmark: a Fanuc Macro B loop of 10,000 iterations planned with the native back end against the
//! reference interpreter (target ≥ 10× faster native).

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use partprogram::{Backend, Dialect, MachineSpec, PlanOptions, compile, plan};

/// 10,000 passes of a loop with arithmetic, a function, a comparison and a conditional assignment.
pub const LOOP: &str = include_str!("macro/loop.nc");

/// The same loop with arithmetic and comparisons only (no host functions).
pub const ARITH: &str = include_str!("macro/arith.nc");

/// 10,000 passes writing and reading a table through computed variable numbers (`#[…]`).
pub const INDEXED: &str = include_str!("macro/indexed.nc");

fn bench_macro_loop(c: &mut Criterion) {
    let m = MachineSpec::new(Dialect::Fanuc, &['X', 'Y', 'Z']);
    let mut g = c.benchmark_group("macro_b");
    g.sample_size(10);
    for (name, src, backend) in [
        ("native_10k_loop", LOOP, Backend::Native),
        ("interpreter_10k_loop", LOOP, Backend::Interpreter),
        ("native_10k_arith", ARITH, Backend::Native),
        ("interpreter_10k_arith", ARITH, Backend::Interpreter),
        ("native_10k_indexed", INDEXED, Backend::Native),
        ("interpreter_10k_indexed", INDEXED, Backend::Interpreter),
    ] {
        let (prog, diags) = compile(&m, "loop", src);
        let prog = prog.unwrap_or_else(|| panic!("{diags:?}"));
        g.bench_function(name, |b| {
            b.iter(|| {
                let p = plan(
                    &prog,
                    PlanOptions {
                        backend,
                        ..PlanOptions::default()
                    },
                );
                black_box(p.map(|p| p.executed).unwrap_or(0))
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench_macro_loop);
criterion_main!(benches);
