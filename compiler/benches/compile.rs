//! Compile-time benchmark: a generated 10,000-statement program through parse + check
//! (`compile`) and through parse + check + cranelift JIT, on one thread (what an online change
//! uses) and on two (parse and JIT; a first load on a 2-core machine). Target: ≤ 100 ms in release.
//! `online_change_1_thread_cached`: the same program with one statement inserted, front end and
//! JIT on one thread, the JIT reusing the unedited program's code (`CodeCache`, as `ncplc run`).

/// The allocator of the `ncplc` binary, so the figures are what the tool does.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

use std::hint::black_box;

use compiler::{MachineContext, compile, compile_with_threads, synth::synthetic_program};
use criterion::{Criterion, criterion_group, criterion_main};

fn bench_compile(c: &mut Criterion) {
    let src = synthetic_program(10_000);
    let ctx = MachineContext {
        spl: 5000,
        ..MachineContext::lathe_like()
    };
    let mut group = c.benchmark_group("compile_10k");
    group.sample_size(10);
    group.bench_function("lex", |b| {
        b.iter(|| compiler::lexer::tokenize(black_box(&src)).0.len())
    });
    group.bench_function("parse", |b| {
        b.iter(|| {
            compiler::parser::parse("bench", black_box(&src))
                .0
                .fast
                .len()
        })
    });
    group.bench_function("parse_check_lower", |b| {
        b.iter(|| {
            let c = compile("bench", black_box(src.as_bytes()), &ctx);
            assert!(c.program.is_some());
            c
        })
    });
    for threads in [1, 2] {
        let opts = compiler::jit::JitOptions {
            threads,
            ..compiler::jit::JitOptions::default()
        };
        let name = format!("parse_check_lower_jit_{threads}_thread");
        group.bench_function(&name, |b| {
            b.iter(|| {
                let c = compile_with_threads("bench", black_box(src.as_bytes()), &ctx, threads);
                let p = c.program.expect("the synthetic program compiles");
                compiler::jit::compile_with(&p, &opts).expect("JIT compiles")
            })
        });
    }
    let mut lines: Vec<&str> = src.lines().collect();
    lines.insert(lines.len() / 3, "V7 = V7 + 1");
    let edited = lines.join("\n") + "\n";
    let opts = compiler::jit::JitOptions::default();
    let old = compile("bench", src.as_bytes(), &ctx)
        .program
        .expect("the synthetic program compiles");
    group.bench_function("online_change_1_thread_cached", |b| {
        b.iter_batched(
            || {
                let mut cache = compiler::jit::CodeCache::new();
                let jit = compiler::jit::compile_cached(&old, &opts, &mut cache).expect("JIT");
                (cache, jit)
            },
            |(mut cache, running)| {
                let c = compile("bench", black_box(edited.as_bytes()), &ctx);
                let p = c.program.expect("the edited program compiles");
                let new = compiler::jit::compile_cached(&p, &opts, &mut cache).expect("JIT");
                (new, running)
            },
            criterion::BatchSize::PerIteration,
        )
    });
    group.finish();
}

criterion_group!(benches, bench_compile);
criterion_main!(benches);
