//! [`Builder`]: a controller's choices, step by step, then [`Builder::build`]: every choice and the
//! machine validated first (all errors in one report), then the assembly — compile beside the I/O
//! start, first image (retain), scheduler, recording, online change, servers.
//!
//! **Invariants:** nothing is started before validation has passed; every assembly function here
//! stays under about 80 lines; the start order is the one `ncplc run` always had (the I/O opens on
//! its own thread while the program compiles on every core).

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::sync::mpsc;
use std::time::Duration;

use packets::PacketIo;
use runtime::clock::{RealClock, VirtualClock};
use runtime::image::Image;
use runtime::online::{self, CompileFn, Note};
use runtime::program::Loaded;
use runtime::scheduler::{Scheduler, Settings};
use sim::HandshakeCounts;

use crate::control::{Controller, Parts};
use crate::hmi_link::HmiLink;
use crate::hmi_link::flow_switch::FlowSwitch;
use crate::io::{IoKind, open_io_with, with_modbus_hmi};
use crate::machine::Machine;
use crate::part_run::PartRun;
use crate::replayer::Replayer;
use crate::servers::{HmiInputs, PartKernel, Server, Start, hmi_token, start_hmi};
use crate::settings::{Clock, Engine, Hmi, Io, Part, Recording, Scan};

/// A part run's kernel with its partprograms' texts, for the web HMI and the servers.
fn part_kernel(
    run: Option<&PartRun>,
    part: Option<&Part>,
    machine: &Machine,
) -> Option<PartKernel> {
    let (run, part) = run.zip(part)?;
    Some((
        run.cnc(),
        crate::hmi_link::kernel_cnc::sources(&part.spec, machine),
    ))
}

/// Why a controller could not be built.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// The choices or the machine are wrong: every problem, one per line (nothing was started).
    #[error("{}", .0.join("\n"))]
    Invalid(Vec<String>),
    /// The PLC program does not compile (the rendered diagnostics).
    #[error("{0}")]
    Program(String),
    /// Starting a part failed after validation (I/O, part run, recording, a server).
    #[error("{0}")]
    Start(String),
}

/// A controller's choices; [`Controller::builder`] makes one.
pub struct Builder {
    dir: PathBuf,
    plc: Option<PathBuf>,
    engine: Engine,
    io: Io,
    part: Option<Part>,
    recording: Option<Recording>,
    hmi: Option<Hmi>,
    modbus_hmi: Option<SocketAddr>,
    servers: Vec<Box<dyn Server>>,
    clock: Clock,
    scan: Scan,
    wrap_io: Option<WrapIo>,
}

/// A decorator put around the opened I/O, given a part run's CNC kernel when there is one (benches
/// time `latch_inputs` through it, or put simulated drives between kernel and scan).
pub type WrapIo = Box<
    dyn FnOnce(Box<dyn PacketIo>, Option<Arc<std::sync::Mutex<cnc::Cnc>>>) -> Box<dyn PacketIo>
        + Send,
>;

/// What validation found usable: the machine, its PLC source and the HMI token.
struct Checked {
    machine: Machine,
    source: Vec<u8>,
    token: Option<hmi::Tokens>,
}

/// What the start-up threads opened: the I/O, the simulated CNC's counts, a part run.
struct Opened {
    io: Box<dyn PacketIo>,
    handshakes: Option<HandshakeCounts>,
    part: Option<PartRun>,
}

impl Controller {
    /// A builder for the machine in `machine_dir` with `ncplc run`'s defaults: JIT, simulated I/O,
    /// real time, no part, no recording, no servers, online change on.
    pub fn builder(machine_dir: impl Into<PathBuf>) -> Builder {
        Builder {
            dir: machine_dir.into(),
            plc: None,
            engine: Engine {
                kind: runtime::compiled::EngineKind::Jit,
                flow: false,
            },
            io: Io { kind: IoKind::Sim },
            part: None,
            recording: None,
            hmi: None,
            modbus_hmi: None,
            servers: Vec::new(),
            clock: Clock::Real { spin_us: 0 },
            scan: Scan::default(),
            wrap_io: None,
        }
    }
}

impl Builder {
    /// Use this PLC source instead of the machine's.
    pub fn plc(mut self, plc: Option<PathBuf>) -> Builder {
        self.plc = plc;
        self
    }

    /// The engine step.
    pub fn engine(mut self, engine: Engine) -> Builder {
        self.engine = engine;
        self
    }

    /// The I/O step.
    pub fn io(mut self, io: Io) -> Builder {
        self.io = io;
        self
    }

    /// The CNC step: run a partprogram and/or MDI blocks on the kernel (simulated I/O only).
    pub fn part(mut self, part: Option<Part>) -> Builder {
        self.part = part;
        self
    }

    /// The recording step.
    pub fn record(mut self, recording: Option<Recording>) -> Builder {
        self.recording = recording;
        self
    }

    /// The web HMI.
    pub fn hmi(mut self, hmi: Option<Hmi>) -> Builder {
        self.hmi = hmi;
        self
    }

    /// The Modbus HMI/SCADA server on this address (in front of the I/O).
    pub fn modbus_hmi(mut self, bind: Option<SocketAddr>) -> Builder {
        self.modbus_hmi = bind;
        self
    }

    /// Another server beside the scan (the extension point: an OPC UA server, …).
    pub fn server(mut self, server: Box<dyn Server>) -> Builder {
        self.servers.push(server);
        self
    }

    /// The clock step.
    pub fn clock(mut self, clock: Clock) -> Builder {
        self.clock = clock;
        self
    }

    /// Ticks, tick length, overruns, online change, retain file, scan CPU.
    pub fn scan(mut self, scan: Scan) -> Builder {
        self.scan = scan;
        self
    }

    /// Puts `wrap` around the I/O once it is open (a part run's kernel I/O included), before the
    /// scheduler takes it: a timing shim for benches, a fault injector for tests.
    pub fn wrap_io(mut self, wrap: WrapIo) -> Builder {
        self.wrap_io = Some(wrap);
        self
    }

    fn virtual_time(&self) -> bool {
        self.clock == Clock::Virtual
    }

    /// Every problem with the choices and the machine, before anything starts.
    fn validate(&self) -> Result<Checked, BuildError> {
        let mut errors = Vec::new();
        if let Some(cpu) = self.scan.scan_cpu
            && let Err(e) = fieldbus::affinity::check_cpu(cpu)
        {
            errors.push(format!("error: --scan-cpu: {e}"));
        }
        if self.part.is_some() && self.io.kind == IoKind::Modbus {
            errors.push(
                "error: --program and --mdi run on the simulated machine (--io sim) or on CiA 402 drives (--io canopen); Modbus TCP has no drives".into(),
            );
        }
        let token = match self.hmi.as_ref().map(hmi_token).transpose() {
            Ok(t) => t,
            Err(e) => {
                errors.push(e);
                None
            }
        };
        let opened = Machine::open(&self.dir, self.plc.as_deref()).map_err(|e| e.to_string());
        let checked = opened.and_then(|machine| {
            let source = machine.read_source().map_err(|e| e.to_string())?;
            Ok((machine, source))
        });
        match checked {
            Ok((machine, source)) if errors.is_empty() => Ok(Checked {
                machine,
                source,
                token,
            }),
            Ok(_) => Err(BuildError::Invalid(errors)),
            Err(e) => {
                errors.push(e);
                Err(BuildError::Invalid(errors))
            }
        }
    }

    /// Validates, then assembles the controller (see the module documentation for the order).
    pub fn build(mut self) -> Result<Controller, BuildError> {
        let checked = self.validate()?;
        let machine = &checked.machine;
        let tick_ms = self.scan.tick_ms.unwrap_or(machine.config.tick_ms).max(1);
        let flow_wanted = Arc::new(AtomicBool::new(self.engine.flow));
        let (first, compile, variant) =
            machine.compile_fns(self.engine.kind, tick_ms, Arc::clone(&flow_wanted));
        let (loaded, mut opened) = self.compile_and_open(&checked, tick_ms, &first)?;
        if let Some(wrap) = self.wrap_io.take() {
            let cnc = opened.part.as_ref().map(PartRun::cnc);
            opened.io = wrap(opened.io, cnc);
        }
        let meta = loaded.meta.clone();
        let retain_path = self.retain_path(machine);
        let mut image = Image::new(meta.image_len(), &machine.config.t_init);
        meta.init_image(image.bytes_mut());
        if let Some(path) = &retain_path {
            crate::retained::restore(path, meta.as_ref(), image.bytes_mut());
        }
        let flow = FlowSwitch::new(flow_wanted, variant);
        let hmi = self.start_hmi(&checked, tick_ms, &opened, flow)?;
        let settings = Settings {
            tick_ns: u64::from(tick_ms) * 1_000_000,
            overrun_limit: self.scan.overrun_limit,
        };
        let kernel = part_kernel(opened.part.as_ref(), self.part.as_ref(), machine);
        let mut sched = Scheduler::new(image, loaded, opened.io, self.make_clock(), settings);
        self.start_recording(&mut sched, opened.part.as_ref(), tick_ms)?;
        let retain = retain_path.map(|p| (crate::retained::start_writer(p.clone(), &mut sched), p));
        let (notes_tx, notes) = mpsc::channel();
        let watch = self.start_watch(machine, checked.source, compile, &mut sched, notes_tx);
        for s in &mut self.servers {
            s.start(Start {
                machine,
                tick_ms,
                kernel: kernel.clone(),
                meta: Arc::clone(&meta),
            })
            .map_err(BuildError::Start)?;
        }
        let realtime = !self.virtual_time();
        Ok(Controller::new(Parts {
            sched,
            tick_ms,
            ticks: self.scan.ticks,
            io_name: io_name(self.io.kind),
            meta,
            part: opened.part,
            until_end: self.part.as_ref().is_some_and(|p| p.until_end),
            handshakes: opened.handshakes,
            hmi,
            messages: (!machine.messages.is_empty())
                .then(|| crate::plc_messages::Messages::new(machine.messages.clone())),
            servers: self.servers,
            notes,
            retain,
            _watch: watch,
            realtime,
            scan_cpu: self.scan.scan_cpu,
        }))
    }

    /// Compiles the first program on every core while the I/O (or a part run's kernel and plans)
    /// starts on its own thread: the first tick waits for the slower of the two, not their sum.
    fn compile_and_open(
        &self,
        checked: &Checked,
        tick_ms: u32,
        first: &CompileFn,
    ) -> Result<(Loaded, Opened), BuildError> {
        let machine = &checked.machine;
        let declared = machine.declared_connectors();
        let plan = IoPlan {
            kind: self.io.kind,
            part: self.part.as_ref(),
            modbus_hmi: self.modbus_hmi,
            nobody: self.hmi.is_none() && self.modbus_hmi.is_none() && self.servers.is_empty(),
            virtual_time: self.virtual_time(),
            ticks: self.scan.ticks,
        };
        let (compiled, opened) = std::thread::scope(|s| {
            let opener = s.spawn(|| plan.open(machine, &declared, tick_ms));
            let compiled = first(&checked.source);
            (compiled, opener.join())
        });
        let loaded = compiled.map_err(|d| BuildError::Program(d.to_string()))?;
        let opened = opened
            .map_err(|_| BuildError::Start("error: the I/O start-up thread panicked".into()))??;
        Ok((loaded, opened))
    }

    /// The retain file of this run: only with PGCFIL OLD, never for recordings or virtual time.
    fn retain_path(&self, machine: &Machine) -> Option<PathBuf> {
        let used = machine.config.restore_old && self.recording.is_none() && !self.virtual_time();
        let path = self.scan.retain_file.clone();
        used.then(|| path.or_else(|| machine.config.retain_file.clone()))
            .flatten()
    }

    fn make_clock(&self) -> Box<dyn runtime::clock::Clock> {
        match self.clock {
            Clock::Virtual => Box::new(VirtualClock::new()),
            Clock::Real { spin_us } => Box::new(RealClock::with_spin(spin_us * 1_000)),
        }
    }

    /// Starts the web HMI when asked, with a part run's kernel behind its Machine page.
    fn start_hmi(
        &self,
        checked: &Checked,
        tick_ms: u32,
        opened: &Opened,
        flow: FlowSwitch,
    ) -> Result<Option<HmiLink>, BuildError> {
        let Some(hmi) = &self.hmi else {
            return Ok(None);
        };
        let inputs = HmiInputs {
            source: &checked.source,
            tick_ms,
            counts: opened.handshakes.clone(),
            kernel: part_kernel(opened.part.as_ref(), self.part.as_ref(), &checked.machine),
            flow,
        };
        start_hmi(
            hmi,
            checked.token.clone().unwrap_or_default(),
            &checked.machine,
            inputs,
        )
        .map(Some)
        .map_err(BuildError::Start)
    }

    /// Connects the recording: the trace (with a part run's header) and the axis positions.
    fn start_recording(
        &self,
        sched: &mut Scheduler,
        part: Option<&PartRun>,
        tick_ms: u32,
    ) -> Result<(), BuildError> {
        let Some(rec) = &self.recording else {
            return Ok(());
        };
        let options = trace::DurableOptions {
            flush: Duration::from_millis(rec.flush_ms),
            wait_when_full: self.virtual_time(),
            ..trace::DurableOptions::default()
        };
        let spec = self.part.as_ref().map(|p| &p.spec);
        let header = part.zip(spec).map(|(p, spec)| p.header(spec));
        let sink = trace::create_part_sink(&rec.path, tick_ms, header.as_ref(), options)
            .map_err(|e| BuildError::Start(format!("{}: {e}", rec.path.display())))?;
        sched.record_to(sink);
        if let Some(p) = part {
            let cnc = p.cnc();
            sched.record_positions(Box::new(move |out| {
                let c = cnc
                    .lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner);
                crate::part_replay::axis_positions(&c, out);
            }));
            if let Some(samples) = p.drive_samples.clone() {
                sched.record_drives(Box::new(move |out| {
                    let s = samples
                        .lock()
                        .unwrap_or_else(std::sync::PoisonError::into_inner);
                    out.clone_from(&s);
                }));
            }
            if let Some(lost) = p.nodes_lost.clone() {
                sched.record_nodes_lost(Box::new(move |out| {
                    let l = lost
                        .lock()
                        .unwrap_or_else(std::sync::PoisonError::into_inner);
                    out.clone_from(&l);
                }));
            }
        }
        Ok(())
    }

    /// Online change: watches the PLC source and hands new programs to the scheduler.
    fn start_watch(
        &self,
        machine: &Machine,
        source: Vec<u8>,
        compile: CompileFn,
        sched: &mut Scheduler,
        notes: mpsc::Sender<Note>,
    ) -> Option<online::OnlineChange> {
        if !self.scan.watch {
            return None;
        }
        let (swap_tx, swap_rx) = mpsc::channel();
        sched.accept_swaps(swap_rx);
        let path = &machine.config.plc_source;
        match online::watch(path, source, compile, swap_tx, notes) {
            Ok(w) => {
                eprintln!("online change: watching {}", path.display());
                Some(w)
            }
            Err(e) => {
                eprintln!("warning: online change disabled: {e}");
                None
            }
        }
    }

    /// The machine opened and its PLC source read, for replays (no I/O, clock or servers).
    pub fn replayer(self) -> Result<Replayer, BuildError> {
        let machine = Machine::open(&self.dir, self.plc.as_deref())
            .map_err(|e| BuildError::Invalid(vec![e.to_string()]))?;
        let source = machine
            .read_source()
            .map_err(|e| BuildError::Invalid(vec![e.to_string()]))?;
        Ok(Replayer::new(machine, source, self.engine.kind))
    }
}

/// What the I/O start-up thread needs of the builder's choices.
struct IoPlan<'a> {
    kind: IoKind,
    part: Option<&'a Part>,
    modbus_hmi: Option<SocketAddr>,
    /// Nobody can press a button: no HMI, no Modbus HMI, no other server.
    nobody: bool,
    virtual_time: bool,
    ticks: Option<u64>,
}

impl IoPlan<'_> {
    /// Opens the I/O: a part run's kernel behind the simulated I/O, or the I/O of the I/O step;
    /// the Modbus HMI in front of either when asked.
    fn open(
        &self,
        machine: &Machine,
        declared: &fieldbus::DeclaredConnectors,
        tick_ms: u32,
    ) -> Result<Opened, BuildError> {
        let Some(part) = self.part else {
            let (io, handshakes) = open_io_with(
                self.kind,
                &machine.dir,
                declared,
                machine.script.clone(),
                machine.signals.clone(),
                tick_ms,
                self.modbus_hmi,
            )
            .map_err(|e| BuildError::Start(e.to_string()))?;
            return Ok(Opened {
                io,
                handshakes,
                part: None,
            });
        };
        let trajectory = part.trajectory.as_deref();
        let (io, mut run) = match self.kind {
            IoKind::Canopen => crate::part_run::start_on_drives(
                &part.spec,
                trajectory,
                machine,
                tick_ms,
                self.virtual_time,
            ),
            _ => crate::part_run::start(&part.spec, trajectory, machine, tick_ms),
        }
        .map_err(BuildError::Start)?;
        let io = match self.modbus_hmi {
            Some(bind) => with_modbus_hmi(&machine.dir, declared, io, bind)
                .map_err(|e| BuildError::Start(e.to_string()))?,
            None => io,
        };
        if self.virtual_time && part.until_end && self.ticks.is_none() && self.nobody {
            // Ten minutes of machine time with nothing happening: nobody will press START.
            run.set_idle_limit(600_000 / u64::from(tick_ms));
        }
        Ok(Opened {
            io,
            handshakes: None,
            part: Some(run),
        })
    }
}

/// The I/O's name in the run's last line.
fn io_name(kind: IoKind) -> &'static str {
    match kind {
        IoKind::Sim => "sim",
        IoKind::Modbus => "modbus",
        IoKind::Canopen => "canopen",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::PartSpec;

    /// Every wrong choice is reported at once, before anything is opened or started.
    #[test]
    fn build_reports_every_problem_in_one_report() {
        let cpus = fieldbus::affinity::cpu_count();
        let missing = PathBuf::from("/nonexistent/ncplc-machine");
        let part = Part {
            spec: PartSpec {
                program: Some(PathBuf::from("PART1")),
                process: 1,
                ..PartSpec::default()
            },
            trajectory: None,
            until_end: true,
        };
        let result = Controller::builder(&missing)
            .io(Io {
                kind: IoKind::Modbus,
            })
            .part(Some(part))
            .scan(Scan {
                scan_cpu: Some(cpus),
                ..Scan::default()
            })
            .build();
        let Err(BuildError::Invalid(errors)) = result else {
            panic!("expected a validation report");
        };
        assert_eq!(
            errors,
            vec![
                format!(
                    "error: --scan-cpu: CPU {cpus} does not exist: this machine has {cpus} CPU(s), numbered 0..{}",
                    cpus - 1
                ),
                "error: --program and --mdi run on the simulated machine (--io sim) or on CiA 402 drives (--io canopen); Modbus TCP has no drives".to_string(),
                "/nonexistent/ncplc-machine: not a machine directory".to_string(),
            ]
        );
    }

    /// A replay of a machine that does not exist fails before compiling anything.
    #[test]
    fn replayer_refuses_a_missing_machine() {
        let result = Controller::builder("/nonexistent/ncplc-machine").replayer();
        let Err(BuildError::Invalid(errors)) = result else {
            panic!("expected a validation report");
        };
        assert_eq!(
            errors,
            vec!["/nonexistent/ncplc-machine: not a machine directory".to_string()]
        );
    }
}
