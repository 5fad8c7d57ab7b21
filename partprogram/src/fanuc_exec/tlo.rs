//! Fanuc/HAAS tool length compensation: `G43 H<n>` adds, `G44 H<n>` subtracts the length of correction
//! entry n on the tool axis; G49, H00, G28 and M02/M30 cancel (HAAS spec §10.1).
//!
//! The active length is part of the axis origin ([`Ex::origin`]): an absolute target includes it, and
//! the change made by G43/G44/G49 is added once to the next incremental move of the axis. The tool
//! axis and the datum come from [`crate::length`]. On a lathe H is the incremental C address, so it
//! never selects a length there.

use super::{Ex, run_err};
use crate::ast::Val;
use crate::codes;
use crate::exec::RunError;
use crate::length::{datum_of_axis, tool_axis};
use crate::program::CBlock;

impl Ex<'_> {
    /// Applies the block's G43/G44/G49 (`g`, ×10 code), its H word and a G28 cancellation; runs before
    /// the block's targets are computed.
    pub(super) fn tool_length(
        &mut self,
        b: &CBlock,
        g: Option<u16>,
        g28: bool,
    ) -> Result<(), RunError> {
        let lathe = !self.axes.contains(&'Y');
        let h = if lathe {
            None
        } else {
            b.word('H').and_then(|w| match w.val {
                Val::Lit(l) => Some(l.value()),
                Val::Param(_) | Val::Expr(_) => None,
            })
        };
        if let Some(h) = h {
            self.tlo_h = h as i64;
        }
        if g28 || g == Some(490) {
            self.set_tlo([0.0; 6]);
            self.tlo_sign = None;
            if g28 {
                // G28 does not see the length: its intermediate point is without it.
                self.tlo_due = [0.0; 6];
            }
            return Ok(());
        }
        match g {
            Some(430) => self.tlo_sign = Some((1.0, self.plane)),
            Some(440) => self.tlo_sign = Some((-1.0, self.plane)),
            _ if h.is_none() => return Ok(()),
            _ => {}
        }
        let Some((sign, plane)) = self.tlo_sign else {
            return Ok(());
        };
        let gname = plane.g();
        let Some(axis) = tool_axis(plane) else {
            return Err(run_err(
                b,
                codes::RUN_TOOL_LENGTH,
                format!("G43/G44 in G{gname}: the plane has no tool axis"),
            ));
        };
        let Some(i) = self.idx(axis) else {
            return Err(run_err(
                b,
                codes::RUN_TOOL_LENGTH,
                format!("G43/G44 in G{gname}: the machine has no tool axis {axis}"),
            ));
        };
        let Some(datum) = datum_of_axis(i) else {
            return Err(run_err(
                b,
                codes::RUN_TOOL_LENGTH,
                format!(
                    "the tool axis {axis} is axis {}: the correction table holds lengths of axes 1..4",
                    i + 1
                ),
            ));
        };
        let entry = usize::try_from(self.tlo_h)
            .ok()
            .and_then(|n| self.corrections.get(n))
            .ok_or_else(|| {
                run_err(
                    b,
                    codes::RUN_TOOL_LENGTH,
                    format!("H{}: the correction table has entries H0..H99", self.tlo_h),
                )
            })?;
        let mut new = [0.0; 6];
        let wear = usize::try_from(self.tlo_h)
            .ok()
            .and_then(|n| self.wear.get(n))
            .map_or(0.0, |w| w[0]);
        new[i] = sign * (entry[datum] + wear);
        if self.tlo_h == 0 {
            // H00 cancels like G49.
            self.tlo_sign = None;
        }
        self.set_tlo(new);
        Ok(())
    }

    /// Makes `new` the active lengths; the change is due on the next incremental move of each axis.
    fn set_tlo(&mut self, new: [f64; 6]) {
        for (i, v) in new.iter().enumerate() {
            self.tlo_due[i] += v - self.tlo[i];
        }
        self.tlo = new;
    }

    /// Cancels the compensation (M02/M30).
    pub(super) fn cancel_tlo(&mut self) {
        self.set_tlo([0.0; 6]);
        self.tlo_sign = None;
        self.tlo_h = 0;
    }

    /// The axes programmed in the block have taken their due length change.
    pub(super) fn tlo_moved(&mut self, vals: &[Option<f64>; 6]) {
        for (due, v) in self.tlo_due.iter_mut().zip(vals) {
            if v.is_some() {
                *due = 0.0;
            }
        }
    }
}
