//! MDI blocks planned off the kernel's thread ([`crate::Cnc::mdi_planned`]): loaded as they are
//! while the set points are the position they were planned from, compiled again here otherwise.

use std::sync::Arc;

use partprogram::canon::Kind as CanonKind;

use super::fixture::{Bench, Plc, block, cnc};
use crate::Mode;

/// A kernel whose MDI "compiler" plans one rapid 2 mm further along X from where X stands.
fn bench() -> Bench {
    let mut c = cnc(false, 100, 100);
    c.set_mdi_compiler_at(Arc::new(|_, _, at: &[(char, f64)]| {
        let x = at.iter().find(|(c, _)| *c == 'X').map_or(0.0, |(_, x)| *x);
        Ok(vec![block(1, CanonKind::Rapid, x + 2.0, &[], None, None)])
    }));
    let mut b = Bench::new(c);
    b.run(2, &Plc::default());
    b.cnc.mode(1, Mode::Mdi).expect("MDI mode");
    b.run(1, &Plc::default());
    b
}

fn x(b: &Bench) -> f64 {
    b.cnc.processes()[0].set_points()[0]
}

#[test]
fn planned_blocks_load_as_they_are_while_the_axes_stand_where_they_were_planned_from() {
    let mut b = bench();
    let at = b.cnc.mdi_start(1).expect("process 1");
    assert_eq!(at, vec![('X', 0.0)]);
    let compile = b.cnc.mdi_compiler_at().expect("shared compiler");
    let blocks = compile(1, "N1 G00 U2", &at).expect("compiles");
    b.cnc
        .mdi_planned(1, "N1 G00 U2", &at, blocks)
        .expect("accepted");
    assert_eq!(
        b.cnc.mdi_compiles(),
        0,
        "the kernel compiled nothing itself"
    );
    b.run(4, &Plc::default());
    assert_eq!(x(&b), 2.0);
}

#[test]
fn planned_blocks_from_a_stale_position_are_compiled_again_from_the_set_points() {
    let mut b = bench();
    // Planned from X 1 (the axis has since moved to 0), to X -3: the kernel sees X at 0 and
    // plans the text again from there (to X 2), as a replay's `mdi` at this tick would.
    let stale = vec![('X', 1.0)];
    let blocks = vec![block(1, CanonKind::Rapid, -3.0, &[], None, None)];
    b.cnc
        .mdi_planned(1, "N1 G00 U2", &stale, blocks)
        .expect("accepted");
    assert_eq!(b.cnc.mdi_compiles(), 1);
    b.run(4, &Plc::default());
    assert_eq!(x(&b), 2.0);
}
