//! The hand-over between the scan thread and the server: the scan copies the packets into a
//! preallocated [`Frame`] of a triple buffer after every tick and drains the clients' accepted
//! writes with `try_recv`; the server's publisher reads the newest frame on its own task.
//!
//! **Invariant:** nothing on the scan's side takes a lock the server holds, allocates in steady
//! state or waits: a copy of [`packets::PACKETS_LEN`] bytes, two integers and a `try_recv` loop.

use std::sync::mpsc;

use fieldbus::exchange::{TripleReader, TripleWriter, triple};
use packets::Signal;
use runtime::scheduler::Scheduler;

/// One published state of the packets.
#[derive(Debug, Clone)]
pub struct Frame {
    /// Bumped on every publish (0: nothing published yet).
    pub seq: u64,
    /// The tick whose scan left this image (the trace's `t`: ticks run − 1).
    pub tick: u64,
    /// Packets A, K, N and T.
    pub image: Vec<u8>,
    /// The wall-clock time of the copy, µs since the Unix epoch (the values' server timestamp:
    /// a client's receive time minus it is the tick-to-client latency).
    pub wall_us: i64,
}

impl Frame {
    fn empty() -> Frame {
        Frame {
            seq: 0,
            tick: 0,
            image: vec![0; packets::PACKETS_LEN],
            wall_us: 0,
        }
    }
}

/// A client's write the server accepted: applied once, before the next scan.
pub type Write = (Signal, u8);

/// An alarm raised (true) or cleared (false), its text and the tick it happened at.
pub type AlarmNote = (bool, String, u64);

/// The scan thread's half.
pub struct ScanSide {
    frames: TripleWriter<Frame>,
    seq: u64,
    writes: mpsc::Receiver<Write>,
    /// Alarms for the `Messages` events.
    pub alarms: mpsc::Sender<AlarmNote>,
}

/// The server's half: the newest frame and where accepted writes go.
pub struct ServerSide {
    /// The newest frame.
    pub frames: TripleReader<Frame>,
    /// Accepted writes, for the scan.
    pub writes: mpsc::Sender<Write>,
    /// The alarms the scan saw.
    pub alarms: mpsc::Receiver<AlarmNote>,
}

/// A connected pair of halves.
pub fn pair() -> (ScanSide, ServerSide) {
    let (frames, reader) = triple(Frame::empty());
    let (tx, rx) = mpsc::channel();
    let (alarm_tx, alarm_rx) = mpsc::channel();
    (
        ScanSide {
            frames,
            seq: 0,
            writes: rx,
            alarms: alarm_tx,
        },
        ServerSide {
            frames: reader,
            writes: tx,
            alarms: alarm_rx,
        },
    )
}

impl ScanSide {
    /// At a tick boundary: queues the accepted writes for the next scan (the scheduler applies
    /// them after the input latch, where the trace records them), then publishes the image.
    pub fn after_tick(&mut self, sched: &mut Scheduler) {
        while let Ok((signal, value)) = self.writes.try_recv() {
            sched.forces_mut().write_once(signal, value);
        }
        self.publish(sched.tick_count().saturating_sub(1), sched.image().bytes());
    }

    /// Copies `image`'s packets as the state after `tick` and hands the frame over.
    pub fn publish(&mut self, tick: u64, image: &[u8]) {
        self.seq += 1;
        let f = self.frames.buf();
        f.seq = self.seq;
        f.tick = tick;
        let n = packets::PACKETS_LEN.min(image.len());
        f.image[..n].copy_from_slice(&image[..n]);
        f.wall_us = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| i64::try_from(d.as_micros()).unwrap_or(i64::MAX));
        self.frames.publish();
    }
}
