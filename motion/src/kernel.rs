//! The kernel: a look-ahead queue of pieces, the profile of the piece being executed, run-time
//! commands (override, hold, law, stop at block end, abort) and the per-tick interpolation.

use std::collections::VecDeque;

use crate::config::{Config, ConfigError, Law};
use crate::geom::{Seg, Shape, Vector, turn_angle, vector};
use crate::moves::{MotionError, Move, Path};
use crate::plan::{self, Motion, Piece};
use crate::profile::Profile;
use crate::smooth::Smoother;
use crate::thread::{self, ThreadRun};

/// The output of one interpolation tick.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Tick {
    /// Set point of every axis, Config order, mm.
    pub position: Vec<f64>,
    /// The block whose path the set point is on (None when idle).
    pub tag: Option<u64>,
    /// Path speed, mm/min.
    pub feed_mm_min: f64,
    /// Blocks whose motion ended during this tick (DEN), in order.
    pub finished: Vec<u64>,
    /// At rest because of a feed hold (or a stop at block end).
    pub held: bool,
}

/// The piece being executed: its profile from `s0` on.
#[derive(Debug, Clone)]
pub(crate) struct Exec {
    pub(crate) prof: Profile,
    pub(crate) t: f64,
    pub(crate) s0: f64,
}

/// The motion kernel of one process.
#[derive(Debug, Clone)]
pub struct Kernel {
    pub(crate) cfg: Config,
    pub(crate) law: Law,
    pub(crate) q: VecDeque<Piece>,
    pub(crate) moves: usize,
    pub(crate) end: Vector,
    pub(crate) exec: Option<Exec>,
    pub(crate) v: f64,
    pub(crate) pos: Vector,
    pub(crate) feed_pct: u16,
    pub(crate) rapid_pct: u16,
    pub(crate) hold: bool,
    pub(crate) abort: bool,
    pub(crate) stop_after: Option<u64>,
    pub(crate) replan: bool,
    /// Spindle position, rev (signed), at the end of the last tick and of this one (None until
    /// the caller gives one: a kernel made anew mid-run does not see a jump from 0).
    pub(crate) spindle: Option<(f64, f64)>,
    /// The thread block at the front of the queue, when one is being run.
    pub(crate) thread: Option<ThreadRun>,
    /// A thread just ended here (spindle position, direction): a thread right after it goes on
    /// locked without waiting for the index.
    pub(crate) thread_chain: Option<(f64, f64)>,
    /// An emergency stop's per-axis deceleration (AFC, mm/s²; None: the axis's own limit).
    pub(crate) emergency: Option<Vec<Option<f64>>>,
    /// A fault for the caller ([`Kernel::take_fault`]).
    pub(crate) fault: Option<MotionError>,
    pub(crate) out: Tick,
    /// The lowest queue index whose geometry changed since the last backward pass (None: the
    /// end speeds are those of the current queue).
    pub(crate) dirty_from: Option<usize>,
    /// Leading pieces whose end speeds no append can change (see [`plan::settled`]).
    pub(crate) final_to: usize,
    /// Some axis has a soft limit (else the path's bounds are not computed).
    pub(crate) soft: bool,
    /// Arc ceilings raised by an override change: (queue index, old cap, old acceleration).
    pub(crate) undo: Vec<(usize, f64, f64)>,
    /// Programmed units → slide mm per axis (0.5 for a diameter axis); the kernel plans and
    /// interpolates in slide mm, and takes and reports positions in programmed units.
    pub(crate) scale: Vec<f64>,
    /// Some axis has a factor other than 1.
    pub(crate) scaled: bool,
    /// Tolerance-band smoothing of short lines ([`crate::smooth`]; None: off).
    pub(crate) smooth: Option<Smoother>,
    /// The last programmed end point pushed (slide mm; `end` is the smoothed one).
    pub(crate) prog_end: Vector,
    /// A move was pushed since the last tick.
    pub(crate) pushed: bool,
}

impl Kernel {
    /// A kernel at rest at `start` (one coordinate per configured axis).
    pub fn new(cfg: Config, start: &[f64]) -> Result<Kernel, ConfigError> {
        cfg.validate()?;
        if start.len() != cfg.axes.len() || start.iter().any(|v| !v.is_finite()) {
            return Err(ConfigError::Start {
                got: start.len(),
                want: cfg.axes.len(),
            });
        }
        let scale = cfg.slide_scale();
        let scaled = scale.iter().any(|k| *k != 1.0);
        let slide: Vec<f64> = start.iter().zip(&scale).map(|(x, k)| x * k).collect();
        let pos = vector(&slide);
        let cfg_soft = cfg
            .axes
            .iter()
            .any(|a| a.soft_min.is_some() || a.soft_max.is_some());
        Ok(Kernel {
            law: cfg.law,
            out: Tick {
                position: start.to_vec(),
                ..Tick::default()
            },
            cfg,
            q: VecDeque::new(),
            moves: 0,
            end: pos,
            exec: None,
            v: 0.0,
            pos,
            feed_pct: 100,
            rapid_pct: 100,
            hold: false,
            abort: false,
            stop_after: None,
            replan: false,
            spindle: None,
            thread: None,
            thread_chain: None,
            emergency: None,
            fault: None,
            dirty_from: None,
            final_to: 0,
            soft: cfg_soft,
            undo: Vec::new(),
            scale,
            scaled,
            smooth: None,
            prog_end: pos,
            pushed: false,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.cfg
    }

    /// Queues a move; refused (before any motion) when its path leaves a soft limit, it lacks a
    /// feed, it is malformed or the queue is full. Under smoothing a short line may be held back
    /// until the points after it are known (it counts against the window meanwhile).
    pub fn push(&mut self, m: Move) -> Result<(), MotionError> {
        let m = if self.scaled {
            m.scaled(&self.scale)
        } else {
            m
        };
        let n = self.cfg.axes.len();
        if self.moves + self.held() >= self.cfg.window {
            return Err(MotionError::QueueFull { tag: m.tag });
        }
        if m.end.len() != n || m.end.iter().any(|v| !v.is_finite()) {
            return Err(MotionError::Invalid {
                tag: m.tag,
                what: format!("{} finite end coordinates expected", n),
            });
        }
        self.pushed = true;
        let end = vector(&m.end);
        let tol = self.cfg.tolerance_mm;
        let Some(sm) = self.smooth.as_mut() else {
            self.prog_end = end;
            return self.enqueue(m);
        };
        sm.push(m, &self.prog_end, tol);
        self.prog_end = end;
        self.drain()
    }

    /// Moves held by the smoother.
    fn held(&self) -> usize {
        self.smooth.as_ref().map_or(0, Smoother::held)
    }

    /// Queues the moves the smoother has made ready.
    fn drain(&mut self) -> Result<(), MotionError> {
        while let Some(m) = self.smooth.as_mut().and_then(Smoother::pop) {
            self.enqueue(m)?;
        }
        Ok(())
    }

    /// Switches tolerance-band smoothing of short lines on or off for the moves pushed from now
    /// on (off: the held moves are queued at once).
    pub fn set_smoothing(&mut self, on: bool) -> Result<(), MotionError> {
        match (on, self.smooth.is_some()) {
            (true, false) => self.smooth = Some(Smoother::default()),
            (false, true) => {
                if let Some(sm) = self.smooth.as_mut() {
                    sm.flush();
                }
                self.drain()?;
                self.smooth = None;
            }
            _ => {}
        }
        Ok(())
    }

    /// The caller has pushed every move that comes before the path stops (the program ends, or
    /// the next block waits for functions): the moves the smoother holds are queued now, the
    /// last one ending at its programmed point, and the path stops at the end of the last queued
    /// move (as before a dwell or an aux record: that end is a known stop, so the move plans
    /// without the kink reserve of an unknown junction). Idempotent. Callers that push at
    /// another rhythm call it at the same point of the block sequence, so that their runs
    /// smooth and plan alike (`ncplc nc run` and the `cnc` kernel's part runs).
    pub fn end_of_input(&mut self) -> Result<(), MotionError> {
        if self.held() > 0 {
            if let Some(sm) = self.smooth.as_mut() {
                sm.flush();
            }
            self.drain()?;
        }
        let n = self.q.len();
        let executing = self.exec.is_some() && n == 1;
        let (dt, acc, pcts) = (
            self.cfg.tick_s,
            self.cfg.acc,
            (self.feed_pct, self.rapid_pct),
        );
        if let Some(last) = self.q.back_mut()
            && !last.exact
        {
            last.exact = true;
            last.v_junction = 0.0;
            if !executing {
                plan::relax(last, &self.cfg.axes, &acc, dt, pcts);
            }
            self.dirty_from = Some(self.dirty_from.map_or(n - 1, |d| d.min(n - 1)));
        }
        Ok(())
    }

    /// Smoothing is on.
    pub fn smoothing(&self) -> bool {
        self.smooth.is_some()
    }

    /// Queues a move (already in slide units, checked for its axis count).
    fn enqueue(&mut self, m: Move) -> Result<(), MotionError> {
        let end = vector(&m.end);
        let seg = plan::segment(&m, &self.end, &end)?;
        let share = seg.as_ref().map_or(0.0, |s| {
            s.max_share().iter().fold(0.0, |m: f64, x| m.max(x.abs()))
        });
        let motion = match (&m.path, m.thread_pitch) {
            (Path::Dwell { seconds }, _) => Motion::Dwell(seconds.max(0.0)),
            (_, Some(lead)) if share > 0.0 && lead > 0.0 && lead.is_finite() => Motion::Thread {
                per_rev: lead / share,
                angle: thread::angle_fraction(m.thread_angle),
            },
            (_, Some(_)) => {
                return Err(MotionError::Invalid {
                    tag: m.tag,
                    what: "G33 thread without a positive lead".into(),
                });
            }
            (Path::Rapid, None) => Motion::Rapid,
            _ => Motion::Feed,
        };
        let feed = match motion {
            Motion::Rapid | Motion::Dwell(_) => f64::INFINITY,
            // The path speed at the programmed spindle speed (F is lead × S along the lead axis).
            Motion::Thread { .. } => m.feed_mm_min.unwrap_or(0.0) / 60.0 / share,
            Motion::Feed => match m.feed_mm_min {
                Some(f) if f > 0.0 && f.is_finite() => f / 60.0,
                _ => {
                    let what = if matches!(m.path, Path::Arc { .. }) {
                        "arc"
                    } else {
                        "linear move"
                    };
                    return Err(MotionError::NoFeed { tag: m.tag, what });
                }
            },
        };
        // A move that goes nowhere (or a dwell) is a stop of its own.
        let (seg, motion) = match seg {
            Some(s) if s.len > 0.0 => (s, motion),
            _ => (
                Seg::line(end, end),
                match motion {
                    Motion::Dwell(t) => Motion::Dwell(t),
                    _ => Motion::Dwell(0.0),
                },
            ),
        };
        self.check_soft(m.tag, &seg)?;
        let rapid = motion == Motion::Rapid;
        let (v_hard, dynm, axis) = plan::dynamics(
            &self.cfg.axes,
            &seg,
            rapid,
            self.law,
            &self.cfg.acc,
            self.cfg.tick_s,
            true,
            plan::CENTRIPETAL_SHARE,
        );
        let len = seg.len;
        let mut piece = Piece {
            seg,
            tag: m.tag,
            den: true,
            motion,
            feed,
            v_hard,
            base: (v_hard, dynm.a),
            dynm,
            axis,
            v_junction: f64::INFINITY,
            v_end: 0.0,
            len_orig: len,
            tol: m.tolerance.unwrap_or(self.cfg.tolerance_mm).max(0.0),
            exact: m.exact_stop || matches!(motion, Motion::Thread { .. } | Motion::Rapid),
            corner: None,
            reserve: true,
            kink_start: false,
            crit_start: f64::INFINITY,
            a_cap: f64::INFINITY,
        };
        // Complex speed: R236 is the path acceleration under smooth connection.
        if self.smooth.is_some() && motion == Motion::Feed && self.cfg.complex.smooth_accel > 0.0 {
            piece.a_cap = self.cfg.complex.smooth_accel;
            piece.dynm.a = piece.dynm.a.min(piece.a_cap);
            piece.base.1 = piece.dynm.a;
        }
        if matches!(motion, Motion::Dwell(_)) {
            piece.exact = true;
        }
        if matches!(motion, Motion::Thread { .. }) && feed > v_hard * (1.0 + 1e-9) {
            return Err(MotionError::ThreadTooFast {
                tag: m.tag,
                need: feed * 60.0,
                limit: v_hard * 60.0,
            });
        }
        plan::tune(&mut piece, self.feed_pct, self.rapid_pct, false);
        let keep_to = self.join(&mut piece);
        self.q.push_back(piece);
        self.moves += 1;
        self.end = end;
        // The backward pass waits until the front reaches a piece whose end speed an append can
        // still change (see `plan_front`): one pass then serves every push since the last one.
        self.dirty_from = Some(self.dirty_from.map_or(keep_to, |d| d.min(keep_to)));
        Ok(())
    }

    /// Sets the junction of the last queued piece with `next`, blending line corners; returns the
    /// first queue index whose geometry changed.
    fn join(&mut self, next: &mut Piece) -> usize {
        let n = self.q.len();
        let executing = self.exec.is_some() && n == 1;
        let (dt, law, acc) = (self.cfg.tick_s, self.law, self.cfg.acc);
        let pcts = (self.feed_pct, self.rapid_pct);
        let complex = self.smooth.is_some();
        let Some(prev) = self.q.back_mut() else {
            return 0;
        };
        if prev.exact || next.exact {
            prev.v_junction = 0.0;
            if !executing {
                plan::relax(prev, &self.cfg.axes, &acc, dt, pcts);
            }
            return n - 1;
        }
        let theta = turn_angle(&prev.seg.tangent(true), &next.seg.tangent(false));
        // Complex speed under contour control (MEFI appendix A6): a joint sharper than R39, or
        // into a block shorter than R382, is the end of smoothness (a stop); otherwise the
        // accuracy and dynamic criteria cap it, and a line shorter than R386 keeps its joint
        // speeds inside.
        let mut crit = f64::INFINITY;
        if complex && prev.motion == Motion::Feed && next.motion == Motion::Feed {
            let cs = &self.cfg.complex;
            if theta > cs.angle || next.len_orig < cs.interrupt_len {
                prev.v_junction = 0.0;
                if !executing {
                    plan::relax(prev, &self.cfg.axes, &acc, dt, pcts);
                }
                return n - 1;
            }
            crit = cs.joint_speed(theta, prev.len_orig, next.len_orig, dt);
            next.crit_start = crit;
            if prev.len_orig < cs.raise_len && !executing {
                prev.feed = prev.feed.min(prev.crit_start.max(crit));
            }
        }
        let lines = matches!(prev.seg.shape, Shape::Line { .. })
            && matches!(next.seg.shape, Shape::Line { .. });
        if lines
            && !executing
            && prev.den
            && let Some((arc, corner)) = plan::blend(prev, next, theta)
        {
            prev.den = false;
            prev.v_junction = f64::INFINITY;
            plan::relax(prev, &self.cfg.axes, &acc, dt, pcts);
            // Both ends of the blend are tangent: no kink reserve.
            let (v_hard, dynm, axis) = plan::dynamics(
                &self.cfg.axes,
                &arc,
                false,
                prev.dynm.law,
                &acc,
                dt,
                false,
                plan::BLEND_CENTRIPETAL_SHARE,
            );
            let len = arc.len;
            let mut piece = Piece {
                seg: arc,
                tag: prev.tag,
                den: true,
                motion: Motion::Feed,
                feed: prev.feed.min(next.feed),
                v_hard,
                base: (v_hard, dynm.a),
                dynm,
                axis,
                v_junction: f64::INFINITY,
                v_end: 0.0,
                len_orig: len,
                tol: prev.tol,
                exact: false,
                corner: Some(corner),
                reserve: false,
                kink_start: false,
                crit_start: f64::INFINITY,
                a_cap: prev.a_cap,
            };
            piece.dynm.a = piece.dynm.a.min(piece.a_cap);
            piece.base.1 = piece.dynm.a;
            // Complex speed: the joint criteria cap the corner.
            piece.feed = piece.feed.min(crit);
            plan::tune(&mut piece, self.feed_pct, self.rapid_pct, false);
            self.q.push_back(piece);
            return n - 1;
        }
        prev.v_junction = plan::kink_cap(&self.cfg.axes, theta, dt, law, &acc).min(crit);
        if prev.v_junction.is_finite() {
            next.kink_start = true;
        } else if !executing {
            plan::relax(prev, &self.cfg.axes, &acc, dt, pcts);
        }
        n - 1
    }

    fn check_soft(&self, tag: u64, seg: &Seg) -> Result<(), MotionError> {
        if !self.soft {
            return Ok(());
        }
        let (lo, hi) = seg.bounds();
        for (i, ax) in self.cfg.axes.iter().enumerate() {
            // The limits are in programmed units (a diameter axis's in diameters).
            let (lo, hi) = (lo[i] / self.scale[i], hi[i] / self.scale[i]);
            if let Some(max) = ax.soft_max
                && hi > max
            {
                return Err(MotionError::SoftLimit {
                    tag,
                    axis: ax.name,
                    limit: max,
                    reach: hi,
                });
            }
            if let Some(min) = ax.soft_min
                && lo < min
            {
                return Err(MotionError::SoftLimit {
                    tag,
                    axis: ax.name,
                    limit: min,
                    reach: lo,
                });
            }
        }
        Ok(())
    }

    /// Free look-ahead slots (blocks).
    pub fn space(&self) -> usize {
        self.cfg.window.saturating_sub(self.moves + self.held())
    }

    /// Feed override, percent (0–255); ramped within the limits from the current tick. An
    /// unchanged value costs nothing (no retune, no replan: the look-ahead stays deferred).
    pub fn set_feed_override(&mut self, pct: u16) {
        let pct = pct.min(255);
        if pct == self.feed_pct {
            return;
        }
        self.feed_pct = pct;
        self.retune();
        self.replan_all();
    }

    /// Rapid override, percent (0–255); an unchanged value costs nothing.
    pub fn set_rapid_override(&mut self, pct: u16) {
        let pct = pct.min(255);
        if pct == self.rapid_pct {
            return;
        }
        self.rapid_pct = pct;
        self.retune();
        self.replan_all();
    }

    /// Raises the ceilings of queued arcs to a raised override (see [`plan::tune`]), unless the
    /// lower tangential accelerations that come with them leave the executed piece unable to
    /// meet its new end speed from the state at which it will be replanned; then every ceiling
    /// stays as it was. (Every later piece is feasible from its planned start speed by the
    /// backward pass.)
    fn retune(&mut self) {
        self.undo.clear();
        for (i, p) in self.q.iter_mut().enumerate() {
            let old = (p.v_hard, p.dynm.a);
            plan::tune(p, self.feed_pct, self.rapid_pct, true);
            if (p.v_hard, p.dynm.a) != old {
                self.undo.push((i, old.0, old.1));
            }
        }
        if self.undo.is_empty() {
            return;
        }
        plan::backward(&mut self.q, self.feed_pct, self.rapid_pct, 0);
        if let (Some(ex), Some(front)) = (&self.exec, self.q.front()) {
            let tr = ex.prof.replan_time(ex.t, front.dynm.law);
            let (x, v, _) = ex.prof.eval(tr);
            let rem = (front.seg.len - ex.s0 - x).max(0.0);
            if front.dynm.reach_down(v, rem) > front.v_end * (1.0 + 1e-9) {
                for &(i, v_hard, a) in &self.undo {
                    self.q[i].v_hard = v_hard;
                    self.q[i].dynm.a = a;
                }
            }
        }
    }

    fn replan_all(&mut self) {
        plan::backward(&mut self.q, self.feed_pct, self.rapid_pct, 0);
        self.dirty_from = None;
        self.final_to = plan::settled(&self.q, self.feed_pct, self.rapid_pct);
        self.replan = self.exec.is_some();
    }

    /// Brings the front piece's end speed up to date with the queue: runs the pending backward
    /// pass when pieces were appended and the front is not yet settled. The speeds are the same
    /// as those of a pass after every push (the pass is exact; only its timing changes).
    fn plan_front(&mut self) {
        if let Some(from) = self.dirty_from
            && self.final_to == 0
        {
            plan::backward(&mut self.q, self.feed_pct, self.rapid_pct, from);
            self.dirty_from = None;
            self.final_to = plan::settled(&self.q, self.feed_pct, self.rapid_pct);
        }
    }

    /// Feed hold (FOLD): decelerate along the path within the limits and hold; release resumes.
    pub fn set_hold(&mut self, on: bool) {
        if !on {
            self.stop_after = None;
        }
        if self.hold != on {
            self.hold = on;
            self.replan = self.exec.is_some();
        }
    }

    /// The acceleration law of blocks pushed from now on.
    pub fn set_law(&mut self, law: Law) {
        self.law = law;
    }

    /// The current acceleration law.
    pub fn law(&self) -> Law {
        self.law
    }

    /// Stop at the end of the block being executed and hold there (release with `set_hold(false)`).
    pub fn stop_at_block_end(&mut self) {
        let Some(tag) = self.q.front().map(|p| p.tag) else {
            return;
        };
        let Some(i) = self.q.iter().position(|p| p.tag == tag && p.den) else {
            return;
        };
        // A corner blend not yet entered is undone, so the stop is at the programmed end point.
        if i >= 1
            && i + 1 < self.q.len()
            && let Some(c) = self.q[i].corner
        {
            self.q.remove(i);
            let (prev, next) = (i - 1, i);
            let d1 = self.q[prev].seg.tangent(true);
            let d2 = self.q[next].seg.tangent(false);
            self.q[prev].seg = Seg::line_along(self.q[prev].seg.start, c, d1);
            self.q[prev].den = true;
            self.q[next].seg = Seg::line_along(c, self.q[next].seg.end, d2);
            self.q[prev].v_junction = 0.0;
        } else {
            self.q[i].v_junction = 0.0;
        }
        self.stop_after = Some(tag);
        self.replan_all();
    }

    /// The fastest in-limit stop along the path, then the queue is cleared.
    pub fn abort(&mut self) {
        self.abort = true;
        self.replan = self.exec.is_some();
    }

    /// Debug view of the first queued pieces and the executing profile (diagnostics).
    pub fn debug_front(&self) -> String {
        format!(
            "v {} exec {:?}\n{:#?}",
            self.v,
            self.exec
                .as_ref()
                .map(|e| (e.t, e.s0, e.prof.duration, e.prof.dist, e.prof.v_end)),
            self.q.iter().take(3).collect::<Vec<_>>()
        )
    }

    /// Current set point.
    pub fn position(&self) -> &[f64] {
        &self.out.position
    }

    /// Queue empty and at rest.
    pub fn is_idle(&self) -> bool {
        self.q.is_empty() && self.exec.is_none() && self.v == 0.0 && self.held() == 0
    }

    fn halting(&self) -> bool {
        self.hold || self.abort
    }

    /// Builds the profile of the front piece from `s0` at speed `v0`.
    pub(crate) fn profile(&self, s0: f64, v0: f64) -> Profile {
        let Some(p) = self.q.front() else {
            return Profile::default();
        };
        let rem = (p.seg.len - s0).max(0.0);
        match p.motion {
            Motion::Dwell(t) => Profile::rest(if s0 > 0.0 { 0.0 } else { t }),
            _ if self.halting() => Profile::stop(&self.stop_dyn(p), rem, v0),
            _ => {
                let cap = plan::cap(p, self.feed_pct, self.rapid_pct);
                Profile::build(&p.dynm, rem, v0, p.v_end, cap)
            }
        }
    }

    fn clear_after_abort(&mut self) {
        self.q.clear();
        if self.smooth.is_some() {
            self.smooth = Some(Smoother::default());
        }
        self.prog_end = self.pos;
        self.moves = 0;
        self.exec = None;
        self.end = self.pos;
        self.abort = false;
        self.replan = false;
        self.stop_after = None;
        self.v = 0.0;
        self.dirty_from = None;
        self.final_to = 0;
        self.thread = None;
        self.thread_chain = None;
        self.emergency = None;
    }

    /// Removes the finished front piece: the position is its end; a block's last piece reports
    /// its DEN (and a stop at its end holds).
    pub(crate) fn pop_front(&mut self) {
        let Some(front) = self.q.pop_front() else {
            return;
        };
        self.pos = front.seg.end;
        self.final_to = self.final_to.saturating_sub(1);
        self.dirty_from = self.dirty_from.map(|d| d.saturating_sub(1));
        if front.den {
            self.moves -= 1;
            self.out.finished.push(front.tag);
            if self.stop_after == Some(front.tag) {
                self.hold = true;
                self.stop_after = None;
            }
        }
    }

    /// Advances one interpolation tick and returns its set points.
    pub fn tick(&mut self) -> &Tick {
        self.out.finished.clear();
        // Nothing pushed since the last tick though there was room: the program has ended or
        // its blocks come slower than they run; the held moves go to the queue.
        if !std::mem::take(&mut self.pushed) && self.held() > 0 && self.space() > 0 {
            if let Some(sm) = self.smooth.as_mut() {
                sm.flush();
            }
            if let Err(e) = self.drain() {
                self.fault = Some(e);
            }
        }
        let mut left = self.cfg.tick_s;
        // At most one restart from rest per tick (see below): a piece that cannot move at all
        // (a zero override) must not spin inside one tick.
        let mut restarted = false;
        loop {
            if self.exec.is_none() {
                if self.abort && self.v == 0.0 {
                    self.clear_after_abort();
                    break;
                }
                if self.q.is_empty() || (self.halting() && self.v == 0.0) {
                    break;
                }
                if let Some(Motion::Thread { per_rev, angle }) = self.q.front().map(|p| p.motion) {
                    if self.thread_step(per_rev, angle, &mut left) {
                        continue;
                    }
                    break;
                }
                self.replan = false;
                self.plan_front();
                self.exec = Some(Exec {
                    prof: self.profile(0.0, self.v),
                    t: 0.0,
                    s0: 0.0,
                });
            }
            let (Some(ex), Some(front)) = (self.exec.as_mut(), self.q.front()) else {
                break;
            };
            // A dwell is not replanned: overrides do not change it, and rebuilding its rest
            // profile would start it over (an override knob turned during a dwell would hold
            // the program there for as long as it moves).
            if self.replan && !matches!(front.motion, Motion::Dwell(_)) {
                // An emergency stop replans at once; so does the exponential law while it
                // accelerates (its acceleration drops to 0 as at the end of a change, and the
                // state is behind and slower than at the end of that acceleration).
                let accelerating = ex.prof.eval(ex.t).2 > 0.0;
                let law = if self.emergency.is_some()
                    || (front.dynm.law == Law::Exponential && accelerating)
                {
                    Law::Linear
                } else {
                    front.dynm.law
                };
                let tr = ex.prof.replan_time(ex.t, law);
                if tr - ex.t <= left {
                    left -= tr - ex.t;
                    ex.t = tr;
                    let (x, v, _) = ex.prof.eval(tr);
                    let s0 = ex.s0 + x;
                    self.plan_front();
                    let prof = self.profile(s0, v);
                    self.exec = Some(Exec { prof, t: 0.0, s0 });
                    self.replan = false;
                    continue;
                }
                // Under the S law, while accelerating: the acceleration falls at the jerk limit
                // from now on, and the new profile starts where it reaches 0. (The state at that
                // point is behind and slower than the old profile's next zero-acceleration
                // instant, so every speed it had to meet stays within reach. A deceleration is
                // left to run to its end, as before.)
                let (x, v, a) = ex.prof.eval(ex.t);
                if let Some(mut prof) = Profile::bridge(&front.dynm, v, a) {
                    let s0 = ex.s0 + x;
                    self.plan_front();
                    let rest = self.profile(s0 + prof.dist, prof.v_end);
                    prof.append(&rest);
                    self.exec = Some(Exec { prof, t: 0.0, s0 });
                    self.replan = false;
                    continue;
                }
            }
            let t_end = ex.t + left;
            if t_end < ex.prof.duration {
                ex.t = t_end;
                break;
            }
            left = t_end - ex.prof.duration;
            ex.t = ex.prof.duration;
            let rem = front.seg.len - ex.s0;
            let done = matches!(front.motion, Motion::Dwell(_))
                || ex.prof.dist >= rem - 1e-9 * (1.0 + rem);
            self.v = ex.prof.v_end;
            if !done {
                // Stopped short of the piece end (hold, abort or a zero override).
                self.v = 0.0;
                if self.abort {
                    self.pos = front.seg.at(ex.s0 + ex.prof.dist);
                    self.clear_after_abort();
                    break;
                }
                if !self.hold && !restarted {
                    // Nothing asked for this stop: a profile replanned while it decelerated
                    // (an override lowered under the S law) can end at rest short of the piece
                    // end, and nothing would ever move the axes again. Go on from rest.
                    let s0 = ex.s0 + ex.prof.dist;
                    restarted = true;
                    self.plan_front();
                    let prof = self.profile(s0, 0.0);
                    self.exec = Some(Exec { prof, t: 0.0, s0 });
                    continue;
                }
                break;
            }
            self.exec = None;
            self.pop_front();
            if self.q.is_empty() {
                // The queue ends at rest (its last end speed is 0); drop rounding residue.
                self.v = 0.0;
            }
        }
        let (pos, tag, v) = match (&self.exec, self.q.front(), self.thread) {
            (Some(ex), Some(p), _) => {
                let (x, v, _) = ex.prof.eval(ex.t);
                (p.seg.at(ex.s0 + x), Some(p.tag), v)
            }
            (None, Some(p), Some(ThreadRun::Cutting { s, .. })) => {
                (p.seg.at(s), Some(p.tag), self.v)
            }
            (None, Some(p), Some(ThreadRun::Waiting)) => (p.seg.start, Some(p.tag), 0.0),
            _ => (self.pos, None, 0.0),
        };
        self.pos = pos;
        for ((o, x), k) in self
            .out
            .position
            .iter_mut()
            .zip(pos.iter())
            .zip(&self.scale)
        {
            *o = *x / *k;
        }
        self.out.tag = tag;
        self.out.feed_mm_min = v * 60.0;
        self.out.held = self.hold && v == 0.0;
        if let Some(s) = self.spindle.as_mut() {
            s.0 = s.1;
        }
        &self.out
    }
}
