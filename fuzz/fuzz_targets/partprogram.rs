#![no_main]
//! Partprograms from arbitrary bytes never panic the compiler or the planner (both dialects).
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    for dialect in [partprogram::Dialect::Mefi, partprogram::Dialect::Fanuc] {
        let spec = partprogram::MachineSpec::new(dialect, &['X', 'Y', 'Z']);
        let (prog, _) = partprogram::compile(&spec, "fuzz", &text);
        if let Some(p) = prog {
            let opts = partprogram::PlanOptions {
                max_blocks: 10_000,
                ..Default::default()
            };
            let _ = partprogram::plan(&p, opts);
        }
    }
});
