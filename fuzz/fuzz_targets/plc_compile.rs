#![no_main]
//! Arbitrary bytes never panic the PLC compiler; a failed compilation always carries a located
//! error, and a program that compiles passes the IR validator.
//! Work is bounded: the whole input must take at most 100 ms + 20 µs per byte of the thread's
//! CPU time (generous for sanitizer builds; a quadratic path on a 64 KB input blows it by orders
//! of magnitude).
/// The machine context, built once: parsing the built-in interface map on every input cost most
/// of an execution.
static CTX: std::sync::LazyLock<compiler::MachineContext> =
    std::sync::LazyLock::new(compiler::MachineContext::lathe_like);

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    ncplc_fuzz::within_linear_budget(data.len(), || {
        let c = compiler::compile("fuzz", data, &CTX);
        match &c.program {
            None => assert!(c.diagnostics.iter().any(|d| d.is_error() && d.line > 0)),
            Some(p) => assert_eq!(p.validate(), Ok(())),
        }
    });
});
