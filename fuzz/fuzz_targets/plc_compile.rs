#![no_main]
//! Arbitrary bytes never panic the PLC compiler; a failed compilation always carries a located
//! error, and a program that compiles passes the IR validator.
//! Work is bounded: the whole input must take at most 100 ms + 20 µs per byte (generous for
//! sanitizer builds; a quadratic path on a 64 KB input blows it by orders of magnitude).
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let started = std::time::Instant::now();
    let ctx = compiler::MachineContext::lathe_like();
    let c = compiler::compile("fuzz", data, &ctx);
    match &c.program {
        None => assert!(c.diagnostics.iter().any(|d| d.is_error() && d.line > 0)),
        Some(p) => assert_eq!(p.validate(), Ok(())),
    }
    let budget = std::time::Duration::from_micros(100_000 + 20 * data.len() as u64);
    assert!(started.elapsed() <= budget, "{} bytes took {:?}", data.len(), started.elapsed());
});
