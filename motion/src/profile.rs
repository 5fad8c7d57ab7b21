//! One-dimensional path-velocity profiles in continuous time: velocity changes shaped by the
//! acceleration law, cruises, and the reachability functions of the look-ahead passes.
//!
//! Every velocity change starts and ends at zero path acceleration, so segments join without an
//! acceleration step under the S law. A deceleration is the time reversal of the acceleration
//! between the same two speeds, so it covers the same distance: the backward pass uses the same
//! reachability function as the forward one.

use crate::config::Law;
use detmath::Det as _;

/// The path dynamics of one segment under one law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dyn {
    /// The law.
    pub law: Law,
    /// Peak path acceleration, mm/s².
    pub a: f64,
    /// Path jerk under the S law, mm/s³ (infinite: none).
    pub j: f64,
    /// Exponential law: acceleration at the start of an acceleration, relative to `a` (≤ 1).
    pub exp_start: f64,
    /// Exponential law: acceleration at the end of an acceleration, relative to `a` (≤ 1).
    pub exp_end: f64,
}

impl Dyn {
    /// True when the exponential law degenerates to a constant acceleration.
    fn exp_flat(&self) -> bool {
        (self.exp_end / self.exp_start - 1.0).abs() < 1e-9
    }

    /// Duration of a velocity change of `dv` ≥ 0 (zero acceleration at both ends).
    pub fn change_time(&self, dv: f64) -> f64 {
        if dv <= 0.0 {
            return 0.0;
        }
        match self.law {
            Law::SCurve if self.j.is_finite() => {
                if dv >= self.a * self.a / self.j {
                    dv / self.a + self.a / self.j
                } else {
                    2.0 * (dv / self.j).sqrt()
                }
            }
            Law::Exponential if !self.exp_flat() => {
                let (a0, a1) = (self.a * self.exp_start, self.a * self.exp_end);
                dv * (a1 / a0).dln() / (a1 - a0)
            }
            _ => dv / self.a,
        }
    }

    /// The mean-velocity fraction: a change from `lo` by `dv` covers `T·(lo + c·dv)`.
    pub fn centroid(&self) -> f64 {
        match self.law {
            Law::Exponential if !self.exp_flat() => {
                let rho = self.exp_end / self.exp_start;
                1.0 / rho.dln() - 1.0 / (rho - 1.0)
            }
            _ => 0.5,
        }
    }

    /// Distance of a change between the speeds `x` and `y` (either order).
    pub fn change_dist(&self, x: f64, y: f64) -> f64 {
        let (lo, hi) = if x <= y { (x, y) } else { (y, x) };
        let dv = hi - lo;
        self.change_time(dv) * (lo + self.centroid() * dv)
    }

    /// The highest speed reachable from `lo` within `len` (also: the highest speed from which
    /// `lo` is reachable within `len`).
    pub fn reach_up(&self, lo: f64, len: f64) -> f64 {
        if len <= 0.0 {
            return lo;
        }
        let lin = (lo * lo + 2.0 * self.a * len).sqrt();
        if matches!(self.law, Law::Linear) || !self.a.is_finite() {
            return lin;
        }
        let (mut a, mut b) = (lo, lin);
        for _ in 0..60 {
            let m = 0.5 * (a + b);
            if self.change_dist(lo, m) <= len {
                a = m;
            } else {
                b = m;
            }
        }
        a
    }

    /// The lowest speed reachable from `hi` within `len` by decelerating.
    pub fn reach_down(&self, hi: f64, len: f64) -> f64 {
        // A relative slack of 1e-9 absorbs the rounding of distances planned to end at rest.
        if self.change_dist(0.0, hi) <= len * (1.0 + 1e-9) {
            return 0.0;
        }
        if matches!(self.law, Law::Linear) {
            return (hi * hi - 2.0 * self.a * len).max(0.0).sqrt();
        }
        let (mut a, mut b) = (0.0, hi);
        for _ in 0..60 {
            let m = 0.5 * (a + b);
            if self.change_dist(m, hi) <= len {
                b = m;
            } else {
                a = m;
            }
        }
        b
    }
}

/// One piece of a profile.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    /// Constant jerk: x = v0·t + a0·t²/2 + j·t³/6.
    Poly { a0: f64, j: f64 },
    /// Exponential acceleration a = a0·e^{k·t}.
    Exp { a0: f64, k: f64 },
}

/// A phase with its start state.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Phase {
    t0: f64,
    dur: f64,
    x0: f64,
    v0: f64,
    kind: Kind,
}

impl Phase {
    fn eval(&self, t: f64) -> (f64, f64, f64) {
        let t = t.clamp(0.0, self.dur);
        match self.kind {
            Kind::Poly { a0, j } => (
                self.x0 + t * (self.v0 + t * (a0 / 2.0 + t * j / 6.0)),
                self.v0 + t * (a0 + t * j / 2.0),
                a0 + j * t,
            ),
            Kind::Exp { a0, k } => {
                let e = (k * t).dexp_m1();
                (
                    self.x0 + self.v0 * t + a0 * (e / k - t) / k,
                    self.v0 + a0 * e / k,
                    a0 * (e + 1.0),
                )
            }
        }
    }

    fn starts_flat(&self) -> bool {
        match self.kind {
            Kind::Poly { a0, .. } => a0 == 0.0,
            Kind::Exp { .. } => false,
        }
    }

    fn flat(&self) -> bool {
        matches!(self.kind, Kind::Poly { a0, j } if a0 == 0.0 && j == 0.0)
    }
}

/// The most phases a profile holds (two S changes of 3 phases and a cruise).
const MAX_PHASES: usize = 8;

const REST: Phase = Phase {
    t0: 0.0,
    dur: 0.0,
    x0: 0.0,
    v0: 0.0,
    kind: Kind::Poly { a0: 0.0, j: 0.0 },
};

/// A velocity profile along a stretch of one segment, from time 0 (fixed size: no allocation).
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    phases: [Phase; MAX_PHASES],
    n: usize,
    /// Total duration, s.
    pub duration: f64,
    /// Distance covered, mm.
    pub dist: f64,
    /// Speed at the end, mm/s.
    pub v_end: f64,
}

impl Default for Profile {
    fn default() -> Self {
        Profile::start(0.0)
    }
}

impl Profile {
    /// An empty profile at speed `v`.
    fn start(v: f64) -> Profile {
        Profile {
            phases: [REST; MAX_PHASES],
            n: 0,
            duration: 0.0,
            dist: 0.0,
            v_end: v,
        }
    }

    fn push(&mut self, dur: f64, kind: Kind) {
        if dur <= 0.0 {
            return;
        }
        let p = Phase {
            t0: self.duration,
            dur,
            x0: self.dist,
            v0: self.v_end,
            kind,
        };
        let (x, v, _) = p.eval(dur);
        if self.n >= MAX_PHASES {
            return;
        }
        self.phases[self.n] = p;
        self.n += 1;
        self.duration += dur;
        self.dist = x;
        self.v_end = v.max(0.0);
    }

    /// A rest of `seconds` (dwell).
    pub fn rest(seconds: f64) -> Profile {
        let mut p = Profile::start(0.0);
        p.push(seconds, Kind::Poly { a0: 0.0, j: 0.0 });
        p
    }

    /// Appends a change from the current end speed to `to`.
    fn change(&mut self, d: &Dyn, to: f64) {
        let from = self.v_end;
        let dv = (to - from).abs();
        if dv <= 0.0 {
            return;
        }
        let sg = if to > from { 1.0 } else { -1.0 };
        match d.law {
            Law::SCurve if d.j.is_finite() => {
                if dv >= d.a * d.a / d.j {
                    let tj = d.a / d.j;
                    self.push(
                        tj,
                        Kind::Poly {
                            a0: 0.0,
                            j: sg * d.j,
                        },
                    );
                    self.push(
                        dv / d.a - tj,
                        Kind::Poly {
                            a0: sg * d.a,
                            j: 0.0,
                        },
                    );
                    self.push(
                        tj,
                        Kind::Poly {
                            a0: sg * d.a,
                            j: -sg * d.j,
                        },
                    );
                } else {
                    let tj = (dv / d.j).sqrt();
                    self.push(
                        tj,
                        Kind::Poly {
                            a0: 0.0,
                            j: sg * d.j,
                        },
                    );
                    self.push(
                        tj,
                        Kind::Poly {
                            a0: sg * d.j * tj,
                            j: -sg * d.j,
                        },
                    );
                }
            }
            Law::Exponential if !d.exp_flat() => {
                let t = d.change_time(dv);
                let (a0, a1) = (d.a * d.exp_start, d.a * d.exp_end);
                let k = (a1 / a0).dln() / t;
                if sg > 0.0 {
                    self.push(t, Kind::Exp { a0, k });
                } else {
                    self.push(t, Kind::Exp { a0: -a1, k: -k });
                }
            }
            _ => self.push(
                dv / d.a,
                Kind::Poly {
                    a0: sg * d.a,
                    j: 0.0,
                },
            ),
        }
        // Land exactly on the target speed.
        self.v_end = to;
    }

    fn cruise(&mut self, len: f64) {
        if len > 0.0 && self.v_end > 0.0 {
            self.push(len / self.v_end, Kind::Poly { a0: 0.0, j: 0.0 });
        }
    }

    /// The fastest profile over `len` from `v0` to (at most) `v1` under the cap `cap`: change to a
    /// peak, cruise, change to the end speed. When `v1` cannot be reached, the end speed is the
    /// nearest reachable one; when `v0` exceeds the cap, the profile first slows to it.
    pub fn build(d: &Dyn, len: f64, v0: f64, v1: f64, cap: f64) -> Profile {
        let mut p = Profile::start(v0);
        if len <= 0.0 {
            return p;
        }
        let v1 = v1.min(d.reach_up(v0, len)).max(d.reach_down(v0, len));
        if v0 > cap {
            let v1c = v1.min(cap);
            if d.change_dist(v0, cap) + d.change_dist(cap, v1c) <= len {
                p.change(d, cap);
                p.cruise(len - d.change_dist(v0, cap) - d.change_dist(cap, v1c));
                p.change(d, v1c);
            } else {
                p.change(d, v1);
                p.cruise(len - p.dist);
            }
            return p;
        }
        let v1 = v1.min(cap);
        let f = |vp: f64| d.change_dist(v0, vp) + d.change_dist(vp, v1);
        let lo = v0.max(v1);
        let peak = if f(cap) <= len {
            cap
        } else if matches!(d.law, Law::Linear) {
            // (2·vp² − v0² − v1²) / 2a = len.
            ((2.0 * d.a * len + v0 * v0 + v1 * v1) / 2.0)
                .sqrt()
                .clamp(lo, cap)
        } else {
            let (mut a, mut b) = (lo, cap);
            for _ in 0..60 {
                let m = 0.5 * (a + b);
                if f(m) <= len {
                    a = m;
                } else {
                    b = m;
                }
            }
            a
        };
        p.change(d, peak);
        p.cruise(len - f(peak));
        p.change(d, v1);
        p
    }

    /// The S law's bridge out of an acceleration `a0` > 0 at speed `v0`: the acceleration falls
    /// to 0 at the jerk limit (a0/j s, +a0²/2j mm/s); a profile built from its end state is
    /// then [`Profile::append`]ed. None when the law has no jerk limit or `a0` ≤ 0.
    pub fn bridge(d: &Dyn, v0: f64, a0: f64) -> Option<Profile> {
        if !(matches!(d.law, Law::SCurve) && d.j.is_finite() && d.j > 0.0 && a0 > 0.0) {
            return None;
        }
        let mut p = Profile::start(v0);
        p.push(a0 / d.j, Kind::Poly { a0, j: -d.j });
        Some(p)
    }

    /// Appends `next` (which starts at this profile's end speed and zero acceleration).
    pub fn append(&mut self, next: &Profile) {
        for ph in &next.phases[..next.n] {
            self.push(ph.dur, ph.kind);
        }
        self.v_end = next.v_end;
    }

    /// A stop as early as the law allows: slow from `v0` to 0, or to the lowest speed reachable
    /// within `len`.
    pub fn stop(d: &Dyn, len: f64, v0: f64) -> Profile {
        let mut p = Profile::start(v0);
        p.change(d, d.reach_down(v0, len.max(0.0)));
        p
    }

    /// Position, speed and acceleration at time `t` (clamped to the profile).
    pub fn eval(&self, t: f64) -> (f64, f64, f64) {
        if t >= self.duration {
            return (self.dist, self.v_end, 0.0);
        }
        let ph = &self.phases[..self.n];
        let i = ph.partition_point(|p| p.t0 + p.dur <= t);
        match ph.get(i) {
            Some(p) => p.eval(t - p.t0),
            None => (self.dist, self.v_end, 0.0),
        }
    }

    /// The earliest time ≥ `t` at which the profile may be replaced without an acceleration step:
    /// any time under the linear law, otherwise inside a cruise or at a change boundary.
    pub fn replan_time(&self, t: f64, law: Law) -> f64 {
        if matches!(law, Law::Linear) {
            return t;
        }
        for p in &self.phases[..self.n] {
            let end = p.t0 + p.dur;
            if end <= t {
                continue;
            }
            let boundary_ok = p.starts_flat() || matches!(law, Law::Exponential);
            if p.flat() || (boundary_ok && p.t0 >= t) {
                return t.max(p.t0);
            }
        }
        self.duration.max(t)
    }
}
