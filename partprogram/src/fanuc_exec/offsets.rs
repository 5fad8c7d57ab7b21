//! Offsets the Fanuc/HAAS program writes itself: `G10 L2` (work offsets G54–G59), `G10 L20`
//! (additional work offsets G154 P1–P99, G110–G129 = P1–P20), `G10 L10`/`L12` (tool length and
//! radius geometry), `G10 L11`/`L13` (their wear; the active value is geometry + wear), the `G52` local shift, the `G92` setting, and the selection of the additional
//! work systems by G110–G129 and `G154 P<n>`.
//!
//! Under G91 a `G10` value is added to the register (Fanuc); under G90 it replaces it. A `G10` of
//! another L number, or a register outside the table, is refused with a located error.

use super::{Ex, run_err};
use crate::ast::Val;
use crate::codes;
use crate::exec::RunError;
use crate::length::datum_of_axis;
use crate::program::CBlock;

/// Rows of the work-offset table: G54–G59 and the 99 additional systems of G154 P1–P99.
pub const WORK_ROWS: usize = 6 + 99;

impl Ex<'_> {
    fn count(b: &CBlock, a: char) -> Option<f64> {
        match b.word(a).map(|w| &w.val) {
            Some(Val::Lit(l)) => Some(l.value()),
            _ => None,
        }
    }

    /// Executes `G10 L<l> P<p> …` of block `b`; `vals` are the block's axis values in mm.
    pub(super) fn g10(&mut self, b: &CBlock, vals: &[Option<f64>; 6]) -> Result<(), RunError> {
        let l = Self::count(b, 'L')
            .ok_or_else(|| run_err(b, codes::RUN_RANGE, "G10 needs L (2, 10–13 or 20)"))?;
        let p = Self::count(b, 'P')
            .ok_or_else(|| run_err(b, codes::RUN_RANGE, format!("G10 L{l} needs P")))?;
        let pi = p as i64;
        if p.fract() != 0.0 {
            return Err(run_err(
                b,
                codes::RUN_RANGE,
                format!("G10 P{p}: P must be an integer"),
            ));
        }
        let abs = self.abs;
        let put = |reg: &mut f64, v: f64| {
            *reg = if abs { v } else { *reg + v };
        };
        match l as i64 {
            2 | 20 => {
                let row = match (l as i64, pi) {
                    (2, 1..=6) => (pi - 1) as usize,
                    (20, 1..=99) => (pi + 5) as usize,
                    (2, _) => {
                        return Err(run_err(
                            b,
                            codes::RUN_RANGE,
                            format!("G10 L2 P{pi}: work offsets are P1..P6 (G54..G59)"),
                        ));
                    }
                    _ => {
                        return Err(run_err(
                            b,
                            codes::RUN_RANGE,
                            format!(
                                "G10 L20 P{pi}: additional work offsets are P1..P99 (G154 P1..P99)"
                            ),
                        ));
                    }
                };
                for (i, v) in vals.iter().enumerate().take(self.axes.len()) {
                    if let Some(v) = v {
                        put(&mut self.work[row][i], *v);
                    }
                }
            }
            10..=13 => {
                let r = self.dim(b, 'R').ok_or_else(|| {
                    run_err(
                        b,
                        codes::RUN_RANGE,
                        format!("G10 L{l} P{pi} needs R (the value)"),
                    )
                })?;
                let wear = matches!(l as i64, 11 | 13);
                let slot = if matches!(l as i64, 12 | 13) {
                    0
                } else if wear {
                    1
                } else {
                    let zi = self.idx('Z').ok_or_else(|| {
                        run_err(
                            b,
                            codes::RUN_TOOL_LENGTH,
                            "G10 L10: the machine has no Z axis",
                        )
                    })?;
                    datum_of_axis(zi).ok_or_else(|| {
                        run_err(
                            b,
                            codes::RUN_TOOL_LENGTH,
                            "G10 L10: Z is not among axes 1..4",
                        )
                    })?
                };
                let limit = if matches!(l as i64, 12 | 13) { 200 } else { 99 };
                let p = usize::try_from(pi)
                    .ok()
                    .filter(|p| (1..=limit).contains(p))
                    .ok_or_else(|| {
                        run_err(
                            b,
                            codes::RUN_RANGE,
                            format!("G10 L{l} P{pi}: registers are P1..P{limit}"),
                        )
                    })?;
                let reg = if wear {
                    // Wear: [length, radius] (slot 1 is L11's length, slot 0 L13's radius).
                    self.wear.get_mut(p).map(|w| &mut w[1 - slot])
                } else {
                    self.corrections.get_mut(p).map(|e| &mut e[slot])
                };
                if let Some(reg) = reg {
                    put(reg, r);
                }
            }
            other => {
                return Err(run_err(
                    b,
                    codes::RUN_BAD_G,
                    format!(
                        "G10 L{other} is not supported: L2 (work offsets), L20 (G154 offsets), L10/L11 (tool length geometry/wear), L12/L13 (tool radius geometry/wear)"
                    ),
                ));
            }
        }
        Ok(())
    }

    /// `G52`: the given axes get the local shift (always absolute, relative to the work zero); the
    /// other axes keep theirs. `G52 X0` cancels the shift of X.
    pub(super) fn g52(&mut self, vals: &[Option<f64>; 6]) {
        for (local, v) in self.local.iter_mut().zip(vals.iter()).take(self.axes.len()) {
            if let Some(v) = v {
                *local = *v;
            }
        }
    }

    /// `G92`: the current position of each given axis becomes the given value; the G52 shift of that
    /// axis is cancelled (HAAS spec §9.7).
    pub(super) fn g92(&mut self, vals: &[Option<f64>; 6]) {
        for (i, v) in vals.iter().enumerate().take(self.axes.len()) {
            if let Some(v) = v {
                self.local[i] = 0.0;
                self.g92[i] = self.machine[i] - self.work[self.wsel][i] - self.tlo[i] - v;
            }
        }
    }

    /// Selects work system `G154 P<p>` (P1..P99), G110..G129 being P1..P20.
    pub(super) fn g154(&mut self, b: &CBlock, p: Option<f64>) -> Result<(), RunError> {
        match p {
            Some(p) if p.fract() == 0.0 && (1.0..=99.0).contains(&p) => {
                self.wsel = 5 + p as usize;
                Ok(())
            }
            _ => Err(run_err(
                b,
                codes::RUN_RANGE,
                "G154 needs P1..P99 (the additional work system)",
            )),
        }
    }
}
