//! Helpers shared by the partprogram integration tests.
#![allow(dead_code)]

use std::path::PathBuf;

use partprogram::{Canon, Dialect, MachineSpec, Plan, PlanOptions, compile, plan};

/// The repository's plc-programs folder.
pub fn machines() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../plc-programs")
}

/// A MEFI mill (X, Y, Z) with the shipped macro folder.
pub fn mill() -> MachineSpec {
    let mut m = MachineSpec::new(Dialect::Mefi, &['X', 'Y', 'Z']);
    m.macro_dir = machines().join("mill/macros");
    m
}

/// A MEFI lathe (X, Z, diameter programming) with the shipped macro folder.
pub fn lathe() -> MachineSpec {
    let mut m = MachineSpec::new(Dialect::Mefi, &['X', 'Z']);
    m.macro_dir = machines().join("lathe/macros");
    m.diameter_x = true;
    m
}

/// Compiles and plans `src` on `m`, panicking with the diagnostics on failure.
pub fn run(m: &MachineSpec, src: &str, opts: PlanOptions) -> Plan {
    let (prog, diags) = compile(m, "test", src);
    let Some(prog) = prog else {
        panic!("compile failed: {diags:#?}")
    };
    match plan(&prog, opts) {
        Ok(p) => p,
        Err((_, d)) => panic!("run failed: {d}"),
    }
}

/// Compiles `src` and returns the diagnostic codes.
pub fn codes(m: &MachineSpec, src: &str) -> Vec<u32> {
    let (_, diags) = compile(m, "test", src);
    diags.iter().map(|d| d.code).collect()
}

/// Rounds to µm.
pub fn um(v: f64) -> f64 {
    (v * 1000.0).round() / 1000.0
}

/// End position of axis `a` in µm-rounded mm.
pub fn end(c: &Canon, a: char) -> f64 {
    um(c.end_of(a).unwrap_or(f64::NAN))
}
