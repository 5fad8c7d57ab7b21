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
    let (io, d) = run(include_str!("fixtures/iocfil_example.txt"));
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
