//! Touching a thread's stack before real-time work starts, so that its pages are faulted in (and,
//! under `mlockall(MCL_ONFAULT)`, locked) at start and not during a tick or an I/O exchange.
//!
//! `ncplc run` locks memory with `MCL_ONFAULT`: a page is locked when first touched, which keeps the
//! start fast (issue 12: plain `mlockall` took 0.1–2.4 s) but would let the first deep call of a
//! thread take page faults at run time. The scan thread and every fieldbus I/O thread call
//! [`prefault_stack`] once as they start.

/// Bytes of the scan thread's stack touched before the first tick.
pub const SCAN_STACK: usize = 256 * 1024;

/// Bytes of an I/O thread's stack touched as it starts (tokio's worker stacks are 2 MiB; the
/// Modbus/CANopen exchange paths use a few tens of KiB).
pub const IO_STACK: usize = 128 * 1024;

/// Page size assumed when touching: every 4 KiB (a larger page is touched more than once, harmless).
const STEP: usize = 4096;

/// Touches the next `bytes` of the calling thread's stack, one write per page.
pub fn prefault_stack(bytes: usize) {
    // Recursion in fixed 16 KiB frames keeps the touched depth exact without a variable-length
    // array; each frame writes each of its pages.
    const FRAME: usize = 16 * 1024;
    #[inline(never)]
    fn touch(left: usize) {
        let mut block = [0u8; FRAME];
        for b in block.iter_mut().step_by(STEP) {
            // black_box keeps the writes.
            *std::hint::black_box(b) = 1;
        }
        std::hint::black_box(&block);
        if left > FRAME {
            touch(left - FRAME);
        }
    }
    touch(bytes);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Minor page faults of the calling thread so far.
    fn thread_minor_faults() -> i64 {
        // SAFETY: getrusage writes into a valid, zeroed rusage block.
        let mut u: libc::rusage = unsafe { std::mem::zeroed() };
        // SAFETY: as above; RUSAGE_THREAD is Linux 2.6.26+.
        unsafe { libc::getrusage(libc::RUSAGE_THREAD, &mut u) };
        u.ru_minflt
    }

    /// Minor faults taken by touching [`IO_STACK`] of a fresh thread's stack, after pre-faulting
    /// it first when `before` is set.
    fn faults_of_a_fresh_thread(before: bool) -> i64 {
        std::thread::Builder::new()
            .stack_size(1 << 20)
            .spawn(move || {
                if before {
                    prefault_stack(IO_STACK);
                }
                let start = thread_minor_faults();
                prefault_stack(IO_STACK);
                thread_minor_faults() - start
            })
            .expect("thread")
            .join()
            .expect("join")
    }

    #[test]
    fn a_prefaulted_stack_takes_no_faults_when_used_later() {
        // A fresh stack faults its pages in when first used deeply; once pre-faulted, the same
        // use faults none (or a stray one).
        let fresh = faults_of_a_fresh_thread(false);
        assert!(
            fresh >= 16,
            "touching 128 KiB of a new stack faulted only {fresh} pages"
        );
        let again = faults_of_a_fresh_thread(true);
        assert!(
            again <= 2,
            "a pre-faulted stack faulted {again} pages again"
        );
    }
}
