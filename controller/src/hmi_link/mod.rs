//! The runtime's side of the web HMI (`ncplc run --hmi`): starts the `hmi` server, answers its
//! requests at tick boundaries (writes and forces go into the scheduler's [`runtime::force::Forces`],
//! commands to the CNC's scan half) and publishes at most every 25 ms (≥ 20 Hz). Publishing is a
//! plain copy of the image and a few numbers into a preallocated [`Frame`] of a triple buffer
//! (no allocation, JSON or names on the scan thread); the render thread ([`render`]) builds the
//! [`hmi::Snapshot`] from the newest frame and puts it into the server's latest-value channel, so
//! the scan never waits for a browser. The PLC messages' list comes from the controller
//! ([`crate::plc_messages`]) when it changes, and the processes an `ack` acknowledged go back to
//! it ([`HmiLink::take_message_acks`]).

pub mod alarms;
pub mod catalog;
pub mod flow_switch;
pub mod forward;
pub mod frame;
pub mod image_cnc;
pub mod kernel_cnc;
pub mod kernel_view;
pub mod modal;
pub mod render;

use std::sync::{Arc, mpsc};
use std::time::{Duration, Instant};

use fieldbus::exchange::{TripleWriter, triple};
use hmi::{Command, MachineStatus, Request, ServerConfig, Snapshot, Toolpath};
use tokio::sync::watch;

use self::alarms::AlarmList;
use self::flow_switch::FlowSwitch;
use self::forward::{Forwarded, MdiPlanner, PlannedMdi};
use self::frame::{Frame, MAX_PROCESSES};
use self::render::{RenderThread, Renderer};
use runtime::online::Note;
use runtime::scheduler::{Event, Scheduler};

/// How often a snapshot is published (40 Hz).
pub const PUBLISH_EVERY: Duration = Duration::from_millis(25);

/// The CNC behind the Machine page, before it is split between the two threads.
pub trait Cnc: Send {
    /// The scan thread's half and the render thread's half.
    fn split(self: Box<Self>) -> (Box<dyn CncScan>, Box<dyn CncView>);
    /// What compiles MDI lines beside the scan (None: nothing to compile, or no kernel).
    fn mdi_planner(&self) -> Option<MdiPlanner> {
        None
    }
}

/// The scan thread's half of the CNC: operator commands and the plain copy into a frame.
pub trait CncScan: Send {
    /// Carries out an operator command for `process` at a tick boundary, or says why not
    /// ([`Command::Ack`] is the HMI's own and never comes here).
    fn command(&mut self, process: u8, command: &Command) -> Result<(), String>;
    /// [`CncScan::command`] with the blocks an MDI command's line was planned to off the scan
    /// ([`forward`]); without them, or without a kernel, the same as [`CncScan::command`].
    fn command_planned(
        &mut self,
        process: u8,
        command: &Command,
        planned: Option<PlannedMdi>,
    ) -> Result<(), String> {
        let _ = planned;
        self.command(process, command)
    }
    /// Copies what the render half needs into `out` (in place: no allocation in steady state).
    fn capture(&mut self, _out: &mut Frame) {}
    /// True for a machine-wide alarm text that a process's own alarm list already shows (the
    /// kernel's alarms also reach the runtime as I/O alarms of device `cnc`).
    fn owns_alarm(&self, _text: &str) -> bool {
        false
    }
}

/// The render thread's half of the CNC: the Machine page's status from a frame.
pub trait CncView: Send {
    /// The per-process state the frame shows.
    fn status(&mut self, frame: &Frame) -> MachineStatus;
    /// The tool path of every process that has one.
    fn toolpaths(&self) -> Vec<Toolpath> {
        Vec::new()
    }
}

/// A running HMI and what the scan keeps for it.
pub struct HmiLink {
    /// The server.
    pub running: hmi::Running,
    frames: TripleWriter<Frame>,
    seq: u64,
    requests: mpsc::Receiver<Forwarded>,
    cnc: Box<dyn CncScan>,
    last_publish: Option<Instant>,
    alarms: AlarmList,
    acks: [u64; MAX_PROCESSES],
    /// The PLC messages as last listed, and the processes acknowledged since the last take.
    messages: (Vec<hmi::MessageEntry>, Vec<u8>),
    online: String,
    flow: Option<FlowSwitch>,
    _render: RenderThread,
}

impl HmiLink {
    /// Starts the server for `catalog`, with `cnc` behind the Machine page and `flow` switching
    /// power flow at run time (None: `POST /api/flow` is refused).
    pub fn start(
        config: ServerConfig,
        catalog: hmi::Catalog,
        cnc: Box<dyn Cnc>,
        tick_ms: u32,
        flow: Option<FlowSwitch>,
    ) -> Result<HmiLink, hmi::StartError> {
        let (snap_tx, snap_rx) = watch::channel(Arc::new(Snapshot::default()));
        let (req_tx, req_rx) = mpsc::channel();
        let demand = Arc::new(hmi::Demand::default());
        let running = hmi::start(config, catalog, snap_rx, req_tx, Arc::clone(&demand))?;
        let (fwd_tx, fwd_rx) = mpsc::channel();
        forward::start(req_rx, fwd_tx, cnc.mdi_planner()).map_err(hmi::StartError::Runtime)?;
        let (scan, view) = cnc.split();
        let (frames, reader) = triple(Frame::with_image(packets::PACKETS_LEN));
        let render = RenderThread::start(reader, Renderer::new(view, tick_ms), snap_tx, demand)
            .map_err(hmi::StartError::Runtime)?;
        Ok(HmiLink {
            running,
            frames,
            seq: 0,
            requests: fwd_rx,
            cnc: scan,
            last_publish: None,
            alarms: AlarmList::default(),
            acks: [0; MAX_PROCESSES],
            messages: (Vec::new(), Vec::new()),
            online: "running".into(),
            flow,
            _render: render,
        })
    }

    /// Keeps the machine-wide alarm list and the online-change status up to date (`tick`: the
    /// tick the event happened at).
    pub fn on_event(&mut self, ev: &Event, tick: u64) {
        match ev {
            Event::Alarm(a) if self.cnc.owns_alarm(a) => {}
            Event::Alarm(a) => self.alarms.raise(a, tick),
            Event::Cleared(a) => self.alarms.clear(a),
            Event::Swapped { tick, .. } => self.online = format!("running since tick {tick}"),
        }
    }

    /// Keeps the online-change status up to date.
    pub fn on_note(&mut self, note: &Note) {
        self.online = match note {
            Note::Compiled { .. } => "compiled; swapping at the next tick".into(),
            Note::Rejected { diagnostics } => format!("edit refused:\n{diagnostics}"),
            Note::Error(e) => format!("online change: {e}"),
        };
    }

    /// At a tick boundary: applies the pending requests, then publishes when due.
    pub fn service(&mut self, sched: &mut Scheduler) {
        let applied_at = sched.tick_count();
        let pending: Vec<Forwarded> = self.requests.try_iter().collect();
        for Forwarded { env, mdi } in pending {
            let forces = sched.forces_mut();
            let reply = match &env.request {
                Request::Write(s, v) => {
                    forces.write_once(*s, *v);
                    Ok(applied_at)
                }
                Request::Force(s, v) => {
                    forces.force(*s, *v);
                    Ok(applied_at)
                }
                Request::Unforce(s) => {
                    if forces.unforce(s) {
                        Ok(applied_at)
                    } else {
                        Err(format!("{s} is not forced"))
                    }
                }
                Request::UnforceAll => {
                    forces.unforce_all();
                    Ok(applied_at)
                }
                Request::Flow(on) => match &mut self.flow {
                    Some(f) => {
                        f.set(*on);
                        Ok(applied_at)
                    }
                    None => Err("power flow cannot be switched in this run".to_string()),
                },
                Request::Command {
                    process,
                    command: Command::Ack,
                } => {
                    self.acknowledge(*process);
                    Ok(applied_at)
                }
                Request::Command { process, command } => {
                    let r = self.cnc.command_planned(*process, command, mdi);
                    if r.is_ok() {
                        sched.record_command(trace::OperatorCommand {
                            process: *process,
                            command: command.clone(),
                            role: Some(env.role),
                        });
                    }
                    r.map(|()| applied_at)
                }
            };
            let _ = env.reply.send(reply);
        }
        let due = self
            .last_publish
            .is_none_or(|t| t.elapsed() >= PUBLISH_EVERY);
        if due {
            self.last_publish = Some(Instant::now());
            self.publish(sched);
        }
        // After the publish: a frame shows the flow only once a scan has filled it.
        if let Some(f) = &mut self.flow {
            f.update(sched);
        }
    }

    /// Acknowledges the alarms of `process` (0: every process and the machine-wide ones); see
    /// [`alarms`] for what that means. The process lists live on the render thread: the frame
    /// carries the count of acknowledges per process.
    fn acknowledge(&mut self, process: u8) {
        if process == 0 {
            self.alarms.acknowledge();
        }
        self.acks[usize::from(process).min(MAX_PROCESSES - 1)] += 1;
        self.messages.1.push(process);
    }

    /// The processes whose acknowledge the HMI applied since the last call (0: every process),
    /// for the PLC messages.
    pub fn take_message_acks(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.messages.1)
    }

    /// The PLC messages' list changed: the next frame shows `entries`.
    pub fn set_messages(&mut self, entries: &[hmi::MessageEntry]) {
        copy_into(&mut self.messages.0, entries);
    }

    /// Publishes the current state now: copies it into the scan's frame and hands the frame to
    /// the render thread.
    pub fn publish(&mut self, sched: &Scheduler) {
        self.seq += 1;
        let f = self.frames.buf();
        f.seq = self.seq;
        f.tick = sched.tick_count();
        let engine = sched.engine_name();
        if f.engine != engine {
            f.engine.clear();
            f.engine.push_str(engine);
        }
        f.scan = (
            sched.stats.last_scan_ns,
            sched.stats.scan.max(),
            sched.stats.overruns,
        );
        f.image.clear();
        f.image
            .extend_from_slice(&sched.image().bytes()[..packets::PACKETS_LEN]);
        f.forced.clear();
        f.forced.extend_from_slice(sched.forces().forced());
        copy_into(&mut f.alarms, self.alarms.entries());
        copy_into(&mut f.messages, &self.messages.0);
        f.online.clone_from(&self.online);
        f.tripped = sched.tripped();
        f.flow_enabled = self.flow.as_ref().is_some_and(FlowSwitch::wanted);
        f.acks = self.acks;
        let (area, map) = &mut f.flow;
        area.clear();
        match sched.flow() {
            Some(m) => {
                if !map.as_ref().is_some_and(|old| Arc::ptr_eq(old, m)) {
                    *map = Some(Arc::clone(m));
                }
                let image = sched.image().bytes();
                let (a, b) = (m.area.0.min(image.len()), m.area.1.min(image.len()));
                area.extend_from_slice(&image[a..b]);
            }
            None => *map = None,
        }
        self.cnc.capture(f);
        self.frames.publish();
    }
}

/// Makes `dst` a copy of `src`, reusing `dst`'s elements (and their allocations).
fn copy_into<T: Clone>(dst: &mut Vec<T>, src: &[T]) {
    dst.truncate(src.len());
    let n = dst.len();
    dst.clone_from_slice(&src[..n]);
    dst.extend_from_slice(&src[n..]);
}
