//! Tolerance-band smoothing of short linear blocks (issue 22; beyond the MEFI manual, as the AI
//! contour / compressor functions of current controls do). CAM output rounds coordinates to
//! 0.001 or 0.0001 mm, so the directions of consecutive chords of a smooth curve jitter and the
//! corner blends between them vary from block to block. The smoother moves each interior end
//! point of a run of short lines onto a local weighted least-squares quadratic through its
//! neighbours (parameterised by the programmed chord length, tricube weights over [`WINDOW`] mm
//! on either side), which removes the jitter, before the kernel plans the run.
//! A fit that would move a point more than [`FIT_CAP`] is the curve itself (a tight corner, a
//! line running into an arc): it is taken in part, fading to nothing at twice the cap, so that
//! neighbouring points never switch abruptly between fits (an abrupt switch leaves a kink of a
//! few µm over a 0.1 mm chord, which the planner must slow down for).
//!
//! Invariants:
//! * A point moves at most `shift` (half the tolerance in force); the smoothed blocks are then
//!   blended with the other half ([`Move::tolerance`]), so every set point stays within the
//!   tolerance of the programmed polyline (a point of a smoothed chord is the same convex
//!   combination of its moved ends as the programmed point is of the programmed ends).
//! * A run is only G01 feed lines of at most [`MAX_LEN`] mm with the same feed, no exact stop,
//!   no thread, no block tolerance of their own, turning at most [`MAX_TURN`] at each joint. A
//!   dwell, an aux record (M, S, T: a stop of zero length), a rapid, an arc, a feed change or a
//!   sharp corner ends it; the run's first start and last end point never move.
//! * Streaming and linear: a point is final once [`HALF`] points after it are known (or the run
//!   ends); each point costs O(HALF).

use std::collections::VecDeque;

use crate::geom::{Vector, turn_angle, vector};
use crate::moves::{Move, Path};

/// Longest block that is smoothed, mm.
pub const MAX_LEN: f64 = 2.0;
/// Sharpest joint inside a run, rad (20°): a sharper one is a corner the run ends at.
pub const MAX_TURN: f64 = 20.0 * std::f64::consts::PI / 180.0;
/// Points on either side of a smoothed point in its fit (at most).
pub const HALF: usize = 12;
/// Share of the tolerance a point may move (the rest is the corner blends').
pub const SHIFT_SHARE: f64 = 0.5;
/// A fit that would move a point farther than this (mm) is not the rounding's jitter but the
/// curve itself (a tight corner or a curvature step the quadratic cannot follow): less of it is
/// taken, none from twice this on.
pub const FIT_CAP: f64 = 0.002;
/// Half-width of the fit's window along the programmed path, mm (chords of half of it or more
/// are not smoothed: too few points fall inside).
pub const WINDOW: f64 = 0.6;

/// The streaming smoother: moves in, moves out (the same blocks and tags; the end points of a
/// run's interior points moved within the band, the run's blocks carrying the blend share of
/// the tolerance).
#[derive(Debug, Clone, Default)]
pub struct Smoother {
    /// Programmed points: up to [`HALF`] final ones as context, then the pending ones;
    /// `pts[done]` is the last final point (at first the run's fixed start).
    pts: VecDeque<Vector>,
    /// Cumulative programmed chord length at each point of `pts`.
    arc: VecDeque<f64>,
    /// Pending moves of the run: `moves[j]` ends at `pts[done + 1 + j]`.
    moves: VecDeque<Move>,
    /// Index in `pts` of the last final point.
    done: usize,
    /// The run's feed (mm/min) and tolerance (mm).
    feed: f64,
    tol: f64,
    /// Moves ready for the kernel.
    out: VecDeque<Move>,
}

impl Smoother {
    /// Number of moves held (pending or ready).
    pub fn held(&self) -> usize {
        self.moves.len() + self.out.len()
    }

    /// Takes the next move that is ready.
    pub fn pop(&mut self) -> Option<Move> {
        self.out.pop_front()
    }

    /// Feeds one move that starts at `start` (the previous move's programmed end); `tol` is the
    /// tolerance in force when the move has none of its own.
    pub fn push(&mut self, m: Move, start: &Vector, tol: f64) {
        let end = vector(&m.end);
        let len = (end - start).norm();
        let f = m.feed_mm_min.unwrap_or(0.0);
        let tol = m.tolerance.unwrap_or(tol);
        let fits = matches!(m.path, Path::Line)
            && !m.exact_stop
            && m.thread_pitch.is_none()
            && len > 0.0
            && len <= MAX_LEN
            && f > 0.0
            && tol > 0.0;
        if !fits {
            self.flush();
            self.pts.clear();
            self.arc.clear();
            self.out.push_back(m);
            return;
        }
        let n = self.pts.len();
        let same = n >= 1 && self.pts[n - 1] == *start && self.feed == f && self.tol == tol;
        let smooth_turn = n >= 2 && {
            let d0 = self.pts[n - 1] - self.pts[n - 2];
            turn_angle(&(d0 / d0.norm()), &((end - start) / len)) <= MAX_TURN
        };
        if !(same && (n == 1 || smooth_turn)) {
            // A new run from `start` (its start point fixed).
            self.flush();
            self.pts.clear();
            self.arc.clear();
            self.pts.push_back(*start);
            self.arc.push_back(0.0);
            self.done = 0;
            self.feed = f;
            self.tol = tol;
        }
        let s = self.arc.back().copied().unwrap_or(0.0) + len;
        self.pts.push_back(end);
        self.arc.push_back(s);
        self.moves.push_back(m);
        // Give out the moves whose end has HALF points after it.
        while self.pts.len() >= self.done + 2 + HALF {
            self.emit();
            while self.done > HALF {
                self.pts.pop_front();
                self.arc.pop_front();
                self.done -= 1;
            }
        }
    }

    /// Ends the run: every pending move is given out (the run's last point unmoved).
    pub fn flush(&mut self) {
        while !self.moves.is_empty() {
            self.emit();
        }
        // The last point is the fixed start of a run that continues from it.
        if let Some(p) = self.pts.back().copied() {
            self.pts.clear();
            self.arc.clear();
            self.pts.push_back(p);
            self.arc.push_back(0.0);
        }
        self.done = 0;
    }

    /// Gives out the first pending move with its end smoothed.
    fn emit(&mut self) {
        let Some(mut m) = self.moves.pop_front() else {
            return;
        };
        let i = self.done + 1;
        let after = self.pts.len() - 1 - i;
        let shift = self.tol * SHIFT_SHARE;
        let cap = shift.min(FIT_CAP);
        let p = self.pts[i];
        let mut q = p;
        if after > 0 {
            // The window is a length, the same for every point (a window of so many chords
            // would jump where the chord length changes, a side running into a corner).
            let (l, r) = (HALF.min(i), HALF.min(after));
            if let Some(c) = weighted_quadratic_at(&self.pts, &self.arc, i, WINDOW, l, r) {
                // Up to `cap` the fit is taken whole; beyond it (the curve itself, not the
                // rounding) less and less of it, none from twice `cap` on: a continuous rule,
                // so that neighbouring points do not switch between fits (which made kinks).
                let d = (c - p).norm();
                let w = if d <= cap {
                    1.0
                } else {
                    ((2.0 * cap - d) / cap).max(0.0)
                };
                q = p + (c - p) * w;
            }
        }
        let n = m.end.len();
        m.end = q.iter().take(n).copied().collect();
        m.tolerance = Some(self.tol - shift);
        self.done = i;
        self.out.push_back(m);
    }
}

/// The value at `arc[i]` of the weighted least-squares quadratic (in the chord length) through
/// the points `i − left ..= i + right` within `h` of it, weighted by the tricube kernel
/// `(1 − (|t|/h)³)³` (weights fall to 0 at the window's edge, so the fit changes continuously as
/// the window slides along the run); None when fewer than three points carry weight.
fn weighted_quadratic_at(
    pts: &VecDeque<Vector>,
    arc: &VecDeque<f64>,
    i: usize,
    h: f64,
    left: usize,
    right: usize,
) -> Option<Vector> {
    let t0 = arc[i];
    let (mut s0, mut s1, mut s2, mut s3, mut s4) = (0.0, 0.0, 0.0, 0.0, 0.0);
    let (mut b0, mut b1, mut b2) = (Vector::zeros(), Vector::zeros(), Vector::zeros());
    let mut used = 0;
    for j in i - left..=i + right {
        let t = arc[j] - t0;
        let u = t.abs() / h;
        if u >= 1.0 {
            continue;
        }
        let v = 1.0 - u * u * u;
        let w = v * v * v;
        used += 1;
        let (t2, p) = (t * t, pts[j]);
        s0 += w;
        s1 += w * t;
        s2 += w * t2;
        s3 += w * t2 * t;
        s4 += w * t2 * t2;
        b0 += p * w;
        b1 += p * (w * t);
        b2 += p * (w * t2);
    }
    if used < 3 {
        return None;
    }
    // Cramer's rule for the intercept of [s0 s1 s2; s1 s2 s3; s2 s3 s4] c = b.
    let det = s0 * (s2 * s4 - s3 * s3) - s1 * (s1 * s4 - s3 * s2) + s2 * (s1 * s3 - s2 * s2);
    let scale = s0 * s2 * s4;
    // A NaN determinant is no fit either.
    if det.abs().partial_cmp(&(1e-12 * scale.abs())) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let c0 = (b0 * (s2 * s4 - s3 * s3) - b1 * (s1 * s4 - s2 * s3) + b2 * (s1 * s3 - s2 * s2)) / det;
    Some(c0)
}

/// The trajectory header's `contour` object: how many blocks ran under contour control and the
/// smoothing it means (`{"blocks":N,"smoothing":"tolerance band","shift_mm":…,"blend_mm":…}`).
pub fn header_json(tol: f64, blocks: usize, cs: &crate::complex::ComplexSpeed) -> String {
    let shift = tol * SHIFT_SHARE;
    format!(
        "{{\"blocks\":{blocks},\"smoothing\":\"{}\",\"shift_mm\":{shift:?},\"blend_mm\":{:?},\"max_len_mm\":{MAX_LEN:?},\"max_turn_deg\":20.0,\"complex_speed\":\"{}\"}}",
        if blocks > 0 { "tolerance band" } else { "off" },
        tol - shift,
        cs.describe()
    )
}

/// The `nc run` summary line about contour control.
pub fn summary_line(tol: f64, blocks: usize, cs: &crate::complex::ComplexSpeed) -> String {
    if blocks == 0 {
        return "contour control: off (G05.1 Q1 / G08 P1 / MEFI G23 switch it on)".into();
    }
    let shift = tol * SHIFT_SHARE;
    format!(
        "contour control: {blocks} blocks; lines ≤ {MAX_LEN} mm smoothed within {shift} mm, blended within {} mm; complex speed {}",
        tol - shift,
        cs.describe()
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cam;
    use detmath::Det as _;

    fn run(moves: &[Move], start: [f64; 3], tol: f64) -> Vec<Move> {
        let mut s = Smoother::default();
        let mut prev = vector(&start);
        let mut out = Vec::new();
        for m in moves {
            s.push(m.clone(), &prev, tol);
            prev = vector(&m.end);
            while let Some(m) = s.pop() {
                out.push(m);
            }
        }
        s.flush();
        while let Some(m) = s.pop() {
            out.push(m);
        }
        out
    }

    fn turns(start: [f64; 3], moves: &[Move]) -> Vec<f64> {
        let mut pts = vec![vector(&start)];
        pts.extend(moves.iter().map(|m| vector(&m.end)));
        pts.windows(3)
            .map(|w| {
                let (a, b) = (w[1] - w[0], w[2] - w[1]);
                turn_angle(&(a / a.norm()), &(b / b.norm()))
            })
            .collect()
    }

    #[test]
    fn a_rounded_chord_circle_keeps_its_blocks_and_loses_its_jitter_within_half_the_tolerance() {
        let p = cam::circle(20.0, 0.08, 3, 6000.0);
        let out = run(&p.moves, p.start, 0.01);
        assert_eq!(out.len(), p.moves.len());
        for (a, b) in p.moves.iter().zip(&out) {
            assert_eq!(a.tag, b.tag);
            assert_eq!(b.tolerance, Some(0.005));
            let d = (vector(&a.end) - vector(&b.end)).norm();
            assert!(d <= 0.005 + 1e-15, "block {} moved {d} mm", a.tag);
        }
        // The last point (the run's end) does not move.
        assert_eq!(
            out.last().map(|m| m.end.clone()),
            p.moves.last().map(|m| m.end.clone())
        );
        // Exact turn: 2π / 1571 = 0.0040 rad. Rounded to 0.001 mm the turns spread widely;
        // smoothed, every interior turn away from the ends is within 40 % of it (0.36 measured
        // with the 0.6 mm window; the 12-point window of before reached 0.33 but made kinks where
        // a line runs into an arc).
        let exact = std::f64::consts::TAU / p.moves.len() as f64;
        let before = turns(p.start, &p.moves);
        let after = turns(p.start, &out);
        let spread = |t: &[f64]| {
            let mid = &t[HALF + 2..t.len() - HALF - 2];
            mid.iter().map(|x| (x - exact).abs()).fold(0.0, f64::max) / exact
        };
        assert!(spread(&before) > 1.0, "rounded: {}", spread(&before));
        assert!(spread(&after) < 0.40, "smoothed: {}", spread(&after));
    }

    /// A pocket's side (0.5 mm lines) running into a corner of radius 6 mm (0.1 mm chords, each
    /// turning 0.0167 rad), rounded to 0.001 mm: no smoothed joint turns more than 1.3 times a
    /// chord's turn (the fits across the curvature step fade out instead of switching window:
    /// the earlier narrowing fits left a joint of 0.051 rad there, a corner speed of 39 mm/s
    /// instead of 69).
    #[test]
    fn a_line_running_into_an_arc_is_smoothed_without_kinks() {
        let mut pts: Vec<[f64; 3]> = (1..=24).map(|k| [28.0, 0.5 * k as f64, 0.0]).collect();
        let n = 94;
        for k in 1..=n {
            let a = std::f64::consts::FRAC_PI_2 * k as f64 / n as f64;
            pts.push([22.0 + 6.0 * a.dcos(), 12.0 + 6.0 * a.dsin(), 0.0]);
        }
        for p in &mut pts {
            *p = p.map(|x| cam::round_to(x, 3));
        }
        let moves = cam::lines(&pts, 4000.0);
        let out = run(&moves, [28.0, 0.0, 0.0], 0.01);
        let chord_turn = std::f64::consts::FRAC_PI_2 / n as f64;
        let worst = |m: &[Move]| turns([28.0, 0.0, 0.0], m).into_iter().fold(0.0, f64::max);
        assert!(
            worst(&moves) > 1.5 * chord_turn,
            "rounded: {}",
            worst(&moves)
        );
        assert!(
            worst(&out) < 1.3 * chord_turn,
            "smoothed: {}",
            worst(&out) / chord_turn
        );
        for (a, b) in moves.iter().zip(&out) {
            assert!((vector(&a.end) - vector(&b.end)).norm() <= FIT_CAP + 1e-15);
        }
    }

    #[test]
    fn a_feed_change_a_dwell_and_a_sharp_corner_end_a_run_at_the_programmed_point() {
        let pts: Vec<[f64; 3]> = (1..=40)
            .map(|k| [k as f64 * 0.1, 0.0001 * (k % 2) as f64, 0.0])
            .collect();
        let mut moves = cam::lines(&pts, 1000.0);
        // Block 20 at another feed; block 30 turns 90° (it goes along Y).
        moves[20].feed_mm_min = Some(2000.0);
        moves[30].end = vec![moves[29].end[0], 1.0, 0.0];
        for m in moves.iter_mut().skip(31) {
            m.end[1] += 1.0;
        }
        let out = run(&moves, [0.0; 3], 0.01);
        // The points before a break (19: before the feed change, 20: its own, 29: the corner)
        // stay where they were programmed.
        for k in [19, 20, 29, 30, 39] {
            assert_eq!(out[k].end, moves[k].end, "block {k}");
        }
        // Inside a run the zigzag of 0.1 µm is smoothed away.
        assert!(out[10].end[1] != moves[10].end[1]);
        // A dwell passes through unchanged and ends the run before it.
        let mut with_dwell = moves[..12].to_vec();
        with_dwell.insert(
            6,
            Move {
                tag: 99,
                path: Path::Dwell { seconds: 0.5 },
                end: moves[5].end.clone(),
                feed_mm_min: None,
                exact_stop: false,
                tolerance: None,
                thread_pitch: None,
                thread_angle: 0.0,
            },
        );
        let out = run(&with_dwell, [0.0; 3], 0.01);
        assert_eq!(out[6].tag, 99);
        assert_eq!(out[5].end, moves[5].end);
        assert_eq!(out[6].tolerance, None);
    }
}
