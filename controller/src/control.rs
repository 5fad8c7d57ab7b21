//! The running [`Controller`]: the one loop ([`Controller::run`], one tick at a time through
//! [`Controller::step`]) and the end of a run ([`Controller::finish`]).
//!
//! ## The order of one tick
//!
//! This is the one place the whole order is written down (ARCHITECTURE.md points here):
//!
//! 1. **Scheduler** ([`Scheduler::step`], `runtime/src/scheduler.rs`): wait for the tick's start on
//!    the clock; take a pending online-change swap; latch the inputs (`PacketIo::latch_inputs` —
//!    with a part run the kernel steps here: `sim/src/kernel.rs`); apply HMI writes and forces
//!    (recorded as inputs); run FAST and the next SLOW slice; forces again (recorded as `forced`);
//!    publish the outputs; record the tick (and the axis positions); retain snapshot on change;
//!    overrun count and safe-state trip.
//! 2. **Operator** of a part run ([`crate::part_run::PartRun::each_tick`]): homing, MDI, program
//!    selection, end and alarm watch; may end the run (`--until-end`).
//! 3. **Events** of the tick (alarms, cleared alarms, swaps) to the web HMI, the other servers and
//!    the [`Observer`]; then the **online-change notes** likewise; then the **PLC messages**
//!    (`crate::plc_messages`: raised and cleared from the scan's request bits, to the servers and
//!    the observer; the acknowledge bits set at the last boundary written back to 0).
//! 4. **Observer** ([`Observer::after_tick`]): the CLI's status line and its stop flag.
//! 5. **Servers**: the web HMI's `service` (requests applied at this boundary, frame published;
//!    an `ack` acknowledges the PLC messages too: their acknowledge bits are written once for the
//!    next scan), then every other [`crate::servers::Server`].

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::mpsc;
use std::time::Instant;

use runtime::online::{Note, OnlineChange};
use runtime::program::ProgramMeta;
use runtime::scheduler::{Event, Scheduler};
use sim::HandshakeCounts;

use crate::hmi_link::HmiLink;
use crate::part_run::PartRun;
use crate::plc_messages::{MessageEvent, Messages};
use crate::servers::Server;

/// What the caller of [`Controller::run`] sees of each tick (the CLI prints it).
pub trait Observer {
    /// An event of the tick just run.
    fn event(&mut self, _event: &Event) {}
    /// An online-change note.
    fn note(&mut self, _note: &Note) {}
    /// A PLC message raised or cleared by the tick just run.
    fn message(&mut self, _message: &MessageEvent) {}
    /// After the tick's events and notes; `false` stops the run.
    fn after_tick(&mut self, _sched: &Scheduler) -> bool {
        true
    }
}

/// An observer that sees nothing and never stops a run (benches, tests).
pub struct Quiet;

impl Observer for Quiet {}

/// Everything the builder assembled.
pub(crate) struct Parts {
    pub sched: Scheduler,
    pub tick_ms: u32,
    pub ticks: Option<u64>,
    pub io_name: &'static str,
    pub meta: Arc<dyn ProgramMeta>,
    pub part: Option<PartRun>,
    pub until_end: bool,
    pub handshakes: Option<HandshakeCounts>,
    pub hmi: Option<HmiLink>,
    /// The PLC messages (None: no process has any).
    pub messages: Option<Messages>,
    pub servers: Vec<Box<dyn Server>>,
    pub notes: mpsc::Receiver<Note>,
    pub retain: Option<(std::thread::JoinHandle<()>, PathBuf)>,
    /// Kept alive for the run: dropping it stops online change.
    pub _watch: Option<OnlineChange>,
    pub realtime: bool,
    pub scan_cpu: Option<usize>,
}

/// A controller ready to run; made by [`crate::Builder::build`].
pub struct Controller {
    p: Parts,
}

/// How a run ended: what the CLI prints and turns into an exit code.
pub struct Ending {
    /// Ticks run.
    pub ticks: u64,
    /// The logic tick (ms).
    pub tick_ms: u32,
    /// The I/O's name (`sim`, `modbus`, `canopen`).
    pub io: &'static str,
    /// The engine's name.
    pub engine: String,
    /// The scan-time and wake-latency summary.
    pub stats: String,
    /// When the first tick started.
    pub first_tick_at: Option<Instant>,
    /// The simulated CNC's handshake summary (scripted sim only).
    pub handshakes: Option<String>,
    /// The part run's summary.
    pub part_summary: Option<String>,
    /// Whether the retained macro variables were saved.
    pub vars_saved: Result<(), String>,
    /// `--until-end`: 0 ended, 1 stopped by an alarm or before the end, 2 trajectory not written.
    pub until_end: Option<u8>,
    /// The scan tripped its safe state.
    pub tripped: bool,
}

impl Controller {
    pub(crate) fn new(parts: Parts) -> Controller {
        Controller { p: parts }
    }

    /// The scheduler (for benches and tests that look at the image).
    pub fn scheduler(&self) -> &Scheduler {
        &self.p.sched
    }

    /// Where the web HMI listens, if it runs.
    pub fn hmi_addr(&self) -> Option<std::net::SocketAddr> {
        self.p.hmi.as_ref().map(|h| h.running.addr)
    }

    /// Publishes the web HMI's frame now ([`Controller::step`] publishes at the HMI's own rate;
    /// benches publish at a rate of theirs). False without an HMI.
    pub fn publish_hmi(&mut self) -> bool {
        match &mut self.p.hmi {
            Some(h) => {
                h.publish(&self.p.sched);
                true
            }
            None => false,
        }
    }

    /// The part run, if any.
    pub fn part(&self) -> Option<&PartRun> {
        self.p.part.as_ref()
    }

    /// Re-anchors the clock at the next tick (after a pause between runs of [`Controller::step`]).
    pub fn resync(&mut self) {
        self.p.sched.resync();
    }

    /// Pins the scan thread and takes real-time priority (real time only), warning when it cannot.
    /// Threads started before (watcher, compiler, retain writer) keep normal priority.
    /// [`Controller::run`] calls it; a caller of [`Controller::step`] calls it once first.
    pub fn enter_realtime(&self) {
        if let Some(cpu) = self.p.scan_cpu
            && let Err(e) = fieldbus::affinity::pin_thread(0, &[cpu])
        {
            eprintln!("warning: cannot pin the scan thread to CPU {cpu} ({e}); running unpinned");
        }
        if self.p.realtime
            && let Some(w) = runtime::clock::enable_realtime(80).warning()
        {
            eprintln!("warning: {w}");
        }
    }

    /// Runs until the tick limit, the end of a `--until-end` part, or `observer` says stop.
    pub fn run(&mut self, observer: &mut dyn Observer) {
        self.enter_realtime();
        let mut left = self.p.ticks;
        while left != Some(0) {
            if let Some(l) = &mut left {
                *l -= 1;
            }
            if !self.step(observer) {
                break;
            }
        }
    }

    /// Runs one tick in the order the module documentation gives; `false`: the run should stop.
    pub fn step(&mut self, observer: &mut dyn Observer) -> bool {
        let p = &mut self.p;
        p.sched.step();
        let s = &mut p.sched;
        if let Some(part) = p.part.as_mut()
            && !part.each_tick(s.tick_count(), p.until_end)
        {
            return false;
        }
        let tick = s.tick_count();
        for ev in s.take_events() {
            if let Some(h) = &mut p.hmi {
                h.on_event(&ev, tick);
            }
            for server in &mut p.servers {
                server.on_event(&ev, tick);
            }
            observer.event(&ev);
        }
        for note in p.notes.try_iter() {
            if let Some(h) = &mut p.hmi {
                h.on_note(&note);
            }
            for server in &mut p.servers {
                server.on_note(&note);
            }
            observer.note(&note);
        }
        if let Some(m) = &mut p.messages {
            // The scan just run is tick `tick - 1`: the trace record holding the bits' edges.
            let mut happened = Vec::new();
            m.scan(s.image().bytes(), tick - 1, &mut happened);
            for ev in &happened {
                for server in &mut p.servers {
                    server.on_message(ev);
                }
                observer.message(ev);
            }
            m.end_pulse(s.forces_mut());
        }
        let go = observer.after_tick(s);
        if let Some(h) = &mut p.hmi {
            if let Some(m) = &mut p.messages
                && m.take_changed()
            {
                h.set_messages(m.entries());
            }
            h.service(s);
            let acks = h.take_message_acks();
            if let Some(m) = &mut p.messages {
                for process in acks {
                    m.acknowledge(process, s.forces_mut());
                }
                if m.take_changed() {
                    h.set_messages(m.entries());
                }
            }
        }
        for server in &mut p.servers {
            server.after_tick(s);
        }
        go
    }

    /// Ends the run: saves the part's macro variables, flushes the trace, puts the I/O in its safe
    /// state, stops the retain writer and saves the final retained data.
    pub fn finish(mut self) -> Result<Ending, String> {
        let p = &mut self.p;
        // The retained macro variables the run wrote, whatever ended it (never by a replay).
        let vars_saved = p.part.as_ref().map_or(Ok(()), |r| r.save_macro_vars());
        p.sched.finish().map_err(|e| format!("trace: {e}"))?;
        let image = p.sched.image().bytes().to_vec();
        if let Some((writer, path)) = p.retain.take() {
            p.sched.detach_retain();
            let _ = writer.join();
            crate::retained::save_final(&path, p.meta.as_ref(), &image);
        }
        let until_end = match p.part.as_mut() {
            Some(r) if p.until_end => Some(r.exit_code()),
            _ => None,
        };
        Ok(Ending {
            ticks: p.sched.tick_count(),
            tick_ms: p.tick_ms,
            io: p.io_name,
            engine: p.sched.engine_name().to_string(),
            stats: p.sched.stats.summary(),
            first_tick_at: p.sched.first_tick_at(),
            handshakes: p.handshakes.as_ref().map(|h| h.summary()),
            part_summary: p.part.as_ref().map(|r| r.summary(p.tick_ms)),
            vars_saved,
            until_end,
            tripped: p.sched.tripped(),
        })
    }
}
