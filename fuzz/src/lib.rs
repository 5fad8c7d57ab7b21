//! What the fuzz targets share: a clock of the calling thread's CPU time, so that a target's
//! work budget (linear in its input) does not fail when the machine is busy. Wall time did: an
//! input that takes 42 ms took 274 ms while other builds ran, and the campaign stopped on it.

use std::time::Duration;

/// The CPU time the calling thread has used since [`CpuClock::start`].
pub struct CpuClock(Duration);

impl CpuClock {
    /// Starts measuring the calling thread's CPU time.
    pub fn start() -> CpuClock {
        CpuClock(thread_cpu())
    }

    /// The calling thread's CPU time since the start.
    pub fn elapsed(&self) -> Duration {
        thread_cpu().saturating_sub(self.0)
    }
}

fn thread_cpu() -> Duration {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes only the timespec it is given, which lives on this stack.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    if rc != 0 {
        return Duration::ZERO;
    }
    Duration::new(
        u64::try_from(ts.tv_sec).unwrap_or(0),
        u32::try_from(ts.tv_nsec).unwrap_or(0),
    )
}
