//! A feed override lowered while the S law decelerates the last piece once left a replanned
//! profile ending at rest short of the piece end, and nothing moved the axes again (found by
//! `props::random_paths_s_law`, shrunk to an arc and a line): the kernel now goes on from rest.

use crate::common::{Cmd, arc, line, mill, run};
use detmath::Det as _;
use motion::Law;

#[test]
fn an_override_lowered_during_an_s_law_deceleration_still_reaches_the_end() {
    let cfg = mill(Law::SCurve);
    let feed = 2139.410607729042;
    // The shrunk case: a counter-clockwise arc around (d·scale) from the origin, then a line of
    // 7.483974 mm along X; override 128 % at tick 19, back to 100 % at tick 3000.
    let scale = 0.5757618136318392;
    let c = [4.258542096153362 * scale, 8.056551271938387 * scale];
    let r = c[0].dhypot(c[1]);
    let a1 = (-c[1]).datan2(-c[0]) + 0.3 + 5.0 * scale;
    let e = [c[0] + r * a1.dcos(), c[1] + r * a1.dsin(), 0.0];
    let end = [e[0] + 7.483974378351711, e[1], 0.0];
    let moves = vec![arc(0, e, c, false, feed), line(1, end, feed)];
    let cmds = [(19, Cmd::Override(128)), (3000, Cmd::Override(100))];
    let a = run(&cfg, &[0.0; 3], &moves, &cmds);
    assert_eq!(a.finished, vec![0, 1], "both blocks end, in order");
    assert_eq!(a.points.last(), Some(&end.to_vec()), "the exact end point");
}
