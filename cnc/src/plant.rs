//! The simulated machine around the controller (the plant): axis drives that follow their set
//! points as a first-order lag with the position-loop gain KV of GMxx, and a spindle that ramps to
//! its reference with the acceleration TSM allows; its encoder's position (revolutions, an index
//! pulse at every whole one) is integrated from the actual speed every tick, for G33.
//!
//! A drive's following error in steady motion is v / KV (10 000 mm/min at KV 20: 8.3 mm), which
//! is what SRV's "without feed-forward" limit is set against.

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
    still_ticks: u32,
    dt: f64,
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
            still_ticks: u32::MAX,
            dt: 0.001,
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

    /// One servo tick of `dt` seconds towards the set point `command`.
    pub fn tick(&mut self, command: f64, dt: f64) {
        self.previous_actual = self.actual;
        if command == self.command {
            self.still_ticks = self.still_ticks.saturating_add(1);
        } else {
            self.still_ticks = 0;
        }
        self.command = command;
        self.dt = dt;
        let k = 1.0 - (-self.kv * dt).dexp();
        self.actual += (command - self.actual) * k;
    }

    /// The actual position.
    pub fn actual(&self) -> f64 {
        self.actual
    }

    /// Set point minus actual position.
    pub fn error(&self) -> f64 {
        self.command - self.actual
    }

    /// The set point has not moved for five time constants (the standby limit applies).
    pub fn settled(&self) -> bool {
        f64::from(self.still_ticks) * self.dt >= 5.0 / self.kv
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
        // KV 20: after 50 ms (one time constant) of a 10 mm step the error is 10·e^-1.
        let mut d = Drive::new(20.0, 0.0);
        for _ in 0..25 {
            d.tick(10.0, 0.002);
        }
        assert!((d.error() - 10.0 * (-1.0f64).dexp()).abs() < 1e-9);
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
