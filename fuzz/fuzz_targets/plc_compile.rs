#![no_main]
//! Arbitrary bytes never panic the PLC compiler; a failed compilation always carries a located
//! error.
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let ctx = compiler::MachineContext::lathe_like();
    let c = compiler::compile("fuzz", data, &ctx);
    if c.program.is_none() {
        assert!(c.diagnostics.iter().any(|d| d.is_error() && d.line > 0));
    }
});
