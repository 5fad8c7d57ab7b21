//! Shared helpers of the motion tests: a 3-axis machine and a runner with the monitor.

#![allow(dead_code)]

use motion::monitor::{Monitor, Report};
use motion::{AccParams, AxisLimits, Config, Kernel, Law, Move, Path};

/// An axis with the same limits for feed and rapid moves.
pub fn axis(name: char, v: f64, a: f64, j: Option<f64>) -> AxisLimits {
    AxisLimits {
        name,
        v_max: v,
        a_max: a,
        j_max: j,
        v_rapid: v,
        a_rapid: a,
        j_rapid: j,
        soft_min: None,
        soft_max: None,
        diameter: false,
    }
}

/// The benchmark mill: each axis 100 mm/s, 1000 mm/s², 1 ms tick, tolerance 0.01 mm.
pub fn mill(law: Law) -> Config {
    let acc = AccParams::default();
    let j = acc.s_jerk(1000.0, 100.0);
    Config {
        axes: vec![
            axis('X', 100.0, 1000.0, j),
            axis('Y', 100.0, 1000.0, j),
            axis('Z', 100.0, 1000.0, j),
        ],
        tick_s: 0.001,
        tolerance_mm: 0.01,
        law,
        window: 500,
        acc,
        complex: motion::complex::ComplexSpeed::default(),
    }
}

/// A feed line.
pub fn line(tag: u64, end: [f64; 3], f: f64) -> Move {
    Move {
        tag,
        path: Path::Line,
        end: end.to_vec(),
        feed_mm_min: Some(f),
        exact_stop: false,
        tolerance: None,
        thread_pitch: None,
        thread_angle: 0.0,
    }
}

/// An XY arc (a helix when Z moves).
pub fn arc(tag: u64, end: [f64; 3], center: [f64; 2], cw: bool, f: f64) -> Move {
    Move {
        tag,
        path: Path::Arc {
            plane: (0, 1),
            center,
            cw,
            turns: 0,
        },
        end: end.to_vec(),
        feed_mm_min: Some(f),
        exact_stop: false,
        tolerance: None,
        thread_pitch: None,
        thread_angle: 0.0,
    }
}

/// A run-time command at a tick.
#[derive(Debug, Clone, Copy)]
pub enum Cmd {
    /// Feed override, percent.
    Override(u16),
    /// Feed hold on/off.
    Hold(bool),
}

/// The outcome of a run.
pub struct Run {
    /// Set points, one per tick (after the start).
    pub points: Vec<Vec<f64>>,
    /// DEN tags in order.
    pub finished: Vec<u64>,
    /// Monitor peaks.
    pub report: Report,
}

/// Pushes `moves` (keeping the queue full), applies `cmds` at their ticks and runs to idle.
pub fn run(cfg: &Config, start: &[f64], moves: &[Move], cmds: &[(usize, Cmd)]) -> Run {
    run_with(cfg, start, moves, cmds, false)
}

/// [`run`] with tolerance-band smoothing on or off.
pub fn run_with(
    cfg: &Config,
    start: &[f64],
    moves: &[Move],
    cmds: &[(usize, Cmd)],
    smooth: bool,
) -> Run {
    let mut k = Kernel::new(cfg.clone(), start).expect("config");
    k.set_smoothing(smooth).expect("smoothing");
    let mut mon = Monitor::new(cfg, start, cfg.law);
    let mut next = 0;
    let mut points = Vec::new();
    let mut finished = Vec::new();
    let mut n = 0usize;
    loop {
        while next < moves.len() && k.space() > 0 {
            k.push(moves[next].clone()).expect("move accepted");
            mon.push(&moves[next]);
            next += 1;
        }
        for (at, c) in cmds {
            if *at == n {
                match *c {
                    Cmd::Override(p) => k.set_feed_override(p),
                    Cmd::Hold(h) => k.set_hold(h),
                }
            }
        }
        if next >= moves.len() && k.is_idle() && cmds.iter().all(|(at, _)| *at < n) {
            break;
        }
        let t = k.tick();
        mon.sample(t);
        finished.extend_from_slice(&t.finished);
        points.push(t.position.clone());
        n += 1;
        assert!(n < 2_000_000, "the run does not end");
    }
    Run {
        points,
        finished,
        report: mon.report().clone(),
    }
}

/// Asserts every peak within its limit (1e-6 relative slack for rounding) and the tolerance.
pub fn assert_within(r: &Report, tol: f64) {
    for i in 0..r.v.len() {
        assert!(r.v[i] <= 1.0 + 1e-6, "axis {i} v {} × limit", r.v[i]);
        assert!(r.a[i] <= 1.0 + 1e-6, "axis {i} a {} × limit", r.a[i]);
        if let Some(j) = r.j[i] {
            assert!(j <= 1.0 + 1e-6, "axis {i} j {j} × limit");
        }
    }
    assert!(
        r.deviation <= tol + 1e-9,
        "deviation {} mm (block {:?})",
        r.deviation,
        r.deviation_tag
    );
}
