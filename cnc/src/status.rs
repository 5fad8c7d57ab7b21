//! The status snapshot an HMI (or the CLI summary) reads: per process the mode, the program and
//! the block, every axis's set point, actual position and following error, feed, spindle speed and
//! the active alarms.

use crate::following::Limit;
use crate::state::{Interp, Mode};

/// One axis.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct AxisStatus {
    /// Address letter.
    pub name: char,
    /// Set point (mm).
    pub command: f64,
    /// Actual position of the simulated drive (mm).
    pub actual: f64,
    /// Set point minus actual (mm).
    pub following_error: f64,
    /// The SRV limit in force now (stand-by at rest, VFF or no-VFF while moving).
    #[serde(serialize_with = "limit_name")]
    pub limit: Limit,
    /// Its value (mm; 0 = unchecked).
    pub limit_mm: f64,
    /// The largest |following error| since power-on (mm).
    pub largest: f64,
}

/// One process.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ProcessStatus {
    /// Process number.
    pub process: u8,
    /// Mode.
    #[serde(serialize_with = "mode_name")]
    pub mode: Mode,
    /// Interpreter state.
    #[serde(serialize_with = "interp_name")]
    pub interp: Interp,
    /// Machine on.
    pub on: bool,
    /// Every axis that needs homing is homed.
    pub homed: bool,
    /// The selected program's name.
    pub program: String,
    /// Index of the current block (0-based).
    pub block: usize,
    /// Its N number.
    pub block_n: Option<u32>,
    /// Axes.
    pub axes: Vec<AxisStatus>,
    /// Path feed (mm/min).
    pub feed_mm_min: f64,
    /// Actual spindle speed (rev/min).
    pub spindle_rpm: f64,
    /// Active alarm messages.
    pub alarms: Vec<String>,
}

fn mode_name<S: serde::Serializer>(m: &Mode, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&format!("{m:?}").to_uppercase())
}

fn interp_name<S: serde::Serializer>(m: &Interp, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&format!("{m:?}").to_lowercase())
}

fn limit_name<S: serde::Serializer>(l: &Limit, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(l.name())
}
