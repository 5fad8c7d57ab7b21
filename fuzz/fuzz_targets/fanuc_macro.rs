#![no_main]
//! Fanuc Macro B programs built from Macro B tokens (each input byte picks one) never panic the
//! compiler or the planner, and the native back end plans them exactly as the interpreter does.
const TOKENS: [&str; 48] = [
    "\n", "\n", "\n", "#1", "#2", "#3", "#100", "#500", "#0", "#[", "[", "]", " = ", "+", "-", "*",
    "/", " MOD ", " AND ", " OR ", " XOR ", " EQ ", " NE ", " GT ", " LE ", "SIN[", "SQRT[",
    "ATAN[", "ROUND[", "BCD[", "1", "2.5", "0", "10", "IF ", " GOTO ", " THEN ", "WHILE ", " DO1",
    "END1", " DO2", "END2", "N10 ", "G01 X", "Y", "G65 P1 A", "M99", ",",
];

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let mut text = String::from("O1\n");
    for b in data {
        text.push_str(TOKENS[usize::from(*b) % TOKENS.len()]);
    }
    text.push_str("\nM30\n");
    let spec = partprogram::MachineSpec::new(partprogram::Dialect::Fanuc, &['X', 'Y', 'Z']);
    let (prog, _) = partprogram::compile(&spec, "fuzz", &text);
    if let Some(p) = prog {
        let run = |backend| {
            let opts = partprogram::PlanOptions {
                backend,
                max_blocks: 10_000,
                ..Default::default()
            };
            match partprogram::plan(&p, opts) {
                Ok(plan) => Ok((
                    plan.blocks,
                    plan.macro_vars
                        .iter()
                        .map(|v| v.to_bits())
                        .collect::<Vec<_>>(),
                )),
                Err((blocks, d)) => Err((blocks, d.code, d.message, d.line)),
            }
        };
        assert_eq!(
            run(partprogram::Backend::Interpreter),
            run(partprogram::Backend::Native),
            "{text}"
        );
    }
});
