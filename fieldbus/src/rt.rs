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

use std::sync::{Arc, Mutex};

/// How far below the scan thread the I/O threads run.
pub const BELOW_SCAN: i32 = 10;

/// The threads of one driver's runtime, and whether they follow the scan's priority yet.
#[derive(Debug, Default)]
pub struct IoThreads {
    tids: Arc<Mutex<Vec<libc::pid_t>>>,
    checked: bool,
    priority: Option<i32>,
}

fn gettid() -> libc::pid_t {
    // SAFETY: gettid takes no arguments and cannot fail.
    unsafe { libc::gettid() }
}

impl IoThreads {
    /// No threads recorded yet.
    pub fn new() -> IoThreads {
        IoThreads::default()
    }

    /// The runtime's `on_thread_start` hook: records the new thread.
    pub fn on_start(&self) -> impl Fn() + Send + Sync + 'static {
        let tids = self.tids.clone();
        move || {
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
