#![no_main]
//! Trace files (text or binary) from arbitrary bytes never panic the reader or `trace recover`;
//! what recovery keeps is a prefix of the input, and of a trace that reads whole it keeps a prefix
//! of the records. The record-by-record reader through a buffer of 1 to 16 bytes (the first
//! input byte picks it) reads exactly what a read of the whole bytes reads, errors included. Sim scripts (`sim.toml`) from arbitrary text never panic their reader.
//! Work is bounded: the whole input must take at most 100 ms + 20 µs per byte of the thread's
//! CPU time (generous for sanitizer builds; a quadratic path on a 64 KB input blows it by orders
//! of magnitude).
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    ncplc_fuzz::within_linear_budget(data.len(), || {
        let whole = trace::Trace::from_bytes(data);
        let capacity = usize::from(data.first().copied().unwrap_or(0) % 16) + 1;
        let streamed =
            trace::reader::Reader::new(std::io::BufReader::with_capacity(capacity, data))
                .and_then(trace::reader::Reader::collect_trace);
        assert_eq!(
            streamed.as_ref().map_err(ToString::to_string),
            whole.as_ref().map_err(ToString::to_string)
        );
        if let Ok(r) = trace::recover::recover(data) {
            assert!(r.kept_bytes + r.dropped_bytes <= data.len());
            if let Ok(t) = &whole {
                assert!(t.ticks.starts_with(&r.trace.ticks));
            }
        }
        if let Ok(s) = std::str::from_utf8(data) {
            let _ = sim::Sim::parse_script(s);
        }
    });
});
