#![no_main]
//! Arbitrary bytes never panic the PLC compiler; a failed compilation always carries a located
//! error, and a program that compiles passes the IR validator.
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let ctx = compiler::MachineContext::lathe_like();
    let c = compiler::compile("fuzz", data, &ctx);
    match &c.program {
        None => assert!(c.diagnostics.iter().any(|d| d.is_error() && d.line > 0)),
        Some(p) => assert_eq!(p.validate(), Ok(())),
    }
});
