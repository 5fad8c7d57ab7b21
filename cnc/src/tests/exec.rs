//! Hand-derived tick sequences of strobe, FIN and DEN (see each test's table).

use partprogram::canon::Kind::{Aux, Linear};

use super::fixture::{Bench, Plc, block, cnc, sig};
use crate::state::Interp;

/// These moves run past the fixture's LO1 (+3 mm): the tests are about stopping them.
fn no_soft_limits(b: &mut Bench) {
    b.cnc.process_mut(1).expect("p1").cfg.axes[0].soft = (None, None);
}

/// The part: N10 S1200 T5 M03 (no motion); N20 G01 X3; N30 M30.
fn part() -> Vec<partprogram::Canon> {
    vec![
        block(10, Aux, 0.0, &[3], Some(1200.0), Some(5)),
        block(20, Linear, 3.0, &[], Some(1200.0), Some(5)),
        block(30, Aux, 3.0, &[30], Some(1200.0), Some(5)),
    ]
}

/// Ticks 0 and 1 with START pressed in the scan of tick 1 (the kernel sees the edge at tick 2).
fn started(parallel: bool) -> Bench {
    let mut b = Bench::new(cnc(parallel, 0, 0));
    b.start_program(part());
    b.run(1, &Plc::default());
    b.step(&Plc {
        start: 1,
        ..Plc::default()
    });
    b
}

#[test]
fn gps0_issues_s_then_t_then_m_and_m30_after_motion() {
    let mut b = started(false);
    // Columns: MSTB, SSTB, TSTB, DEN, CYCLE. Each function: code at t, strobe t+1, FIN seen and
    // strobe dropped t+2, FIN = 0 seen t+3 (the next code goes out in the same tick).
    let expected: Vec<[u8; 5]> = vec![
        [0, 0, 0, 1, 1], // t2  START seen, S1200 code written
        [0, 1, 0, 1, 1], // t3  SSTB
        [0, 0, 0, 1, 1], // t4  SFIN seen
        [0, 0, 0, 1, 1], // t5  SFIN = 0 seen, T5 code written
        [0, 0, 1, 1, 1], // t6  TSTB
        [0, 0, 0, 1, 1], // t7
        [0, 0, 0, 1, 1], // t8  M03 code written
        [1, 0, 0, 1, 1], // t9  MSTB
        [0, 0, 0, 1, 1], // t10
        [0, 0, 0, 0, 1], // t11 M03 done: N10 ends, N20 moves (X = 1)
        [0, 0, 0, 0, 1], // t12 X = 2
        [0, 0, 0, 1, 1], // t13 X = 3, DEN; N30's M30 (after motion) code written
        [1, 0, 0, 1, 1], // t14 MSTB
        [0, 0, 0, 1, 1], // t15
        [0, 0, 0, 1, 0], // t16 M30 done: reset request, the program ends
    ];
    let rows = b.run(expected.len(), &Plc::default());
    assert_eq!(rows, expected);
    assert_eq!(sig("W4K0").read(&b.image), 0xB0); // 1200 = 0x04B0, little-endian
    assert_eq!(sig("W4K1").read(&b.image), 0x04);
    assert_eq!(sig("W5K0").read(&b.image), 0x05); // T5 in BCD
    assert_eq!(sig("W3K0").read(&b.image), 0x30); // M30 in BCD
    let c = b.cnc.processes()[0].counters().clone();
    assert_eq!(c.blocks, 3);
    assert_eq!(c.handshakes, [2, 1, 1]);
    assert_eq!(c.ended, 1);
    assert_eq!(b.cnc.processes()[0].state().interp, Interp::Idle);
}

#[test]
fn gps1_strobes_s_t_and_the_first_m_together() {
    let mut b = started(true);
    let expected: Vec<[u8; 5]> = vec![
        [0, 0, 0, 1, 1], // t2 S, T, M03 codes written
        [1, 1, 1, 1, 1], // t3 three strobes
        [0, 0, 0, 1, 1], // t4 three FINs seen
        [0, 0, 0, 0, 1], // t5 FINs low: N20 moves, X = 1
        [0, 0, 0, 0, 1], // t6 X = 2
        [0, 0, 0, 1, 1], // t7 X = 3, DEN, M30 code
        [1, 0, 0, 1, 1], // t8
        [0, 0, 0, 1, 1], // t9
        [0, 0, 0, 1, 0], // t10 end
    ];
    assert_eq!(b.run(expected.len(), &Plc::default()), expected);
}

#[test]
fn m00_stops_at_block_end_and_start_resumes() {
    let mut b = Bench::new(cnc(false, 0, 0));
    b.start_program(vec![
        block(10, Linear, 1.0, &[0], None, None),
        block(20, Linear, 2.0, &[30], None, None),
    ]);
    b.run(1, &Plc::default());
    b.step(&Plc {
        start: 1,
        ..Plc::default()
    });
    let rows = b.run(5, &Plc::default());
    // t2 X=1 DEN and M00 code; t3 MSTB; t4; t5 M00 done: stop (CYCLE 0); t6 still stopped.
    assert_eq!(
        rows,
        vec![
            [0, 0, 0, 1, 1],
            [1, 0, 0, 1, 1],
            [0, 0, 0, 1, 1],
            [0, 0, 0, 1, 0],
            [0, 0, 0, 1, 0],
        ]
    );
    assert_eq!(b.cnc.processes()[0].state().interp, Interp::Paused);
    b.step(&Plc {
        start: 1,
        ..Plc::default()
    });
    // t8 START edge: N20 moves to X=2 in the same tick.
    assert_eq!(b.step(&Plc::default()), [0, 0, 0, 1, 1]);
    assert_eq!(b.cnc.processes()[0].set_points(), &[2.0]);
}

#[test]
fn m01_stops_only_with_uso() {
    for (uso, interp) in [(0, Interp::Idle), (1, Interp::Paused)] {
        let mut b = Bench::new(cnc(false, 0, 0));
        b.start_program(vec![
            block(10, Linear, 1.0, &[1], None, None),
            block(20, Aux, 1.0, &[30], None, None),
        ]);
        let plc = Plc {
            uso,
            ..Plc::default()
        };
        b.run(1, &plc);
        b.step(&Plc { start: 1, ..plc });
        // X=1 and M01 (t2..t5), then M30 (t5..t8) unless USO stops after M01.
        b.run(8, &plc);
        assert_eq!(b.cnc.processes()[0].state().interp, interp, "USO {uso}");
    }
}

#[test]
fn unanswered_strobe_raises_one_stopping_alarm_naming_function_and_block() {
    let mut b = Bench::new(cnc(false, 5, 0));
    b.start_program(vec![block(10, Aux, 0.0, &[3], None, None)]);
    let plc = Plc {
        m_fin: false,
        ..Plc::default()
    };
    b.run(1, &plc);
    b.step(&Plc { start: 1, ..plc });
    // t2 code, t3 strobe (since 3), t8 = 3 + 5: timeout.
    let rows = b.run(7, &plc);
    assert_eq!(rows[5][0], 1, "MSTB still up at t7");
    let p = b.cnc.process_mut(1).expect("p1");
    let alarms = p.take_new_alarms();
    assert_eq!(
        alarms
            .iter()
            .map(|a| a.message.as_str())
            .collect::<Vec<_>>(),
        ["process 1: M03 not acknowledged (FIN) within the strobe timeout (block 1 (N10))"]
    );
    assert_eq!(rows[6][0], 0, "the alarm clears the strobe");
    assert_eq!(sig("I1K4").read(&b.image), 1, "ALARM");
    assert_eq!(p.state().interp, Interp::Idle);
}

#[test]
fn estop_during_motion_stops_and_alarms_and_ers_resets() {
    let mut b = Bench::new(cnc(false, 0, 0));
    no_soft_limits(&mut b);
    b.start_program(vec![block(10, Linear, 10.0, &[30], None, None)]);
    b.run(1, &Plc::default());
    b.step(&Plc {
        start: 1,
        ..Plc::default()
    });
    b.run(3, &Plc::default()); // t2..t4: X = 1, 2, 3
    b.step(&Plc {
        estop: 0,
        ..Plc::default()
    }); // t5: X = 4; the scan opens the chain
    b.step(&Plc {
        estop: 0,
        ..Plc::default()
    }); // t6: e-stop seen
    let p = &b.cnc.processes()[0];
    assert_eq!(p.set_points(), &[4.0]);
    assert!(!p.state().on);
    assert_eq!(p.alarms()[0].message, "process 1: emergency stop");
    assert_eq!(sig("I1K5").read(&b.image), 0, "CYCLE");
    assert_eq!(
        sig("I0K2").read(&b.image),
        0,
        "CONP (not mapped here) stays 0"
    );
    b.step(&Plc {
        ers: 1,
        ..Plc::default()
    }); // t7: chain closed again; ERS in the scan
    b.step(&Plc::default()); // t8: ERS edge: reset
    assert_eq!(sig("I0K1").read(&b.image), 1, "RESET pulse");
    assert!(b.cnc.processes()[0].alarms().is_empty());
    b.step(&Plc::default());
    assert_eq!(sig("I0K1").read(&b.image), 0, "one tick");
}

#[test]
fn rabi_dropped_holds_the_move_then_alarms_after_the_timeout() {
    let mut b = Bench::new(cnc(false, 0, 4));
    no_soft_limits(&mut b);
    b.start_program(vec![block(10, Linear, 10.0, &[30], None, None)]);
    b.run(1, &Plc::default());
    b.step(&Plc {
        start: 1,
        ..Plc::default()
    });
    b.run(2, &Plc::default()); // t2, t3: X = 1, 2; RABI dropped in the scan of t3
    let off = Plc {
        rabi: 0,
        ..Plc::default()
    };
    b.step(&off); // t3 scan writes RABI 0
    b.run(2, &off); // t4, t5: held
    assert_eq!(b.cnc.processes()[0].set_points(), &[3.0]);
    assert!(b.cnc.processes()[0].alarms().is_empty());
    b.run(2, &off); // t6, t7: fourth tick waiting: alarm
    let p = &b.cnc.processes()[0];
    assert_eq!(
        p.alarms()[0].message,
        "process 1: axis enable (RABI) missing for a moving axis (block 1 (N10))"
    );
    assert_eq!(p.state().interp, Interp::Idle);
}

#[test]
fn reset_during_motion_returns_to_the_program_start() {
    let mut b = Bench::new(cnc(false, 0, 0));
    no_soft_limits(&mut b);
    b.start_program(vec![
        block(10, Linear, 5.0, &[], None, None),
        block(20, Aux, 5.0, &[30], None, None),
    ]);
    b.run(1, &Plc::default());
    b.step(&Plc {
        start: 1,
        ..Plc::default()
    });
    b.run(2, &Plc::default());
    b.cnc.reset();
    b.step(&Plc::default());
    let p = &b.cnc.processes()[0];
    assert_eq!(p.state().interp, Interp::Idle);
    assert_eq!(p.status().block, 0);
    assert!(!p.state().moving);
    assert_eq!(p.set_points(), &[2.0]);
}

#[test]
fn two_processes_run_their_programs_side_by_side() {
    use crate::{Cnc, MachineSignals, Process, ProcessSignals, Timing};
    // Process 2 on the mill's magazine addresses: MSTB I6K0, MFIN U30K0, MCODE W7K0, START U30K3.
    let single = cnc(false, 0, 0);
    let mut procs: Vec<Process> = Vec::new();
    let mut first = single;
    let p1 = std::mem::replace(
        first.process_mut(1).expect("p1"),
        Process::new(
            crate::config::ProcessConfig {
                number: 9,
                axes: Vec::new(),
                spindle: None,
                m_timing: super::fixture::lathe_m(),
                parallel: false,
                int_tick_s: 0.01,
                qfd: None,
                handwheels: [false; 2],
            },
            ProcessSignals::default(),
            Box::new(crate::interp::NoMotion),
            &[],
            Timing {
                logic_tick_s: 0.01,
                strobe_timeout_ticks: 0,
                rabi_timeout_ticks: 0,
            },
        ),
    );
    procs.push(p1);
    let roles = [
        ("MSTB", "I6K0"),
        ("MFIN", "U30K0"),
        ("MCODE", "W7K0"),
        ("START", "U30K3"),
        ("CYCLE", "I6K5"),
    ];
    let p2 = Process::new(
        crate::config::ProcessConfig {
            number: 2,
            axes: Vec::new(),
            spindle: None,
            m_timing: super::fixture::lathe_m(),
            parallel: false,
            int_tick_s: 0.01,
            qfd: None,
            handwheels: [false; 2],
        },
        ProcessSignals::from_roles(|r| roles.iter().find(|(n, _)| *n == r).map(|(_, a)| sig(a))),
        Box::new(crate::interp::NoMotion),
        &[],
        Timing {
            logic_tick_s: 0.01,
            strobe_timeout_ticks: 0,
            rabi_timeout_ticks: 0,
        },
    );
    procs.push(p2);
    let mut b = Bench::new(Cnc::new(
        procs,
        MachineSignals {
            reset: Some(sig("I0K1")),
            estop: Some(sig("U11K4")),
        },
    ));
    b.start_program(vec![
        block(10, Linear, 2.0, &[], None, None),
        block(20, Aux, 2.0, &[30], None, None),
    ]);
    {
        let p2 = b.cnc.process_mut(2).expect("p2");
        p2.load(
            "magazine",
            vec![
                block(10, Aux, 0.0, &[0], None, None),
                block(20, Aux, 0.0, &[30], None, None),
            ],
        )
        .expect("idle");
        p2.command(crate::Command::SetMode(crate::Mode::Auto));
    }
    b.run(1, &Plc::default());
    // START for both: process 1 through the fixture's PLC (seen at t2), process 2 on its own
    // START bit, set before tick 1 (seen at t1).
    sig("U30K3").write(&mut b.out, 1);
    b.step(&Plc {
        start: 1,
        ..Plc::default()
    });
    let mut p2_strobes = Vec::new();
    for _ in 0..10 {
        b.step(&Plc::default());
        let stb = sig("I6K0").read(&b.image);
        sig("U30K0").write(&mut b.out, stb); // the magazine logic answers at once
        p2_strobes.push((stb, sig("W7K0").read(&b.image)));
    }
    // Process 2: M00 (t1 code, t2 strobe, t3 FIN seen, t4 done → paused); START stays 1: no edge.
    assert_eq!(p2_strobes[0], (1, 0x00));
    assert_eq!(p2_strobes[1], (0, 0x00));
    assert_eq!(b.cnc.processes()[1].state().interp, Interp::Paused);
    assert_eq!(b.cnc.processes()[1].counters().handshakes[0], 1);
    // Process 1 meanwhile moved to X = 2 and ended with M30 (t2 X=1, t3 X=2 + code, t4..t6).
    assert_eq!(b.cnc.processes()[0].counters().ended, 1);
    assert_eq!(b.cnc.processes()[0].set_points(), &[2.0]);
    // A new START edge for process 2 resumes it to its M30.
    sig("U30K3").write(&mut b.out, 0);
    b.step(&Plc::default());
    sig("U30K3").write(&mut b.out, 1);
    for _ in 0..6 {
        b.step(&Plc::default());
        let stb = sig("I6K0").read(&b.image);
        sig("U30K0").write(&mut b.out, stb);
    }
    assert_eq!(b.cnc.processes()[1].counters().ended, 1);
    assert_eq!(b.cnc.processes()[1].counters().handshakes[0], 2);
}

#[test]
fn the_block_skip_switch_at_start_selects_the_skipped_plan() {
    for (bskip, blocks) in [(0, 3), (1, 2)] {
        let mut b = Bench::new(cnc(false, 0, 0));
        let plain = vec![
            block(10, Linear, 1.0, &[], None, None),
            block(20, Linear, 2.0, &[], None, None),
            block(30, Aux, 2.0, &[30], None, None),
        ];
        let skipped = vec![plain[1].clone(), plain[2].clone()];
        b.start_program(Vec::new());
        b.cnc
            .process_mut(1)
            .expect("p1")
            .load_with_skip("t", plain.into(), skipped.into())
            .expect("idle");
        let plc = Plc {
            bskip,
            ..Plc::default()
        };
        b.run(1, &plc);
        b.step(&Plc { start: 1, ..plc });
        b.run(10, &plc);
        let c = b.cnc.processes()[0].counters();
        assert_eq!((c.blocks, c.ended), (blocks, 1), "BSKIP {bskip}");
    }
}

#[test]
fn look_ahead_queues_function_free_blocks_so_den_stays_low_between_them() {
    let mut b = Bench::new(cnc(false, 0, 0));
    b.start_program(vec![
        block(10, Linear, 1.0, &[], None, None),
        block(20, Linear, 2.0, &[], None, None),
        block(30, Linear, 3.0, &[30], None, None),
    ]);
    b.run(1, &Plc::default());
    b.step(&Plc {
        start: 1,
        ..Plc::default()
    });
    let rows = b.run(4, &Plc::default());
    // t2..t4: X = 1, 2, 3 without DEN between the blocks (all three queued at t2); t4 DEN and the
    // M30 code (after motion); t5 MSTB.
    assert_eq!(
        rows.iter().map(|r| (r[0], r[3])).collect::<Vec<_>>(),
        [(0, 0), (0, 0), (0, 1), (1, 1)]
    );
    assert_eq!(b.cnc.processes()[0].counters().blocks, 2);
}

#[test]
fn an_immediate_function_goes_to_mimm_without_a_handshake() {
    let mut b = Bench::new(cnc(false, 0, 0));
    b.start_program(vec![
        block(10, Linear, 2.0, &[50], None, None),
        block(20, Aux, 2.0, &[30], None, None),
    ]);
    b.run(1, &Plc::default());
    b.step(&Plc {
        start: 1,
        ..Plc::default()
    });
    let mut mimm = Vec::new();
    for _ in 0..7 {
        let r = b.step(&Plc::default());
        mimm.push((sig("W3K1").read(&b.image), r[0]));
    }
    // M50 (m_type 10): 50H in MIMM while N10 moves (t2: X = 1), no strobe; at t3 N10 ends
    // (X = 2) and N20, which has none, clears it and writes M30's code; M30's strobe at t4.
    assert_eq!(
        mimm,
        [(0x50, 0), (0, 0), (0, 1), (0, 0), (0, 0), (0, 0), (0, 0)]
    );
    assert_eq!(b.cnc.processes()[0].counters().handshakes[0], 1);
}

#[test]
fn reset_with_the_estop_chain_still_open_raises_the_alarm_again() {
    let mut b = Bench::new(cnc(false, 0, 0));
    b.run(2, &Plc::default());
    let open = Plc {
        estop: 0,
        ..Plc::default()
    };
    b.run(2, &open); // the scan opens the chain, the kernel sees it
    assert_eq!(b.cnc.processes()[0].alarms().len(), 1);
    b.step(&Plc {
        estop: 0,
        ers: 1,
        ..Plc::default()
    }); // ERS in the scan, chain still open
    b.step(&open); // ERS edge: RESET clears the list, the open chain raises the alarm again
    let p = &b.cnc.processes()[0];
    let alarms: Vec<&str> = p.alarms().iter().map(|a| a.message.as_str()).collect();
    assert_eq!(alarms, ["process 1: emergency stop"]);
    assert!(!p.state().on);
    b.run(3, &open);
    assert_eq!(b.cnc.processes()[0].alarms().len(), 1, "raised once");
    // Closed again: RESET clears it for good.
    b.step(&Plc {
        ers: 1,
        ..Plc::default()
    });
    b.run(2, &Plc::default());
    assert!(b.cnc.processes()[0].alarms().is_empty());
    assert!(b.cnc.processes()[0].state().on);
}

#[test]
fn a_halted_plc_stops_every_process_for_good() {
    let mut b = Bench::new(cnc(false, 0, 0));
    b.run(2, &Plc::default());
    assert!(b.cnc.processes()[0].state().on);
    // The runtime tripped on overruns: the outputs the kernel reads are frozen with ESTOP closed.
    b.cnc.plc_halted();
    b.cnc.plc_halted(); // once is enough
    b.run(2, &Plc::default());
    let p = &b.cnc.processes()[0];
    let alarms: Vec<&str> = p.alarms().iter().map(|a| a.message.as_str()).collect();
    assert_eq!(
        alarms,
        [
            "process 1: the PLC logic halted (scan overruns)",
            "process 1: emergency stop"
        ]
    );
    assert!(!p.state().on);
    // A RESET (ERS) clears the list, but the machine stays off: the logic no longer runs.
    b.step(&Plc {
        ers: 1,
        ..Plc::default()
    });
    b.run(2, &Plc::default());
    assert!(!b.cnc.processes()[0].state().on);
}
