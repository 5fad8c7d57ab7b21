//! Program flow of the MEFI executor: calls of subprograms, macros and fixed cycles (with the
//! snapshot a fixed cycle restores), returns with repetition, and G73 jumps with their counters.

use std::collections::HashMap;

use super::{Exec, Frame, Snapshot, run_err};
use crate::codes;
use crate::exec::RunError;
use crate::program::{CBlock, UnitKind};

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
            counters: HashMap::new(),
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
            fr.counters.clear();
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
        let target = *unit.index.get(&(lv as u32)).ok_or_else(|| {
            run_err(
                b,
                codes::RUN_TARGET,
                format!("jump to N{lv}, which is not in this program unit"),
            )
        })?;
        let Some(fr) = self.frames.last_mut() else {
            return Ok(());
        };
        let take = match fr.counters.get(&bi).copied() {
            None => {
                if q > 0 {
                    fr.counters.insert(bi, q - 1);
                    true
                } else {
                    false
                }
            }
            Some(0) => {
                fr.counters.remove(&bi);
                false
            }
            Some(k) => {
                fr.counters.insert(bi, k - 1);
                true
            }
        };
        if take {
            fr.pc = target;
        }
        Ok(())
    }
}
