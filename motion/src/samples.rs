//! The benchmark programs of issue 10 as moves for a 3-axis machine (X, Y, Z): squares,
//! circles, a zigzag, a circle of 0.08 mm segments, a spiral pocket and a 3-D CAM-like raster.

use crate::config::{AccParams, AxisLimits, Config, Law};
use crate::kernel::Kernel;
use crate::moves::{Move, Path};
use detmath::Det as _;

/// The benchmark mill the samples are measured on: each axis 100 mm/s and 1000 mm/s²
/// (rapids alike, no jerk limit), a 1 ms tick, tolerance 0.01 mm, linear law, a 500-block window.
pub fn mill() -> Config {
    let ax = |name| AxisLimits {
        name,
        v_max: 100.0,
        a_max: 1000.0,
        j_max: None,
        v_rapid: 100.0,
        a_rapid: 1000.0,
        j_rapid: None,
        soft_min: None,
        soft_max: None,
        diameter: false,
    };
    Config {
        axes: vec![ax('X'), ax('Y'), ax('Z')],
        tick_s: 0.001,
        tolerance_mm: 0.01,
        law: Law::Linear,
        window: 500,
        acc: AccParams::default(),
        complex: crate::complex::ComplexSpeed::default(),
    }
}

/// Runs `moves` from `start` on `cfg` until the kernel is idle, feeding the queue as it empties;
/// the number of ticks (the motion time in ticks), or the first error as text.
pub fn ticks_to_idle(cfg: Config, moves: &[Move], start: [f64; 3]) -> Result<u64, String> {
    ticks_to_idle_with(cfg, moves, start, false)
}

/// [`ticks_to_idle`] with tolerance-band smoothing on or off ([`crate::smooth`]).
pub fn ticks_to_idle_with(
    cfg: Config,
    moves: &[Move],
    start: [f64; 3],
    smooth: bool,
) -> Result<u64, String> {
    let mut k = Kernel::new(cfg, &start).map_err(|e| e.to_string())?;
    k.set_smoothing(smooth).map_err(|e| e.to_string())?;
    let (mut next, mut n) = (0, 0);
    loop {
        while next < moves.len() && k.space() > 0 {
            k.push(moves[next].clone()).map_err(|e| e.to_string())?;
            next += 1;
            if next == moves.len() {
                k.end_of_input().map_err(|e| e.to_string())?;
            }
        }
        if next >= moves.len() && k.is_idle() {
            return Ok(n);
        }
        k.tick();
        n += 1;
    }
}

fn mv(tag: u64, path: Path, end: [f64; 3], f: f64) -> Move {
    Move {
        tag,
        path,
        end: end.to_vec(),
        feed_mm_min: Some(f),
        exact_stop: false,
        tolerance: None,
        thread_pitch: None,
        thread_angle: 0.0,
    }
}

fn lines(pts: &[[f64; 3]], f: f64) -> Vec<Move> {
    pts.iter()
        .enumerate()
        .map(|(i, p)| mv(i as u64, Path::Line, *p, f))
        .collect()
}

/// Three laps of a 50 mm square at F6000.
pub fn squares() -> Vec<Move> {
    let sq = [
        [50.0, 0.0, 0.0],
        [50.0, 50.0, 0.0],
        [0.0, 50.0, 0.0],
        [0.0, 0.0, 0.0],
    ];
    let pts: Vec<[f64; 3]> = (0..3).flat_map(|_| sq).collect();
    lines(&pts, 6000.0)
}

/// Two full circles of radius 20 mm (start and end at (20, 0)) at F6000.
pub fn circles() -> Vec<Move> {
    (0..2)
        .map(|i| {
            let path = Path::Arc {
                plane: (0, 1),
                center: [0.0, 0.0],
                cw: false,
                turns: 0,
            };
            mv(i, path, [20.0, 0.0, 0.0], 6000.0)
        })
        .collect()
}

/// 40 zigzag strokes of 10 × 1 mm at F6000.
pub fn zigzag() -> Vec<Move> {
    let pts: Vec<[f64; 3]> = (1..=40)
        .map(|k| [if k % 2 == 1 { 10.0 } else { 0.0 }, k as f64, 0.0])
        .collect();
    lines(&pts, 6000.0)
}

/// A circle of radius 20 mm as 0.08 mm chords (1571 segments) at F6000, from (20, 0).
pub fn chord_circle() -> Vec<Move> {
    let n = (2.0 * std::f64::consts::PI * 20.0 / 0.08).round() as usize;
    let pts: Vec<[f64; 3]> = (1..=n)
        .map(|k| {
            let a = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
            [20.0 * a.dcos(), 20.0 * a.dsin(), 0.0]
        })
        .collect();
    lines(&pts, 6000.0)
}

/// An Archimedean spiral pocket from r = 4 to r = 24 mm (2 mm per turn) of 0.5 mm chords at
/// F3000, from (4, 0).
pub fn spiral() -> Vec<Move> {
    let mut pts = Vec::new();
    let mut a: f64 = 0.0;
    loop {
        let r = 4.0 + 2.0 * a / (2.0 * std::f64::consts::PI);
        if r > 24.0 {
            break;
        }
        a += 0.5 / r;
        let r = 4.0 + 2.0 * a / (2.0 * std::f64::consts::PI);
        pts.push([r * a.dcos(), r * a.dsin(), 0.0]);
    }
    lines(&pts, 3000.0)
}

/// A 3-D CAM-like raster over z = 2·sin(x/5)·cos(y/7): rows of 0.1 mm segments along X,
/// 1 mm apart, at F6000, `rows` rows of 40 mm, from (0, 0, 2).
pub fn cam(rows: usize) -> Vec<Move> {
    let z = |x: f64, y: f64| 2.0 * (x / 5.0).dsin() * (y / 7.0).dcos();
    let mut pts = Vec::new();
    for r in 0..rows {
        let y = r as f64;
        for k in 0..=400 {
            let k = if r % 2 == 0 { k } else { 400 - k };
            let x = k as f64 * 0.1;
            pts.push([x, y, z(x, y)]);
        }
    }
    lines(&pts, 6000.0)
}

/// The start point of each sample (where its first move starts).
pub fn start(name: &str) -> [f64; 3] {
    match name {
        "circles" | "chord_circle" => [20.0, 0.0, 0.0],
        "spiral" => [4.0, 0.0, 0.0],
        _ => [0.0, 0.0, 0.0],
    }
}
