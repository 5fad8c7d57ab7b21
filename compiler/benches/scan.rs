//! Scan-time and compile-time benchmarks on a generated 10,000-statement program: the JIT's tick
//! against the interpreter's and against gcc -O2 on the same program emitted as C
//! ([`compiler::cgen`]), the front end, and JIT compile time under several cranelift settings.

#[path = "support/gcc_scan.rs"]
mod gcc_scan;
#[path = "support/scan_source.rs"]
mod scan_source;

/// The allocator of the `ncplc` binary, so the figures are what the tool does.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

use std::hint::black_box;
use std::sync::Arc;

use compiler::jit::{self, JitOptions};
use compiler::{Engine, Interpreter, MachineContext, compile};
use criterion::{Criterion, criterion_group, criterion_main};

fn program(n: usize) -> compiler::ir::Program {
    let src = scan_source::source(n);
    let c = compile("bench", src.as_bytes(), &MachineContext::lathe_like());
    match c.program {
        Some(p) => p,
        None => panic!(
            "generated program does not compile: {:?}",
            c.diagnostics.first()
        ),
    }
}

fn scan(c: &mut Criterion) {
    let p = Arc::new(program(10_000));
    let mut g = c.benchmark_group("scan_10k");
    let mut interp = Interpreter::new(p.clone());
    let mut jit = jit::compile(&p).expect("jit");
    let speed = JitOptions {
        opt_level: "speed",
        ..JitOptions::default()
    };
    let mut jit_speed = jit::compile_with(&p, &speed).expect("jit");
    let engines: [(&str, &mut dyn Engine); 3] = [
        ("interp", &mut interp),
        ("jit", &mut jit),
        ("jit_opt_speed", &mut jit_speed),
    ];
    for (name, engine) in engines {
        let mut image = p.new_image();
        let mut t = 0u8;
        g.bench_function(name, |b| {
            b.iter(|| {
                t = t.wrapping_add(1);
                image[0] = t;
                image[128 + 12] = t & 0x9F;
                engine.tick(black_box(&mut image));
            })
        });
    }
    match gcc_scan::GccScan::build(&compiler::cgen::emit_c(&p), &["-O2"]) {
        Ok(native) => {
            same_images_as_the_interpreter(&p, &native);
            let mut image = p.new_image();
            let mut t = 0u8;
            g.bench_function("gcc_O2", |b| {
                b.iter(|| {
                    t = t.wrapping_add(1);
                    image[0] = t;
                    image[128 + 12] = t & 0x9F;
                    native.tick(black_box(&mut image));
                })
            });
        }
        Err(e) => eprintln!("scan_10k/gcc_O2 skipped: {e}"),
    }
    g.finish();
}

/// The gcc build must produce the interpreter's images, tick for tick, under the benchmark's inputs.
fn same_images_as_the_interpreter(p: &Arc<compiler::ir::Program>, native: &gcc_scan::GccScan) {
    let mut interp = Interpreter::new(p.clone());
    let (mut a, mut c) = (p.new_image(), p.new_image());
    for t in 1..=600u32 {
        for image in [&mut a, &mut c] {
            image[0] = t as u8;
            image[128 + 12] = t as u8 & 0x9F;
        }
        interp.tick(&mut a);
        native.tick(&mut c);
        assert!(
            a == c,
            "tick {t}: the gcc build departs from the interpreter"
        );
    }
}

fn compile_time(c: &mut Criterion) {
    let src = scan_source::source(10_000);
    let ctx = MachineContext::lathe_like();
    let p = program(10_000);
    let mut g = c.benchmark_group("compile_10k");
    g.sample_size(10);
    g.bench_function("front_end", |b| {
        b.iter(|| compile("bench", black_box(src.as_bytes()), &ctx))
    });
    let opts = |opt_level, regalloc, chunk_cost, threads| JitOptions {
        opt_level,
        regalloc,
        chunk_cost,
        threads,
        ..JitOptions::default()
    };
    let variants = [
        (
            "jit_default_none_single_pass_2000_1_thread",
            JitOptions::default(),
        ),
        (
            "jit_none_single_pass_2000_auto_threads",
            opts("none", "single_pass", 2000, 0),
        ),
        (
            "jit_none_backtracking_2000",
            opts("none", "backtracking", 2000, 0),
        ),
        (
            "jit_speed_single_pass_2000",
            opts("speed", "single_pass", 2000, 0),
        ),
        (
            "jit_none_single_pass_250",
            opts("none", "single_pass", 250, 0),
        ),
    ];
    for (name, opts) in variants {
        g.bench_function(name, |b| {
            b.iter(|| jit::compile_with(black_box(&p), &opts).expect("jit"))
        });
    }
    g.bench_function("front_end_plus_jit", |b| {
        b.iter(|| {
            let c = compile("bench", black_box(src.as_bytes()), &ctx);
            c.program.map(|p| jit::compile(&p).expect("jit"))
        })
    });
    g.finish();
}

criterion_group!(benches, scan, compile_time);
criterion_main!(benches);
