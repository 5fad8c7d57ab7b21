//! A G33 thread waits at its start for the spindle's index pulse ([`motion`]'s thread lock): with
//! the spindle stopped (M05, no S, its contactors off, override 0 %) or a process without a
//! spindle it would wait for ever, so the kernel stops the process with an alarm naming the block;
//! so it does when the spindle's actual speed would make the thread too fast for the axes.

use crate::process::Process;

impl Process {
    /// Raises a stopping alarm when the interpolator waits for the spindle's index while the
    /// spindle neither turns nor is commanded to.
    pub(crate) fn watch_thread_wait(&mut self) {
        if let Some(fault) = self.interp.take_fault() {
            let block = self.block_label();
            self.raise(format!("{fault} ({block})"), true);
            return;
        }
        if !self.interp.waiting_for_spindle() {
            return;
        }
        let turning = self
            .spindle
            .as_ref()
            .is_some_and(|s| s.target() != 0.0 || s.actual() != 0.0);
        if !turning {
            let block = self.block_label();
            self.raise(
                format!("G33 thread waits for the spindle's index pulse with the spindle stopped ({block})"),
                true,
            );
        }
    }
}
