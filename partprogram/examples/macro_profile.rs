//! Plans a Fanuc Macro B program N times with one back end, for instruction counts under
//! `valgrind --tool=callgrind` (the machine is shared: counts, not wall time).
//!
//! `cargo run --release -p partprogram --example macro_profile -- <file.nc> <native|interpreter> [N]`
//! (the benchmark loops are `partprogram/benches/macro/*.nc`).

use partprogram::{Backend, Dialect, MachineSpec, PlanOptions, compile, plan};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (Some(file), Some(backend)) = (args.get(1), args.get(2)) else {
        eprintln!("usage: macro_profile <file.nc> <native|interpreter> [N]");
        std::process::exit(2);
    };
    let backend = match backend.as_str() {
        "native" => Backend::Native,
        "interpreter" => Backend::Interpreter,
        other => {
            eprintln!("unknown back end {other}: native or interpreter");
            std::process::exit(2);
        }
    };
    let n: u32 = args.get(3).and_then(|v| v.parse().ok()).unwrap_or(1);
    let src = match std::fs::read_to_string(file) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("{file}: {e}");
            std::process::exit(2);
        }
    };
    let m = MachineSpec::new(Dialect::Fanuc, &['X', 'Y', 'Z']);
    let (prog, diags) = compile(&m, file, &src);
    let Some(prog) = prog else {
        eprintln!("{diags:?}");
        std::process::exit(1);
    };
    let mut executed = 0;
    for _ in 0..n {
        match plan(
            &prog,
            PlanOptions {
                backend,
                ..PlanOptions::default()
            },
        ) {
            Ok(p) => executed += p.executed,
            Err((_, d)) => {
                eprintln!("{d}");
                std::process::exit(1);
            }
        }
    }
    println!("{n} plans, {executed} blocks executed");
}
