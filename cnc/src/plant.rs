//! The simulated machine around the controller (the plant): axis drives whose ideal velocity loop
//! runs the velocity command `w + KV · e` (e = set point − actual, w the controller's velocity
//! feed-forward of [`crate::servo`], 0 without VFF), and a spindle that ramps to its reference
//! with the acceleration TSM allows; its encoder's position (revolutions, an index pulse at every
//! whole one) is integrated from the actual speed every tick, for G33.
//!
//! The set point moves linearly between two interpolation ticks (speed s = Δ/dt) and w is held
//! over the tick, so the error obeys `de/dt = s − w − KV·e` and is integrated exactly:
//! `eₙ = e∞ + (eₙ₋₁ − e∞)·e^(−KV·dt)` with `e∞ = (s − w)/KV`. Without feed-forward a drive in
//! steady motion lags exactly v/KV (12 000 mm/min at KV 20: 10 mm), which SRV's no-VFF limit is
//! set against; with w = Kvff·s it lags (1 − Kvff)·v/KV, 0 at Kvff = 1.

use detmath::Det as _;
use packets::Signal;

/// The plant's wiring to packet A (from `sim.toml`): the spindle drive's at-speed and zero-speed
/// contacts, and the PLC outputs that must be on for the spindle to turn (its contactors).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct PlantSignals {
    /// Input set while the spindle is at its reference (POM max_deviation).
    pub at_speed: Option<Signal>,
    /// Input set while the spindle is below its stop threshold.
    pub stopped: Option<Signal>,
    /// Outputs of which one must be 1 for the spindle to turn (empty: always allowed).
    pub run: Vec<Signal>,
}

/// One axis drive.
#[derive(Debug, Clone, PartialEq)]
pub struct Drive {
    kv: f64,
    command: f64,
    actual: f64,
    offset: f64,
    home_switch: Option<f64>,
    /// Edges of the + and − hardware limit switches on the machine's scale (MFC), when simulated.
    limit_switches: [Option<f64>; 2],
    /// The actual position one servo tick before, for the direction of motion.
    previous_actual: f64,
}

impl Drive {
    /// A drive at rest at `pos` with gain `kv` (1/s).
    pub fn new(kv: f64, pos: f64) -> Drive {
        Drive {
            kv,
            command: pos,
            actual: pos,
            offset: 0.0,
            home_switch: None,
            limit_switches: [None; 2],
            previous_actual: pos,
        }
    }

    /// Places the machine: the axis stands at `start` on the machine's own scale (the controller
    /// counts from 0 until it is homed), with its home switch edge at `home_switch`.
    pub fn place(&mut self, start: f64, home_switch: Option<f64>) {
        self.offset = start - self.actual;
        self.home_switch = home_switch;
    }

    /// Position on the machine's scale.
    pub fn machine_position(&self) -> f64 {
        self.actual + self.offset
    }

    /// The home switch's edge on the machine's scale, when simulated.
    pub fn home_switch(&self) -> Option<f64> {
        self.home_switch
    }

    /// Places the + and − hardware limit switches: each is pressed from its edge outwards.
    pub fn set_limit_switches(&mut self, positive: Option<f64>, negative: Option<f64>) {
        self.limit_switches = [positive, negative];
    }

    /// The + and − limit switches: pressed or not, `None` where the machine does not simulate one.
    pub fn limit_pressed(&self) -> [Option<bool>; 2] {
        let p = self.machine_position();
        [
            self.limit_switches[0].map(|edge| p >= edge),
            self.limit_switches[1].map(|edge| p <= edge),
        ]
    }

    /// The direction the axis actually moved in the last servo tick: 1, −1 or 0 (the switch is
    /// pressed by the slide, which lags its set point).
    pub fn direction(&self) -> f64 {
        let d = self.actual - self.previous_actual;
        if d > 0.0 {
            1.0
        } else if d < 0.0 {
            -1.0
        } else {
            0.0
        }
    }

    /// The controller's coordinates move by −`shift` (homing sets a new zero).
    pub fn shift(&mut self, shift: f64) {
        self.command -= shift;
        self.actual -= shift;
        self.offset += shift;
    }

    /// One servo tick of `dt` seconds: the set point moves linearly to `command`, the controller
    /// adds the velocity feed-forward `feed_forward` (mm/s) to KV × error.
    pub fn tick(&mut self, command: f64, feed_forward: f64, dt: f64) {
        self.previous_actual = self.actual;
        let speed = if dt > 0.0 {
            (command - self.command) / dt
        } else {
            0.0
        };
        let settled = (speed - feed_forward) / self.kv;
        let q = (-self.kv * dt).dexp();
        let error = settled + (self.command - self.actual - settled) * q;
        self.command = command;
        self.actual = command - error;
    }

    /// One servo tick of an axis on a bus drive: the set point is `command`, the actual
    /// position the drive's healthy answer (unchanged without one).
    pub fn follow_bus(&mut self, command: f64, actual: Option<f64>) {
        self.previous_actual = self.actual;
        self.command = command;
        if let Some(a) = actual {
            self.actual = a;
        }
    }

    /// The set point of the last tick.
    pub fn command(&self) -> f64 {
        self.command
    }

    /// The actual position.
    pub fn actual(&self) -> f64 {
        self.actual
    }

    /// Set point minus actual position.
    pub fn error(&self) -> f64 {
        self.command - self.actual
    }
}

/// The spindle: speed (rev/min, negative = CCW) ramping to the reference, and its position.
#[derive(Debug, Clone, PartialEq)]
pub struct Spindle {
    accel: f64,
    target: f64,
    actual: f64,
    /// Encoder position, revolutions (signed) since power-on: the index pulse is at every whole
    /// revolution.
    position: f64,
}

impl Spindle {
    /// A stopped spindle with `accel` rev/min per second.
    pub fn new(accel: f64) -> Spindle {
        Spindle {
            accel,
            target: 0.0,
            actual: 0.0,
            position: 0.0,
        }
    }

    /// The speed reference (rev/min, signed).
    pub fn set_target(&mut self, rpm: f64) {
        self.target = rpm;
    }

    /// One tick of `dt` seconds: the speed ramps, the position advances at the mean speed.
    pub fn tick(&mut self, dt: f64) {
        let step = self.accel * dt;
        let d = self.target - self.actual;
        let before = self.actual;
        self.actual += d.clamp(-step, step);
        self.position += (before + self.actual) * 0.5 / 60.0 * dt;
    }

    /// The encoder position, revolutions (signed; the index pulse at every whole revolution).
    pub fn position(&self) -> f64 {
        self.position
    }

    /// The actual speed (rev/min, signed).
    pub fn actual(&self) -> f64 {
        self.actual
    }

    /// The reference (rev/min, signed).
    pub fn target(&self) -> f64 {
        self.target
    }

    /// At the reference within the fraction `dev` (POM max_deviation_speed); never when the
    /// reference is 0.
    pub fn at_speed(&self, dev: f64) -> bool {
        self.target != 0.0 && (self.actual - self.target).abs() <= dev * self.target.abs()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drive_lags_by_one_time_constant() {
        // KV 20: a 10 mm step taken in one tick of 2 ms (s = 5000 mm/s) leaves the error
        // e₁ = 250·(1 − q), q = e^(−0.04); 24 more ticks (48 ms) at rest decay it by q²⁴.
        let mut d = Drive::new(20.0, 0.0);
        d.tick(10.0, 0.0, 0.002);
        let q = (-0.04f64).dexp();
        assert!((d.error() - 250.0 * (1.0 - q)).abs() < 1e-9);
        for _ in 0..24 {
            d.tick(10.0, 0.0, 0.002);
        }
        assert!((d.error() - 250.0 * (1.0 - q) * q.powi(24)).abs() < 1e-9);
    }

    /// A rapid at 12 m/min (200 mm/s) on a KV 20 axis, 2 ms ticks, from rest at the RAP
    /// acceleration 800 mm/s² (a linear ramp of 0.25 s = 125 ticks), then at speed.
    fn rapid(kvff: f64, fqf_hz: f64, vff: bool) -> (f64, f64) {
        use crate::servo::{FeedForward, Gains};
        let g = Gains {
            kvff,
            fqf_hz,
            ..Gains::with_kv(20.0)
        };
        let (dt, a, v) = (0.002, 800.0, 200.0);
        let mut d = Drive::new(20.0, 0.0);
        let mut ff = FeedForward::default();
        let (mut sp, mut speed, mut peak) = (0.0, 0.0f64, 0.0f64);
        for _ in 0..1000 {
            let before = speed;
            speed = (speed + a * dt).min(v);
            let delta = (before + speed) / 2.0 * dt;
            sp += delta;
            let w = ff.step(&g, vff, delta, d.error(), dt);
            d.tick(sp, w, dt);
            peak = peak.max(d.error().abs());
        }
        (d.error(), peak)
    }

    #[test]
    fn without_feed_forward_a_rapid_lags_v_over_kv() {
        // e∞ = s/KV at every tick: 200/20 = 10 mm once at speed; after 1.75 s at speed the
        // transient is gone (q^875 ≈ 6e-16 of it), and the lag never exceeds it.
        let (end, peak) = rapid(1.0, 0.0, false);
        assert!((end - 10.0).abs() < 1e-9, "{end}");
        assert!(peak <= 10.0 + 1e-9, "{peak}");
    }

    #[test]
    fn with_kvff_1_a_rapid_has_no_lag_and_kvff_095_lags_five_percent() {
        // w = Kvff·s: e∞ = (1 − Kvff)·s/KV: 0 at Kvff 1; 0.05 × 10 mm at 0.95.
        let (end, peak) = rapid(1.0, 0.0, true);
        assert!(end.abs() < 1e-9 && peak < 1e-9, "{end} {peak}");
        let (end, peak) = rapid(0.95, 0.0, true);
        assert!((end - 0.5).abs() < 1e-9, "{end}");
        assert!(peak <= 0.5 + 1e-9, "{peak}");
    }

    #[test]
    fn fqf_adds_a_transient_lag_while_accelerating() {
        // FQF 20 Hz, p = e^(−0.08π): during the ramp the filtered speed lags s by
        // L = a·dt·p/(1 − p) → 800·0.002·p/(1 − p) = 5.600 mm/s, so e∞ = L/KV → 0.2800 mm; the
        // error stays below it (≤ 0.1 × v/KV = 1 mm, the target) and is 0 at speed.
        let p = (-0.08 * std::f64::consts::PI).dexp();
        let bound = 800.0 * 0.002 * p / (1.0 - p) / 20.0;
        assert!((bound - 0.280_0).abs() < 1e-4, "{bound}");
        let (end, peak) = rapid(1.0, 20.0, true);
        assert!(end.abs() < 1e-9, "{end}");
        assert!(peak <= bound && peak > 0.9 * bound, "{peak} {bound}");
    }

    #[test]
    fn spindle_ramps_at_the_tsm_rate() {
        // 1500 rev/min per s: 1200 rev/min is reached after 0.8 s (400 ticks of 2 ms).
        let mut s = Spindle::new(1500.0);
        s.set_target(1200.0);
        for _ in 0..399 {
            s.tick(0.002);
        }
        assert!((s.actual() - 1197.0).abs() < 1e-6);
        assert!(s.at_speed(0.1));
        s.tick(0.002);
        assert_eq!(s.actual(), 1200.0);
        s.set_target(0.0);
        assert!(!s.at_speed(0.1));
    }

    #[test]
    fn spindle_position_integrates_the_speed() {
        // 1500 rev/min per s from rest to 1200 rev/min: 0.8 s of ramp cover 0.8 × 10 rev/s =
        // 8 rev; then 0.2 s at 20 rev/s, 4 rev; index pulses at every whole revolution.
        let mut s = Spindle::new(1500.0);
        s.set_target(1200.0);
        for _ in 0..500 {
            s.tick(0.002);
        }
        assert!((s.position() - 12.0).abs() < 1e-9, "{}", s.position());
        // Backwards (M04) the position decreases.
        s.set_target(-1200.0);
        for _ in 0..800 {
            s.tick(0.002);
        }
        // 1.6 s (800 ticks) from +20 to −20 rev/s: a symmetric ramp turns 0 rev net.
        assert!((s.position() - 12.0).abs() < 1e-9, "{}", s.position());
    }
}
