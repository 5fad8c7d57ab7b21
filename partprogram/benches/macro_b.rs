//! Benchmark: a Fanuc Macro B loop of 10,000 iterations planned with the native back end against the
//! reference interpreter (target ≥ 10× faster native).

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use partprogram::{Backend, Dialect, MachineSpec, PlanOptions, compile, plan};

/// 10,000 passes of a loop with arithmetic, a function, a comparison and a conditional assignment.
pub const LOOP: &str = "O1
#1 = 0
#2 = 0
#3 = 0
WHILE [#1 LT 10000] DO1
#2 = #2 + [#1 * 0.5 - 3] / 7
#3 = #3 + ABS[#2] MOD 5
IF [#2 GT 1000] THEN #2 = #2 - 1000
#1 = #1 + 1
END1
G00 X[#2 / 100]
M30
";

/// The same loop with arithmetic and comparisons only (no host functions).
pub const ARITH: &str = "O1
#1 = 0
#2 = 0
#3 = 0
WHILE [#1 LT 10000] DO1
#2 = #2 + [#1 * 0.5 - 3] / 7
#3 = #3 + #2 * 2
IF [#2 GT 1000] THEN #2 = #2 - 1000
#1 = #1 + 1
END1
G00 X[#2 / 100]
M30
";

fn bench_macro_loop(c: &mut Criterion) {
    let m = MachineSpec::new(Dialect::Fanuc, &['X', 'Y', 'Z']);
    let mut g = c.benchmark_group("macro_b");
    g.sample_size(10);
    for (name, src, backend) in [
        ("native_10k_loop", LOOP, Backend::Native),
        ("interpreter_10k_loop", LOOP, Backend::Interpreter),
        ("native_10k_arith", ARITH, Backend::Native),
        ("interpreter_10k_arith", ARITH, Backend::Interpreter),
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
