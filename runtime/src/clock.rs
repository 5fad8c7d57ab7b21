//! Two clocks behind one interface: real time (absolute deadlines on `CLOCK_MONOTONIC`) and
//! virtual time (unthrottled: waiting jumps straight to the deadline, for replay and tests).
//!
//! [`enable_realtime`] asks for `SCHED_FIFO` and `mlockall`; when that is not permitted the loop
//! runs as a plain thread and the caller prints one warning.

/// A source of time for the scheduler, in nanoseconds since an arbitrary start.
pub trait Clock: Send {
    /// The current time.
    fn now_ns(&mut self) -> u64;
    /// Waits until `deadline_ns` (returns at once if it has passed) and returns the time on waking.
    fn sleep_until(&mut self, deadline_ns: u64) -> u64;
    /// True for virtual time (no overruns are possible and latency means nothing).
    fn is_virtual(&self) -> bool;
}

/// Real time on `CLOCK_MONOTONIC`.
#[derive(Debug)]
pub struct RealClock {
    origin: libc::timespec,
    spin_ns: u64,
}

fn monotonic() -> libc::timespec {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; CLOCK_MONOTONIC always exists on Linux.
    unsafe { libc::clock_gettime(libc::CLOCK_MONOTONIC, &mut ts) };
    ts
}

fn ts_ns(ts: &libc::timespec) -> i128 {
    i128::from(ts.tv_sec) * 1_000_000_000 + i128::from(ts.tv_nsec)
}

impl RealClock {
    /// A clock whose zero is now.
    pub fn new() -> RealClock {
        RealClock {
            origin: monotonic(),
            spin_ns: 0,
        }
    }

    /// A clock that sleeps until `spin_ns` before each deadline and busy-waits the rest (lower
    /// wake latency for one core's worth of spinning).
    pub fn with_spin(spin_ns: u64) -> RealClock {
        RealClock {
            origin: monotonic(),
            spin_ns,
        }
    }
}

impl Default for RealClock {
    fn default() -> Self {
        RealClock::new()
    }
}

impl Clock for RealClock {
    fn now_ns(&mut self) -> u64 {
        u64::try_from(ts_ns(&monotonic()) - ts_ns(&self.origin)).unwrap_or(0)
    }

    fn sleep_until(&mut self, deadline_ns: u64) -> u64 {
        if self.spin_ns > 0 {
            self.sleep_abs(deadline_ns.saturating_sub(self.spin_ns));
            loop {
                let now = self.now_ns();
                if now >= deadline_ns {
                    return now;
                }
                std::hint::spin_loop();
            }
        }
        self.sleep_abs(deadline_ns);
        self.now_ns()
    }

    fn is_virtual(&self) -> bool {
        false
    }
}

impl RealClock {
    fn sleep_abs(&mut self, deadline_ns: u64) {
        let abs = ts_ns(&self.origin) + i128::from(deadline_ns);
        let ts = libc::timespec {
            tv_sec: (abs / 1_000_000_000) as libc::time_t,
            tv_nsec: (abs % 1_000_000_000) as libc::c_long,
        };
        loop {
            // SAFETY: `ts` is a valid timespec; a null remainder is allowed with TIMER_ABSTIME.
            let rc = unsafe {
                libc::clock_nanosleep(
                    libc::CLOCK_MONOTONIC,
                    libc::TIMER_ABSTIME,
                    &ts,
                    std::ptr::null_mut(),
                )
            };
            if rc != libc::EINTR {
                break;
            }
        }
    }
}

/// Virtual time: sleeping sets the time to the deadline.
#[derive(Debug, Default)]
pub struct VirtualClock {
    now: u64,
}

impl VirtualClock {
    /// A virtual clock at zero.
    pub fn new() -> VirtualClock {
        VirtualClock { now: 0 }
    }
}

impl Clock for VirtualClock {
    fn now_ns(&mut self) -> u64 {
        self.now
    }

    fn sleep_until(&mut self, deadline_ns: u64) -> u64 {
        self.now = self.now.max(deadline_ns);
        self.now
    }

    fn is_virtual(&self) -> bool {
        true
    }
}

/// What [`enable_realtime`] achieved.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RealtimeStatus {
    /// `SCHED_FIFO` is active for the calling thread.
    pub fifo: bool,
    /// Memory is locked.
    pub locked: bool,
}

impl RealtimeStatus {
    /// The single warning to print when something was not permitted, or `None`.
    pub fn warning(&self) -> Option<String> {
        match (self.fifo, self.locked) {
            (true, true) => None,
            (false, false) => Some("real-time scheduling (SCHED_FIFO) and mlockall not permitted; running as a plain thread".into()),
            (false, true) => Some("real-time scheduling (SCHED_FIFO) not permitted; running as a plain thread".into()),
            (true, false) => Some("mlockall not permitted; page faults may delay ticks".into()),
        }
    }
}

/// Asks for `SCHED_FIFO` priority `priority` for the calling thread, locks all memory, and sets the
/// thread's timer slack to 1 ns so that deadlines are not rounded up.
pub fn enable_realtime(priority: i32) -> RealtimeStatus {
    let param = libc::sched_param {
        sched_priority: priority,
    };
    // SAFETY: plain syscalls on the calling thread with a valid parameter block.
    let fifo =
        unsafe { libc::pthread_setschedparam(libc::pthread_self(), libc::SCHED_FIFO, &param) } == 0;
    let locked = lock_memory();
    fieldbus::prefault::prefault_stack(fieldbus::prefault::SCAN_STACK);
    // The kernel may delay a timer wake-up by the thread's timer slack (50 µs by default), which is
    // most of the scan's median wake latency; 1 ns asks for the deadline itself. Best effort: a
    // kernel that refuses keeps the default, which only costs latency.
    // SAFETY: PR_SET_TIMERSLACK takes one integer argument and touches only the calling thread.
    let _ = unsafe { libc::prctl(libc::PR_SET_TIMERSLACK, 1 as libc::c_ulong) };
    RealtimeStatus { fifo, locked }
}

/// `MCL_ONFAULT` (Linux 4.4+; the `libc` crate defines it only for some targets).
const MCL_ONFAULT: libc::c_int = 4;

/// Locks the process's memory. With `MCL_ONFAULT` a page is locked when it is first touched, not
/// faulted in up front: plain `MCL_CURRENT | MCL_FUTURE` faulted in every mapping (the JIT's,
/// the allocator's reservations, the recording ring) and took 1.3 s before the first tick on the
/// 2-core development machine (strace, debug build, 2026-11-25); with `MCL_ONFAULT` it is a few
/// µs. Falls back to plain locking on kernels without it.
fn lock_memory() -> bool {
    // SAFETY: mlockall takes flags only.
    let onfault = unsafe { libc::mlockall(libc::MCL_CURRENT | libc::MCL_FUTURE | MCL_ONFAULT) };
    // SAFETY: as above.
    onfault == 0 || unsafe { libc::mlockall(libc::MCL_CURRENT | libc::MCL_FUTURE) } == 0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn virtual_time_jumps_to_deadlines_and_never_goes_back() {
        let mut c = VirtualClock::new();
        assert_eq!(c.sleep_until(1_000_000), 1_000_000);
        assert_eq!(c.sleep_until(500), 1_000_000);
        assert_eq!(c.now_ns(), 1_000_000);
    }

    #[test]
    fn real_time_waits_at_least_until_the_deadline() {
        let mut c = RealClock::new();
        let start = c.now_ns();
        let woke = c.sleep_until(start + 2_000_000);
        assert!(woke >= start + 2_000_000, "{woke} < {}", start + 2_000_000);
        let mut c = RealClock::with_spin(500_000);
        let start = c.now_ns();
        let woke = c.sleep_until(start + 1_000_000);
        assert!(woke >= start + 1_000_000, "{woke} < {}", start + 1_000_000);
    }
}
