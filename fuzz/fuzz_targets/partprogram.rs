#![no_main]
//! Partprograms from arbitrary bytes never panic the compiler or the planner (both dialects, and a
//! 4-axis MEFI machine so that the G14–G16 planes of machine constant 341 are planned too).
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let machines: [(partprogram::Dialect, &[char]); 3] = [
        (partprogram::Dialect::Mefi, &['X', 'Y', 'Z']),
        (partprogram::Dialect::Fanuc, &['X', 'Y', 'Z']),
        (partprogram::Dialect::Mefi, &['X', 'Y', 'Z', 'A']),
    ];
    for (dialect, axes) in machines {
        let spec = partprogram::MachineSpec::new(dialect, axes);
        // Compiling is bounded by the input: 100 ms + 20 µs per byte (generous for sanitizers).
        let mut prog = None;
        ncplc_fuzz::within_linear_budget(data.len(), || {
            prog = partprogram::compile(&spec, "fuzz", &text).0;
        });
        if let Some(p) = prog {
            let opts = partprogram::PlanOptions {
                max_blocks: 10_000,
                ..Default::default()
            };
            let _ = partprogram::plan(&p, opts);
        }
    }
});
