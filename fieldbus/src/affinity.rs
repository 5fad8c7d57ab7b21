//! CPU affinity: pinning a thread to a set of CPUs, a deployment knob for the scan and I/O threads.
//!
//! Real controllers pin the scan thread to a core of its own and the fieldbus I/O threads to the
//! core that takes the NIC interrupt, so that a wake-up does not have to cross cores. The I/O map
//! names the drivers' CPUs (`[affinity] io_cpus = [1]`, applied by [`crate::rt::IoThreads`] to every
//! runtime thread as it starts); `ncplc run --scan-cpu N` pins the scan thread. CPU indices are
//! checked against the machine ([`check_cpu`]); when the kernel refuses the affinity (a cgroup or
//! container without those CPUs) the caller warns once and runs unpinned.

/// A CPU index the machine does not have.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("CPU {cpu} does not exist: this machine has {count} CPU(s), numbered 0..{last}", last = count.saturating_sub(1))]
pub struct NoSuchCpu {
    /// The index asked for.
    pub cpu: usize,
    /// How many CPUs the machine has.
    pub count: usize,
}

/// The number of CPUs the machine has (configured, online or not); at least 1.
pub fn cpu_count() -> usize {
    // SAFETY: sysconf takes a constant and has no side effects.
    let n = unsafe { libc::sysconf(libc::_SC_NPROCESSORS_CONF) };
    usize::try_from(n).unwrap_or(1).max(1)
}

/// Checks `cpu` against a machine of `count` CPUs.
pub fn check_cpu_of(cpu: usize, count: usize) -> Result<usize, NoSuchCpu> {
    // The kernel's cpu_set_t cannot name more CPUs than CPU_SETSIZE whatever the count says.
    if cpu < count && cpu < libc::CPU_SETSIZE as usize {
        Ok(cpu)
    } else {
        Err(NoSuchCpu { cpu, count })
    }
}

/// Checks `cpu` against this machine ([`cpu_count`]).
pub fn check_cpu(cpu: usize) -> Result<usize, NoSuchCpu> {
    check_cpu_of(cpu, cpu_count())
}

/// Pins the thread `tid` (0 = the calling thread) to `cpus`; an empty list changes nothing.
/// Fails with the kernel's error (e.g. `EINVAL` for CPUs outside the process's cgroup, `EPERM`).
pub fn pin_thread(tid: libc::pid_t, cpus: &[usize]) -> std::io::Result<()> {
    if cpus.is_empty() {
        return Ok(());
    }
    // SAFETY: cpu_set_t is a plain bit array; all zeroes is the empty set.
    let mut set: libc::cpu_set_t = unsafe { std::mem::zeroed() };
    for &cpu in cpus {
        if cpu >= libc::CPU_SETSIZE as usize {
            return Err(std::io::Error::from_raw_os_error(libc::EINVAL));
        }
        // SAFETY: `cpu` is below CPU_SETSIZE, the size of `set`.
        unsafe { libc::CPU_SET(cpu, &mut set) };
    }
    // SAFETY: `set` is a valid cpu_set_t of the size passed.
    let rc = unsafe { libc::sched_setaffinity(tid, std::mem::size_of::<libc::cpu_set_t>(), &set) };
    if rc == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error())
    }
}

/// The CPUs thread `tid` (0 = the calling thread) may run on, in increasing order.
pub fn thread_cpus(tid: libc::pid_t) -> std::io::Result<Vec<usize>> {
    // SAFETY: as in `pin_thread`.
    let mut set: libc::cpu_set_t = unsafe { std::mem::zeroed() };
    // SAFETY: `set` is a valid, writable cpu_set_t of the size passed.
    let rc =
        unsafe { libc::sched_getaffinity(tid, std::mem::size_of::<libc::cpu_set_t>(), &mut set) };
    if rc != 0 {
        return Err(std::io::Error::last_os_error());
    }
    // SAFETY: reads of a valid set with indices below CPU_SETSIZE.
    Ok((0..libc::CPU_SETSIZE as usize)
        .filter(|&c| unsafe { libc::CPU_ISSET(c, &set) })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cpu_indices_are_checked_against_the_count() {
        assert_eq!(check_cpu_of(0, 2), Ok(0));
        assert_eq!(check_cpu_of(1, 2), Ok(1));
        assert_eq!(check_cpu_of(2, 2), Err(NoSuchCpu { cpu: 2, count: 2 }));
        assert_eq!(
            check_cpu_of(1024, 4096),
            Err(NoSuchCpu {
                cpu: 1024,
                count: 4096
            })
        );
        assert_eq!(
            NoSuchCpu { cpu: 3, count: 2 }.to_string(),
            "CPU 3 does not exist: this machine has 2 CPU(s), numbered 0..1"
        );
        assert!(check_cpu(cpu_count()).is_err());
        assert_eq!(check_cpu(0), Ok(0));
    }

    #[test]
    fn a_thread_pins_itself_to_a_cpu_it_may_use() {
        std::thread::spawn(|| {
            let allowed = thread_cpus(0).expect("affinity");
            let last = *allowed.last().expect("some CPU");
            pin_thread(0, &[last]).expect("pin to an allowed CPU");
            assert_eq!(thread_cpus(0).expect("affinity"), vec![last]);
            assert!(pin_thread(0, &[libc::CPU_SETSIZE as usize]).is_err());
            assert_eq!(pin_thread(0, &[]).ok(), Some(()), "empty list: unchanged");
            assert_eq!(thread_cpus(0).expect("affinity"), vec![last]);
        })
        .join()
        .expect("thread");
    }
}
