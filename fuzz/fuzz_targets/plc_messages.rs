#![no_main]
//! PLC message files (`MP0/MESSAG`, docs/plc-messages.md) from arbitrary bytes never panic the
//! reader; every line is a message or exactly one diagnostic, every span lies inside the text and
//! every number is 1..=64.
//! Work is bounded: the whole input must take at most 100 ms + 20 µs per byte of the thread's
//! CPU time.
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    ncplc_fuzz::within_linear_budget(data.len(), || {
        let text = characterization::decode::decode(data);
        let mut sink = diag::Sink::unbounded();
        let file = characterization::messages::parse_into("MP0/MESSAG", &text, &mut sink);
        let (kept, _) = sink.finish();
        assert!(kept.iter().all(|d| d.span.end <= text.len()));
        assert!(file.texts.keys().all(|n| (1..=64).contains(n)));
        let lines = text
            .split_inclusive('\n')
            .map(|l| {
                l.trim_end_matches(['\n', '\r'])
                    .trim_start_matches([' ', '\t'])
            })
            .filter(|l| !l.is_empty() && !l.starts_with(';'))
            .count();
        assert_eq!(file.texts.len() + kept.len(), lines);
    });
});
