//! The controller's half of an axis's position loop as the manual defines it: when velocity
//! feed-forward (VFF) is on, the velocity the controller commands besides KV × error
//! (003:2369-2397, 003:3532-3554, Appendix A 003:7210).
//!
//! VFF is on for a move programmed in a block in MDI, AUTO or STEP while the process's system
//! variable UEP is 0 ([`vff_active`]); it is off in the manual modes (MANU, MANJ, HOME, the
//! handwheel) and whenever UEP = 1. While it is on, the feed-forward is
//!
//! `w = Kvff · v_f + Kvffi · ∫e dt`
//!
//! where `v_f` is the set point's velocity over the tick (Δset point / dt) passed through FQF's
//! first-order low-pass of bandwidth FQF Hz ("a low-pass filter after KFF, its band the position
//! loop's", Appendix A; FQF = 0: no filter) and `∫e dt` the integral of the following error while
//! VFF is on (Kvffi, the manual's "integral coefficient of the PID regulator", in 1/s²; the manual
//! gives no unit). The drive's velocity command is then `w + KV · e`. With Kvff = 1 and no filter
//! a constant-speed move has no following error at all; without VFF it lags v/KV.
//!
//! When VFF goes off the filter's input is 0 (its output decays, no step) and the integral is
//! cleared. Pure arithmetic on the set points and errors the caller gives: the plant
//! ([`crate::plant::Drive`]) and a bus drive (a velocity offset beside a CSP target) use it alike.
//! `exp` comes from `detmath`, so a run is the same on every machine.

use detmath::Det as _;

use crate::state::Mode;

/// The loop constants of one axis (GMxx KV, FRC Kvff/Kvffi, FQF).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gains {
    /// Position-loop gain KV (1/s).
    pub kv: f64,
    /// FRC Kvff: velocity feed-forward coefficient (default 1).
    pub kvff: f64,
    /// FRC Kvffi: integral coefficient (1/s², default 0).
    pub kvffi: f64,
    /// FQF: bandwidth of the feed-forward filter in Hz (0 = no filter).
    pub fqf_hz: f64,
}

impl Gains {
    /// KV alone: Kvff 1, Kvffi 0, no filter (the manual's defaults).
    pub fn with_kv(kv: f64) -> Gains {
        Gains {
            kv,
            kvff: 1.0,
            kvffi: 0.0,
            fqf_hz: 0.0,
        }
    }
}

/// VFF applies: a move programmed in a block (`programmed`) in MDI, AUTO or STEP with UEP = 0.
pub fn vff_active(mode: Mode, uep: bool, programmed: bool) -> bool {
    programmed && !uep && matches!(mode, Mode::Mdi | Mode::Auto | Mode::Step)
}

/// The feed-forward state of one axis: the filtered velocity and the error integral.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FeedForward {
    filtered: f64,
    integral: f64,
}

impl FeedForward {
    /// The feed-forward velocity (mm/s) for a tick of `dt` s in which the set point moves by
    /// `delta`, `error` being the following error at the tick's start and `on` whether VFF applies.
    pub fn step(&mut self, g: &Gains, on: bool, delta: f64, error: f64, dt: f64) -> f64 {
        let v = if on && dt > 0.0 { delta / dt } else { 0.0 };
        self.filtered = if g.fqf_hz > 0.0 {
            let p = (-2.0 * std::f64::consts::PI * g.fqf_hz * dt).dexp();
            v + (self.filtered - v) * p
        } else {
            v
        };
        if on {
            self.integral += error * dt;
        } else {
            self.integral = 0.0;
        }
        g.kvff * self.filtered + g.kvffi * self.integral
    }

    /// Forgets the filter and the integral (the axis stopped by an alarm, coordinates shifted).
    pub fn clear(&mut self) {
        *self = FeedForward::default();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vff_only_for_programmed_moves_in_the_program_modes_with_uep_0() {
        for m in Mode::ALL {
            let program_mode = matches!(m, Mode::Mdi | Mode::Auto | Mode::Step);
            assert_eq!(vff_active(m, false, true), program_mode, "{m:?}");
            assert!(!vff_active(m, true, true), "{m:?}");
            assert!(!vff_active(m, false, false), "{m:?}");
        }
    }

    #[test]
    fn the_feed_forward_is_kvff_times_the_set_point_speed_without_filter() {
        // 0.4 mm in 2 ms = 200 mm/s; Kvff 0.95 → 190 mm/s.
        let g = Gains {
            kvff: 0.95,
            ..Gains::with_kv(20.0)
        };
        let mut f = FeedForward::default();
        assert!((f.step(&g, true, 0.4, 0.0, 0.002) - 190.0).abs() < 1e-9);
        assert_eq!(f.step(&g, false, 0.4, 0.0, 0.002), 0.0);
    }

    #[test]
    fn fqf_filters_the_velocity_with_its_bandwidth() {
        // FQF 20 Hz, 2 ms: p = e^(−2π·20·0.002) = e^(−0.08π); after n ticks of 200 mm/s the
        // filtered speed is 200·(1 − pⁿ).
        let g = Gains {
            fqf_hz: 20.0,
            ..Gains::with_kv(20.0)
        };
        let p = (-0.08 * std::f64::consts::PI).dexp();
        let mut f = FeedForward::default();
        let mut w = 0.0;
        for _ in 0..5 {
            w = f.step(&g, true, 0.4, 0.0, 0.002);
        }
        assert!((w - 200.0 * (1.0 - p.powi(5))).abs() < 1e-9, "{w}");
        // Off: the input is 0 and the output decays from where it was.
        let off = f.step(&g, false, 0.4, 0.0, 0.002);
        assert!((off - w * p).abs() < 1e-9, "{off}");
    }

    #[test]
    fn kvffi_integrates_the_error_while_on_and_clears_when_off() {
        // Kvffi 10/s², no Kvff: 3 ticks of 1 mm error × 2 ms → ∫ = 0.006 mm·s → 0.06 mm/s.
        let g = Gains {
            kvff: 0.0,
            kvffi: 10.0,
            ..Gains::with_kv(20.0)
        };
        let mut f = FeedForward::default();
        let mut w = 0.0;
        for _ in 0..3 {
            w = f.step(&g, true, 0.0, 1.0, 0.002);
        }
        assert!((w - 0.06).abs() < 1e-12, "{w}");
        assert_eq!(f.step(&g, false, 0.0, 1.0, 0.002), 0.0);
        assert!((f.step(&g, true, 0.0, 1.0, 0.002) - 0.02).abs() < 1e-12);
    }
}
