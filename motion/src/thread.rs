//! G33 position-locked to the spindle. A thread block waits at its start point for the spindle's
//! index pulse (plus the programmed start angle: MEFI `I`, degrees after the zero pulse), then its
//! path position is the lead × the revolutions turned since then, so a speed change of the spindle
//! (or its override) mid-thread keeps the pitch exact and every pass re-enters the same groove
//! (manual 000:918–920). No ramps (000:618): the axis starts and stops with the spindle's speed.
//! A thread that directly follows a thread continues locked, without waiting for the index.
//!
//! The lead is along the piece's dominant axis (the one with the largest share of the direction,
//! as for a Fanuc taper thread); the path advances `lead / share` per revolution.

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
