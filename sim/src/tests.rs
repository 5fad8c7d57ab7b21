//! Tests of the simulated CNC: scripted inputs, feedback, the handshake of process 1 and 2.

use super::*;
use runtime::testkit::sig;

fn sim(text: &str, tick_ms: u32) -> Sim {
    Sim::new(
        Sim::parse_script(text).expect("script"),
        CncSignals::default(),
        tick_ms,
    )
    .expect("sim")
}

#[test]
fn scripted_inputs_and_feedback_with_delay() {
    let mut s = sim(
        "[[at]]\ntick = 1\nset = { I0A0 = 1 }\n[[follow]]\ninput = \"I0A3\"\noutput = \"U4A0\"\ndelay_ms = 20\n",
        10,
    );
    let mut img = vec![0u8; packets::PACKETS_LEN];
    let mut seen = Vec::new();
    for t in 0..6 {
        s.latch_inputs(t, &mut img);
        seen.push((sig("I0A0").read(&img), sig("I0A3").read(&img)));
        // The "logic": U4A0 copies I0A0.
        let v = sig("I0A0").read(&img);
        sig("U4A0").write(&mut img, v);
        s.publish_outputs(t, &img);
    }
    // U4A0 rises at the end of tick 1; 20 ms = 2 ticks later than the next tick: tick 4.
    assert_eq!(seen, vec![(0, 0), (1, 0), (1, 0), (1, 0), (1, 1), (1, 1)]);
}

#[test]
fn m_function_runs_the_handshake_against_a_logic() {
    let mut s = sim("strobe_timeout_ms = 100\n[[at]]\ntick = 0\nm = [3]\n", 10);
    let mut img = vec![0u8; packets::PACKETS_LEN];
    let mut log = Vec::new();
    for t in 0..8 {
        s.latch_inputs(t, &mut img);
        // Logic: MFIN = MSTB and MCODE = 03.
        let fin = sig("I1K0").read(&img) == 1 && sig("W3K0").read(&img) == 0x03;
        sig("U11K0").write(&mut img, u8::from(fin));
        log.push((sig("I1K0").read(&img), sig("U11K0").read(&img)));
        s.publish_outputs(t, &img);
    }
    assert_eq!(
        log,
        vec![
            (0, 0),
            (1, 1),
            (0, 0),
            (0, 0),
            (0, 0),
            (0, 0),
            (0, 0),
            (0, 0)
        ]
    );
    assert_eq!(s.completed(), [1, 0, 0]);
    assert!(s.take_alarms().is_empty());
}

#[test]
fn unanswered_strobe_raises_an_alarm_naming_the_function() {
    let mut s = sim("strobe_timeout_ms = 30\n[[at]]\ntick = 0\nm = [91]\n", 10);
    let mut img = vec![0u8; packets::PACKETS_LEN];
    let mut alarms = Vec::new();
    for t in 0..10 {
        s.latch_inputs(t, &mut img);
        s.publish_outputs(t, &img);
        alarms.extend(s.take_alarms());
    }
    assert_eq!(alarms.len(), 1);
    assert_eq!(
        alarms[0].message,
        "M91 not acknowledged (FIN) within the strobe timeout"
    );
}

#[test]
fn a_periodic_schedule_repeats() {
    let mut s = sim(
        "period = 3\n[[at]]\ntick = 1\nset = { I0A0 = 1 }\n[[at]]\ntick = 2\nset = { I0A0 = 0 }\n",
        10,
    );
    let mut img = vec![0u8; packets::PACKETS_LEN];
    let mut seen = Vec::new();
    for t in 0..7 {
        s.latch_inputs(t, &mut img);
        seen.push(sig("I0A0").read(&img));
    }
    assert_eq!(seen, vec![0, 1, 0, 0, 1, 0, 0]);
}

#[test]
fn bad_scripts_are_rejected() {
    assert!(Sim::parse_script("bogus = 1\n").is_err());
    let script = Sim::parse_script("[[at]]\ntick = 0\nset = { I0A0 = 2 }\n").expect("toml");
    assert!(Sim::new(script, CncSignals::default(), 10).is_err());
}

/// The mill's interface map: the default one plus process 2 (MSTB_T I6K0, MCODE_T W7K0, MFIN_T U30K0).
fn mill_signals() -> CncSignals {
    let o = compiler::InterfaceMap::parse(
        "interface.toml",
        include_str!("../../plc-programs/mill/interface.toml"),
    )
    .expect("the mill's map parses");
    let map = compiler::InterfaceMap::builtin()
        .with_overrides(o)
        .expect("no clash");
    CncSignals::from_map(&map, 2)
}

fn mill_sim(text: &str) -> Sim {
    Sim::new(Sim::parse_script(text).expect("script"), mill_signals(), 10).expect("sim")
}

#[test]
fn process_2_signals_come_from_the_map_roles() {
    let s = mill_signals();
    let p2 = s.process(2).expect("process 2");
    assert_eq!(
        p2.channels,
        [
            Some(ChannelSignals {
                strobe: sig("I6K0"),
                fin: sig("U30K0"),
                code: sig("W7K0"),
            }),
            None,
            None
        ]
    );
    assert_eq!(
        s.process(1).and_then(|p| p.channels[0]).map(|c| c.strobe),
        Some(sig("I1K0"))
    );
    assert_eq!(s.reset, sig("I0K1"));
}

#[test]
fn process_2_m_function_strobes_at_its_tick_and_clears_after_fin() {
    let mut s = mill_sim("strobe_timeout_ms = 100\n[[at]]\ntick = 2\nprocess = 2\nm = [30]\n");
    let mut img = vec![0u8; packets::PACKETS_LEN];
    let mut log = Vec::new();
    for t in 0..7 {
        s.latch_inputs(t, &mut img);
        // Logic: MFIN_T = MSTB_T and MCODE_T = 30H.
        let fin = sig("I6K0").read(&img) == 1 && sig("W7K0").read(&img) == 0x30;
        sig("U30K0").write(&mut img, u8::from(fin));
        log.push((
            sig("I6K0").read(&img),
            sig("U30K0").read(&img),
            sig("W7K0").read(&img),
            sig("I1K0").read(&img),
        ));
        s.publish_outputs(t, &img);
    }
    assert_eq!(
        log,
        vec![
            (0, 0, 0, 0),
            (0, 0, 0, 0),
            (0, 0, 0x30, 0), // tick 2: the code is written
            (1, 1, 0x30, 0), // tick 3: the strobe rises, the logic answers
            (0, 0, 0x30, 0), // tick 4: FIN seen, strobe cleared
            (0, 0, 0x30, 0),
            (0, 0, 0x30, 0),
        ]
    );
    let counts = s.counts();
    assert_eq!(counts.completed(2), Some([1, 0, 0]));
    assert_eq!(s.completed(), [0, 0, 0]);
    assert_eq!(
        counts.summary(),
        "handshake p1   M 0  S 0  T 0  completed, 0 timeouts\n\
         handshake p2   M 1  S -  T -  completed, 0 timeouts\n"
    );
    assert!(s.take_alarms().is_empty());
}

#[test]
fn an_unanswered_process_2_strobe_raises_an_alarm_naming_process_2() {
    let mut s = mill_sim("strobe_timeout_ms = 30\n[[at]]\ntick = 0\nprocess = 2\nm = [0]\n");
    let mut img = vec![0u8; packets::PACKETS_LEN];
    let mut alarms = Vec::new();
    for t in 0..9 {
        s.latch_inputs(t, &mut img);
        // The logic answers late, from tick 6 on.
        let fin = t >= 6 && sig("I6K0").read(&img) == 1;
        sig("U30K0").write(&mut img, u8::from(fin));
        s.publish_outputs(t, &img);
        alarms.extend(
            s.take_alarms()
                .into_iter()
                .map(|a| (t, a.message, a.cleared)),
        );
    }
    assert_eq!(
        alarms,
        vec![
            (
                4,
                "process 2: M00 not acknowledged (FIN) within the strobe timeout".to_string(),
                false
            ),
            (7, "process 2: M00 acknowledged late".to_string(), true),
        ]
    );
    let counts = s.counts();
    assert_eq!((counts.timeouts(1), counts.timeouts(2)), (0, 1));
    assert_eq!(counts.completed(2), Some([1, 0, 0]));
}

#[test]
fn a_general_reset_clears_the_strobes_of_every_process() {
    let mut s = mill_sim(
        "strobe_timeout_ms = 0\n[[at]]\ntick = 0\nm = [3]\n[[at]]\ntick = 0\nprocess = 2\nm = [30, 2]\n\
         [[at]]\ntick = 3\nset = { I0K1 = 1 }\n[[at]]\ntick = 4\nset = { I0K1 = 0 }\n",
    );
    let mut img = vec![0u8; packets::PACKETS_LEN];
    let mut strobes = Vec::new();
    for t in 0..8 {
        s.latch_inputs(t, &mut img);
        strobes.push((sig("I1K0").read(&img), sig("I6K0").read(&img)));
        s.publish_outputs(t, &img);
    }
    // Both strobes rise at tick 1; the reset at tick 3 drops them and forgets process 2's M02.
    assert_eq!(
        strobes,
        vec![
            (0, 0),
            (1, 1),
            (1, 1),
            (0, 0),
            (0, 0),
            (0, 0),
            (0, 0),
            (0, 0)
        ]
    );
    assert_eq!(s.counts().completed(2), Some([0, 0, 0]));
}

#[test]
fn functions_of_a_process_without_their_handshake_are_refused() {
    let err = |text: &str| {
        Sim::new(Sim::parse_script(text).expect("toml"), mill_signals(), 10)
            .err()
            .map(|e| e.to_string())
    };
    assert_eq!(
        err("[[at]]\ntick = 5\nprocess = 2\ns = 100\n").as_deref(),
        Some(
            "sim script: tick 5: process 2 has no S handshake (SSTB, SFIN, SCODE) in the interface map"
        )
    );
    assert_eq!(
        err("[[at]]\ntick = 0\nprocess = 3\nm = [0]\n").as_deref(),
        Some(
            "sim script: tick 0: process 3 has no M handshake (MSTB, MFIN, MCODE) in the interface map"
        )
    );
    assert_eq!(
        err("[[at]]\ntick = 0\nprocess = 6\n").as_deref(),
        Some("sim script: tick 0: process 6 is outside 1..5")
    );
    assert_eq!(err("[[at]]\ntick = 0\nprocess = 2\nm = [2]\n"), None);
}
