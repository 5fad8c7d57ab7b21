//! The CAM benchmark set (issue 22): programs as a CAM system writes them, for a 3-axis mill
//! (X, Y, Z). Circles, ellipses and a free-form curve as chords of 0.02–0.5 mm, a 3-D surface
//! raster and a pocket of short segments, every coordinate rounded to 3 or 4 decimals (so that
//! consecutive directions jitter along a smooth curve), each at several feeds.
//!
//! Invariants: every program is a list of G01 lines from [`CamProgram::start`]; the generators
//! are deterministic (detmath) and the rounding is `round(x · 10^d) / 10^d`.

use crate::moves::{Move, Path};
use detmath::Det as _;
use std::f64::consts::TAU;

/// One program of the set.
#[derive(Debug, Clone)]
pub struct CamProgram {
    /// Short name: shape, size, chord, decimals, feed (`circle_r20_c0.08_d4_f6000`).
    pub name: String,
    /// Where the first move starts (the rapid before the program goes there).
    pub start: [f64; 3],
    /// The G01 blocks.
    pub moves: Vec<Move>,
}

/// `x` rounded to `dec` decimals.
pub fn round_to(x: f64, dec: u32) -> f64 {
    let k = 10f64.powi(dec as i32);
    (x * k).round() / k
}

fn rounded(p: [f64; 3], dec: u32) -> [f64; 3] {
    [
        round_to(p[0], dec),
        round_to(p[1], dec),
        round_to(p[2], dec),
    ]
}

/// G01 moves through `pts` (already rounded) at `feed` mm/min, tags from 0.
pub fn lines(pts: &[[f64; 3]], feed: f64) -> Vec<Move> {
    pts.iter()
        .enumerate()
        .map(|(i, p)| Move {
            tag: i as u64,
            path: Path::Line,
            end: p.to_vec(),
            feed_mm_min: Some(feed),
            exact_stop: false,
            tolerance: None,
            thread_pitch: None,
            thread_angle: 0.0,
        })
        .collect()
}

/// A closed planar curve `c(φ)`, φ ∈ [0, 2π], as chords of about `chord` mm (uniform in φ by
/// its length), rounded to `dec` decimals; returns (start, end points).
fn closed_curve(c: impl Fn(f64) -> [f64; 2], chord: f64, dec: u32) -> ([f64; 3], Vec<[f64; 3]>) {
    // The curve's length from a fine polygon.
    let fine = 20_000;
    let mut len = 0.0;
    let mut prev = c(0.0);
    for k in 1..=fine {
        let p = c(TAU * k as f64 / fine as f64);
        len += (p[0] - prev[0]).dhypot(p[1] - prev[1]);
        prev = p;
    }
    let n = ((len / chord).round() as usize).max(3);
    let at = |k: usize| {
        let p = c(TAU * (k % n) as f64 / n as f64);
        rounded([p[0], p[1], 0.0], dec)
    };
    (at(0), (1..=n).map(at).collect())
}

/// A circle of radius `r` centred at the origin, from (r, 0), counter-clockwise.
pub fn circle(r: f64, chord: f64, dec: u32, feed: f64) -> CamProgram {
    let (start, pts) = closed_curve(|a| [r * a.dcos(), r * a.dsin()], chord, dec);
    CamProgram {
        name: format!("circle_r{r}_c{chord}_d{dec}_f{feed}"),
        start,
        moves: lines(&pts, feed),
    }
}

/// An ellipse with half-axes `a` (X) and `b` (Y), from (a, 0), counter-clockwise.
pub fn ellipse(a: f64, b: f64, chord: f64, dec: u32, feed: f64) -> CamProgram {
    let (start, pts) = closed_curve(|t| [a * t.dcos(), b * t.dsin()], chord, dec);
    CamProgram {
        name: format!("ellipse_{a}x{b}_c{chord}_d{dec}_f{feed}"),
        start,
        moves: lines(&pts, feed),
    }
}

/// A free-form closed curve: r(φ) = 20 + 4·sin(3φ) + 2·cos(5φ) (curvature varying along it).
pub fn freeform(chord: f64, dec: u32, feed: f64) -> CamProgram {
    let (start, pts) = closed_curve(
        |a| {
            let r = 20.0 + 4.0 * (3.0 * a).dsin() + 2.0 * (5.0 * a).dcos();
            [r * a.dcos(), r * a.dsin()]
        },
        chord,
        dec,
    );
    CamProgram {
        name: format!("freeform_c{chord}_d{dec}_f{feed}"),
        start,
        moves: lines(&pts, feed),
    }
}

/// A 3-D surface raster over z = 2·sin(x/5)·cos(y/7) + 0.5·sin((x+y)/3): `rows` rows of 40 mm
/// along X (alternating direction), 1 mm apart, as `step` mm segments rounded to `dec`.
pub fn raster(rows: usize, step: f64, dec: u32, feed: f64) -> CamProgram {
    let z =
        |x: f64, y: f64| 2.0 * (x / 5.0).dsin() * (y / 7.0).dcos() + 0.5 * ((x + y) / 3.0).dsin();
    let n = (40.0 / step).round() as usize;
    let mut pts = Vec::new();
    for r in 0..rows {
        let y = r as f64;
        for k in 0..=n {
            let k = if r % 2 == 0 { k } else { n - k };
            let x = k as f64 * step;
            pts.push(rounded([x, y, z(x, y)], dec));
        }
    }
    let start = pts[0];
    CamProgram {
        name: format!("raster_{rows}x40_s{step}_d{dec}_f{feed}"),
        start,
        moves: lines(&pts[1..], feed),
    }
}

/// A pocket of `loops` offset rounded rectangles (60 × 40 mm outside, 2 mm step inwards,
/// corner radius shrinking from 8 mm), the straight sides split into 0.5 mm segments and the
/// corners into chords of `chord` mm, rounded to `dec`; each loop is joined to the next by a
/// short step inwards.
pub fn pocket(loops: usize, chord: f64, dec: u32, feed: f64) -> CamProgram {
    let mut pts = Vec::new();
    for l in 0..loops {
        let off = 2.0 * l as f64;
        let (w, h) = (30.0 - off, 20.0 - off);
        let rc = (8.0 - off).max(1.0);
        if w <= rc || h <= rc {
            break;
        }
        // Counter-clockwise from (w, 0): right side up, top-right corner, ...
        let corners = [
            (w - rc, h - rc, 0.0),
            (-(w - rc), h - rc, 0.25),
            (-(w - rc), -(h - rc), 0.5),
            (w - rc, -(h - rc), 0.75),
        ];
        let mut cur = [w, 0.0];
        let side = |pts: &mut Vec<[f64; 3]>, to: [f64; 2], cur: &mut [f64; 2]| {
            let d = (to[0] - cur[0]).dhypot(to[1] - cur[1]);
            let n = ((d / 0.5).ceil() as usize).max(1);
            for k in 1..=n {
                let t = k as f64 / n as f64;
                let p = [cur[0] + (to[0] - cur[0]) * t, cur[1] + (to[1] - cur[1]) * t];
                pts.push(rounded([p[0], p[1], 0.0], dec));
            }
            *cur = to;
        };
        for (cx, cy, q) in corners {
            let a0 = TAU * q;
            side(
                &mut pts,
                [cx + rc * a0.dcos(), cy + rc * a0.dsin()],
                &mut cur,
            );
            let n = ((rc * TAU / 4.0 / chord).round() as usize).max(2);
            for k in 1..=n {
                let a = a0 + TAU / 4.0 * k as f64 / n as f64;
                cur = [cx + rc * a.dcos(), cy + rc * a.dsin()];
                pts.push(rounded([cur[0], cur[1], 0.0], dec));
            }
        }
        side(&mut pts, [w, 0.0], &mut cur);
        // Step inwards to the next loop's start.
        pts.push(rounded([w - 2.0, 0.0, 0.0], dec));
    }
    pts.pop();
    CamProgram {
        name: format!("pocket_{loops}_c{chord}_d{dec}_f{feed}"),
        start: [30.0, 0.0, 0.0],
        moves: lines(&pts, feed),
    }
}

/// The benchmark set: each shape at several feeds.
pub fn set() -> Vec<CamProgram> {
    let mut v = Vec::new();
    for f in [3000.0, 6000.0] {
        v.push(circle(20.0, 0.08, 4, f));
        v.push(circle(20.0, 0.08, 3, f));
    }
    v.push(circle(20.0, 0.02, 3, 3000.0));
    v.push(circle(5.0, 0.5, 3, 3000.0));
    for f in [3000.0, 6000.0] {
        v.push(ellipse(30.0, 15.0, 0.1, 3, f));
    }
    v.push(ellipse(30.0, 15.0, 0.05, 4, 6000.0));
    for f in [2000.0, 5000.0] {
        v.push(freeform(0.05, 4, f));
    }
    v.push(freeform(0.2, 3, 5000.0));
    for f in [3000.0, 6000.0] {
        v.push(raster(10, 0.2, 3, f));
    }
    for f in [2000.0, 4000.0] {
        v.push(pocket(5, 0.1, 3, f));
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding_to_three_and_four_decimals() {
        assert_eq!(round_to(1.23456, 3), 1.235);
        assert_eq!(round_to(-1.23444, 4), -1.2344);
    }

    #[test]
    fn the_issue_circle_has_1571_chords_of_0_08_mm_rounded_to_4_decimals() {
        let p = circle(20.0, 0.08, 4, 6000.0);
        assert_eq!(p.moves.len(), 1571);
        assert_eq!(p.start, [20.0, 0.0, 0.0]);
        assert_eq!(
            p.moves.last().map(|m| m.end.clone()),
            Some(vec![20.0, 0.0, 0.0])
        );
        for m in &p.moves {
            for x in &m.end {
                assert_eq!(*x, round_to(*x, 4));
            }
        }
    }

    #[test]
    fn the_pocket_is_closed_loops_of_short_segments() {
        let p = pocket(5, 0.1, 3, 2000.0);
        let mut prev = p.start;
        for m in &p.moves {
            let d = (m.end[0] - prev[0]).dhypot(m.end[1] - prev[1]);
            assert!(d > 0.0 && d <= 2.0 + 1e-9, "segment of {d} mm");
            prev = [m.end[0], m.end[1], m.end[2]];
        }
    }
}
