//! Program flow of the MEFI executor: calls of subprograms, macros and fixed cycles (with the
//! snapshot a fixed cycle restores), returns with repetition, and G73 jumps with their counters.

use super::{Exec, Frame, Snapshot, run_err};
use crate::codes;
use crate::exec::RunError;
use crate::jit::region::IDLE;
use crate::program::{CBlock, Unit, UnitKind};

/// Fresh jump counters for a frame of `unit`: one idle slot per block.
pub(super) fn idle_counters(unit: Option<&Unit>) -> Vec<i64> {
    vec![IDLE; unit.map_or(0, |u| u.end - u.start)]
}

impl Exec<'_> {
    pub(super) fn call(
        &mut self,
        b: &CBlock,
        unit: usize,
        repeat: i64,
        cycle: Option<Box<Snapshot>>,
    ) -> Result<(), RunError> {
        if self.frames.len() >= 64 {
            return Err(run_err(
                b,
                codes::RUN_LIMIT,
                "calls nested deeper than 64 levels",
            ));
        }
        let start = self.prog.units[unit].start;
        self.frames.push(Frame {
            unit,
            pc: start,
            counters: idle_counters(self.prog.units.get(unit)),
            repeat,
            cycle,
        });
        Ok(())
    }

    pub(super) fn ret(&mut self, bi: usize) -> Result<(), RunError> {
        let Some(fr) = self.frames.last_mut() else {
            return Ok(());
        };
        if self.prog.units[fr.unit].kind == UnitKind::Main {
            let b = &self.prog.blocks[bi];
            return Err(run_err(b, codes::RUN_TARGET, "G70 in the main program"));
        }
        if fr.repeat > 1 {
            fr.repeat -= 1;
            fr.pc = self.prog.units[fr.unit].start;
            fr.counters.fill(IDLE);
            return Ok(());
        }
        if let Some(fr) = self.frames.pop()
            && let Some(s) = fr.cycle
        {
            self.st.r = s.r;
            self.modal = s.modal;
            self.st.m_groups = s.m_groups;
            self.st.g_groups = s.g_groups;
            self.st.s_t_d = s.s_t_d;
        }
        Ok(())
    }

    pub(super) fn jump(
        &mut self,
        b: &CBlock,
        bi: usize,
        l: Option<i64>,
        q: i64,
    ) -> Result<(), RunError> {
        let Some(lv) = l else {
            return Err(run_err(b, codes::RUN_TARGET, "G73 without L"));
        };
        let unit = &self.prog.units[b.unit];
        let target = unit.index.get(lv as u32).ok_or_else(|| {
            run_err(
                b,
                codes::RUN_TARGET,
                format!("jump to N{lv}, which is not in this program unit"),
            )
        })?;
        let start = unit.start;
        let Some(fr) = self.frames.last_mut() else {
            return Ok(());
        };
        // One counter per jump block of the frame (the region functions share this layout).
        let Some(slot) = bi.checked_sub(start).and_then(|i| fr.counters.get_mut(i)) else {
            return Ok(());
        };
        let take = match *slot {
            IDLE => {
                if q > 0 {
                    *slot = q - 1;
                    true
                } else {
                    false
                }
            }
            0 => {
                *slot = IDLE;
                false
            }
            k => {
                *slot = k - 1;
                true
            }
        };
        if take {
            fr.pc = target;
        }
        Ok(())
    }
}
