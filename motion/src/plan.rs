//! The look-ahead planner: moves become pieces (lines, arcs, corner-blend arcs) with their speed
//! caps and path dynamics; junctions get a speed cap; the backward pass limits every piece's end
//! speed so that everything after it can still be met.

use detmath::Det as _;
use std::collections::VecDeque;
use std::f64::consts::{PI, TAU};

use crate::config::{AccParams, AxisLimits, Law};
use crate::geom::{Seg, Shape, Vector};
use crate::moves::{MotionError, Move, Path};
use crate::profile::Dyn;

/// Share of an axis's acceleration available to centripetal acceleration on arcs.
pub const CENTRIPETAL_SHARE: f64 = 0.7;
/// The same on corner blends: short arcs between lines (a chord polygon's corners), whose speed
/// changes mostly happen on the lines around them.
pub const BLEND_CENTRIPETAL_SHARE: f64 = 0.8;
/// Share of an axis's acceleration (and jerk) reserved for the direction change at an unblended
/// junction between pieces whose tangents differ slightly (kept by the pieces on either side of
/// such a kink, and by a piece whose end junction is not known yet).
pub const KINK_SHARE: f64 = 0.02;
/// S law: share of an axis's jerk for the path's tangential jerk (the rest covers the steps of
/// centripetal acceleration where the curvature changes, and the rotation of the acceleration on
/// arcs).
pub const JERK_TANGENT_LINE: f64 = 0.68;
/// S law on arcs: share of an axis's jerk for the tangential jerk.
pub const JERK_TANGENT_ARC: f64 = 0.4;
/// S law: share of an axis's jerk × tick for the centripetal-acceleration step at a curvature change.
pub const JERK_STEP: f64 = 0.3;
/// S law: share of an axis's jerk for the rotation of the centripetal acceleration (v³κ²).
pub const JERK_ROTATION: f64 = 0.28;
/// Turns sharper than this (rad) are not blended: the tool stops at the corner.
pub const MAX_BLEND_TURN: f64 = PI * (179.0 / 180.0);

/// What kind of motion a piece is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Motion {
    /// G00 at the axes' rapid speed × rapid override.
    Rapid,
    /// Feed move at the programmed feed × feed override.
    Feed,
    /// G33: position locked to the spindle ([`crate::thread`]), no override, no blending.
    Thread {
        /// Path advance per spindle revolution, mm.
        per_rev: f64,
        /// Start angle after the index pulse, fraction of a revolution in [0, 1).
        angle: f64,
    },
    /// Dwell at rest, s.
    Dwell(f64),
}

/// One piece of the path in the look-ahead queue.
#[derive(Debug, Clone, PartialEq)]
pub struct Piece {
    /// Geometry.
    pub seg: Seg,
    /// The move it belongs to.
    pub tag: u64,
    /// The last piece of its move (its end is the move's DEN).
    pub den: bool,
    /// Kind of motion.
    pub motion: Motion,
    /// Programmed path speed, mm/s (rapid: infinite; thread: pitch × rev/s).
    pub feed: f64,
    /// Speed cap from the axis limits and the centripetal acceleration, mm/s.
    pub v_hard: f64,
    /// Path dynamics (the tangential acceleration follows the cap, see [`tune`]).
    pub dynm: Dyn,
    /// The untuned speed cap and tangential acceleration (before [`tune`]).
    pub base: (f64, f64),
    /// Per axis: the largest share of the direction, the centripetal share per (mm/s)², and the
    /// acceleration available (98 % of the limit under the piece's law).
    pub axis: [Vector; 3],
    /// Speed cap at the end (the junction with the next piece).
    pub v_junction: f64,
    /// End-speed limit from the backward pass.
    pub v_end: f64,
    /// Length before blending shortened it.
    pub len_orig: f64,
    /// Path tolerance for blending at its end, mm (0: exact corner).
    pub tol: f64,
    /// Exact stop requested at its end.
    pub exact: bool,
    /// For a corner-blend arc: the programmed corner it replaces.
    pub corner: Option<Vector>,
    /// Its dynamics keep the kink reserve ([`KINK_SHARE`]).
    pub reserve: bool,
    /// Its start is an unblended kink (the reserve stays).
    pub kink_start: bool,
    /// Complex speed: the joint speed the criteria allow at its start (infinite: none).
    pub crit_start: f64,
    /// Complex speed: the path acceleration under smooth connection (R236; infinite: none).
    pub a_cap: f64,
}

/// Recomputes a piece's dynamics without the kink reserve once both its junctions are known to
/// be smooth (a corner blend, a stop or the start at rest) under the overrides (percent).
pub fn relax(p: &mut Piece, axes: &[AxisLimits], acc: &AccParams, dt: f64, pcts: (u16, u16)) {
    if !p.reserve || p.kink_start || matches!(p.motion, Motion::Dwell(_)) {
        return;
    }
    let rapid = p.motion == Motion::Rapid;
    p.reserve = false;
    if matches!(p.seg.shape, Shape::Line { .. }) {
        // A line has no centripetal part: only the tangential acceleration grows.
        let mut amin = f64::INFINITY;
        for (i, ax) in axes.iter().enumerate() {
            let (_, a, _) = axis_vaj(ax, rapid, p.dynm.law, acc);
            p.axis[2][i] = a;
            if p.axis[0][i] > 0.0 {
                amin = amin.min(a / p.axis[0][i]);
            }
        }
        if amin.is_finite() {
            p.dynm.a = amin.min(p.a_cap);
            p.base.1 = p.dynm.a;
        }
        return;
    }
    let share = if p.corner.is_some() {
        BLEND_CENTRIPETAL_SHARE
    } else {
        CENTRIPETAL_SHARE
    };
    let (v_hard, dynm, axis) = dynamics(axes, &p.seg, rapid, p.dynm.law, acc, dt, false, share);
    p.v_hard = v_hard;
    p.base = (v_hard, dynm.a.min(p.a_cap));
    p.dynm = dynm;
    p.dynm.a = p.base.1;
    p.axis = axis;
    tune(p, pcts.0, pcts.1, false);
}

/// The per-law limits of every axis for feed or rapid moves: (v, a, j) in mm/s, mm/s², mm/s³.
pub fn axis_vaj(ax: &AxisLimits, rapid: bool, law: Law, acc: &AccParams) -> (f64, f64, f64) {
    let (v, a, j) = if rapid {
        (ax.v_rapid, ax.a_rapid, ax.j_rapid)
    } else {
        (ax.v_max, ax.a_max, ax.j_max)
    };
    match law {
        Law::SCurve => (v, a * acc.linear_part_s, j.unwrap_or(f64::INFINITY)),
        _ => (v, a, f64::INFINITY),
    }
}

/// The speed cap and path dynamics of `seg` for these axes; `reserve`: keep [`KINK_SHARE`] of
/// every axis's acceleration for a kink at either end; `centripetal`: the share of every axis's
/// acceleration the centripetal acceleration may take.
#[allow(clippy::too_many_arguments)]
pub fn dynamics(
    axes: &[AxisLimits],
    seg: &Seg,
    rapid: bool,
    law: Law,
    acc: &AccParams,
    dt: f64,
    reserve: bool,
    centripetal: f64,
) -> (f64, Dyn, [Vector; 3]) {
    let keep = if reserve { 1.0 - KINK_SHARE } else { 1.0 };
    let mut share = seg.max_share();
    let mut curv = seg.curvature_share();
    if let (Some((ts, ns)), Shape::Arc { r0, .. }) = (seg.arc_shares(), &seg.shape) {
        // Exact over the sweep: far below the plane-wide bound on corner blends.
        share = share.inf(&ts);
        curv = curv.inf(&(ns / *r0));
    }
    let kappa = curv.max();
    let tangent = if kappa > 0.0 {
        JERK_TANGENT_ARC
    } else {
        JERK_TANGENT_LINE
    };
    let mut v_hard = f64::INFINITY;
    let mut jmin = f64::INFINITY;
    for (i, ax) in axes.iter().enumerate() {
        let (v, a, j) = axis_vaj(ax, rapid, law, acc);
        if share[i] > 0.0 {
            v_hard = v_hard.min(v / share[i]);
            jmin = jmin.min(tangent * j / share[i]);
        }
        if curv[i] > 0.0 {
            v_hard = v_hard.min((centripetal * a / curv[i]).sqrt());
            if j.is_finite() {
                v_hard = v_hard.min((JERK_STEP * j * dt / curv[i]).sqrt());
                v_hard = v_hard.min((JERK_ROTATION * j / (curv[i] * kappa)).dcbrt());
            }
        }
    }
    let mut amin = f64::INFINITY;
    let mut avail = Vector::zeros();
    for (i, ax) in axes.iter().enumerate() {
        let (_, a, _) = axis_vaj(ax, rapid, law, acc);
        avail[i] = keep * a;
        if share[i] > 0.0 {
            let left = keep * a - v_hard * v_hard * curv[i];
            amin = amin.min(left / share[i]);
        }
    }
    if !amin.is_finite() {
        amin = 1.0;
        v_hard = f64::INFINITY;
    }
    let top = acc.min_exp.max(acc.max_exp);
    let d = Dyn {
        law,
        a: amin,
        j: if law == Law::SCurve {
            jmin
        } else {
            f64::INFINITY
        },
        exp_start: acc.min_exp / top,
        exp_end: acc.max_exp / top,
    };
    (v_hard, d, [share, curv, avail])
}

/// Sets an arc piece's tangential acceleration to what its speed cap under the current overrides
/// leaves of every axis's acceleration after the centripetal part, and fixes that cap as the
/// piece's ceiling. With `raise_only` (an override change on a queued piece) the ceiling only
/// rises, re-tuned from the piece's untuned cap and acceleration: a lower override keeps the old
/// ceiling, whose acceleration holds at every speed up to it, so the change is safe even for the
/// piece being executed.
pub fn tune(p: &mut Piece, feed_pct: u16, rapid_pct: u16, raise_only: bool) {
    let [share, curv, avail] = &p.axis;
    if curv.max() <= 0.0 {
        return;
    }
    let (v_base, a_base) = p.base;
    let c = cap_at(p, v_base, feed_pct, rapid_pct).min(v_base);
    if raise_only && c <= p.v_hard {
        return;
    }
    // On a planar circular arc an axis sees a_t·t_i + a_n·n_i with t ⟂ n in the plane, so
    // |a_i| ≤ |(a_t, a_n)|·share_i: the tangential and centripetal parts add as a vector. On
    // helices and spirals they are added as magnitudes.
    // The shares in `p.axis` are exact over the sweep (see `Seg::arc_shares`), valid for the
    // sum of magnitudes; the vector bound needs the plane-wide share √(e1_i² + e2_i²), and each
    // axis takes the better of the two.
    let plane = match &p.seg.shape {
        Shape::Arc {
            e1,
            e2,
            r0,
            r1,
            lift,
            ..
        } if r0 == r1 && lift.norm() == 0.0 => Some((e1, e2, *r0)),
        _ => None,
    };
    let mut a = f64::INFINITY;
    for i in 0..share.len() {
        if share[i] > 0.0 {
            let mut best = (avail[i] - c * c * curv[i]) / share[i];
            if let Some((e1, e2, r)) = plane {
                let o = e1[i].dhypot(e2[i]);
                let an = c * c * o / r;
                best = best.max((avail[i] * avail[i] - an * an).max(0.0).sqrt() / o);
            }
            a = a.min(best);
        }
    }
    if a.is_finite() && a > 0.0 && a > a_base {
        p.dynm.a = a.min(p.a_cap);
        p.v_hard = c;
    } else if raise_only {
        p.dynm.a = a_base;
        p.v_hard = v_base;
    }
}

/// The speed cap of a direction change of `theta` rad within one tick `dt` (no blend).
pub fn kink_cap(axes: &[AxisLimits], theta: f64, dt: f64, law: Law, acc: &AccParams) -> f64 {
    let k = 2.0 * (theta / 2.0).dsin();
    if k <= 0.0 {
        return f64::INFINITY;
    }
    let mut cap = f64::INFINITY;
    for ax in axes {
        let (_, a, j) = axis_vaj(ax, false, law, acc);
        cap = cap.min(KINK_SHARE * a * dt / k);
        if j.is_finite() {
            cap = cap.min(KINK_SHARE * j * dt * dt / k);
        }
    }
    cap
}

/// The geometry of a move from `start`: its segment (None for a dwell).
pub fn segment(m: &Move, start: &Vector, end: &Vector) -> Result<Option<Seg>, MotionError> {
    match &m.path {
        Path::Dwell { .. } => Ok(None),
        Path::Rapid | Path::Line => Ok(Some(Seg::line(*start, *end))),
        Path::Arc {
            plane: (a, b),
            center,
            cw,
            turns,
        } => {
            let bad = |what: &str| MotionError::Invalid {
                tag: m.tag,
                what: what.into(),
            };
            if a == b || *a >= m.end.len() || *b >= m.end.len() {
                return Err(bad("arc plane axes out of range"));
            }
            let rel0 = (start[*a] - center[0], start[*b] - center[1]);
            let rel1 = (end[*a] - center[0], end[*b] - center[1]);
            let r0 = rel0.0.dhypot(rel0.1);
            let r1 = rel1.0.dhypot(rel1.1);
            if r0 <= 0.0 || r1 <= 0.0 || !(r0.is_finite() && r1.is_finite()) {
                return Err(bad("arc with zero radius"));
            }
            let p0 = rel0.1.datan2(rel0.0);
            let p1 = rel1.1.datan2(rel1.0);
            let mut sweep = if *cw { p0 - p1 } else { p1 - p0 }.rem_euclid(TAU);
            if sweep < 1e-12 {
                sweep = TAU;
            }
            sweep += TAU * f64::from(*turns);
            let mut ea = Vector::zeros();
            ea[*a] = 1.0;
            let mut eb = Vector::zeros();
            eb[*b] = 1.0;
            let e1 = ea * p0.dcos() + eb * p0.dsin();
            let mut e2 = eb * p0.dcos() - ea * p0.dsin();
            if *cw {
                e2 = -e2;
            }
            let mut c = *start;
            c[*a] = center[0];
            c[*b] = center[1];
            let mut lift = end - start;
            lift[*a] = 0.0;
            lift[*b] = 0.0;
            Ok(Some(Seg::arc(*start, *end, c, e1, e2, r0, r1, sweep, lift)))
        }
    }
}

/// Blends the corner between `prev` (a line, not started) and `next` (a line) with a circular arc
/// that passes within `tol` of the corner; shortens both lines and returns the arc and the corner.
pub fn blend(prev: &mut Piece, next: &mut Piece, theta: f64) -> Option<(Seg, Vector)> {
    let tol = prev.tol.min(next.tol);
    if tol <= 0.0 || theta <= 1e-9 || theta >= MAX_BLEND_TURN {
        return None;
    }
    let h = theta / 2.0;
    let q = (theta / 4.0).dsin();
    // Corner-to-arc distance R(1/cos h − 1) = tol, with R = d / tan h.
    let d_tol = tol * h.dsin() / (2.0 * q * q);
    let d = d_tol
        .min(prev.len_orig / 2.0)
        .min(next.len_orig / 2.0)
        .min(prev.seg.len);
    if d <= 0.0 || d > next.seg.len {
        return None;
    }
    let corner = prev.seg.end;
    let u1 = prev.seg.tangent(true);
    let u2 = next.seg.tangent(false);
    let r = d / h.dtan();
    let bis = (u2 - u1).normalize();
    let center = corner + bis * (r / h.dcos());
    let a = corner - u1 * d;
    let b = corner + u2 * d;
    let e1 = (a - center) / r;
    let arc = Seg::arc(a, b, center, e1, u1, r, r, theta, Vector::zeros());
    prev.seg = Seg::line_along(prev.seg.start, a, u1);
    next.seg = Seg::line_along(b, next.seg.end, u2);
    Some((arc, corner))
}

/// The piece's speed cap under the overrides (percent).
pub fn cap(p: &Piece, feed_pct: u16, rapid_pct: u16) -> f64 {
    cap_at(p, p.v_hard, feed_pct, rapid_pct)
}

/// The piece's speed cap under the overrides (percent) with the hard cap `v_hard`.
fn cap_at(p: &Piece, v_hard: f64, feed_pct: u16, rapid_pct: u16) -> f64 {
    match p.motion {
        Motion::Rapid => v_hard * f64::from(rapid_pct) / 100.0,
        Motion::Feed => v_hard.min(p.feed * f64::from(feed_pct) / 100.0),
        Motion::Thread { .. } => v_hard.min(p.feed),
        Motion::Dwell(_) => 0.0,
    }
}

/// The backward pass from the end of the queue: every piece's end speed allows stopping at the
/// end of the queue and meeting every junction and cap after it. Below index `keep_to` (pieces
/// whose geometry did not change) it stops at the first end speed that did not change.
pub fn backward(q: &mut VecDeque<Piece>, feed_pct: u16, rapid_pct: u16, keep_to: usize) {
    let n = q.len();
    let mut next_start = 0.0_f64; // the highest speed allowed at the start of piece k+1
    for k in (0..n).rev() {
        let v = if k + 1 == n {
            0.0
        } else {
            q[k].v_junction
                .min(cap(&q[k], feed_pct, rapid_pct))
                .min(next_start)
        };
        let unchanged = q[k].v_end == v;
        q[k].v_end = v;
        let p = &q[k];
        next_start = match p.motion {
            Motion::Dwell(_) => 0.0,
            _ => p
                .dynm
                .reach_up(v, p.seg.len)
                .min(cap(p, feed_pct, rapid_pct)),
        };
        if unchanged && k < keep_to {
            break;
        }
    }
}

/// How many leading pieces of the queue have end speeds that no later append can change: the
/// count before the last piece (from the tail) whose allowed start speed is its own cap however
/// the queue continues. The walk assumes the worst continuation, a stop at the start of the last
/// piece (the only piece an append reshapes), so that later appends can only raise the speeds
/// it sees; a margin of 1e-9 keeps rounding from deciding.
pub fn settled(q: &VecDeque<Piece>, feed_pct: u16, rapid_pct: u16) -> usize {
    let n = q.len();
    let mut next_start = 0.0_f64;
    for k in (0..n.saturating_sub(1)).rev() {
        let p = &q[k];
        if matches!(p.motion, Motion::Dwell(_)) {
            return k;
        }
        let c = cap(p, feed_pct, rapid_pct);
        let v = p.v_junction.min(c).min(next_start);
        let reach = p.dynm.reach_up(v, p.seg.len);
        if reach >= c * (1.0 + 1e-9) {
            return k;
        }
        next_start = reach.min(c);
    }
    0
}
