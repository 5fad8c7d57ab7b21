//! What the partprogram compiler needs to know about a machine.
//!
//! [`MachineSpec`] is deliberately decoupled from the characterization crate: the runtime builds it from
//! IOCFIL section 2 (`Mxx=m_type,m_request,class` per process) and the AXCFIL axis names, plus the
//! documented machine options (dialect, macro folder, diameter programming, double precision), and the
//! correction table at power-up (`TAB0.KOR`, read by [`crate::kor::parse_kor`]) with the MEFI length
//! correction method (machine constant 329).

use std::collections::BTreeMap;
use std::path::PathBuf;

use crate::kor::CorrectionTable;

/// Partprogram dialect.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Dialect {
    /// MEFI CNC8x6 (NC-110/NC-2xx): `%n` header, `"…"` comments, R parameters, G26–G29 arithmetic.
    Mefi,
    /// Fanuc/HAAS ISO dialect: `O` numbers, `( )` comments, M97/M98/M99.
    Fanuc,
}

impl std::str::FromStr for Dialect {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "mefi" | "cnc8x6" => Ok(Dialect::Mefi),
            "fanuc" | "haas" | "iso" => Ok(Dialect::Fanuc),
            other => Err(format!("unknown dialect `{other}` (use mefi or fanuc)")),
        }
    }
}

/// Timing of one declared M function (IOCFIL section 2 `Mxx=m_type,m_request,class`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub struct MTiming {
    /// Bit sum: 01 before motion, 02 after motion, 04 in STOP, 10 immediate, 40 modal.
    pub m_type: u8,
    /// Bit sum: 02 optional stop, 04 blocks calculation, 08 stop at end of block, 20 reset request.
    pub m_request: u8,
    /// Visualization class (low nibble) and memorized-search class (high nibble).
    pub class: u8,
}

impl MTiming {
    /// True when the function is executed before the motion of its block.
    pub fn before_motion(&self) -> bool {
        self.m_type & 0x01 != 0
    }
}

/// One process (channel) of the machine.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct ProcessSpec {
    /// M functions declared for this process, by number.
    pub declared_m: BTreeMap<u16, MTiming>,
    /// Axis address letters in axis order (lathe `['X','Z']`, mill `['X','Y','Z']`).
    pub axes: Vec<char>,
}

/// How arithmetic parameter numbers ≥ 50 are read (machine constant 283, decade 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum DoublePrecision {
    /// Decade 4 = 0: numbers 50..99 mean the pair (n−50, n−49).
    #[default]
    Enabled,
    /// Decade 4 = 1: numbers 0..95 are single parameters, no double precision.
    Disabled,
    /// Decade 4 = 2: decade 1 of R95 selects (0 = enabled, 1 = disabled).
    ByR95,
}

/// MEFI length correction method: machine constant 329, decade 7 (structure-motion spec §13.8).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum LengthMethod {
    /// Decade 7 = 0: `&k1k2k3k4` selects per axis (0 none, 1 add, 2 subtract) the data of entry D.
    #[default]
    A,
    /// Decade 7 = 1: `D<n>` adds every length of entry n (axes 1..4); `D0` cancels; `&` has no effect.
    B,
    /// Decade 7 = 2 (printed "0", reading uncertain): `&1` adds every length of entry D, `&0` cancels.
    C,
}

/// A length correction method that is not A, B or C.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "unknown length correction method `{0}` (use A, B or C: machine constant 329 decade 7 = 0, 1, 2)"
)]
pub struct UnknownLengthMethod(pub String);

impl std::str::FromStr for LengthMethod {
    type Err = UnknownLengthMethod;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_uppercase().as_str() {
            "A" | "0" => Ok(LengthMethod::A),
            "B" | "1" => Ok(LengthMethod::B),
            "C" | "2" => Ok(LengthMethod::C),
            other => Err(UnknownLengthMethod(other.to_string())),
        }
    }
}

/// Why a machine-constants file (`nc/CONSTANTS`) or one of its values was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ConstantsError {
    /// A line is not `R<n>: <value>`.
    #[error("line {line}: expected `R<n>: <value>`, found `{text}`")]
    Syntax {
        /// 1-based line number.
        line: usize,
        /// The line, comment removed.
        text: String,
    },
    /// Constant 329's decade 7 names no length correction method.
    #[error("R{constant}: {source}")]
    LengthMethod {
        /// The constant (329).
        constant: u32,
        /// The bad method.
        source: UnknownLengthMethod,
    },
}

/// Everything the partprogram compiler and planner need from a machine.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MachineSpec {
    /// Dialect of the machine's partprograms.
    pub dialect: Dialect,
    /// Folder of macro files `L<n>` and fixed-cycle files.
    pub macro_dir: PathBuf,
    /// Processes; partprograms are compiled for process 1 unless told otherwise.
    pub processes: Vec<ProcessSpec>,
    /// Lathe diameter programming of X (G74 state at start).
    pub diameter_x: bool,
    /// Interpolation plane at program start: 17 (XY), 18 (ZX) or 19 (YZ).
    pub default_plane: u8,
    /// Double-precision arithmetic setting.
    pub double_precision: DoublePrecision,
    /// Tolerance (mm) for "end point is on the circle" (machine constant 55).
    pub circle_tolerance: f64,
    /// When true, M functions not declared in IOCFIL section 2 are errors (false: not checked).
    pub check_m_declared: bool,
    /// The correction table at power-up (the machine's `TAB0.KOR`); empty: all zero.
    #[serde(default)]
    pub corrections: CorrectionTable,
    /// The zero-offset table at power-up (the machine's `TAB0.POS`); default: all zero.
    #[serde(default)]
    pub zero_offsets: crate::pos::ZeroOffsets,
    /// MEFI length correction method (machine constant 329, decade 7).
    #[serde(default)]
    pub length_method: LengthMethod,
    /// Machine constant 8: the thread run-in/run-out slope, or the parameters holding it
    /// ([`crate::thread`]); 0: not set.
    #[serde(default)]
    pub thread_constant: i64,
    /// Machine constant 341: the correction planes of G14, G15, G16 as two-decade pairs (first, second
    /// axis ordinal) from the low-order end; 0 means the defaults 34, 24, 41 ([`MachineSpec::plane_341`]).
    #[serde(default)]
    pub planes_341: i64,
    /// Fanuc Macro B `#500`–`#999` at the start of a plan (the machine's `nc/MACROVARS`); empty:
    /// all null.
    #[serde(default)]
    pub retained: crate::macro_b::retained::Retained,
}

impl MachineSpec {
    /// A machine with sensible defaults for `dialect` and the given axes (one process, no M declarations
    /// checked).
    pub fn new(dialect: Dialect, axes: &[char]) -> Self {
        let lathe = !axes.contains(&'Y');
        MachineSpec {
            dialect,
            macro_dir: PathBuf::new(),
            processes: vec![ProcessSpec {
                declared_m: BTreeMap::new(),
                axes: axes.to_vec(),
            }],
            diameter_x: false,
            default_plane: if lathe { 18 } else { 17 },
            double_precision: DoublePrecision::Enabled,
            circle_tolerance: 0.002,
            check_m_declared: false,
            corrections: CorrectionTable::default(),
            zero_offsets: crate::pos::ZeroOffsets::default(),
            length_method: LengthMethod::A,
            thread_constant: 0,
            planes_341: 0,
            retained: crate::macro_b::retained::Retained::default(),
        }
    }

    /// The axes of process 1 (X, Y, Z when none are configured).
    pub fn axes(&self) -> Vec<char> {
        match self.processes.first() {
            Some(p) if !p.axes.is_empty() => p.axes.clone(),
            _ => vec!['X', 'Y', 'Z'],
        }
    }

    /// The (first, second) axis ordinals of the correction plane of G14, G15 or G16: pair 1, 2 or 3 of
    /// machine constant 341 counted from the low-order end (structure spec §13.7); a pair `00` (and
    /// the whole constant 0) takes its default `34`, `24`, `41`. Other `g` are clamped to 14..=16.
    pub fn plane_341(&self, g: u16) -> (u8, u8) {
        let k = u32::from(g.saturating_sub(14).min(2));
        let pair = (self.planes_341.unsigned_abs() / 100u64.pow(k)) % 100;
        let pair = if pair == 0 {
            [34, 24, 41][k as usize]
        } else {
            pair
        };
        ((pair / 10) as u8, (pair % 10) as u8)
    }

    /// The axis letters of the G14/G15/G16 correction plane of process 1, or why the process has none.
    pub fn plane_341_axes(&self, g: u16) -> Result<(char, char), String> {
        let (o1, o2) = self.plane_341(g);
        let axes = self.axes();
        let letter = |o: u8| {
            usize::from(o)
                .checked_sub(1)
                .and_then(|i| axes.get(i))
                .copied()
        };
        match (letter(o1), letter(o2)) {
            (Some(a), Some(b)) if a != b => Ok((a, b)),
            _ => Err(format!(
                "G{g} selects the correction plane of axes {o1} and {o2} (machine constant 341 pair {}), but the process has {} axes ({})",
                g.saturating_sub(14).min(2) + 1,
                axes.len(),
                axes.iter().collect::<String>()
            )),
        }
    }

    /// The timing of M `m` in process 1, if declared.
    pub fn m_timing(&self, m: u16) -> Option<MTiming> {
        self.processes
            .first()
            .and_then(|p| p.declared_m.get(&m).copied())
    }
}

/// Reads machine constants written as in `TAB0.REK` listings: one `R<n>: <value>` per line, the
/// value's decimal point insignificant (`R340: 00233.112` = 233112), `"` starts a comment; returns
/// (constant number, value) pairs in file order, or the first bad line.
pub fn parse_constants(text: &str) -> Result<Vec<(u32, i64)>, ConstantsError> {
    let mut out = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let line = line.split('"').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let bad = || ConstantsError::Syntax {
            line: k + 1,
            text: line.to_string(),
        };
        let (name, value) = line.split_once(':').ok_or_else(bad)?;
        let n: u32 = name
            .trim()
            .strip_prefix('R')
            .and_then(|d| d.parse().ok())
            .ok_or_else(bad)?;
        let value = value.trim();
        let (neg, digits) = match value.strip_prefix('-') {
            Some(d) => (true, d),
            None => (false, value.strip_prefix('+').unwrap_or(value)),
        };
        let digits: String = digits.chars().filter(|c| *c != '.').collect();
        if digits.is_empty()
            || digits.len() > 9
            || !digits.bytes().all(|c| c.is_ascii_digit())
            || value.matches('.').count() > 1
        {
            return Err(bad());
        }
        let v: i64 = digits.parse().map_err(|_| bad())?;
        out.push((n, if neg { -v } else { v }));
    }
    Ok(out)
}

impl MachineSpec {
    /// Applies machine constant `n` with value `v`: 8 (thread run-in/run-out slope), 329 (decade 7:
    /// length correction method 0 A, 1 B, 2 C) and 341 (G14–G16 planes); other constants do not concern
    /// the planner and are ignored.
    pub fn set_constant(&mut self, n: u32, v: i64) -> Result<(), ConstantsError> {
        match n {
            8 => self.thread_constant = v,
            341 => self.planes_341 = v,
            329 => {
                let d7 = (v.unsigned_abs() / 1_000_000) % 10;
                self.length_method =
                    d7.to_string()
                        .parse()
                        .map_err(|source| ConstantsError::LengthMethod {
                            constant: n,
                            source,
                        })?;
            }
            _ => {}
        }
        Ok(())
    }
}
