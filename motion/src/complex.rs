//! "Complex speed" (MEFI manual, appendix A6, 000:4570–4705): the joint-speed criteria of
//! smooth block connection and their machine constants, read from `nc/CONSTANTS` (listing
//! format `R385: 10000`; the decimal point of a TAB0.REK listing carries no meaning, the digits
//! are the register's value).
//!
//! | constant | meaning | unit of the digits | default (manual's example) |
//! |---|---|---|---|
//! | R39 | tolerance angle of smooth connection under G23: a sharper joint is a stop | 0.001° | 60000 (60°) |
//! | R384 decades 1–4 | accuracy criterion L: v ≤ L / (Ts · tan(α/2)); 0: off | µm | 10 |
//! | R385 decades 1–7 | dynamic criterion a: v ≤ a · Ts / (2 · sin(α/2)) | mm/s² | 10000 |
//! | R385 decade 8 | block-length correction of the dynamic criterion: reference 1, 0.5, 0.1, 0.05 mm (1–4); 0 off | – | 0 |
//! | R386 | blocks shorter than this keep their joint speeds inside (no speed-up between); 0: every block may speed up | µm | 0 |
//! | R236 | path acceleration under smooth connection; 0: the axes' (R52) | mm/s² | 0 |
//! | R382 | a block shorter than this interrupts the smooth connection: the path stops at its start; 0 or negative ("a minus sign blocks the limit"): off | µm | 0 |
//!
//! R382 follows the seed (000:4612–4618): "if the block is shorter than the limit, the smooth
//! connection is interrupted at this place". Which joint "this place" is, is not said; here it
//! is the joint into the short block (reading uncertain). The manual's next constant joins blocks
//! shorter than its limit with a neighbour; its number is lost in our copy (probably R383): a
//! positive R383 is refused (not supported) rather than ignored.
//!
//! The manual does not give the block-length correction's formula; here the dynamic criterion
//! of a block of length l is scaled by √(l / reference) (the centripetal speed over a chord
//! polygon grows with the square root of the chord), capped at 1 — documented, not the
//! manual's. Whatever the criteria allow, the axes' own limits still hold at every tick: the
//! criteria only ever lower a joint's speed.
//!
//! Invariants: every value is range-checked when read; out of range is an error naming the
//! constant, its value and the range.

use detmath::Det as _;

/// The complex-speed constants in force.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ComplexSpeed {
    /// R39: joints turning more than this (rad) stop under G23.
    pub angle: f64,
    /// R384 decades 1–4: the accuracy criterion's deviation, mm (0: off).
    pub accuracy_mm: f64,
    /// R385 decades 1–7: the dynamic criterion's acceleration, mm/s².
    pub dynamic: f64,
    /// R385 decade 8: the reference block length of its correction, mm (None: no correction).
    pub dyn_ref_len: Option<f64>,
    /// R386: blocks shorter than this (mm) keep their joint speeds inside (0: none).
    pub raise_len: f64,
    /// R236: the path acceleration under smooth connection, mm/s² (0: the axes').
    pub smooth_accel: f64,
    /// R382: a block shorter than this (mm) stops the path at its start (0: off).
    pub interrupt_len: f64,
}

impl Default for ComplexSpeed {
    /// The manual's example values (R39 60°, R385 10000 mm/s², R236 and R386 0: the axes' and
    /// every block), with the accuracy criterion at 10 µm (its example value is lost).
    fn default() -> Self {
        ComplexSpeed {
            angle: 60f64.to_radians(),
            accuracy_mm: 0.010,
            dynamic: 10_000.0,
            dyn_ref_len: None,
            raise_len: 0.0,
            smooth_accel: 0.0,
            interrupt_len: 0.0,
        }
    }
}

/// A complex-speed constant out of range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("R{constant}: {value} is out of range ({range})")]
pub struct ConstantError {
    /// The constant's number.
    pub constant: u32,
    /// The value as read.
    pub value: i64,
    /// What is allowed.
    pub range: &'static str,
}

impl ComplexSpeed {
    /// Applies machine constant `n` with the digits `v` (other constants are not this module's
    /// and are left alone).
    pub fn set_constant(&mut self, n: u32, v: i64) -> Result<(), ConstantError> {
        let bad = |range| ConstantError {
            constant: n,
            value: v,
            range,
        };
        match n {
            39 => {
                if !(1..=180_000).contains(&v) {
                    return Err(bad("1…180000, thousandths of a degree"));
                }
                self.angle = (v as f64 / 1000.0).to_radians();
            }
            384 => {
                if !(0..=99_9999).contains(&v) {
                    return Err(bad("0…999999: decades 5–6 a percentage, 1–4 µm"));
                }
                self.accuracy_mm = (v % 10_000) as f64 / 1000.0;
            }
            385 => {
                if !(0..=49_999_999).contains(&v) || v % 10_000_000 == 0 {
                    return Err(bad(
                        "decades 1–7 an acceleration of 1…9999999 mm/s², decade 8 0…4",
                    ));
                }
                self.dynamic = (v % 10_000_000) as f64;
                self.dyn_ref_len = match v / 10_000_000 {
                    1 => Some(1.0),
                    2 => Some(0.5),
                    3 => Some(0.1),
                    4 => Some(0.05),
                    _ => None,
                };
            }
            386 => {
                if !(0..=99_999_999).contains(&v) {
                    return Err(bad("0…99999999 µm"));
                }
                self.raise_len = v as f64 / 1000.0;
            }
            236 => {
                if !(0..=9_999_999).contains(&v) {
                    return Err(bad("0…9999999 mm/s²"));
                }
                self.smooth_accel = v as f64;
            }
            382 => {
                if !(-99_999_999..=99_999_999).contains(&v) {
                    return Err(bad("−99999999…99999999 µm (negative or 0: off)"));
                }
                self.interrupt_len = v.max(0) as f64 / 1000.0;
            }
            383 if v > 0 => {
                return Err(bad(
                    "joining short blocks with a neighbour is not supported: 0 or negative (off)",
                ));
            }
            _ => {}
        }
        Ok(())
    }

    /// The joint speed the two criteria allow (mm/s) for a turn of `alpha` rad between blocks
    /// of lengths `l1`, `l2` mm at the tick `ts` s; infinite for a straight joint.
    pub fn joint_speed(&self, alpha: f64, l1: f64, l2: f64, ts: f64) -> f64 {
        if alpha <= 0.0 {
            return f64::INFINITY;
        }
        let mut v = self.dynamic * ts / (2.0 * (alpha / 2.0).dsin());
        if let Some(r) = self.dyn_ref_len {
            v *= (l1.min(l2) / r).min(1.0).sqrt();
        }
        if self.accuracy_mm > 0.0 && alpha < std::f64::consts::PI {
            v = v.min(self.accuracy_mm / (ts * (alpha / 2.0).dtan()));
        }
        v
    }

    /// The header/summary description: `R39 60°, R384 10 µm, R385 10000 mm/s², R386 0 mm, R236 axes`.
    pub fn describe(&self) -> String {
        format!(
            "R39 {}°, R384 {} µm, R385 {} mm/s²{}, R386 {} mm, R236 {}{}",
            (self.angle.to_degrees() * 1000.0).round() / 1000.0,
            (self.accuracy_mm * 1000.0).round(),
            self.dynamic,
            self.dyn_ref_len.map_or(String::new(), |r| format!(
                " (block-length reference {r} mm)"
            )),
            self.raise_len,
            if self.smooth_accel > 0.0 {
                format!("{} mm/s²", self.smooth_accel)
            } else {
                "the axes'".into()
            },
            if self.interrupt_len > 0.0 {
                format!(", R382 {} mm", self.interrupt_len)
            } else {
                String::new()
            }
        )
    }
}

/// Why `nc/CONSTANTS` gives no complex-speed constants: the line and what is wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("line {line}: {what}")]
pub struct ConstantsFileError {
    /// 1-based line number.
    pub line: usize,
    /// What is wrong.
    pub what: String,
}

/// The complex-speed constants of a `nc/CONSTANTS` text (the manual's defaults for the ones it
/// does not set).
pub fn from_constants(text: &str) -> Result<ComplexSpeed, ConstantsFileError> {
    let pairs = partprogram::machine::parse_constants(text).map_err(|e| match e {
        partprogram::machine::ConstantsError::Syntax { line, text } => ConstantsFileError {
            line,
            what: format!("expected `R<n>: <value>`, found `{text}`"),
        },
        other => ConstantsFileError {
            line: 0,
            what: other.to_string(),
        },
    })?;
    let mut c = ComplexSpeed::default();
    for (n, v) in pairs {
        c.set_constant(n, v).map_err(|e| {
            // The last line that sets R<n> (the one in force).
            let line = text
                .lines()
                .enumerate()
                .filter(|(_, l)| {
                    let l = l.trim_start();
                    l.strip_prefix('R')
                        .and_then(|r| r.split(':').next())
                        .and_then(|d| d.trim().parse::<u32>().ok())
                        == Some(n)
                })
                .map(|(i, _)| i + 1)
                .last()
                .unwrap_or(0);
            ConstantsFileError {
                line,
                what: e.to_string(),
            }
        })?;
    }
    Ok(c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_criteria_follow_the_manuals_formulas() {
        let c = ComplexSpeed::default();
        // 10°, Ts 1 ms: dynamic 10000 · 0.001 / (2 sin 5°) = 57.3686 mm/s; accuracy
        // 0.010 / (0.001 · tan 5°) = 114.301 mm/s: the dynamic one is lower.
        let a = 10f64.to_radians();
        let v = c.joint_speed(a, 1.0, 1.0, 0.001);
        assert!((v - 57.368_566).abs() < 1e-5, "{v}");
        // 90°: dynamic 7.0711 mm/s, accuracy 10 mm/s.
        let v = c.joint_speed(std::f64::consts::FRAC_PI_2, 1.0, 1.0, 0.001);
        assert!((v - 7.071_068).abs() < 1e-5, "{v}");
        // A tighter accuracy (1 µm) wins: 0.001 / (0.001 · tan 5°) = 11.430 mm/s.
        let mut t = c;
        t.set_constant(384, 20_0001)
            .unwrap_or_else(|e| panic!("{e}"));
        let v = t.joint_speed(a, 1.0, 1.0, 0.001);
        assert!((v - 11.430_052).abs() < 1e-5, "{v}");
        assert_eq!(c.joint_speed(0.0, 1.0, 1.0, 0.001), f64::INFINITY);
    }

    #[test]
    fn constants_set_the_criteria_and_out_of_range_values_are_named() {
        let mut c = ComplexSpeed::default();
        c.set_constant(39, 30_000).unwrap_or_else(|e| panic!("{e}"));
        assert!((c.angle - 30f64.to_radians()).abs() < 1e-15);
        c.set_constant(385, 3_0005000)
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!((c.dynamic, c.dyn_ref_len), (5000.0, Some(0.1)));
        c.set_constant(386, 2500).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(c.raise_len, 2.5);
        c.set_constant(236, 400).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(c.smooth_accel, 400.0);
        let e = c.set_constant(39, 200_000).err();
        assert_eq!(
            e.map(|e| e.to_string()),
            Some("R39: 200000 is out of range (1…180000, thousandths of a degree)".into())
        );
        assert!(c.set_constant(385, 5_0001000).is_err());
        assert!(c.set_constant(385, 0).is_err());
        assert!(c.set_constant(236, -1).is_err());
        // R382 in µm; a minus sign blocks it; the joining constant (R383) is refused when on.
        c.set_constant(382, 50).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(c.interrupt_len, 0.05);
        assert!(c.describe().ends_with(", R382 0.05 mm"), "{}", c.describe());
        c.set_constant(382, -50).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(c.interrupt_len, 0.0);
        assert_eq!(c.set_constant(383, -10), Ok(()));
        assert_eq!(
            c.set_constant(383, 10).err().map(|e| e.to_string()),
            Some("R383: 10 is out of range (joining short blocks with a neighbour is not supported: 0 or negative (off))".into())
        );
        // Constants of other modules are left alone.
        assert_eq!(c.set_constant(329, 1_000_000), Ok(()));
    }

    #[test]
    fn a_constants_file_gives_the_criteria_or_the_line_of_the_bad_value() {
        let c = from_constants("R329: 01000.000\nR39: 00045.000 \"degrees\nR384: 20005\n")
            .unwrap_or_else(|e| panic!("{e}"));
        assert!((c.angle - 45f64.to_radians()).abs() < 1e-15);
        assert_eq!(c.accuracy_mm, 0.005);
        assert_eq!(c.dynamic, 10_000.0);
        let e = from_constants("R8: 0\n\nR385: 9.0000000\n").err();
        assert_eq!(
            e.map(|e| e.to_string()),
            Some(
                "line 3: R385: 90000000 is out of range (decades 1–7 an acceleration of 1…9999999 mm/s², decade 8 0…4)"
                    .into()
            )
        );
    }
}
