//! Property tests: random lines, arcs, helices, short segments and reversals under random
//! override and hold sequences stay within every limit and the tolerance, end exactly at the
//! last programmed point, and run bit-identically twice.

use crate::common;
use detmath::Det as _;

use common::{Cmd, arc, assert_within, line, mill, run};
use motion::{Law, Move};
use proptest::prelude::*;

/// One random step: a line of random length and direction (short ones included, reversals
/// from the sign flips) or an arc/helix around a centre beside the current point.
fn path() -> impl Strategy<Value = Vec<(u8, [f64; 3], f64, bool)>> {
    prop::collection::vec(
        (
            0u8..3,
            [-10.0f64..10.0, -10.0f64..10.0, -3.0f64..3.0],
            0.05f64..1.0,
            any::<bool>(),
        ),
        1..20,
    )
}

fn moves(steps: &[(u8, [f64; 3], f64, bool)], feed: f64) -> Vec<Move> {
    let mut p = [0.0f64; 3];
    let mut out = Vec::new();
    for (i, (kind, d, scale, cw)) in steps.iter().enumerate() {
        let tag = i as u64;
        match kind {
            0 => {
                p = [p[0] + d[0], p[1] + d[1], p[2] + d[2]];
                out.push(line(tag, p, feed));
            }
            1 => {
                // Short segment (0.005–0.1 mm).
                let s = scale * 0.1 / (d[0].dhypot(d[1]).dhypot(d[2]) + 1e-9);
                p = [p[0] + d[0] * s, p[1] + d[1] * s, p[2] + d[2] * s];
                out.push(line(tag, p, feed));
            }
            _ => {
                // Arc of a random sweep around a centre at (d0, d1)·scale from p; Z lift = helix.
                let c = [p[0] + d[0] * scale, p[1] + d[1] * scale];
                let r = (p[0] - c[0]).dhypot(p[1] - c[1]);
                if r < 1e-3 {
                    continue;
                }
                let a0 = (p[1] - c[1]).datan2(p[0] - c[0]);
                let a1 = a0 + (if *cw { -1.0 } else { 1.0 }) * (0.3 + 5.0 * scale);
                let e = [c[0] + r * a1.dcos(), c[1] + r * a1.dsin(), p[2] + d[2]];
                out.push(arc(tag, e, c, *cw, feed));
                p = e;
            }
        }
    }
    out
}

fn commands(raw: &[(usize, u16, u8)]) -> Vec<(usize, Cmd)> {
    raw.iter()
        .map(|&(at, pct, kind)| match kind {
            0 => (at, Cmd::Override(pct)),
            1 => (at, Cmd::Hold(true)),
            _ => (at, Cmd::Hold(false)),
        })
        .chain(std::iter::once((3000, Cmd::Hold(false))))
        .chain(std::iter::once((3000, Cmd::Override(100))))
        .collect()
}

fn check(law: Law, steps: &[(u8, [f64; 3], f64, bool)], feed: f64, raw: &[(usize, u16, u8)]) {
    let cfg = mill(law);
    let ms = moves(steps, feed);
    if ms.is_empty() {
        return;
    }
    let cmds = commands(raw);
    let a = run(&cfg, &[0.0; 3], &ms, &cmds);
    assert_within(&a.report, cfg.tolerance_mm);
    let last = ms.last().map(|m| m.end.clone()).unwrap_or_default();
    assert_eq!(a.points.last(), Some(&last), "exact end point");
    let tags: Vec<u64> = ms.iter().map(|m| m.tag).collect();
    assert_eq!(a.finished, tags, "every block's DEN once, in order");
    let b = run(&cfg, &[0.0; 3], &ms, &cmds);
    assert!(a.points == b.points, "bit-identical rerun");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    #[test]
    fn random_paths_linear_law(steps in path(), feed in 1200.0f64..9000.0,
                               raw in prop::collection::vec((0usize..2500, 0u16..256, 0u8..3), 0..6)) {
        check(Law::Linear, &steps, feed, &raw);
    }

    #[test]
    fn random_paths_s_law(steps in path(), feed in 1200.0f64..9000.0,
                          raw in prop::collection::vec((0usize..2500, 0u16..256, 0u8..3), 0..6)) {
        check(Law::SCurve, &steps, feed, &raw);
    }

    #[test]
    fn random_paths_exponential_law(steps in path(), feed in 1200.0f64..9000.0,
                                    raw in prop::collection::vec((0usize..2500, 0u16..256, 0u8..3), 0..6)) {
        check(Law::Exponential, &steps, feed, &raw);
    }
}
