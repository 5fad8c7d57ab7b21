//! The manual's IOCFIL examples (§2.6, §2.2.5, §2.4.6) and the fragments of chapter 6: each loads,
//! or fails with exactly the errors the manual implies.

use characterization::iocfil::{self, Handwheel, Sequencing};
use characterization::reader::read;

/// (code, line, column) of every diagnostic of reading + decoding `src` as IOCFIL.
fn run(src: &str) -> (iocfil::Iocfil, Vec<(u32, u32, u32)>) {
    let (file, mut diags) = read("IOCFIL", src.as_bytes());
    let (io, more) = iocfil::parse(&file);
    diags.extend(more);
    (
        io,
        diags.iter().map(|d| (d.code, d.line, d.column)).collect(),
    )
}

#[test]
fn full_example_loads_and_decodes() {
    let (io, d) = run(include_str!("../fixtures/iocfil_example.txt"));
    assert_eq!(d, []);
    assert_eq!(io.alm, Some(0));
    assert!(io.plc_autoload());
    assert_eq!(io.input_connectors(), [0, 1, 2, 3]);
    assert_eq!(io.inputs[0].index, 1);
    assert_eq!(io.output_connectors(), [4, 5]);
    assert_eq!((io.tick_logic_ms, io.time_slow_ms), (10, 3));
    assert_eq!(io.spl, None);
    assert_eq!(io.spl_or_default(), 1);
    assert_eq!(io.processes.len(), 2);
    let p1 = &io.processes[0];
    assert_eq!(p1.m_functions.len(), 16);
    let m00 = p1.m_function(0).copied().map(|m| {
        (
            m.m_type,
            m.m_request,
            m.class,
            m.flags.stop_at_end,
            m.flags.blocks_calculation,
            m.flags.after_motion,
        )
    });
    assert_eq!(m00, Some((0x06, 0x0C, 0x00, true, true, true)));
    let m03 = p1.m_function(3).copied();
    assert_eq!(
        m03.map(|m| (
            m.flags.before_motion,
            m.flags.in_stop,
            m.flags.modal,
            m.search_class(),
            m.display_class()
        )),
        Some((true, true, true, 2, 1))
    );
    let m06 = p1.m_function(6).copied();
    assert_eq!(
        m06.map(|m| (
            m.flags.tool_offset_request,
            m.flags.blocks_calculation,
            m.search_class(),
            m.display_class()
        )),
        Some((true, true, 6, 2))
    );
    assert_eq!(p1.m_function(30).map(|m| m.flags.reset_request), Some(true));
    assert_eq!(p1.m_function(4), None);
    assert_eq!(p1.sequencing(), Sequencing::Sequential);
    // Process 2 writes the same declarations with one-digit hex: identical values.
    let p2 = &io.processes[1];
    let strip = |p: &iocfil::IoProcess| {
        p.m_functions
            .iter()
            .map(|m| (m.number, m.m_type, m.m_request, m.class))
            .collect::<Vec<_>>()
    };
    assert_eq!(strip(p1), strip(p2));
    assert_eq!(p1.spindle, Some('S'));
    let ta = p1.ptp_axes[0];
    assert_eq!(
        (
            ta.number,
            ta.axis,
            ta.axis_type,
            ta.has_dac(),
            ta.rotary(),
            ta.absolute()
        ),
        (1, 'V', 0x0E, false, true, true)
    );
    assert_eq!(
        (ta.positions, ta.limit_1, ta.limit_2),
        (Some(32.0), Some(0.7), Some(0.3))
    );
    let as1 = p1.index_axes[0];
    assert_eq!(
        (as1.axis, as1.incremental, as1.linear, as1.positions),
        ('B', false, false, 360)
    );
    assert_eq!(p1.ucda, ['B']);
    assert_eq!(p1.cwd, Some(0x40));
    assert_eq!(
        p1.adv,
        Some([Some(Handwheel::Axis('A')), Some(Handwheel::Electronic)])
    );
    assert_eq!(
        (p2.spindle, p2.cwd, p2.ptp_axes.len()),
        (Some('S'), Some(0x40), 0)
    );
    assert_eq!(
        io.t_bytes(),
        [
            (0, 0x10),
            (1, 0),
            (2, 0x10),
            (3, 0),
            (4, 0x15),
            (5, 0),
            (6, 2),
            (7, 0),
            (8, 9),
            (9, 0),
            (10, 2),
            (11, 0)
        ]
    );
}

/// Wraps section bodies into an otherwise valid IOCFIL (CLO is added to section 1 unless given).
fn wrap(s1: &str, s2: &str, s3: &str, s4: &str) -> String {
    let clo = if s1.contains("CLO") { "" } else { "CLO=10,2\n" };
    format!("*1\n{clo}{s1}*2\n{s2}*3\n{s3}*4\n{s4}")
}

#[test]
fn section1_example_has_a_seven_field_ou0() {
    // §2.2.5 (003:5772-5779): `OU0=4,5,,,,,` has 7 of OUx's 8 parameters, so it breaks the fixed
    // parameter count (error 10, at the end of the record). Everything else loads.
    let src = "*1\nALM=0\nIN0=0,1,2,3,,,,\nOU0=4,5,,,,,\nCLO=10,2\nSPL=400\n*2\n*3\n*4\n";
    let (io, d) = run(src);
    assert_eq!(d, [(10, 4, 13)]);
    assert_eq!(io.input_connectors(), [0, 1, 2, 3]);
    assert_eq!(io.spl, Some(400));
    let (io, d) = run(&src.replace("OU0=4,5,,,,,", "OU0=4,5,,,,,,"));
    assert_eq!(d, []);
    assert_eq!(io.output_connectors(), [4, 5]);
}

#[test]
fn alm_commented_out_is_debug_mode() {
    let (io, d) = run(&wrap(";ALM=0\n", "", "", ""));
    assert_eq!(d, []);
    assert!(!io.plc_autoload());
}

#[test]
fn connector_examples_with_blank_fields() {
    for (line, ins, outs) in [
        ("IN0=0,1,2,3, , , ,\n", vec![0, 1, 2, 3], vec![]),
        ("IN0=0,1, , , , , ,\n", vec![0, 1], vec![]),
        ("OU0=4,5, , , , , ,\n", vec![], vec![4, 5]),
    ] {
        let (io, d) = run(&wrap(line, "", "", ""));
        assert_eq!(d, [], "{line}");
        assert_eq!(
            (io.input_connectors(), io.output_connectors()),
            (ins, outs),
            "{line}"
        );
    }
}

#[test]
fn typical_m_declarations() {
    let (io, d) = run(&wrap(
        "",
        "PRO=1\nM01=02,02,10\nM00=02,08,10\nM30=02,24,10\nM03=45, 00, 11\n",
        "",
        "",
    ));
    assert_eq!(d, []);
    let p = &io.processes[0];
    assert_eq!(
        p.m_function(1)
            .map(|m| (m.flags.optional_stop, m.search_class(), m.display_class())),
        Some((true, 1, 0))
    );
    assert_eq!(p.m_function(0).map(|m| m.flags.stop_at_end), Some(true));
    assert_eq!(
        p.m_function(30)
            .map(|m| (m.flags.reset_request, m.flags.blocks_calculation)),
        Some((true, true))
    );
    assert_eq!(
        p.m_function(3).map(|m| (
            m.flags.before_motion,
            m.flags.in_stop,
            m.flags.modal,
            m.class
        )),
        Some((true, true, true, 0x11))
    );
}

#[test]
fn handwheel_example_iocfil() {
    // §2.4.6: the `.....` lines stand for omitted text; `.` cannot start a line (error 2).
    let verbatim = ";Файл IOCFIL:\n*1\n.....\n*2\n.....\n*3\n.....\nADV=P,0\n*4\n";
    let (_, d) = run(verbatim);
    assert_eq!(d, [(2, 3, 1), (2, 5, 1), (2, 7, 1), (116, 2, 1)]);
    let (io, d) = run(&wrap("", "", "PRO=1\nADV=P,0\n", ""));
    assert_eq!(d, []);
    assert_eq!(
        io.processes[0].adv,
        Some([Some(Handwheel::Axis('P')), Some(Handwheel::Electronic)])
    );
}

#[test]
fn dac_examples_and_asm() {
    let (io, d) = run(&wrap("", "", "PRO=1\nASM=S\nDAC=1,2,8,14,16,,,\n", ""));
    assert_eq!(d, []);
    assert_eq!(io.processes[0].dac, [1, 2, 8, 14, 16]);
    let (io, d) = run(&wrap(
        "",
        "",
        "PRO=1\nDAC=-201,-202,-208,-214,-216,,,\n",
        "",
    ));
    assert_eq!(d, []);
    assert_eq!(io.processes[0].dac, [-201, -202, -208, -214, -216]);
}

#[test]
fn packet_t_mapping() {
    let (io, d) = run(&wrap("", "", "", "T01=AA\nT05=1\nT63=FE\nT64=FF\n"));
    assert_eq!(d, []);
    // T01 -> W0T0 (byte 0), T05 -> W1T0 (byte 4), T63 -> W15T2 (62), T64 -> W15T3 (63).
    assert_eq!(io.t_bytes(), [(0, 0xAA), (4, 1), (62, 0xFE), (63, 0xFF)]);
}

#[test]
fn suggested_vectors_of_the_spec() {
    assert_eq!(run(&wrap("CLO=0,0\n", "", "", "")).1, [(103, 2, 5)]);
    assert_eq!(
        run(&wrap("", "PRO=1\nM05=00,00,21\n", "", "")).1,
        [(113, 5, 5)]
    );
    assert_eq!(run(&wrap("", "PRO=1\nGPS=2\n", "", "")).1, [(130, 5, 5)]);
}
