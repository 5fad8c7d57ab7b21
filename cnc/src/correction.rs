//! The tool-correction request (IOCFIL m_request 10, e.g. `M06=02,14,62`): when the block of a
//! function with it ends, the process re-plans its program with the correction table as it is
//! now (the part run's [`Replanner`]) and takes every following block from the new plan, so that
//! offsets entered since the program was selected take effect from the next block. The request
//! always comes with the calculation block (04, 003:5859), so no following block is queued yet.
//!
//! The new plan must have the same blocks (number, unit, kind and M functions, one for one);
//! otherwise — a macro that branches on an offset — the request is a stopping alarm naming the
//! block rather than a guess. Both plans (with and without block skip) are replaced, so that a
//! restart after RESET keeps the new offsets.

use partprogram::Canon;

use crate::process::Process;

/// Re-plans the program named by the first argument (with block skip when the second is true)
/// with the current correction table; None when the program cannot be re-planned (MDI text).
pub type Replanner = Box<dyn Fn(&str, bool) -> Option<Result<Vec<Canon>, String>> + Send>;

/// The same blocks, one for one (the end points, feeds and offsets may differ).
fn aligned(a: &[Canon], b: &[Canon]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| x.n == y.n && x.unit == y.unit && x.kind == y.kind && x.m == y.m)
}

impl Process {
    /// Sets the re-planner the tool-correction request uses (none: the request changes nothing).
    pub fn set_replanner(&mut self, f: Replanner) {
        self.replanner = Some(f);
    }

    /// The block before `self.next` asked for new corrections: splice the re-planned blocks.
    pub(crate) fn correction_request(&mut self) {
        let Some(f) = self.replanner.as_ref() else {
            return;
        };
        let name = self.program_name.clone();
        let Some(active) = f(&name, self.skip_selected) else {
            return;
        };
        let other = self
            .programs
            .as_ref()
            .and_then(|_| f(&name, !self.skip_selected));
        let block = format!("block {}", self.next);
        let new = match active {
            Ok(b) if aligned(&self.program, &b) => b,
            Ok(_) => {
                let m = format!(
                    "tool-correction request ({block}): the program plans different blocks with \
                     the new corrections"
                );
                self.raise(m, true);
                return;
            }
            Err(e) => {
                self.raise(format!("tool-correction request ({block}): {e}"), true);
                return;
            }
        };
        let at = self.next.min(new.len());
        // The program is shared with the part run that planned it: the merged one is a new vector.
        let mut program = self.program[..at].to_vec();
        program.extend_from_slice(&new[at..]);
        self.program = std::sync::Arc::new(program);
        if let (Some((plain, skipped)), Some(Ok(o))) = (self.programs.as_mut(), other) {
            let (mine, theirs) = if self.skip_selected {
                (skipped, plain)
            } else {
                (plain, skipped)
            };
            *mine = std::sync::Arc::new(new);
            if aligned(theirs, &o) {
                *theirs = std::sync::Arc::new(o);
            }
        }
        self.counters.corrections += 1;
    }
}
