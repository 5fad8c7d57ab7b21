//! What the fuzz targets share: a clock of the calling thread's CPU time in user mode, so that a
//! target's work budget (linear in its input) does not fail when the machine is busy. Wall time
//! did: an input that takes 42 ms took 274 ms while other builds ran, and the campaign stopped on
//! it. Kernel time did too: a PGCFIL input of 908 bytes that runs in under 1 ms was charged 147 ms
//! of CPU time while memory was short (page faults reclaiming memory count as the thread's system
//! time); the work a quadratic path does is user time, which is what the budget measures.

use std::time::Duration;

/// The user-mode CPU time the calling thread has used since [`CpuClock::start`].
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

/// The user-mode CPU time of the calling thread (`getrusage(RUSAGE_THREAD)`).
fn thread_cpu() -> Duration {
    // SAFETY: an all-zero `rusage` is a valid value of the plain C struct.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: getrusage writes only the struct it is given, which lives on this stack.
    let rc = unsafe { libc::getrusage(libc::RUSAGE_THREAD, &mut usage) };
    if rc != 0 {
        return Duration::ZERO;
    }
    Duration::new(
        u64::try_from(usage.ru_utime.tv_sec).unwrap_or(0),
        u32::try_from(usage.ru_utime.tv_usec)
            .unwrap_or(0)
            .saturating_mul(1000),
    )
}

/// The work budget of a parser on `len` bytes: 100 ms + 20 µs per byte of CPU time (generous for
/// sanitizer builds; a quadratic path on a 64 KB input blows it by orders of magnitude).
pub fn linear_budget(len: usize) -> Duration {
    Duration::from_micros(100_000 + 20 * len as u64)
}

/// Runs `work` (a pure function of the input) and panics when it takes more than
/// [`linear_budget`]`(len)` of CPU time three times in a row: the fastest of up to three runs
/// counts. A virtual machine's host that deschedules the vCPU charges the stall to the thread that
/// was running (a PGCFIL input of 1,255 bytes that runs in 1 ms was charged 152 ms of user time
/// and stopped the campaign), but a slow path is slow every time.
pub fn within_linear_budget(len: usize, mut work: impl FnMut()) {
    let budget = linear_budget(len);
    let mut fastest = Duration::MAX;
    for _ in 0..3 {
        let started = CpuClock::start();
        work();
        fastest = fastest.min(started.elapsed());
        if fastest <= budget {
            return;
        }
    }
    panic!("{len} bytes took {fastest:?} (the fastest of 3 runs) > {budget:?}");
}
