//! Scan-code profile of the scan benchmark's 10,000-statement program (the callgrind target for
//! the JIT-vs-gcc comparison): `cargo run -p compiler --example scan_profile -- <engine> [ticks]
//! [statements]` with `engine` one of `interp`, `jit` (default options), `jit-speed`
//! (`opt_level=speed`), `jit-flow` (the program instrumented for an HMI's power flow,
//! `compiler::ir::flow`), `gcc` (the program emitted as C, `gcc -O2`), `all` (the JIT and gcc timed
//! in alternating rounds of `ticks` ticks, best round each), `text` (the JIT's machine code into
//! `scan_profile.text`, for `objdump -b binary -m i386:x86-64 -D`), `clif` (print the cranelift
//! IR), `c` (print the C). Run under `valgrind --tool=callgrind --toggle-collect='*run_ticks*'`
//! so that only the ticks are counted; prints a checksum of the final image.

#[path = "../benches/support/gcc_scan.rs"]
mod gcc_scan;
#[path = "../benches/support/scan_source.rs"]
mod scan_source;

use std::hint::black_box;
use std::sync::Arc;

use compiler::jit::{self, JitOptions};
use compiler::{Engine, Interpreter, MachineContext, compile};

/// One engine's tick over an image.
type Tick<'a> = &'a mut dyn FnMut(&mut [u8]);

/// The benchmark's inputs for `ticks` ticks (the same as `benches/scan.rs`).
#[inline(never)]
fn run_ticks(tick: &mut dyn FnMut(&mut [u8]), image: &mut [u8], ticks: u32) {
    for t in 1..=ticks {
        image[0] = t as u8;
        image[128 + 12] = t as u8 & 0x9F;
        tick(black_box(image));
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let what = args.get(1).map_or("jit", String::as_str);
    let ticks: u32 = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(1000);
    let n: usize = args.get(3).and_then(|a| a.parse().ok()).unwrap_or(10_000);
    let src = scan_source::source(n);
    let c = compile("bench", src.as_bytes(), &MachineContext::lathe_like());
    let Some(p) = c.program else {
        eprintln!("does not compile: {:?}", c.diagnostics.first());
        std::process::exit(1);
    };
    let p = Arc::new(p);
    let mut image = p.new_image();
    let speed = speed_options();
    match what {
        "interp" => {
            let mut e = Interpreter::new(p.clone());
            run_ticks(&mut |i| e.tick(i), &mut image, ticks);
        }
        "jit-flow" => {
            let (f, _) = compiler::ir::flow::instrument(&p).expect("instruments");
            let f = Arc::new(f);
            image = f.new_image();
            let mut e = jit::compile(&f).expect("jit");
            run_ticks(&mut |i| e.tick(i), &mut image, ticks);
        }
        "jit" | "jit-speed" => {
            let opts = if what == "jit" {
                JitOptions::default()
            } else {
                speed
            };
            let mut e = jit::compile_with(&p, &opts).expect("jit");
            run_ticks(&mut |i| e.tick(i), &mut image, ticks);
        }
        "gcc" => {
            let e = gcc_scan::GccScan::build(&compiler::cgen::emit_c(&p), &["-O2"]).expect("gcc");
            run_ticks(&mut |i| e.tick(i), &mut image, ticks);
        }
        "all" => side_by_side(&p, ticks),
        "ctime" => compile_times(&p),
        "text" => {
            let e = jit::compile_with(&p, &speed).expect("jit");
            std::fs::write("scan_profile.text", e.machine_code()).expect("write");
        }
        "clif" => print!("{}", jit::emit_clif(&p).expect("clif")),
        "c" => print!("{}", compiler::cgen::emit_c(&p)),
        other => {
            eprintln!("unknown engine {other}");
            std::process::exit(2);
        }
    }
    let sum = image.iter().fold(0u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x100_0000_01B3)
    });
    println!("{what}: {ticks} ticks, image checksum {sum:016x}");
}

/// The second JIT's settings (`jit-speed`, `text` and the second column of `all`), from
/// `SCAN_OPT` (default `speed`), `SCAN_RA` (default `single_pass`) and `SCAN_WINDOW` (default 1).
fn speed_options() -> JitOptions {
    let env = |k: &str, d: &'static str| -> &'static str {
        std::env::var(k).map_or(d, |v| Box::leak(v.into_boxed_str()))
    };
    JitOptions {
        opt_level: env("SCAN_OPT", "speed"),
        regalloc: env("SCAN_RA", "single_pass"),
        cache_window: env("SCAN_WINDOW", "1").parse().unwrap_or(1),
        ..JitOptions::default()
    }
}

/// The JIT (default and `speed`) and gcc -O2 timed in alternating rounds; prints the best round's
/// time per tick of each and the JIT/gcc ratio.
fn side_by_side(p: &Arc<compiler::ir::Program>, ticks: u32) {
    let mut jit = jit::compile(p).expect("jit");
    let mut jit_speed = jit::compile_with(p, &speed_options()).expect("jit");
    let gcc = gcc_scan::GccScan::build(&compiler::cgen::emit_c(p), &["-O2"]).expect("gcc");
    let mut best = [f64::MAX; 3];
    for _ in 0..40 {
        let mut ticks_of: [Tick; 3] =
            [&mut |i| jit.tick(i), &mut |i| jit_speed.tick(i), &mut |i| {
                gcc.tick(i)
            }];
        for (k, tick) in ticks_of.iter_mut().enumerate() {
            let mut image = p.new_image();
            let t = std::time::Instant::now();
            run_ticks(*tick, &mut image, ticks);
            let us = t.elapsed().as_secs_f64() * 1e6 / f64::from(ticks.max(1));
            best[k] = best[k].min(us);
        }
    }
    println!(
        "jit {:.1} us, jit-speed {:.1} us, gcc -O2 {:.1} us per tick: jit/gcc {:.2}",
        best[0],
        best[1],
        best[2],
        best[0] / best[2]
    );
}

/// Best-of-5 JIT compile time of the program under the default and the `SCAN_*` settings.
fn compile_times(p: &Arc<compiler::ir::Program>) {
    for (ra, opt) in [
        ("single_pass", "none"),
        ("backtracking", "none"),
        ("backtracking", "speed"),
    ] {
        let opts = JitOptions {
            opt_level: opt,
            regalloc: ra,
            ..JitOptions::default()
        };
        let best = (0..5)
            .map(|_| {
                let t = std::time::Instant::now();
                drop(jit::compile_with(p, &opts).expect("jit"));
                t.elapsed().as_secs_f64() * 1e3
            })
            .fold(f64::MAX, f64::min);
        println!("compile {ra} {opt}: {best:.1} ms");
    }
}
