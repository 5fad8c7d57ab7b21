//! The simulated machine's script as written in `<machine>/sim.toml` (see the [`super`] docs).

use std::collections::BTreeMap;

use serde::Deserialize;

/// The script as written in `sim.toml`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Script {
    /// Strobe timeout in ms (0: none; default 10 000).
    #[serde(default = "default_timeout")]
    pub strobe_timeout_ms: u64,
    /// When set, the `at` schedule repeats every `period` ticks (for long captures and benchmarks).
    #[serde(default)]
    pub period: Option<u64>,
    /// Process 1's handshake signal addresses that differ from the interface map (name → address).
    #[serde(default)]
    pub signals: BTreeMap<String, String>,
    /// Scheduled actions.
    #[serde(default)]
    pub at: Vec<At>,
    /// Feedback rules.
    #[serde(default)]
    pub follow: Vec<Follow>,
    /// The CNC kernel's settings (used when `ncplc run --program` runs a part).
    #[serde(default)]
    pub cnc: CncSettings,
    /// The simulated spindle drive's wiring (kernel runs).
    #[serde(default)]
    pub spindle: SpindleWiring,
    /// `[[axis]]`: where the simulated machine's axes stand at power-on and their home switches.
    #[serde(default)]
    pub axis: Vec<AxisPlace>,
    /// `[part]`: the operator and machine script of a part run (`ncplc run --program`), used
    /// instead of the top-level `at`/`follow` (whose strobes are the scripted CNC's).
    #[serde(default)]
    pub part: Option<PartScript>,
    /// `[[handwheel]]`: the packet-A pulse counters of the handwheels (IOCFIL ADV channels).
    #[serde(default)]
    pub handwheel: Vec<HandwheelWiring>,
}

/// `[[handwheel]]`: where a handwheel channel's pulse counter is wired (kernel runs).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HandwheelWiring {
    /// The process (1..5, default 1).
    #[serde(default = "process_one")]
    pub process: u8,
    /// The ADV channel, 1 or 2.
    pub channel: u8,
    /// The packet-A input byte that counts the pulses modulo 256 (`W1A3`).
    pub counter: String,
}

/// `[[axis]]`: one axis of the simulated machine (positions on the machine's own scale, mm).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisPlace {
    /// Axis letter of process 1 (`X`).
    pub name: char,
    /// Position at power-on (the controller counts from 0 until homed).
    #[serde(default)]
    pub start: f64,
    /// Edge of the home switch (pressed beyond it in the MCZ search direction).
    pub home_switch: Option<f64>,
    /// Edge of the + hardware limit switch (AXCFIL MFC): pressed at or beyond it.
    pub limit_pos: Option<f64>,
    /// Edge of the − hardware limit switch (AXCFIL MFC): pressed at or below it.
    pub limit_neg: Option<f64>,
}

/// `[part]`: `[[part.at]]` and `[[part.follow]]` for part runs.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartScript {
    /// Scheduled inputs (no m, s or t: the program issues them).
    #[serde(default)]
    pub at: Vec<At>,
    /// Feedback rules.
    #[serde(default)]
    pub follow: Vec<Follow>,
}

/// `[cnc]`: settings of the kernel in a part run.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CncSettings {
    /// A block waits this long for a missing axis enable (RABI) before the alarm (ms; 0: never).
    #[serde(default = "default_rabi_timeout")]
    pub rabi_timeout_ms: u64,
    /// Every axis counts as referenced at power-on (absolute encoders; no homing cycle needed).
    #[serde(default)]
    pub referenced: bool,
    /// Programs of the other processes in a part run (process number → program name), selected
    /// in AUTO and started by the operator alongside `--program`.
    #[serde(default)]
    pub programs: std::collections::BTreeMap<String, String>,
}

impl Default for CncSettings {
    fn default() -> Self {
        CncSettings {
            rabi_timeout_ms: default_rabi_timeout(),
            referenced: false,
            programs: std::collections::BTreeMap::new(),
        }
    }
}

fn default_rabi_timeout() -> u64 {
    5_000
}

/// `[spindle]`: which packet-A signals the simulated spindle drive uses.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpindleWiring {
    /// Input set while the spindle turns at its reference.
    pub at_speed: Option<String>,
    /// Input set while the spindle stands still.
    pub stopped: Option<String>,
    /// Contactor outputs: the spindle turns only while one of them is 1.
    #[serde(default)]
    pub run: Vec<String>,
}

fn default_timeout() -> u64 {
    10_000
}

fn process_one() -> u8 {
    1
}

/// Actions at one tick.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct At {
    /// The tick.
    pub tick: u64,
    /// The process whose handshake carries `m`, `s` and `t` (1..5, default 1).
    #[serde(default = "process_one")]
    pub process: u8,
    /// Input signals to set (held until changed).
    #[serde(default)]
    pub set: BTreeMap<String, u64>,
    /// M functions to issue, in order.
    #[serde(default)]
    pub m: Vec<u32>,
    /// S function to issue.
    pub s: Option<u32>,
    /// T function to issue.
    pub t: Option<u32>,
    /// Handwheels to turn (part runs): ADV channel → pulses (signed, 100 per revolution).
    #[serde(default)]
    pub turn: BTreeMap<String, i64>,
}

impl Default for At {
    fn default() -> Self {
        At {
            tick: 0,
            process: 1,
            set: BTreeMap::new(),
            m: Vec::new(),
            s: None,
            t: None,
            turn: BTreeMap::new(),
        }
    }
}

/// An input that follows an output after a delay (spindle at speed, lubrication level, …).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Follow {
    /// The input driven.
    pub input: String,
    /// The output followed.
    pub output: String,
    /// Further outputs OR'ed with `output`.
    #[serde(default)]
    pub or_outputs: Vec<String>,
    /// The delay in ms (rounded up to ticks; 0 = the next tick).
    #[serde(default)]
    pub delay_ms: u64,
    /// The input is the inverse of the output.
    #[serde(default)]
    pub invert: bool,
}

/// Why a script cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// TOML syntax or an unknown key.
    #[error("sim script: {0}")]
    Toml(#[from] toml::de::Error),
    /// A bad signal name or value.
    #[error("sim script: {0}")]
    Invalid(String),
}
