//! Compile-time profile of the generated 10,000-statement program: front-end phases, CLIF size
//! and JIT time at 1 and 2 threads. `cargo run --release -p compiler --example compile_profile
//! -- [statements] [repeats] [what]` (`what`: all, front, front2, e2e, jit1, jit2, clif, source, edit); also the callgrind target.

/// The allocator of the `ncplc` binary, so the figures are what the tool does.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

use std::time::Instant;

use compiler::jit::{self, JitOptions};
use compiler::{MachineContext, compile, synth::synthetic_program};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(10_000);
    let reps: usize = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(5);
    let what = args.get(3).map_or("all", String::as_str);
    let src = synthetic_program(n);
    let ctx = MachineContext {
        spl: 5000,
        ..MachineContext::lathe_like()
    };
    // Best of `reps` runs; `PROFILE_MEDIAN=1` prints the median as well.
    let best = |f: &mut dyn FnMut()| {
        let mut t: Vec<f64> = (0..reps)
            .map(|_| {
                let t = Instant::now();
                f();
                t.elapsed().as_secs_f64() * 1e3
            })
            .collect();
        t.sort_by(f64::total_cmp);
        if std::env::var_os("PROFILE_MEDIAN").is_some() {
            eprintln!("  median {:.2} ms", t[t.len() / 2]);
        }
        t.first().copied().unwrap_or(f64::NAN)
    };
    if what == "source" {
        // The generated program itself, e.g. for `ncplc build --plc` on a machine.
        print!("{src}");
        return;
    }
    let c = compile("bench", src.as_bytes(), &ctx);
    let Some(p) = c.program else {
        eprintln!("does not compile: {:?}", c.diagnostics.first());
        std::process::exit(1);
    };
    let stmts = p.statement_count();
    if what == "front2" {
        for _ in 0..reps {
            std::hint::black_box(compiler::compile_with_threads(
                "bench",
                src.as_bytes(),
                &ctx,
                2,
            ));
        }
        return;
    }
    if what == "clif" {
        print!("{}", jit::emit_clif(&p).expect("clif"));
        return;
    }
    if matches!(what, "all" | "front") {
        let lex = best(&mut || {
            std::hint::black_box(compiler::lexer::tokenize(&src).0.len());
        });
        let parse = best(&mut || {
            std::hint::black_box(compiler::parser::parse("bench", &src).0.fast.len());
        });
        let front = best(&mut || {
            std::hint::black_box(compile("bench", src.as_bytes(), &ctx));
        });
        let front2 = best(&mut || {
            std::hint::black_box(compiler::compile_with_threads(
                "bench",
                src.as_bytes(),
                &ctx,
                2,
            ));
        });
        println!(
            "lex {lex:.2} ms, lex+parse {parse:.2} ms, front end {front:.2} ms (2 threads {front2:.2} ms)"
        );
    }
    for (name, threads) in [("jit1", 1), ("jit2", 2)] {
        if what == "all" || what == name {
            let chunk_cost = std::env::var("CHUNK_COST")
                .ok()
                .and_then(|c| c.parse().ok())
                .unwrap_or(JitOptions::default().chunk_cost);
            let opts = JitOptions {
                threads,
                chunk_cost,
                ..JitOptions::default()
            };
            let t = best(&mut || {
                std::hint::black_box(jit::compile_with(&p, &opts).expect("jit"));
            });
            println!("JIT {threads} thread(s) {t:.2} ms");
        }
    }
    if matches!(what, "all" | "edit") {
        // An online change: one statement inserted a third into the source, front end and JIT on
        // one thread, the JIT reusing the code of the unchanged functions (`CodeCache`).
        let mut lines: Vec<&str> = src.lines().collect();
        let at = lines.len() / 3;
        lines.insert(at, "V7 = V7 + 1");
        let edited = lines.join("\n") + "\n";
        let opts = JitOptions::default();
        let mut cache = jit::CodeCache::new();
        let mut times: Vec<f64> = (0..reps)
            .map(|_| {
                // Every repetition starts from the unedited program's code.
                cache = jit::CodeCache::new();
                jit::compile_cached(&p, &opts, &mut cache).expect("jit");
                let t = Instant::now();
                let c = compile("bench", edited.as_bytes(), &ctx);
                let p = c.program.expect("compiles");
                std::hint::black_box(jit::compile_cached(&p, &opts, &mut cache).expect("jit"));
                t.elapsed().as_secs_f64() * 1e3
            })
            .collect();
        times.sort_by(f64::total_cmp);
        let t = times[times.len() / 2];
        println!(
            "online change (1 thread, cached): median {t:.2} ms, {} functions compiled, {} reused",
            cache.compiled(),
            cache.reused()
        );
    }
    if matches!(what, "all" | "e2e") {
        for threads in [1, 2] {
            let opts = JitOptions {
                threads,
                ..JitOptions::default()
            };
            let t = best(&mut || {
                let c = compiler::compile_with_threads("bench", src.as_bytes(), &ctx, threads);
                let p = c.program.expect("compiles");
                std::hint::black_box(jit::compile_with(&p, &opts).expect("jit"));
            });
            println!("front end + JIT, {threads} thread(s): {t:.2} ms");
        }
    }
    if what == "all" {
        let st = jit::clif_stats(&p, &JitOptions::default()).expect("clif");
        println!(
            "{stmts} statements, {} functions, {} blocks, {} CLIF insts ({:.2} per statement)",
            st.functions,
            st.blocks,
            st.insts,
            st.insts as f64 / stmts as f64
        );
    }
}
