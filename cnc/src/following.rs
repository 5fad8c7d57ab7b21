//! The following-error monitor: every interpolation tick, per axis, the set point and the actual
//! position (the plant's today, a drive's position actual value tomorrow) against the one of SRV's
//! three limits in force (003:2199-2219):
//!
//! * **stand-by** (`servo_error_stand_by`) while the axis is at rest: its set point has not moved
//!   for five time constants 5/KV (a drive that still settles after a stop is "moving");
//! * **VFF** (`servo_error_VFF`) while it moves, or settles, with velocity feed-forward
//!   ([`crate::servo::vff_active`]: a programmed move in MDI/AUTO/STEP with UEP = 0);
//! * **no-VFF** (`servo_error_no_VFF`) while it moves, or settles, without it (jogs, homing, the
//!   handwheel, UEP = 1).
//!
//! A limit of 0 (or an empty SRV field) is not checked. The largest error of each axis is kept
//! with the limit in force at that tick, for the run summary. Invariant: the monitor only reads
//! what it is given; the caller decides what an [`Exceeded`] does (the process stops with an alarm).

use std::fmt;

/// SRV's three limits of one axis (mm or degrees; 0 = unchecked).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SrvLimits {
    /// servo_error_stand_by: at rest.
    pub standby: f64,
    /// servo_error_VFF: moving with velocity feed-forward.
    pub vff: f64,
    /// servo_error_no_VFF: moving without it.
    pub no_vff: f64,
}

/// Which of SRV's limits applies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Limit {
    /// At rest.
    Standby,
    /// Moving with velocity feed-forward.
    Vff,
    /// Moving without velocity feed-forward.
    NoVff,
}

impl Limit {
    /// The limit's name in messages: "stand-by", "VFF" or "no-VFF".
    pub fn name(self) -> &'static str {
        match self {
            Limit::Standby => "stand-by",
            Limit::Vff => "VFF",
            Limit::NoVff => "no-VFF",
        }
    }

    /// Why it applies: "at rest", "moving with feed-forward", "moving without feed-forward".
    pub fn why(self) -> &'static str {
        match self {
            Limit::Standby => "at rest",
            Limit::Vff => "moving with feed-forward",
            Limit::NoVff => "moving without feed-forward",
        }
    }

    /// Its value in `srv`.
    pub fn of(self, srv: &SrvLimits) -> f64 {
        match self {
            Limit::Standby => srv.standby,
            Limit::Vff => srv.vff,
            Limit::NoVff => srv.no_vff,
        }
    }
}

/// A following error beyond the limit in force: the alarm's content.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Exceeded {
    /// The axis's address letter.
    pub axis: char,
    /// |set point − actual| (mm).
    pub error: f64,
    /// The limit in force.
    pub limit: Limit,
    /// Its value (mm).
    pub allowed: f64,
}

impl fmt::Display for Exceeded {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "following error of axis {}: {:.3} mm exceeds SRV {} limit {} mm ({})",
            self.axis,
            self.error,
            self.limit.name(),
            self.allowed,
            self.limit.why()
        )
    }
}

/// The largest following error of an axis and the limit it was checked against.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Peak {
    /// |set point − actual| (mm).
    pub error: f64,
    /// The limit in force at that tick.
    pub limit: Limit,
    /// Its value (mm; 0 = unchecked).
    pub allowed: f64,
}

/// The monitor of one axis.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisMonitor {
    name: char,
    srv: SrvLimits,
    /// Time an axis needs to settle after its set point stops: 5/KV (s).
    settle_s: f64,
    set_point: f64,
    /// Ticks since the set point last moved, and the tick's length (s).
    still_ticks: u32,
    dt: f64,
    /// The last move of the set point had feed-forward.
    vff: bool,
    peak: Option<Peak>,
}

impl AxisMonitor {
    /// The monitor of axis `name` with gain `kv` (1/s), at rest at `set_point`.
    pub fn new(name: char, srv: SrvLimits, kv: f64, set_point: f64) -> AxisMonitor {
        AxisMonitor {
            name,
            srv,
            settle_s: 5.0 / kv,
            set_point,
            still_ticks: u32::MAX,
            dt: 0.001,
            vff: false,
            peak: None,
        }
    }

    /// The axis is at rest: its set point has not moved for 5/KV.
    pub fn at_rest(&self) -> bool {
        f64::from(self.still_ticks) * self.dt >= self.settle_s
    }

    /// The limit in force now.
    pub fn limit(&self) -> Limit {
        if self.at_rest() {
            Limit::Standby
        } else if self.vff {
            Limit::Vff
        } else {
            Limit::NoVff
        }
    }

    /// One tick of `dt` s: the set point and actual position at its end, and whether the set
    /// point moved with feed-forward; `Some` when the error exceeds the limit in force.
    pub fn check(&mut self, set_point: f64, actual: f64, vff: bool, dt: f64) -> Option<Exceeded> {
        if set_point != self.set_point {
            self.set_point = set_point;
            self.still_ticks = 0;
            self.vff = vff;
        } else {
            self.still_ticks = self.still_ticks.saturating_add(1);
        }
        self.dt = dt;
        let error = (set_point - actual).abs();
        let limit = self.limit();
        let allowed = limit.of(&self.srv);
        if self.peak.is_none_or(|p| error > p.error) {
            self.peak = Some(Peak {
                error,
                limit,
                allowed,
            });
        }
        (allowed > 0.0 && error > allowed).then_some(Exceeded {
            axis: self.name,
            error,
            limit,
            allowed,
        })
    }

    /// The coordinates move by −`shift` (homing sets a new zero).
    pub fn shift(&mut self, shift: f64) {
        self.set_point -= shift;
    }

    /// The largest error seen and the limit it was checked against (None before the first tick).
    pub fn peak(&self) -> Option<Peak> {
        self.peak
    }

    /// The axis's address letter.
    pub fn name(&self) -> char {
        self.name
    }
}

/// The run summary's text for every axis's peak: `X 0.012 mm (SRV VFF 2 mm), Z …`; an axis
/// never checked is left out, and `-` stands for no axis at all.
pub fn summary(peaks: &[(char, Option<Peak>)]) -> String {
    let parts: Vec<String> = peaks
        .iter()
        .filter_map(|(name, p)| {
            let p = p.as_ref()?;
            let allowed = if p.allowed > 0.0 {
                format!("{} mm", p.allowed)
            } else {
                "unchecked".to_string()
            };
            Some(format!(
                "{name} {:.3} mm (SRV {} {allowed})",
                p.error,
                p.limit.name()
            ))
        })
        .collect();
    if parts.is_empty() {
        "-".to_string()
    } else {
        parts.join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SRV: SrvLimits = SrvLimits {
        standby: 0.5,
        vff: 2.0,
        no_vff: 10.0,
    };

    #[test]
    fn each_limit_applies_in_its_state_and_the_alarm_says_why() {
        // KV 20: at rest 5/20 = 0.25 s after the set point stops (125 ticks of 2 ms).
        let mut m = AxisMonitor::new('Z', SRV, 20.0, 0.0);
        assert_eq!(m.limit(), Limit::Standby);
        assert_eq!(m.check(0.0, -0.4, false, 0.002), None);
        let e = m.check(0.0, -0.6, false, 0.002).expect("beyond 0.5");
        assert_eq!(
            e.to_string(),
            "following error of axis Z: 0.600 mm exceeds SRV stand-by limit 0.5 mm (at rest)"
        );
        // Moving with feed-forward: 2 mm.
        assert_eq!(m.check(1.0, -0.9, true, 0.002), None);
        assert_eq!(
            m.check(2.0, -0.1, true, 0.002)
                .map(|e| e.to_string())
                .as_deref(),
            Some(
                "following error of axis Z: 2.100 mm exceeds SRV VFF limit 2 mm (moving with feed-forward)"
            )
        );
        // Without: 10 mm.
        assert_eq!(m.check(12.0, 2.0, false, 0.002), None);
        assert_eq!(
            m.check(24.0, 13.9, false, 0.002)
                .map(|e| e.to_string())
                .as_deref(),
            Some(
                "following error of axis Z: 10.100 mm exceeds SRV no-VFF limit 10 mm (moving without feed-forward)"
            )
        );
        // Settling keeps the moving limit for 0.25 s, then stand-by.
        for _ in 0..124 {
            assert_eq!(m.check(24.0, 23.0, false, 0.002), None);
        }
        assert_eq!(m.limit(), Limit::NoVff);
        assert!(m.check(24.0, 23.0, false, 0.002).is_some());
        assert_eq!(m.limit(), Limit::Standby);
        // The peak is the 10.1 mm, with the no-VFF limit.
        let p = m.peak().expect("peak");
        assert_eq!((p.limit, p.allowed), (Limit::NoVff, 10.0));
        assert!((p.error - 10.1).abs() < 1e-9);
    }

    #[test]
    fn the_summary_gives_each_axis_its_peak_and_limit() {
        let peak = |error, limit, allowed| {
            Some(Peak {
                error,
                limit,
                allowed,
            })
        };
        assert_eq!(
            summary(&[
                ('X', peak(0.0123, Limit::Vff, 2.0)),
                ('Z', peak(9.8, Limit::NoVff, 0.0)),
                ('Y', None)
            ]),
            "X 0.012 mm (SRV VFF 2 mm), Z 9.800 mm (SRV no-VFF unchecked)"
        );
        assert_eq!(summary(&[]), "-");
    }

    #[test]
    fn a_limit_of_0_is_not_checked() {
        let mut m = AxisMonitor::new('X', SrvLimits::default(), 20.0, 0.0);
        assert_eq!(m.check(100.0, 0.0, true, 0.002), None);
        assert_eq!(m.peak().map(|p| p.allowed), Some(0.0));
    }
}
