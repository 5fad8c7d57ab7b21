#![no_main]
//! `sim.toml` texts validated against a machine (the mill's interface map with its two processes,
//! packet-A connectors 0–2 in and 4–6 out, handwheel channel 1 of process 1, axes X, Y, Z of
//! process 1 with limit switch inputs on X only) never panic the validation `check` reports and
//! `run` refuses; a script comes back exactly when there is no error, and every diagnostic's span
//! lies inside the text. Work is bounded: the whole input must take at most 100 ms + 20 µs per
//! byte of the thread's CPU time.
use std::sync::OnceLock;

use sim::validate::{AxisWiring, Machine};

/// What the script is checked against, built once.
struct Fixture {
    map: compiler::InterfaceMap,
    signals: sim::CncSignals,
    written: Vec<packets::Signal>,
    axes: Vec<AxisWiring>,
}

fn fixture() -> &'static Fixture {
    static F: OnceLock<Fixture> = OnceLock::new();
    F.get_or_init(|| {
        let own = compiler::InterfaceMap::parse(
            "interface.toml",
            include_str!("../../plc-programs/mill/interface.toml"),
        )
        .expect("the mill's map parses");
        let map = compiler::InterfaceMap::builtin()
            .with_overrides(own)
            .expect("no clash");
        let signals = sim::CncSignals::from_map(&map, 2);
        let written = ["I1K0", "I1K1", "W3K0"]
            .iter()
            .map(|s| s.parse().expect("signal"))
            .collect();
        let axes = vec![
            AxisWiring {
                name: 'X',
                limits: (true, true),
            },
            AxisWiring {
                name: 'Y',
                limits: (false, false),
            },
            AxisWiring {
                name: 'Z',
                limits: (false, false),
            },
        ];
        Fixture {
            map,
            signals,
            written,
            axes,
        }
    })
}

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let f = fixture();
    let adv = |p: u8, c: u8| p == 1 && c == 1;
    let machine = Machine {
        a_inputs: &[0, 1, 2],
        a_outputs: &[4, 5, 6],
        interface: &f.map,
        signals: &f.signals,
        kernel_written: &f.written,
        adv: &adv,
        dir: None,
        axes: &f.axes,
    };
    ncplc_fuzz::within_linear_budget(data.len(), || {
        let (script, diags) = sim::validate::check("sim.toml", text, &machine);
        assert_eq!(script.is_some(), !diags.iter().any(|d| d.is_error()));
        for d in &diags {
            assert!(
                d.span.start <= d.span.end && d.span.end <= text.len(),
                "{d:?}"
            );
        }
    });
});
