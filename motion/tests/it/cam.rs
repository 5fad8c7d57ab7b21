//! The CAM benchmark set (issue 22) through the kernel with contour control (tolerance-band
//! smoothing and complex speed) and the independent monitor: every axis within its limits and
//! every set point within the tolerance of the programmed polyline at every tick, every block
//! finished once and in order. The long programs are in the kernel bench.

use crate::common;

use common::{assert_within, mill, run, run_with};
use motion::{Law, bound::lower_bound, cam};

fn check(p: &cam::CamProgram, law: Law) -> f64 {
    let cfg = mill(law);
    let r = run_with(&cfg, &p.start, &p.moves, &[], true);
    assert_within(&r.report, cfg.tolerance_mm);
    let tags: Vec<u64> = p.moves.iter().map(|m| m.tag).collect();
    assert_eq!(
        r.finished, tags,
        "{}: every block finished once, in order",
        p.name
    );
    assert_eq!(
        r.points.last().map(|v| v.as_slice()),
        p.moves.last().map(|m| m.end.as_slice())
    );
    r.points.len() as f64 * 0.001
}

#[test]
fn short_cam_programs_stay_within_the_limits_and_the_tolerance_under_contour_control() {
    for p in [
        cam::circle(5.0, 0.5, 3, 3000.0),
        cam::circle(20.0, 0.08, 4, 6000.0),
        cam::ellipse(30.0, 15.0, 0.1, 3, 6000.0),
        cam::freeform(0.2, 3, 5000.0),
        cam::raster(2, 0.2, 3, 6000.0),
        cam::pocket(2, 0.1, 3, 4000.0),
    ] {
        check(&p, Law::Linear);
    }
}

#[test]
fn the_s_law_keeps_the_jerk_limit_under_contour_control() {
    for p in [
        cam::circle(20.0, 0.08, 3, 6000.0),
        cam::raster(2, 0.2, 3, 3000.0),
    ] {
        check(&p, Law::SCurve);
    }
}

#[test]
fn a_rounded_chord_circle_runs_near_the_feed_with_smoothing() {
    // The circle, r 20 mm, 1571 chords of 0.08 mm at F6000, with its coordinates
    // rounded to 0.001 mm (1.61 × the bound without smoothing, 1.082 with it).
    let p = cam::circle(20.0, 0.08, 3, 6000.0);
    let cfg = mill(Law::Linear);
    let lb = lower_bound(&cfg, &p.start, &p.moves);
    let plain = run(&cfg, &p.start, &p.moves, &[]).points.len() as f64 * 0.001;
    let smooth = check(&p, Law::Linear);
    println!("bound {lb:.3} s, plain {plain:.3} s, smoothed {smooth:.3} s");
    assert!(smooth / lb <= 1.10, "ratio {}", smooth / lb);
    assert!(smooth < plain);
}

#[test]
fn short_cam_programs_are_faster_than_linuxcnc() {
    // LinuxCNC 2.9's time / bound on the same programs and limits (motion/compare/linuxcnc,
    // 2026-11-28, README).
    let cfg = mill(Law::Linear);
    for (p, linuxcnc) in [
        (cam::circle(5.0, 0.5, 3, 3000.0), 1.1503),
        (cam::circle(20.0, 0.08, 3, 6000.0), 1.1485),
        (cam::ellipse(30.0, 15.0, 0.1, 3, 6000.0), 1.1423),
        (cam::freeform(0.2, 3, 5000.0), 1.1318),
    ] {
        let t = check(&p, Law::Linear);
        let lb = lower_bound(&cfg, &p.start, &p.moves);
        assert!(t / lb < linuxcnc, "{}: {} ≥ {linuxcnc}", p.name, t / lb);
    }
}

/// R382 under contour control: a block (0.3 mm) shorter than it (0.5 mm) interrupts the smooth
/// connection — the path stops at the block's start (within one tick's deceleration: at most a · Ts = 1 mm/s) —
/// while without it the straight path keeps F through the short block; both within the limits.
#[test]
fn a_block_shorter_than_r382_stops_the_path_at_its_start() {
    let moves = [
        common::line(0, [5.0, 0.0, 0.0], 3000.0),
        common::line(1, [5.3, 0.0, 0.0], 3000.0),
        common::line(2, [10.0, 0.0, 0.0], 3000.0),
    ];
    let lowest_inside = |cfg: &motion::Config| {
        let r = run_with(cfg, &[0.0; 3], &moves, &[], true);
        assert_within(&r.report, cfg.tolerance_mm);
        assert_eq!(r.finished, [0, 1, 2]);
        // The speed between X2 and X8 (the ramps from and to rest are 1.25 mm long).
        let lowest = r
            .points
            .windows(2)
            .filter(|w| (2.0..8.0).contains(&w[0][0]))
            .map(|w| (w[1][0] - w[0][0]) / 0.001)
            .fold(f64::INFINITY, f64::min);
        (lowest, r.points.len())
    };
    let mut cfg = mill(Law::Linear);
    let (v_off, n_off) = lowest_inside(&cfg);
    cfg.complex.set_constant(382, 500).expect("R382 500 µm");
    let (v_on, n_on) = lowest_inside(&cfg);
    assert!(v_off > 49.9, "without R382 the path keeps 50 mm/s: {v_off}");
    assert!(v_on <= 1.0 + 1e-9, "with R382 the path stops at X5: {v_on}");
    // The stop costs a ramp down and up of 50 ms each over 2.5 mm, which took 50 ms at F.
    assert_eq!(
        n_on,
        n_off + 50,
        "{n_on} ticks with the stop, {n_off} without"
    );
}
