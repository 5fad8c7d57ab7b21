//! G33 position-locked to the spindle: the thread waits for the index (plus the start angle), then
//! the thread axis follows the spindle position, whatever its speed, overrides or a feed hold.
//!
//! The spindle positions fed in are multiples of 1/16 revolution, so every expected coordinate
//! below (lead 1.5 mm × revolutions) is exact in binary.

use motion::{Config, Kernel, MotionError, Move, Path};

/// A two-axis lathe (X, Z; radius programming) with the benchmark mill's axes (100 mm/s, 1000
/// mm/s²), 2 ms tick.
fn lathe() -> Config {
    let mut c = motion::samples::mill();
    c.axes.truncate(2);
    c.axes[1].name = 'Z';
    c.tick_s = 0.002;
    c.window = 16;
    c
}

/// A G33 move to (x, z) with lead 1.5 mm at S 600 (F = 900 mm/min), start angle `deg`.
fn thread(tag: u64, x: f64, z: f64, deg: f64) -> Move {
    Move {
        tag,
        path: Path::Line,
        end: vec![x, z],
        feed_mm_min: Some(900.0),
        exact_stop: false,
        tolerance: None,
        thread_pitch: Some(1.5),
        thread_angle: deg,
    }
}

fn rapid(tag: u64, x: f64, z: f64) -> Move {
    Move {
        tag,
        path: Path::Rapid,
        end: vec![x, z],
        feed_mm_min: None,
        exact_stop: false,
        tolerance: None,
        thread_pitch: None,
        thread_angle: 0.0,
    }
}

/// A kernel at (10, 5) whose spindle stands at `rev`.
fn kernel_at(rev: f64) -> Kernel {
    let mut k = Kernel::new(lathe(), &[10.0, 5.0]).expect("config");
    k.set_spindle_position(rev);
    k.tick();
    k
}

#[test]
fn pitch_stays_exact_across_a_spindle_speed_step() {
    // The spindle stands at 90° when the block is reached and turns 1/16 rev per tick (31.25
    // rev/s); the index is passed at the end of tick 12 (0.25 + 12/16 = 1.0 rev).
    let mut k = kernel_at(0.25);
    k.push(thread(1, 10.0, -9.0, 0.0)).expect("thread");
    let mut spin = 0.25;
    for tick in 1..=90 {
        // From tick 21 on the spindle turns twice as fast (1/8 rev per tick).
        spin += if tick <= 20 { 0.0625 } else { 0.125 };
        k.set_spindle_position(spin);
        let t = k.tick().clone();
        let z = if tick <= 12 {
            5.0
        } else {
            5.0 - 1.5 * (spin - 1.0)
        };
        assert_eq!(t.position, vec![10.0, z], "tick {tick}, spindle {spin}");
        assert_eq!(t.tag, Some(1));
        assert!(t.finished.is_empty());
    }
    // Tick 90: spindle 10.25 rev, Z = 5 − 1.5 × 9.25 = −8.875; the end (14 mm = 9⅓ rev after the
    // index) is reached within tick 91.
    assert_eq!(k.position(), &[10.0, -8.875]);
    k.set_spindle_position(spin + 0.125);
    let t = k.tick();
    assert_eq!(t.finished, vec![1]);
    assert_eq!(t.position, vec![10.0, -9.0]);
    assert!(k.is_idle());
}

#[test]
fn feed_override_does_not_change_a_thread() {
    let mut k = kernel_at(0.9375);
    k.push(thread(1, 10.0, -9.0, 0.0)).expect("thread");
    k.set_feed_override(50);
    let mut spin = 0.9375;
    for _ in 0..9 {
        spin += 0.0625;
        k.set_spindle_position(spin);
        k.tick();
    }
    // Index at 1.0 (tick 1), then 8 ticks of 1/16 rev: 0.5 rev × 1.5 mm.
    assert_eq!(k.position(), &[10.0, 4.25]);
}

/// Runs a two-pass thread (pass, rapid out, rapid back to the start, pass) with the spindle
/// turning `step` rev per tick from `rev0`; returns per pass the spindle position when the
/// block was reached and every (spindle, Z) while cutting.
fn two_passes(rev0: f64, step: f64, deg: f64) -> Vec<(f64, Vec<(f64, f64)>)> {
    let mut k = kernel_at(rev0);
    for m in [
        thread(1, 10.0, -9.0, deg),
        rapid(2, 12.0, -9.0),
        rapid(3, 12.0, 5.0),
        rapid(4, 9.8, 5.0),
        thread(5, 9.8, -9.0, deg),
    ] {
        k.push(m).expect("push");
    }
    let mut spin = rev0;
    let mut passes: Vec<(f64, Vec<(f64, f64)>)> = Vec::new();
    let mut last_tag = None;
    for _ in 0..20_000 {
        spin += step;
        k.set_spindle_position(spin);
        let before = spin - step;
        let t = k.tick().clone();
        if matches!(t.tag, Some(1 | 5)) {
            if t.tag != last_tag {
                passes.push((before, Vec::new()));
            }
            let z = t.position[1];
            if z != 5.0
                && let Some(p) = passes.last_mut()
            {
                p.1.push((spin, z));
            }
        }
        last_tag = t.tag;
        if k.is_idle() {
            break;
        }
    }
    passes
}

#[test]
fn every_pass_starts_at_the_same_spindle_angle() {
    // 3/32 rev per tick (46.875 rev/s, 70.3 mm/s): the index falls inside ticks, and the rapids
    // between the passes take a number of ticks that brings the spindle to the second pass at
    // another angle.
    for deg in [0.0, 180.0] {
        let passes = two_passes(0.3, 0.09375, deg);
        assert_eq!(passes.len(), 2);
        let angle = |r: f64| r.rem_euclid(1.0);
        assert_ne!(angle(passes[0].0), angle(passes[1].0), "arrival angles");
        for (_, cut) in &passes {
            assert!(cut.len() > 10);
            // Z − 5 = −1.5 × (revolutions since the start mark), the mark at `deg` after an index:
            // the spindle angle minus the revolutions cut is the start angle, every tick.
            for &(spin, z) in cut {
                let revs = (5.0 - z) / 1.5;
                let start = (spin - revs).rem_euclid(1.0);
                let want = deg / 360.0;
                let d = (start - want).abs();
                assert!(d.min(1.0 - d) < 1e-9, "spindle {spin} Z {z}");
            }
        }
    }
}

#[test]
fn feed_hold_during_a_thread_stops_at_its_end() {
    let mut k = kernel_at(0.9375);
    k.push(thread(1, 10.0, -9.0, 0.0)).expect("thread");
    k.push(rapid(2, 12.0, -9.0)).expect("rapid");
    let mut spin = 0.9375;
    let mut held_ticks = 0;
    let mut done = false;
    for tick in 1..=400 {
        spin += 0.0625;
        k.set_spindle_position(spin);
        if tick == 40 {
            k.set_hold(true);
        }
        let t = k.tick().clone();
        if !done {
            if t.finished == [1] {
                // 14 mm = 9⅓ rev after the index at 1.0: within tick 151 (0.9375 + 151/16 =
                // 10.375 ≥ 10.333 > 10.3125).
                assert_eq!(tick, 151);
                assert_eq!(t.position, vec![10.0, -9.0]);
                done = true;
            } else {
                assert_eq!(
                    t.position,
                    vec![10.0, 5.0 - 1.5 * (spin - 1.0)],
                    "tick {tick}"
                );
            }
        } else {
            // The rapid after the thread does not start while the hold is on.
            assert_eq!(t.position, vec![10.0, -9.0]);
            assert!(t.held);
            held_ticks += 1;
        }
    }
    assert!(done);
    assert_eq!(held_ticks, 249);
    k.set_hold(false);
    for _ in 0..200 {
        k.tick();
    }
    assert_eq!(k.position(), &[12.0, -9.0]);
}

#[test]
fn a_thread_faster_than_the_axes_is_refused_before_it_starts() {
    let mut k = kernel_at(0.0);
    // Lead 6 mm at S 1200: F 7200 mm/min along Z, which allows 100 mm/s = 6000 mm/min.
    let mut m = thread(7, 10.0, -9.0, 0.0);
    m.thread_pitch = Some(6.0);
    m.feed_mm_min = Some(7200.0);
    let e = k.push(m).expect_err("too fast");
    assert_eq!(
        e,
        MotionError::ThreadTooFast {
            tag: 7,
            need: 7200.0,
            limit: 6000.0
        }
    );
    assert!(k.is_idle());
}

#[test]
fn a_thread_after_a_thread_goes_on_without_waiting() {
    // A run-out: Z from 5 to −4 (6 rev), then X 10 → 11.5 over Z −4 → −5.5 (Z dominant: lead
    // along Z, one more rev). The spindle passes the index at the start and no other wait follows.
    let mut k = kernel_at(0.9375);
    k.push(thread(1, 10.0, -4.0, 0.0)).expect("thread");
    k.push(thread(2, 11.5, -5.5, 0.0)).expect("run-out");
    let mut spin = 0.9375;
    let mut out = Vec::new();
    for _ in 0..120 {
        spin += 0.0625;
        k.set_spindle_position(spin);
        out.push((spin, k.tick().clone()));
    }
    // Spindle 1.0 + 6 = 7.0 at the end of the first block (tick 97), 8.0 at the run-out's end.
    let (s97, t97) = &out[96];
    assert_eq!(*s97, 7.0);
    assert_eq!(t97.finished, vec![1]);
    assert_eq!(t97.position, vec![10.0, -4.0]);
    // Half a revolution into the run-out: X and Z each advance 0.75 mm.
    let (s105, t105) = &out[104];
    assert_eq!(*s105, 7.5);
    assert!((t105.position[0] - 10.75).abs() < 1e-12 && (t105.position[1] + 4.75).abs() < 1e-12);
    assert_eq!(out[112].1.finished, vec![2]);
    assert!(k.is_idle());
}

#[test]
fn a_thread_the_spindle_makes_too_fast_does_not_start() {
    // Queued at S600 (15 mm/s), but the spindle turns 1/8 rev per 2 ms tick (62.5 rev/s: 93.75
    // mm/s, fine) and then 1/4 rev per tick (125 rev/s: 187.5 mm/s > 100): the thread does not
    // start at the index and the kernel reports the fault once.
    let mut k = kernel_at(0.875);
    k.push(thread(3, 10.0, -9.0, 0.0)).expect("thread");
    k.set_spindle_position(1.125);
    k.tick();
    assert_eq!(k.position(), &[10.0, 5.0]);
    assert_eq!(
        k.take_fault(),
        Some(MotionError::ThreadTooFast {
            tag: 3,
            need: 187.5 * 60.0,
            limit: 6000.0
        })
    );
    assert_eq!(k.take_fault(), None);
    assert!(k.waiting_for_index());
    // Slower again, it starts at the next index (2.0, passed at 1/8 rev per tick) and follows.
    for (rev, z) in [(1.875, 5.0), (2.0, 5.0), (2.125, 4.8125)] {
        k.set_spindle_position(rev);
        k.tick();
        assert_eq!(k.position(), &[10.0, z]);
    }
    assert_eq!(k.take_fault(), None);
}

#[test]
fn a_kernel_made_mid_run_takes_the_first_spindle_position_as_it_stands() {
    // The cnc makes a kernel anew at homing or a handwheel move; the spindle has turned 500.25
    // rev by then: the thread waits for 501, it does not take the 500 revolutions as turned.
    let mut k = Kernel::new(lathe(), &[10.0, 5.0]).expect("config");
    k.push(thread(1, 10.0, -9.0, 0.0)).expect("thread");
    let mut spin = 500.25;
    for _ in 0..12 {
        k.set_spindle_position(spin);
        k.tick();
        assert_eq!(k.position(), &[10.0, 5.0]);
        spin += 0.0625;
    }
    // Tick 13 ends at 501.0 (the index), tick 14 at 501.0625.
    k.set_spindle_position(501.0);
    k.tick();
    k.set_spindle_position(501.0625);
    k.tick();
    assert_eq!(k.position(), &[10.0, 5.0 - 1.5 * 0.0625]);
}
