//! Closed-form profiles: a lone line under the three laws, a full circle at the centripetal
//! limit, the feed-hold stop distance, arc soft limits and a point-to-point move.

use crate::common;
use detmath::Det as _;

use common::{Cmd, Run, arc, assert_within, line, mill, run};
use motion::{Kernel, Law, MotionError, Move, Path, PtpAxis};

const DT: f64 = 0.001;

fn ticks(t: f64) -> usize {
    (t / DT).ceil() as usize
}

#[test]
fn lone_line_trapezoid_time() {
    // X 100 mm at F3000 = 50 mm/s; tangential acceleration 0.98 × 1000: T = L/v + v/A.
    let r = run(
        &mill(Law::Linear),
        &[0.0; 3],
        &[line(1, [100.0, 0.0, 0.0], 3000.0)],
        &[],
    );
    assert_eq!(r.points.len(), ticks(100.0 / 50.0 + 50.0 / 980.0)); // 2052
    assert_eq!(r.points.last(), Some(&vec![100.0, 0.0, 0.0]));
    assert_eq!(r.finished, vec![1]);
    assert_within(&r.report, 0.01);
}

#[test]
fn lone_line_s_curve_time() {
    // S law: peak acceleration 1.5 × 1000 × 0.98 = 1470, axis jerk 1500² / (2 · 0.5 · 100)
    // = 22500, of which 0.68 for the path tangent = 15300. 0 → 50 mm/s: 50 < 1470²/15300, so
    // the acceleration is triangular, Tc = 2√(50/15300); T = L/v + Tc.
    let r = run(
        &mill(Law::SCurve),
        &[0.0; 3],
        &[line(1, [100.0, 0.0, 0.0], 3000.0)],
        &[],
    );
    let tc = 2.0 * (50.0f64 / 15300.0).sqrt();
    assert_eq!(r.points.len(), ticks(2.0 + tc)); // 2115
    assert_eq!(r.points.last(), Some(&vec![100.0, 0.0, 0.0]));
    assert_within(&r.report, 0.01);
    // The jerk reaches its share of the limit (0.68 of 22500) within 1 %.
    let j = r.report.j[0].expect("jerk limited");
    assert!((j - 0.68).abs() < 0.01, "{j}");
}

#[test]
fn lone_line_exponential_time() {
    // Exponential law, ACC min_exp 1, max_exp 4: the acceleration grows from 980/4 to 980;
    // a change of dv takes Tc = dv·ln 4 / (980 − 245) and covers Tc·(lo + c·dv) with
    // c = 1/ln 4 − 1/3; accelerate 0 → 50 and back: T = L/v + 2·Tc·(1 − c).
    let r = run(
        &mill(Law::Exponential),
        &[0.0; 3],
        &[line(1, [100.0, 0.0, 0.0], 3000.0)],
        &[],
    );
    let tc = 50.0 * 4.0f64.dln() / 735.0;
    let c = 1.0 / 4.0f64.dln() - 1.0 / 3.0;
    assert_eq!(r.points.len(), ticks(2.0 + 2.0 * tc * (1.0 - c))); // 2115
    assert_eq!(r.points.last(), Some(&vec![100.0, 0.0, 0.0]));
    assert_within(&r.report, 0.01);
}

#[test]
fn full_circle_at_the_centripetal_limit() {
    // r = 10 mm at F6000 (100 mm/s): 70 % of 1000 mm/s² as centripetal acceleration caps the
    // speed at √(700 · 10) = 83.666 mm/s; on a planar arc the tangential part adds to it as a
    // vector within 98 % of the limit: a_t = √(980² − 700²) = 685.857 mm/s².
    let m = arc(1, [10.0, 0.0, 0.0], [0.0, 0.0], false, 6000.0);
    let r = run(&mill(Law::Linear), &[10.0, 0.0, 0.0], &[m], &[]);
    let v = 7000.0f64.sqrt();
    let t = 2.0 * std::f64::consts::PI * 10.0 / v + v / (980.0f64 * 980.0 - 700.0 * 700.0).sqrt();
    assert_eq!(r.points.len(), ticks(t)); // 873
    assert_eq!(r.points.last(), Some(&vec![10.0, 0.0, 0.0]));
    assert_within(&r.report, 1e-9);
    // The axes' acceleration never exceeds 98 % of the limit and reaches at least the
    // centripetal 70 % at full speed.
    let a = r.report.a[0];
    assert!((0.7 - 1e-3..=0.98 + 1e-9).contains(&a), "{a}");
}

#[test]
fn feed_hold_stops_in_the_minimum_distance_and_resumes() {
    // Cruising at 100 mm/s along X, hold at tick 1000: the stop takes v²/(2a) = 10⁴/1960 mm.
    let moves = [line(1, [200.0, 0.0, 0.0], 6000.0)];
    let cmds = [(1000, Cmd::Hold(true)), (1500, Cmd::Hold(false))];
    let r = run(&mill(Law::Linear), &[0.0; 3], &moves, &cmds);
    let at_hold = r.points[999][0];
    let held = r.points[1400][0];
    assert!(
        (held - at_hold - 1e4 / 1960.0).abs() < 1e-9,
        "{}",
        held - at_hold
    );
    assert_eq!(r.points[1499][0], held);
    assert_eq!(r.points.last(), Some(&vec![200.0, 0.0, 0.0]));
    assert_within(&r.report, 0.01);
}

#[test]
fn arc_beyond_a_soft_limit_is_refused_with_the_reach() {
    // The half circle (10,0) → (−10,0) counter-clockwise passes (0,10): Y max 9 is crossed
    // although both end points are inside.
    let mut cfg = mill(Law::Linear);
    cfg.axes[1].soft_max = Some(9.0);
    let mut k = Kernel::new(cfg, &[10.0, 0.0, 0.0]).expect("config");
    let e = k.push(arc(7, [-10.0, 0.0, 0.0], [0.0, 0.0], false, 1000.0));
    assert_eq!(
        e,
        Err(MotionError::SoftLimit {
            tag: 7,
            axis: 'Y',
            limit: 9.0,
            reach: 10.0
        })
    );
    assert!(k.is_idle());
}

#[test]
fn ptp_move_is_a_trapezoid() {
    // 100 mm at 50 mm/s, 500 mm/s², no jerk limit: T = 100/50 + 50/500 = 2.1 s.
    let mut p = PtpAxis::new(50.0, 500.0, None, DT, 0.0);
    p.move_to(100.0, 80.0);
    let mut n = 0;
    let mut last = 0.0;
    while !p.is_idle() {
        last = p.tick();
        n += 1;
        assert!(n < 10_000);
    }
    assert_eq!(last, 100.0);
    assert!((2100..=2101).contains(&n), "{n}");
}

#[test]
fn benchmark_programs_never_slower_than_linuxcnc() {
    // LinuxCNC 2.9's planner on the same programs and limits, headless
    // (motion/compare/linuxcnc/run.sh, 2026-11-25): time / lower bound per program. The squares
    // and the CAM raster stop at their 90° corners (a 0.01 mm blend admits ~4 mm/s), which the
    // bound ignores; the chord circle's acceleration from rest along one axis costs ≥ 0.1 s.
    use motion::{bound::lower_bound, samples};
    let cfg = mill(Law::Linear);
    for (name, moves, linuxcnc) in [
        ("squares", samples::squares(), 1.2147),
        ("circles", samples::circles(), 1.1037),
        ("zigzag", samples::zigzag(), 1.0173),
        ("chord_circle", samples::chord_circle(), 1.1481),
        ("spiral", samples::spiral(), 1.0057),
        ("cam", samples::cam(20), 1.1923),
    ] {
        let start = samples::start(name);
        let r = run(&cfg, &start, &moves, &[]);
        assert_within(&r.report, cfg.tolerance_mm);
        let t = r.points.len() as f64 * DT;
        let lb = lower_bound(&cfg, &start, &moves);
        println!("{name}: {t:.3} s, bound {lb:.3} s, ratio {:.4}", t / lb);
        assert!(t / lb < linuxcnc, "{name}: ratio {} ≥ {linuxcnc}", t / lb);
    }
}

/// A kernel 500 ticks into line 1 of two (X 0→100, then Y to 50, blended), cruising at 100 mm/s.
fn cruising_along_x() -> Kernel {
    let mut k = Kernel::new(mill(Law::Linear), &[0.0; 3]).expect("config");
    k.push(line(1, [100.0, 0.0, 0.0], 6000.0)).expect("push");
    k.push(line(2, [100.0, 50.0, 0.0], 6000.0)).expect("push");
    for _ in 0..500 {
        k.tick();
    }
    k
}

#[test]
fn abort_stops_in_the_minimum_distance_and_clears_the_queue() {
    // Cruising at 100 mm/s along X (line 1 of 2), abort at tick 500: line 1 starts at rest and
    // ends in a corner blend, so it keeps no kink reserve: the stop takes 10⁴/2000 mm at the full
    // 1000 mm/s²; the queue is dropped (no DEN), and a new move starts from where the axes stopped.
    let mut k = cruising_along_x();
    let at = k.position()[0];
    k.abort();
    let mut n = 0;
    while !k.is_idle() {
        assert!(k.tick().finished.is_empty());
        n += 1;
        assert!(n < 1000);
    }
    assert!((k.position()[0] - at - 1e4 / 2000.0).abs() < 1e-9);
    assert_eq!(k.space(), 500);
    let stop = k.position().to_vec();
    k.push(line(3, [0.0, 0.0, 0.0], 6000.0))
        .expect("push after abort");
    let first = k.tick().position.clone();
    assert!(
        first[0] < stop[0] && first[0] > stop[0] - 0.01,
        "{first:?} from {stop:?}"
    );
}

#[test]
fn stop_at_block_end_holds_at_the_block_end_point() {
    // Two lines with a blended corner; stop at the end of block 1: the axes rest at (50, 0),
    // block 1's DEN comes, block 2 waits for the release.
    let mut k = Kernel::new(mill(Law::Linear), &[0.0; 3]).expect("config");
    k.push(line(1, [50.0, 0.0, 0.0], 6000.0)).expect("push");
    k.push(line(2, [50.0, 50.0, 0.0], 6000.0)).expect("push");
    k.tick();
    k.stop_at_block_end();
    let mut den = Vec::new();
    for _ in 0..2000 {
        den.extend(k.tick().finished.clone());
    }
    assert_eq!(den, vec![1]);
    assert_eq!(k.position(), &[50.0, 0.0, 0.0]);
    assert!(k.tick().held);
    k.set_hold(false);
    while !k.is_idle() {
        den.extend(k.tick().finished.clone());
    }
    assert_eq!(den, vec![1, 2]);
    assert_eq!(k.position(), &[50.0, 50.0, 0.0]);
}

#[test]
fn raising_the_override_speeds_up_an_arc_already_planned() {
    // A full circle r = 10 mm at F3000 (50 mm/s) is planned at 100 %: its ceiling is 50 mm/s and
    // the tangential acceleration √(980² − (50²/10)²) = 947.63 mm/s². At tick 500 (cruising) the
    // override goes to 150 %: the queued arc re-tunes to 75 mm/s with √(980² − 562.5²) =
    // 802.50 mm/s² and speeds up (before, planned arcs kept their speed).
    let m = arc(1, [10.0, 0.0, 0.0], [0.0, 0.0], false, 3000.0);
    let r = run(
        &mill(Law::Linear),
        &[10.0, 0.0, 0.0],
        &[m],
        &[(500, Cmd::Override(150))],
    );
    let speed = |w: &[Vec<f64>]| {
        let d: f64 = (0..3).map(|i| (w[1][i] - w[0][i]).powi(2)).sum();
        d.sqrt() / DT
    };
    let peak = r.points.windows(2).map(speed).fold(0.0, f64::max);
    // The chord of 0.075 mm on r = 10 is shorter than the arc by a factor 1 − θ²/24, θ = 0.0075.
    assert!((peak - 75.0).abs() < 1e-3, "{peak}");
    // 0 → 50 at a1, cruise to t = 0.5 s, 50 → 75 and 75 → 0 at a2, cruise between.
    let (a1, a2) = (
        (980.0f64 * 980.0 - 250.0 * 250.0).sqrt(),
        (980.0f64 * 980.0 - 562.5 * 562.5).sqrt(),
    );
    let at_change = 50.0 * 50.0 / (2.0 * a1) + 50.0 * (0.5 - 50.0 / a1);
    let rest = 2.0 * std::f64::consts::PI * 10.0 - at_change;
    let (up, down) = (
        (75.0 * 75.0 - 50.0 * 50.0) / (2.0 * a2),
        75.0 * 75.0 / (2.0 * a2),
    );
    let t = 0.5 + 25.0 / a2 + (rest - up - down) / 75.0 + 75.0 / a2; // 1.0739 s
    let n = r.points.len() as f64;
    assert!((n - t / DT).abs() <= 1.0, "{n} ticks, {t} s");
    assert_eq!(r.points.last(), Some(&vec![10.0, 0.0, 0.0]));
    assert_within(&r.report, 1e-9);
}

#[test]
fn a_raise_the_executed_arc_cannot_absorb_keeps_the_old_ceiling() {
    // An arc of r = 3.303 mm at F2669 (44.48 mm/s, below the centripetal cap √(700 · 3.303) =
    // 48.08 mm/s) ending at rest; at tick 150 it is decelerating with the tangential acceleration
    // of its 44.48 mm/s ceiling. 108 % would raise the ceiling to 48.04 mm/s with a smaller
    // acceleration that can no longer stop it at the end: the raise is refused and the motion
    // is the same as without it (tick for tick; the replan from mid-arc rounds differently).
    let scale = 0.3990946132440193f64;
    let c = [5.949679714521503 * scale, 5.751928022042237 * scale];
    let r0 = c[0].dhypot(c[1]);
    let a0 = (-c[1]).datan2(-c[0]);
    let a1 = a0 + 0.3 + 5.0 * scale;
    let m = arc(
        1,
        [c[0] + r0 * a1.dcos(), c[1] + r0 * a1.dsin(), 0.0],
        c,
        false,
        2669.015,
    );
    let plain = run(&mill(Law::Linear), &[0.0; 3], std::slice::from_ref(&m), &[]);
    let raised = run(
        &mill(Law::Linear),
        &[0.0; 3],
        &[m],
        &[(150, Cmd::Override(108))],
    );
    assert_eq!(raised.points.len(), plain.points.len());
    let gap = raised
        .points
        .iter()
        .zip(&plain.points)
        .flat_map(|(a, b)| a.iter().zip(b).map(|(x, y)| (x - y).abs()))
        .fold(0.0, f64::max);
    assert!(gap < 1e-9, "{gap}");
    assert_within(&raised.report, 1e-9);
}

/// A 0.1 s dwell lasts 100 ticks of 1 ms even when the feed override is set again every tick, to
/// the same value or to a new one (a change replans; a replan used to start the dwell over, so a
/// dwell under a moving override knob never ended).
#[test]
fn a_dwell_ends_while_the_override_is_set_every_tick() {
    let cfg = common::mill(Law::Linear);
    let dwell = |tag| Move {
        tag,
        path: Path::Dwell { seconds: 0.1 },
        end: vec![0.0; 3],
        feed_mm_min: None,
        exact_stop: true,
        tolerance: None,
        thread_pitch: None,
        thread_angle: 0.0,
    };
    let cmds: Vec<(usize, Cmd)> = (0..150).map(|n| (n, Cmd::Override(100))).collect();
    let r = run(&cfg, &[0.0; 3], &[dwell(1)], &cmds);
    assert_eq!(r.finished, vec![1]);
    let mut k = motion::Kernel::new(cfg, &[0.0; 3]).expect("config");
    k.push(dwell(7)).expect("dwell");
    let mut ended = None;
    for n in 1..=200 {
        k.set_feed_override(100);
        if k.tick().finished.contains(&7) {
            ended = Some(n);
            break;
        }
    }
    assert_eq!(ended, Some(100));
    let mut k = motion::Kernel::new(common::mill(Law::Linear), &[0.0; 3]).expect("config");
    k.push(dwell(8)).expect("dwell");
    let mut ended = None;
    for n in 1..=200u16 {
        k.set_feed_override(if n % 2 == 0 { 100 } else { 50 });
        if k.tick().finished.contains(&8) {
            ended = Some(n);
            break;
        }
    }
    assert_eq!(ended, Some(100));
}

#[test]
fn emergency_stop_decelerates_at_the_afc_rate() {
    // As above, but the stop is the limit-switch emergency stop with AFC X = 5000 mm/s² (Y, Z
    // keep their 1000): cruising at 100 mm/s along X it takes 10⁴/(2·5000) = 1 mm instead of the
    // normal abort's 5 mm; along a 45° XY line both axes share the path, so the path deceleration
    // is min(5000, 1000)·√2 and the stop takes 10⁴/(2·1000·√2) mm.
    let mut k = cruising_along_x();
    let at = k.position()[0];
    k.emergency_stop(&[Some(5000.0), None, None]);
    while !k.is_idle() {
        assert!(k.tick().finished.is_empty());
    }
    assert!(
        (k.position()[0] - at - 1.0).abs() < 1e-9,
        "{:?}",
        k.position()
    );

    // The S law does not delay an emergency stop to its next instant of zero acceleration.
    let mut k = Kernel::new(mill(Law::SCurve), &[0.0; 3]).expect("config");
    k.push(line(1, [200.0, 200.0, 0.0], 6000.0)).expect("push");
    for _ in 0..1500 {
        k.tick();
    }
    let t = k.tick().clone();
    let v = t.feed_mm_min / 60.0;
    let at = t.position.clone();
    k.emergency_stop(&[Some(5000.0), None, None]);
    while !k.is_idle() {
        k.tick();
    }
    let a = 1000.0 * std::f64::consts::SQRT_2;
    let d = ((k.position()[0] - at[0]).powi(2) + (k.position()[1] - at[1]).powi(2)).sqrt();
    assert!((d - v * v / (2.0 * a)).abs() < 1e-9, "{d} at {v} mm/s");
}

/// A 200 mm line along X at 100 mm/s under `law`, FEED HOLD before tick 40, released at 2000:
/// the run and the X set point of every tick.
fn hold_at_tick_40(law: Law) -> (Run, Vec<f64>) {
    let moves = [line(1, [200.0, 0.0, 0.0], 6000.0)];
    let cmds = [(40, Cmd::Hold(true)), (2000, Cmd::Hold(false))];
    let r = run(&mill(law), &[0.0; 3], &moves, &cmds);
    let x = r.points.iter().map(|p| p[0]).collect();
    (r, x)
}

#[test]
fn s_law_hold_while_accelerating_ramps_the_acceleration_down_at_once() {
    // S law along X from rest: path jerk j = 0.68 (JERK_TANGENT_LINE) × 22 500 = 15 300 mm/s³,
    // acceleration 1.5 × 1000 × 0.98 = 1470 mm/s². FEED HOLD before tick 40 (t0 = 0.04 s),
    // inside the first jerk phase: a0 = j·t0, v0 = j·t0²/2, x0 = j·t0³/6. The acceleration falls
    // at once at the jerk limit (t0 s, to v = j·t0², +5/6·j·t0³), then the stop from j·t0² is
    // triangular (j·t0² < a²/j): 2·t0 s, j·t0³. At rest after 4·t0 = 160 ticks, at X = 2·j·t0³
    // = 1.9584 mm. (Before, the replan waited for the end of the acceleration to 100 mm/s:
    // at rest after 323 ticks at X 16.169 mm.)
    let (r, x) = hold_at_tick_40(Law::SCurve);
    let (j, t0) = (0.68 * 22_500.0, 0.04);
    assert!((x[159] - 2.0 * j * t0 * t0 * t0).abs() < 1e-9, "{}", x[159]);
    assert!(x[158] < x[159]);
    assert_eq!(x[1999], x[159]);
    assert_within(&r.report, 0.01);
    assert_eq!(r.points.last(), Some(&vec![200.0, 0.0, 0.0]));
}

#[test]
fn exponential_law_hold_while_accelerating_replans_at_once() {
    // Exponential law (ACC 1,4) along X from rest at a = 980 mm/s²: a change of dv takes
    // T = 4·dv·ln 4/(3a), its acceleration a/4·e^{kt}, k = ln 4/T. FEED HOLD before tick 40
    // (t0 = 0.04 s) of the change to 100 mm/s: the acceleration drops to 0 (as at the end of a
    // change) and the stop is one change from v(t0) to 0 (acceleration −a·e^{−kt}). At rest
    // after 40 + 21.49 ticks at X = 0.311697 mm (before, the replan waited for the end of the
    // acceleration: at rest after 377 ticks at X 14.637 mm).
    let (r, x) = hold_at_tick_40(Law::Exponential);
    let cfg = mill(Law::Exponential);
    let (a, ln4, t0) = (980.0f64, 4.0f64.dln(), 0.04);
    let k1 = ln4 / (4.0 * 100.0 * ln4 / (3.0 * a));
    let x0 = a / 4.0 * ((k1 * t0).dexp_m1() - k1 * t0) / (k1 * k1);
    let v0 = a / 4.0 * (k1 * t0).dexp_m1() / k1;
    let t2 = 4.0 * v0 * ln4 / (3.0 * a);
    let k2 = ln4 / t2;
    let stop = v0 * t2 - a * ((-k2 * t2).dexp_m1() + k2 * t2) / (k2 * k2);
    assert!((t2 / cfg.tick_s - 21.488).abs() < 1e-3);
    assert!(
        (x[61] - x0 - stop).abs() < 1e-9,
        "{} vs {}",
        x[61],
        x0 + stop
    );
    assert!(x[60] < x[61]);
    assert_eq!(x[1999], x[61]);
    assert_within(&r.report, 0.01);
    assert_eq!(r.points.last(), Some(&vec![200.0, 0.0, 0.0]));
}
