//! Real-time priority for a driver's I/O threads, following the scan thread's.
//!
//! `ncplc run` opens the I/O before the scan thread takes `SCHED_FIFO`, so the drivers' threads
//! cannot simply inherit it. Instead each driver records the ids of its runtime's threads
//! ([`IoThreads::on_start`], [`IoThreads::on_stop`]) and, at its first latch, looks at the calling
//! thread, which is the scan: when that runs `SCHED_FIFO` or `SCHED_RR` at priority `p`, the I/O
//! threads move to `SCHED_FIFO` at `p - 10` (at least 1) — above every ordinary thread, so build
//! jobs or a busy desktop cannot delay the processing of an answer, and below the scan, so the I/O
//! can never delay a tick. The I/O threads block in `epoll` between requests (they never spin),
//! so they cannot starve the rest of the machine either. Without real time nothing changes.
//!
//! With CPUs given ([`IoThreads::pinned`], io.toml `[affinity] io_cpus`) every runtime thread also
//! pins itself to them as it starts ([`crate::affinity`]); when the kernel refuses, one warning is
//! printed and the threads run unpinned.

use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::{Arc, Mutex};

/// How far below the scan thread the I/O threads run.
pub const BELOW_SCAN: i32 = 10;

/// The threads of one driver's runtime, and whether they follow the scan's priority yet.
#[derive(Debug, Default)]
pub struct IoThreads {
    tids: Arc<Mutex<Vec<libc::pid_t>>>,
    checked: bool,
    priority: Option<i32>,
    cpus: Arc<Vec<usize>>,
    /// [`PIN_NONE`], [`PIN_OK`] or [`PIN_FAILED`].
    pin: Arc<AtomicU8>,
}

const PIN_NONE: u8 = 0;
const PIN_OK: u8 = 1;
const PIN_FAILED: u8 = 2;

fn gettid() -> libc::pid_t {
    // SAFETY: gettid takes no arguments and cannot fail.
    unsafe { libc::gettid() }
}

impl IoThreads {
    /// No threads recorded yet.
    pub fn new() -> IoThreads {
        IoThreads::default()
    }

    /// No threads recorded yet; each will pin itself to `cpus` as it starts (empty = unpinned).
    pub fn pinned(cpus: &[usize]) -> IoThreads {
        IoThreads {
            cpus: Arc::new(cpus.to_vec()),
            ..IoThreads::default()
        }
    }

    /// The runtime's `on_thread_start` hook: pre-faults the new thread's stack
    /// ([`crate::prefault`]), pins it when CPUs were given, and records it.
    pub fn on_start(&self) -> impl Fn() + Send + Sync + 'static {
        let tids = self.tids.clone();
        let cpus = self.cpus.clone();
        let pin = self.pin.clone();
        move || {
            crate::prefault::prefault_stack(crate::prefault::IO_STACK);
            if !cpus.is_empty() {
                match crate::affinity::pin_thread(0, &cpus) {
                    Ok(()) => {
                        let _ = pin.compare_exchange(
                            PIN_NONE,
                            PIN_OK,
                            Ordering::AcqRel,
                            Ordering::Acquire,
                        );
                    }
                    Err(e) => {
                        if pin.swap(PIN_FAILED, Ordering::AcqRel) != PIN_FAILED {
                            eprintln!(
                                "warning: cannot pin the fieldbus I/O threads to CPU(s) {cpus:?} ({e}); running unpinned"
                            );
                        }
                    }
                }
            }
            if let Ok(mut t) = tids.lock() {
                t.push(gettid());
            }
        }
    }

    /// The runtime's `on_thread_stop` hook: forgets the thread (its id may be reused).
    pub fn on_stop(&self) -> impl Fn() + Send + Sync + 'static {
        let tids = self.tids.clone();
        move || {
            let me = gettid();
            if let Ok(mut t) = tids.lock() {
                t.retain(|&x| x != me);
            }
        }
    }

    /// Called on the scan thread at every latch; the first time the runtime's threads are recorded
    /// (and their list is not being changed) it moves them below the scan's real-time priority.
    /// Never blocks.
    pub fn follow_scan(&mut self) {
        if self.checked {
            return;
        }
        // The runtime's worker may not have recorded itself yet: look again at the next latch.
        let Ok(tids) = self.tids.try_lock() else {
            return;
        };
        if tids.is_empty() {
            return;
        }
        self.checked = true;
        // SAFETY: plain queries about the calling thread.
        let policy = unsafe { libc::sched_getscheduler(0) };
        if policy != libc::SCHED_FIFO && policy != libc::SCHED_RR {
            return;
        }
        let mut param = libc::sched_param { sched_priority: 0 };
        // SAFETY: `param` is a valid, writable parameter block.
        if unsafe { libc::sched_getparam(0, &mut param) } != 0 {
            return;
        }
        let io = libc::sched_param {
            sched_priority: (param.sched_priority - BELOW_SCAN).max(1),
        };
        let mut moved = 0;
        for &tid in tids.iter() {
            // SAFETY: `tid` is a live thread of this process (recorded at start, removed at stop).
            if unsafe { libc::sched_setscheduler(tid, libc::SCHED_FIFO, &io) } == 0 {
                moved += 1;
            }
        }
        if moved > 0 {
            self.priority = Some(io.sched_priority);
        }
    }

    /// Whether the I/O threads are pinned: `None` when no CPUs were given or no thread has
    /// started yet, `Some(false)` when the kernel refused.
    pub fn is_pinned(&self) -> Option<bool> {
        match self.pin.load(Ordering::Acquire) {
            PIN_OK => Some(true),
            PIN_FAILED => Some(false),
            _ => None,
        }
    }

    /// The `SCHED_FIFO` priority the I/O threads took, once they did.
    pub fn priority(&self) -> Option<i32> {
        self.priority
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The runtime's worker starts on its own thread: wait (boundedly) until it is recorded.
    fn recorded(threads: &IoThreads) -> Vec<libc::pid_t> {
        for _ in 0..2000 {
            let t = threads.tids.lock().expect("list").clone();
            if !t.is_empty() {
                return t;
            }
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        Vec::new()
    }

    #[test]
    fn a_plain_scan_thread_leaves_the_io_threads_alone() {
        let mut threads = IoThreads::new();
        let rt = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .on_thread_start(threads.on_start())
            .on_thread_stop(threads.on_stop())
            .build()
            .expect("runtime");
        assert_eq!(recorded(&threads).len(), 1);
        // The test thread runs SCHED_OTHER.
        threads.follow_scan();
        assert_eq!(threads.priority(), None);
        assert!(threads.checked, "looked once");
        drop(rt);
        assert!(
            threads.tids.lock().expect("list").is_empty(),
            "stopped threads are forgotten"
        );
    }

    #[test]
    fn io_threads_pin_themselves_as_they_start() {
        let allowed = crate::affinity::thread_cpus(0).expect("affinity");
        let last = *allowed.last().expect("some CPU");
        let threads = IoThreads::pinned(&[last]);
        let _rt = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .on_thread_start(threads.on_start())
            .on_thread_stop(threads.on_stop())
            .build()
            .expect("runtime");
        let tid = recorded(&threads)[0];
        assert_eq!(threads.is_pinned(), Some(true));
        assert_eq!(
            crate::affinity::thread_cpus(tid).expect("affinity"),
            vec![last]
        );
        // A CPU the kernel cannot take: warned once, the thread runs where it may.
        let refused = IoThreads::pinned(&[libc::CPU_SETSIZE as usize]);
        let _rt2 = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .on_thread_start(refused.on_start())
            .on_thread_stop(refused.on_stop())
            .build()
            .expect("runtime");
        let tid = recorded(&refused)[0];
        assert_eq!(refused.is_pinned(), Some(false));
        assert_eq!(
            crate::affinity::thread_cpus(tid).expect("affinity"),
            allowed
        );
        assert_eq!(IoThreads::new().is_pinned(), None);
    }

    #[test]
    fn a_real_time_scan_thread_moves_the_io_threads_below_it() {
        let mut threads = IoThreads::new();
        let _rt = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .on_thread_start(threads.on_start())
            .on_thread_stop(threads.on_stop())
            .build()
            .expect("runtime");
        let tid = recorded(&threads)[0];
        let mut early = IoThreads::new();
        early.follow_scan();
        assert!(!early.checked, "no thread recorded yet: look again later");
        // A scan thread of its own (SCHED_FIFO 30) so that the test thread keeps its policy.
        let scan = std::thread::spawn(move || {
            let p = libc::sched_param { sched_priority: 30 };
            // SAFETY: plain syscall on the calling thread with a valid parameter block.
            if unsafe { libc::sched_setscheduler(0, libc::SCHED_FIFO, &p) } != 0 {
                return None; // not permitted here: nothing to check
            }
            threads.follow_scan();
            Some(threads.priority())
        });
        let Some(got) = scan.join().expect("scan thread") else {
            return;
        };
        assert_eq!(got, Some(20));
        let mut p = libc::sched_param { sched_priority: 0 };
        // SAFETY: queries of a live thread of this process into a valid parameter block.
        let policy = unsafe { libc::sched_getscheduler(tid) };
        // SAFETY: as above.
        unsafe { libc::sched_getparam(tid, &mut p) };
        assert_eq!((policy, p.sched_priority), (libc::SCHED_FIFO, 20));
    }
}
