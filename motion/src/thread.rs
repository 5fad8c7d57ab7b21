//! G33 position-locked to the spindle. A thread block waits at its start point for the spindle's
//! index pulse (plus the programmed start angle: MEFI `I`, degrees after the zero pulse), then its
//! path position is the lead × the revolutions turned since then, so a speed change of the spindle
//! (or its override) mid-thread keeps the pitch exact and every pass re-enters the same groove
//! (manual 000:918–920). No ramps (000:618): the axis starts and stops with the spindle's speed.
//! A thread that directly follows a thread continues locked, without waiting for the index.
//!
//! The lead is along the piece's dominant axis (the one with the largest share of the direction,
//! as for a Fanuc taper thread); the path advances `lead / share` per revolution.

use crate::kernel::{Exec, Kernel};
use crate::moves::MotionError;
use crate::plan::Motion;

/// Where the thread block at the front of the queue is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum ThreadRun {
    /// At the start point, waiting for the spindle to pass the start angle.
    Waiting,
    /// Cutting: `origin` is the spindle position (rev) at the thread's start, `dir` the direction
    /// of rotation then (±1), `s` the path position (mm along the piece).
    Cutting {
        /// Spindle position at the start, rev.
        origin: f64,
        /// Direction of rotation at the start, ±1.
        dir: f64,
        /// Path position, mm.
        s: f64,
    },
}

/// The spindle position (rev) at which the spindle, moving from `from` to `to` within a tick,
/// passes `angle` (fraction of a revolution after an index pulse, in its direction of rotation),
/// and the direction; None when it does not pass it (or stands still). A mark exactly at `from`
/// was passed before.
pub(crate) fn crossing(from: f64, to: f64, angle: f64) -> Option<(f64, f64)> {
    if to == from || !(to - from).is_finite() {
        return None;
    }
    let dir = if to > from { 1.0 } else { -1.0 };
    let (u0, u1) = (dir * from, dir * to);
    let mark = (u0 - angle).floor() + 1.0 + angle;
    (mark <= u1).then_some((dir * mark, dir))
}

/// The fraction of the tick (0..=1) at which the spindle, moving from `prev` to `cur` over the
/// tick, stands at `at`.
pub(crate) fn tick_fraction(prev: f64, cur: f64, at: f64) -> f64 {
    if cur == prev {
        return 1.0;
    }
    ((at - prev) / (cur - prev)).clamp(0.0, 1.0)
}

/// The start angle as a fraction of a revolution in [0, 1) from degrees.
pub(crate) fn angle_fraction(deg: f64) -> f64 {
    if !deg.is_finite() {
        return 0.0;
    }
    (deg / 360.0).rem_euclid(1.0)
}

impl Kernel {
    /// The spindle's position (revolutions, signed, integrated from its actual speed; an index
    /// pulse at every whole revolution) at the end of the coming tick: G33 threads follow it.
    pub fn set_spindle_position(&mut self, rev: f64) {
        if rev.is_finite() {
            let prev = self.spindle.map_or(rev, |s| s.0);
            self.spindle = Some((prev, rev));
        }
    }

    /// A G33 thread at the front waits for the spindle to pass its start angle.
    pub fn waiting_for_index(&self) -> bool {
        matches!(self.thread, Some(ThreadRun::Waiting))
    }

    /// The fault that keeps the kernel from going on (a thread the spindle's actual speed makes
    /// too fast), once; the caller aborts.
    pub fn take_fault(&mut self) -> Option<MotionError> {
        self.fault.take()
    }

    /// Runs the thread block at the front for what is `left` of this tick ([`crate::thread`]):
    /// waits for the spindle to pass the start angle, then follows the spindle position. True
    /// when the thread ended within the tick (`left` is then what remains after its end). A feed
    /// hold does not stop a thread: it takes effect at the thread's end (the block after it
    /// does not start); an abort stops it along the path within the limits.
    pub(crate) fn thread_step(&mut self, per_rev: f64, angle: f64, left: &mut f64) -> bool {
        let dt = self.cfg.tick_s;
        let Some((prev, cur)) = self.spindle else {
            // No spindle position yet: the thread waits.
            self.thread = Some(ThreadRun::Waiting);
            self.v = 0.0;
            return false;
        };
        let from = prev + (1.0 - *left / dt) * (cur - prev);
        let Some(len) = self.q.front().map(|p| p.seg.len) else {
            return false;
        };
        let run = match (self.thread.take(), self.thread_chain.take()) {
            (Some(r), _) => r,
            (None, Some((origin, dir))) => ThreadRun::Cutting {
                origin,
                dir,
                s: 0.0,
            },
            (None, None) => ThreadRun::Waiting,
        };
        let (origin, dir) = match run {
            ThreadRun::Cutting { origin, dir, .. } => (origin, dir),
            ThreadRun::Waiting => match crossing(from, cur, angle) {
                Some(c) if !self.thread_too_fast(per_rev, (cur - prev).abs() / dt) => c,
                _ => {
                    self.thread = Some(ThreadRun::Waiting);
                    self.v = 0.0;
                    return false;
                }
            },
        };
        let s = per_rev * dir * (cur - origin);
        if s < len - 1e-9 * (1.0 + len) {
            let s = s.max(0.0);
            self.v = per_rev * (cur - prev).abs() / dt;
            if self.abort {
                // From here on an ordinary stop along the path (the abort clears the queue).
                self.exec = Some(Exec {
                    prof: self.profile(s, self.v),
                    t: 0.0,
                    s0: s,
                });
            } else {
                self.thread = Some(ThreadRun::Cutting { origin, dir, s });
            }
            return false;
        }
        // The thread ends within this tick, where the spindle stands at `end`.
        let end = origin + dir * len / per_rev;
        let f = tick_fraction(prev, cur, end);
        *left = (dt * (1.0 - f)).min(*left);
        self.pop_front();
        if let Some(Motion::Thread { .. }) = self.q.front().map(|p| p.motion) {
            self.thread_chain = Some((end, dir));
        } else {
            self.v = 0.0;
        }
        true
    }

    /// At the start of a thread: true (and the fault recorded) when the spindle's actual speed
    /// (rev/s; raised by its override, say, since the block was queued) would take the path
    /// faster than the axes allow; the thread then does not start.
    pub(crate) fn thread_too_fast(&mut self, per_rev: f64, rev_s: f64) -> bool {
        let Some(p) = self.q.front() else {
            return false;
        };
        let need = per_rev * rev_s;
        if need <= p.v_hard * (1.0 + 1e-6) {
            return false;
        }
        if self.fault.is_none() {
            self.fault = Some(MotionError::ThreadTooFast {
                tag: p.tag,
                need: need * 60.0,
                limit: p.v_hard * 60.0,
            });
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_finds_the_next_mark_in_the_direction_of_rotation() {
        // Forward from 2.75 to 3.25 rev: the index (angle 0) is at 3.0.
        assert_eq!(crossing(2.75, 3.25, 0.0), Some((3.0, 1.0)));
        // A start angle of 180° is at 2.5 and 3.5: not within (2.75, 3.25].
        assert_eq!(crossing(2.75, 3.25, 0.5), None);
        // Backwards (M04) from -0.25 to -0.75: 180° after the index going down is at -0.5.
        assert_eq!(crossing(-0.25, -0.75, 0.5), Some((-0.5, -1.0)));
        // A mark exactly at the start was passed before; one exactly at the end counts.
        assert_eq!(crossing(3.0, 3.5, 0.0), None);
        assert_eq!(crossing(2.5, 3.0, 0.0), Some((3.0, 1.0)));
        assert_eq!(crossing(1.0, 1.0, 0.0), None);
    }

    #[test]
    fn fractions() {
        assert_eq!(tick_fraction(2.0, 3.0, 2.25), 0.25);
        assert_eq!(angle_fraction(-90.0), 0.75);
        assert_eq!(angle_fraction(540.0), 0.5);
    }
}
