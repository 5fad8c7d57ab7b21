//! Lock-free exchange of images between the real-time scan and the I/O tasks.
//!
//! The scan thread must never wait for the network. Every device task and the scan share images
//! through a [`triple`] buffer: the writer fills its private slot and publishes it with one atomic
//! swap, the reader picks up the newest published slot with one atomic swap, and neither ever waits
//! for the other. Alarms travel from the I/O tasks to the scan through an `rtrb` ring
//! ([`alarm_ring`]); a full ring drops the alarm rather than block.

use std::cell::UnsafeCell;
use std::sync::Arc;
use std::sync::atomic::{AtomicU8, Ordering};

use packets::IoAlarm;

/// Marks the shared slot as holding a value the reader has not seen yet.
const DIRTY: u8 = 0b100;
/// Mask for the slot index inside the shared word.
const INDEX: u8 = 0b011;

struct Shared<T> {
    slots: [UnsafeCell<T>; 3],
    /// Index of the slot that is neither the writer's nor the reader's, plus [`DIRTY`].
    back: AtomicU8,
}

// SAFETY: each slot is accessed by at most one side at a time: the writer owns the slot whose index it
// holds, the reader owns its own, and ownership only changes hands through the atomic swap on `back`
// (AcqRel), which orders the previous owner's accesses before the next owner's.
unsafe impl<T: Send> Sync for Shared<T> {}

/// The writing side of a triple buffer.
pub struct TripleWriter<T> {
    shared: Arc<Shared<T>>,
    idx: u8,
}

/// The reading side of a triple buffer.
pub struct TripleReader<T> {
    shared: Arc<Shared<T>>,
    idx: u8,
}

/// A triple buffer whose three slots start as copies of `init`.
pub fn triple<T: Clone + Send>(init: T) -> (TripleWriter<T>, TripleReader<T>) {
    let shared = Arc::new(Shared {
        slots: [
            UnsafeCell::new(init.clone()),
            UnsafeCell::new(init.clone()),
            UnsafeCell::new(init),
        ],
        back: AtomicU8::new(1),
    });
    (
        TripleWriter {
            shared: shared.clone(),
            idx: 0,
        },
        TripleReader { shared, idx: 2 },
    )
}

impl<T> TripleWriter<T> {
    /// The writer's private slot. After a [`publish`](Self::publish) it holds an older value, so
    /// writers rewrite every field they care about before publishing again.
    pub fn buf(&mut self) -> &mut T {
        // SAFETY: slot `idx` belongs to the writer until the next publish (see `Shared`).
        unsafe { &mut *self.shared.slots[self.idx as usize].get() }
    }

    /// Hands the private slot to the reader as the newest value (wait-free).
    pub fn publish(&mut self) {
        let old = self.shared.back.swap(self.idx | DIRTY, Ordering::AcqRel);
        self.idx = old & INDEX;
    }
}

impl<T> TripleReader<T> {
    /// The newest published value and whether it is new since the previous call (wait-free).
    pub fn read(&mut self) -> (&T, bool) {
        let fresh = self.shared.back.load(Ordering::Acquire) & DIRTY != 0;
        if fresh {
            let old = self.shared.back.swap(self.idx, Ordering::AcqRel);
            self.idx = old & INDEX;
        }
        // SAFETY: slot `idx` belongs to the reader until its next swap (see `Shared`).
        (
            unsafe { &*self.shared.slots[self.idx as usize].get() },
            fresh,
        )
    }
}

/// The packet-A outputs the scan commanded, as handed to an I/O task.
#[derive(Debug, Clone)]
pub(crate) struct OutFrame {
    /// 0 until the scan publishes for the first time; bumped on each change.
    pub seq: u64,
    /// Packet A as the scan wrote it.
    pub data: [u8; 128],
}

/// Alarms a driver keeps for a runtime that does not call `take_alarms`; later ones are dropped.
pub const MAX_PENDING_ALARMS: usize = 256;

/// Producer side of the alarm ring (held by the I/O tasks, behind their own lock if shared).
pub type AlarmTx = rtrb::Producer<IoAlarm>;
/// Consumer side of the alarm ring (held by the driver on the scan thread).
pub type AlarmRx = rtrb::Consumer<IoAlarm>;

/// An alarm ring with room for `capacity` alarms.
pub fn alarm_ring(capacity: usize) -> (AlarmTx, AlarmRx) {
    rtrb::RingBuffer::new(capacity)
}

/// Pops every alarm waiting in `rx`.
pub fn drain_alarms(rx: &mut AlarmRx) -> Vec<IoAlarm> {
    let mut out = Vec::new();
    while let Ok(a) = rx.pop() {
        out.push(a);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reader_sees_only_the_newest_published_value() {
        let (mut w, mut r) = triple(0u32);
        assert_eq!(r.read(), (&0, false));
        *w.buf() = 1;
        w.publish();
        *w.buf() = 2;
        w.publish();
        assert_eq!(r.read(), (&2, true));
        assert_eq!(r.read(), (&2, false));
        *w.buf() = 3;
        assert_eq!(r.read(), (&2, false), "unpublished writes stay invisible");
        w.publish();
        assert_eq!(r.read(), (&3, true));
    }

    #[test]
    fn concurrent_reader_never_sees_a_torn_or_older_value() {
        let (mut w, mut r) = triple([0u64; 16]);
        let writer = std::thread::spawn(move || {
            for i in 1..=20_000u64 {
                *w.buf() = [i; 16];
                w.publish();
            }
        });
        let mut last = 0;
        while last < 20_000 {
            let (v, _) = r.read();
            assert!(v.iter().all(|&x| x == v[0]), "torn read {v:?}");
            assert!(v[0] >= last, "went back from {last} to {}", v[0]);
            last = v[0];
            if writer.is_finished() && r.read().0[0] == 20_000 {
                break;
            }
        }
        writer.join().expect("writer thread");
        assert_eq!(r.read().0[0], 20_000);
    }

    #[test]
    fn alarm_ring_drains_in_order_and_drops_when_full() {
        let (mut tx, mut rx) = alarm_ring(2);
        for i in 0..3 {
            let _ = tx.push(IoAlarm {
                device: format!("d{i}"),
                message: String::new(),
                cleared: false,
            });
        }
        let names: Vec<String> = drain_alarms(&mut rx)
            .into_iter()
            .map(|a| a.device)
            .collect();
        assert_eq!(names, ["d0", "d1"]);
        assert!(drain_alarms(&mut rx).is_empty());
    }
}
