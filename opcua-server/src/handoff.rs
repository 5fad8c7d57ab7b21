//! The hand-over between the scan thread and the server: after every tick the scan fills a
//! [`Frame`] (the packets, the PLC variables' bytes, a part run's kernel values, the tick, the
//! wall-clock time) taken from a pool of [`RING`] preallocated frames and pushes it into a
//! wait-free SPSC ring (`rtrb`; the server gives each frame back through a second ring once it
//! has published it), and drains the clients' accepted writes and operator commands with
//! `try_recv`; the server's publisher pops every frame in order, so no tick's change is merged
//! into the next one.
//!
//! **Invariant:** nothing on the scan's side takes a lock the server holds, allocates or waits:
//! a copy of [`packets::PACKETS_LEN`] bytes (and the variables' bytes) into a pooled frame, two
//! ring operations on pointers and `try_recv` loops. The only lock is the part run's kernel (as
//! the web HMI's scan half takes it: for its values and for a command, which goes to the kernel
//! here, at the tick boundary, through [`controller::servers::kernel_command`], the web HMI's
//! path, recorded in the trace). When the pool is empty (the server fell [`RING`] ticks behind)
//! the frame is dropped and counted; the next one the server gets still carries the whole image,
//! so values stay right and only that tick's pulses can be missed.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, mpsc};

use hmi::{Command, Role};
use packets::Signal;

use crate::variables::{Layout, VARS_MAX};
use runtime::scheduler::Scheduler;

/// Frames the ring holds (at a 10 ms tick: 2.56 s of server delay; about 850 KiB).
pub const RING: usize = 256;

/// Processes a kernel has at most (1..5).
pub const MAX_PROCESSES: usize = 5;

/// What the Machine Tools model shows of one process of a part run's kernel.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct KernelValues {
    /// Blocks the process has executed in this run.
    pub blocks: u64,
    /// The spindle's actual speed (rev/min, signed by direction).
    pub spindle_rpm: f64,
}

/// One published state of the packets.
#[derive(Debug, Clone, Copy)]
pub struct Frame {
    /// The tick whose scan left this image (the trace's `t`: ticks run − 1).
    pub tick: u64,
    /// Packets A, K, N and T.
    pub image: [u8; packets::PACKETS_LEN],
    /// The wall-clock time of the copy, µs since the Unix epoch (the values' server timestamp:
    /// a client's receive time minus it is the tick-to-client latency).
    pub wall_us: i64,
    /// A part run's kernel, by process number − 1 (all zero without one).
    pub kernel: [KernelValues; MAX_PROCESSES],
    /// The PLC variables' image bytes ([`crate::variables::Layout::window`]).
    pub vars: [u8; VARS_MAX],
    /// False once an online change replaced the program the variables' layout is for.
    pub vars_valid: bool,
}

/// A client's write the server accepted: applied once, before the next scan.
pub type Write = (Signal, u8);

/// An alarm raised (true) or cleared (false), its text and the tick it happened at.
pub type AlarmNote = (bool, String, u64);

/// A PLC message raised or cleared (docs/plc-messages.md): the `Messages` event's fields.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MessageNote {
    /// Raised (true) or cleared.
    pub raised: bool,
    /// The process whose request bit it is (the event's source: its channel).
    pub process: u8,
    /// The message text.
    pub text: String,
    /// OPC UA severity 1..1000 (MSGPRIO).
    pub severity: u16,
    /// The tick whose scan raised or cleared it.
    pub tick: u64,
}

/// A client's operator command (a method call) for the scan: the kernel's answer goes to `reply`
/// (the tick it was applied at, or why it was refused).
#[derive(Debug)]
pub struct CommandRequest {
    /// The process (channel), 1..5.
    pub process: u8,
    /// START, HOLD or RESET.
    pub command: Command,
    /// The caller's role (recorded in the trace).
    pub role: Role,
    /// Where the answer goes.
    pub reply: tokio::sync::oneshot::Sender<Result<u64, String>>,
}

impl Frame {
    /// A frame of zeros (the pool's initial content).
    fn empty() -> Box<Frame> {
        Box::new(Frame {
            tick: 0,
            image: [0; packets::PACKETS_LEN],
            wall_us: 0,
            kernel: [KernelValues::default(); MAX_PROCESSES],
            vars: [0; VARS_MAX],
            vars_valid: true,
        })
    }
}

/// The scan thread's half.
pub struct ScanSide {
    frames: rtrb::Producer<Box<Frame>>,
    free: rtrb::Consumer<Box<Frame>>,
    dropped: Arc<AtomicU64>,
    writes: mpsc::Receiver<Write>,
    commands: mpsc::Receiver<CommandRequest>,
    /// The part run's kernel the commands go to (None: no part run, every command is refused).
    pub kernel: Option<Arc<Mutex<cnc::Cnc>>>,
    /// Per process: the kernel's status, copied in place every tick (allocated once).
    statuses: Vec<cnc::status::ProcessStatus>,
    /// The PLC variables the frames carry.
    pub vars: Layout,
    /// Alarms for the `Messages` events.
    pub alarms: mpsc::Sender<AlarmNote>,
    /// PLC messages for the `Messages` events.
    pub messages: mpsc::Sender<MessageNote>,
}

/// The server's half: the frames in tick order and where accepted writes go.
pub struct ServerSide {
    /// The frames, oldest first (give each back with [`ServerSide::recycle`]).
    pub frames: rtrb::Consumer<Box<Frame>>,
    free: rtrb::Producer<Box<Frame>>,
    /// Frames the scan dropped because the ring was full.
    pub dropped: Arc<AtomicU64>,
    /// Accepted writes, for the scan.
    pub writes: mpsc::Sender<Write>,
    /// Operator commands, for the scan.
    pub commands: mpsc::Sender<CommandRequest>,
    /// The alarms the scan saw.
    pub alarms: mpsc::Receiver<AlarmNote>,
    /// The PLC messages the scan saw.
    pub messages: mpsc::Receiver<MessageNote>,
}

/// A connected pair of halves.
pub fn pair() -> (ScanSide, ServerSide) {
    let (producer, consumer) = rtrb::RingBuffer::new(RING);
    let (mut free_tx, free_rx) = rtrb::RingBuffer::new(RING);
    for _ in 0..RING {
        // RING slots for RING frames: every push succeeds.
        let _ = free_tx.push(Frame::empty());
    }
    let dropped = Arc::new(AtomicU64::new(0));
    let (tx, rx) = mpsc::channel();
    let (alarm_tx, alarm_rx) = mpsc::channel();
    let (message_tx, message_rx) = mpsc::channel();
    let (cmd_tx, cmd_rx) = mpsc::channel();
    (
        ScanSide {
            frames: producer,
            free: free_rx,
            dropped: Arc::clone(&dropped),
            writes: rx,
            commands: cmd_rx,
            kernel: None,
            statuses: Vec::new(),
            vars: Layout::default(),
            alarms: alarm_tx,
            messages: message_tx,
        },
        ServerSide {
            frames: consumer,
            free: free_tx,
            dropped,
            writes: tx,
            commands: cmd_tx,
            alarms: alarm_rx,
            messages: message_rx,
        },
    )
}

impl ScanSide {
    /// At a tick boundary: queues the accepted writes for the next scan (the scheduler applies
    /// them after the input latch, where the trace records them), gives the operator commands to
    /// the kernel (recorded for the next tick, as the web HMI's), then publishes the image.
    pub fn after_tick(&mut self, sched: &mut Scheduler) {
        while let Ok((signal, value)) = self.writes.try_recv() {
            sched.forces_mut().write_once(signal, value);
        }
        while let Ok(c) = self.commands.try_recv() {
            let answer = match &self.kernel {
                Some(k) => {
                    controller::servers::kernel_command(sched, k, c.process, &c.command, c.role)
                }
                None => {
                    Err("no part run: the kernel takes commands with --program or --mdi".into())
                }
            };
            // The caller may have timed out and gone: nobody is waiting then.
            let _ = c.reply.send(answer);
        }
        let kernel = self.kernel_values();
        let valid = self
            .vars
            .same_program(runtime::compiled::base_program(sched.meta().as_ref()));
        self.publish(
            sched.tick_count().saturating_sub(1),
            sched.image().bytes(),
            kernel,
            valid,
        );
    }

    /// The kernel's blocks and spindle speed per process (zero without a part run).
    fn kernel_values(&mut self) -> [KernelValues; MAX_PROCESSES] {
        let mut out = [KernelValues::default(); MAX_PROCESSES];
        let Some(k) = &self.kernel else {
            return out;
        };
        let c = k.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        for (i, p) in c.processes().iter().enumerate() {
            match self.statuses.get_mut(i) {
                Some(st) => p.status_into(st),
                None => self.statuses.push(p.status()),
            }
            let slot = usize::from(p.number()).wrapping_sub(1);
            if let (Some(v), Some(st)) = (out.get_mut(slot), self.statuses.get(i)) {
                *v = KernelValues {
                    blocks: p.counters().blocks,
                    spindle_rpm: st.spindle_rpm,
                };
            }
        }
        out
    }

    /// Copies `image`'s packets, the variables' bytes and the kernel's values as the state after
    /// `tick` into a frame of the pool and hands it to the server (dropped when the pool is empty).
    pub fn publish(
        &mut self,
        tick: u64,
        image: &[u8],
        kernel: [KernelValues; MAX_PROCESSES],
        vars_valid: bool,
    ) {
        let Ok(mut f) = self.free.pop() else {
            self.dropped.fetch_add(1, Ordering::Relaxed);
            return;
        };
        f.tick = tick;
        f.wall_us = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| i64::try_from(d.as_micros()).unwrap_or(i64::MAX));
        f.kernel = kernel;
        f.vars_valid = vars_valid;
        let n = packets::PACKETS_LEN.min(image.len());
        f.image[..n].copy_from_slice(&image[..n]);
        f.image[n..].fill(0);
        if vars_valid && let Some(src) = image.get(self.vars.window.clone()) {
            f.vars[..src.len()].copy_from_slice(src);
        }
        // RING frames in all: the ring always has a slot for a frame taken from the pool.
        let _ = self.frames.push(f);
    }
}

impl ServerSide {
    /// Gives a published frame back to the scan's pool.
    pub fn recycle(&mut self, frame: Box<Frame>) {
        // RING frames in all: the pool always has a slot for one coming back.
        let _ = self.free.push(frame);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_arrive_in_order_and_an_empty_pool_drops_and_counts() {
        let (mut scan, mut server) = pair();
        let mut image = vec![0u8; packets::PACKETS_LEN];
        for t in 0..(RING as u64 + 3) {
            image[0] = t as u8;
            scan.publish(t, &image, Default::default(), true);
        }
        assert_eq!(server.dropped.load(Ordering::Relaxed), 3);
        let mut got = Vec::new();
        while let Ok(f) = server.frames.pop() {
            got.push((f.tick, f.image[0]));
            server.recycle(f);
        }
        assert_eq!(got.len(), RING);
        assert_eq!(got[0], (0, 0));
        assert_eq!(got[RING - 1], (RING as u64 - 1, (RING - 1) as u8));
        // The frames came back: the next tick goes through again.
        image[0] = 7;
        scan.publish(99, &image, Default::default(), true);
        let f = server.frames.pop().ok();
        assert_eq!(f.map(|f| (f.tick, f.image[0])), Some((99, 7)));
        assert_eq!(server.dropped.load(Ordering::Relaxed), 3);
    }
}
