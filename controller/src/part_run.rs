//! The part run of a controller (`--program`, `--mdi`, `--until-end`): builds the CNC kernel
//! behind the simulated I/O, plays the operator (MDI blocks first, then the program selected in
//! AUTO; the cycle itself starts when the PLC raises START), watches for the end, and prints the
//! summary (cycle time, blocks, M/S/T handshakes with their FIN wait, alarms, largest following
//! error).
//!
//! Retained macro variables: the machine's `nc/MACROVARS` is read once at the start (a replay takes
//! the text its trace header recorded instead) and every plan of the run starts from it;
//! [`PartRun::save_macro_vars`] writes back, atomically, the variables changed by the plans that
//! ran (the MDI programs, then the selected program once its cycle started), whatever ended the
//! run (the end, an alarm, a reset, `--ticks`, Ctrl-C). A replay never writes it.

use std::collections::VecDeque;
use std::sync::{Arc, Mutex, PoisonError};

use cnc::interp::Interpolator;
use cnc::{Cnc, Interp, Mode, ProcessConfig};
use packets::PacketIo;

use crate::machine::Machine;
use partprogram::macro_b::retained::{Retained, format_retained, parse_retained};
use runtime::machine_facts::Facts;
use sim::kernel::{KernelIo, KernelSetup};
use sim::part::{Part, files_read, load_part, plan_text_from};
use trace::{FileCrc, OtherProgram, PartHeader};

/// The program of another process (`sim.toml [cnc] programs`).
struct Other {
    process: u8,
    part: Part,
    selected: bool,
    started: bool,
}

/// A running part: the shared kernel and what the operator still has to do.
pub struct PartRun {
    cnc: Arc<Mutex<Cnc>>,
    /// The axes on CiA 402 drives (a run with `--io canopen`), for the trace header.
    pub(crate) drives: Vec<trace::HeaderDrive>,
    /// The packet-A input bytes the simulated I/O nodes carry (trace header `bus_inputs`).
    pub(crate) bus_inputs: Vec<u16>,
    /// The drives' feedback the kernel took at the last latch, for the recording.
    pub(crate) drive_samples: Option<crate::drive_io::Samples>,
    /// The I/O nodes newly lost at the last latch, for the recording.
    pub(crate) nodes_lost: Option<crate::drive_io::NodesLost>,
    process: u8,
    part: Option<Part>,
    mdi: VecDeque<String>,
    mdi_running: bool,
    machine: std::path::PathBuf,
    dialect: Option<String>,
    started: Option<u64>,
    /// In virtual time with nobody to press a button: after this many ticks with no axis moving
    /// and no block running, the run stops (else `--until-end` would spin for ever).
    idle_limit: Option<u64>,
    /// The tick since which nothing has happened (see `idle_limit`).
    idle_since: Option<u64>,
    finished: Option<u64>,
    alarms: Vec<String>,
    failed: bool,
    program_selected: bool,
    homing_started: bool,
    others: Vec<Other>,
    mdi_files: Vec<(String, String)>,
    trajectory: Option<std::io::BufWriter<std::fs::File>>,
    /// The retained-variables text the run started from (None: no file), for the trace header.
    vars_text: Option<String>,
    /// The retained variables the run started from.
    vars_start: Retained,
    /// The retained variables at the end of each MDI program planned, in order.
    vars_mdi: Arc<Mutex<Vec<Retained>>>,
    /// The selected program's cycle started (its plan's variables count as written).
    program_ran: bool,
}

/// MDI text as a program of the machine's dialect (`--dialect`, else `nc/DIALECT`). An operator
/// types blocks, not programs: a MEFI line without its block number gets `N<line>` (MEFI blocks
/// start with N; Fanuc's N is optional), and no M02/M30 is asked for.
fn mdi_program(dir: &std::path::Path, dialect: Option<&str>, text: &str) -> String {
    let fanuc = dialect.is_some_and(|d| d.eq_ignore_ascii_case("fanuc"))
        || diag::read_config(&sim::machine_view::dialect_file(dir))
            .is_ok_and(|d| d.trim().eq_ignore_ascii_case("fanuc"));
    if fanuc {
        return format!("O9999\n{text}\n");
    }
    let mut program = String::from("%999999\n");
    for (i, line) in text.lines().enumerate() {
        let t = line.trim_start();
        if !t.is_empty() && !t.starts_with(['N', 'n', '"', '/']) {
            program.push_str(&format!("N{} ", i + 1));
        }
        program.push_str(line);
        program.push('\n');
    }
    program
}

/// The interpolator of a process: the `motion` crate's kernel with the machine's complex-speed
/// constants (none for a process without coordinated axes).
pub fn make_interp(
    axcfil: &characterization::axcfil::Axcfil,
    complex: motion::complex::ComplexSpeed,
    cfg: &ProcessConfig,
    start: &[f64],
) -> Result<Box<dyn Interpolator>, String> {
    if cfg.axes.is_empty() {
        return Ok(Box::new(cnc::interp::NoMotion));
    }
    Ok(Box::new(cnc::motion_link::MotionKernel::new(
        axcfil, cfg, start, complex,
    )?))
}

/// The number of `blocks` under contour control (Fanuc G05.1 Q1 / G08 P1, MEFI G23).
pub fn contour_blocks(blocks: &[partprogram::Canon]) -> usize {
    blocks.iter().filter(|b| b.modal.contour).count()
}

/// What the operator of a part run does: the `ncplc run` options a replay needs too.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct PartSpec {
    /// `--program`.
    pub program: Option<std::path::PathBuf>,
    /// `--process`.
    pub process: u8,
    /// `--dialect`.
    pub dialect: Option<String>,
    /// `--mdi`, in order.
    pub mdi: Vec<String>,
    /// `--kor-change`.
    pub kor_change: Option<std::path::PathBuf>,
    /// Where the retained macro variables come from.
    pub vars: VarsSource,
}

/// Where a part run takes its retained macro variables `#500`–`#999` from.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub enum VarsSource {
    /// The machine's file `nc/MACROVARS` (a live run).
    #[default]
    Machine,
    /// The text a trace header recorded (a replay; None: there was no file).
    Recorded(Option<String>),
}

impl PartSpec {
    /// The options a trace header names.
    pub fn from_header(h: &PartHeader) -> PartSpec {
        PartSpec {
            program: h.program.as_ref().map(std::path::PathBuf::from),
            process: h.process,
            dialect: h.dialect.clone(),
            mdi: h.mdi.clone(),
            kor_change: h.kor_change.as_ref().map(std::path::PathBuf::from),
            vars: VarsSource::Recorded(h.macro_vars.clone()),
        }
    }
}

/// The version of the kernel a trace header names: a replay by another kernel may diverge.
pub fn kernel_version() -> String {
    format!("cnc {}", cnc::VERSION)
}

/// Builds the kernel I/O for `spec` and the part run that drives it; with `trajectory`, the set
/// points of every interpolation tick of the process go to that file (`ncplc run --trajectory`).
pub fn start(
    spec: &PartSpec,
    trajectory: Option<&std::path::Path>,
    machine: &Machine,
    tick_ms: u32,
) -> Result<(Box<dyn PacketIo>, PartRun), String> {
    let (io, mut run) = start_spec(spec, machine, tick_ms)?;
    if let Some(path) = trajectory {
        use std::io::Write as _;
        let contour = run.part.as_ref().map_or(0, |p| contour_blocks(&p.blocks));
        let header = run
            .lock()
            .process_mut(spec.process)
            .ok()
            .and_then(|p| p.record_trajectory(contour))
            .ok_or_else(|| format!("error: process {} has no interpolated axes", spec.process))?;
        let file = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut w = std::io::BufWriter::new(file);
        writeln!(w, "{header}").map_err(|e| format!("{}: {e}", path.display()))?;
        run.trajectory = Some(w);
    }
    Ok((io, run))
}

/// [`start`] with the axes on the CiA 402 drives of io.toml (`--io canopen`): the CANopen master
/// clocked by the kernel's interpolation tick (process 1's), in lock-step with the scan when
/// `lockstep` (virtual time on the virtual bus).
pub fn start_on_drives(
    spec: &PartSpec,
    trajectory: Option<&std::path::Path>,
    machine: &Machine,
    tick_ms: u32,
    lockstep: bool,
) -> Result<(Box<dyn PacketIo>, PartRun), String> {
    let (kernel, mut run) = start(spec, trajectory, machine, tick_ms)?;
    let cnc = run.cnc();
    let (int_tick_s, syncs) = run
        .lock()
        .processes()
        .first()
        .map_or((f64::from(tick_ms) / 1000.0, 1), |p| p.interpolation());
    let timing = fieldbus::canopen::drive::DriveTiming {
        int_tick: std::time::Duration::from_secs_f64(int_tick_s),
        syncs,
        lockstep,
    };
    let declared = machine.declared_connectors();
    // The simulated drives get the simulated machine behind their axes (home switch, marks).
    let models: Vec<((u8, char), fieldbus::canopen::drive_sim::SimMachine)> = {
        let c = run.lock();
        c.processes()
            .iter()
            .flat_map(|p| {
                p.axis_names().into_iter().filter_map(move |a| {
                    let m = p.bus_machine(a)?;
                    let sim = fieldbus::canopen::drive_sim::SimMachine {
                        start: m.start,
                        home_switch: m.home_switch,
                        mark_pitch: m.mark_pitch,
                    };
                    Some(((p.number(), a), sim))
                })
            })
            .collect()
    };
    let model = |process: u32, axis: char| {
        models
            .iter()
            .find(|((p, a), _)| u32::from(*p) == process && *a == axis)
            .map(|(_, m)| *m)
    };
    let canopen = fieldbus::open_canopen(&machine.dir, &declared, timing, &model)
        .map_err(|d| crate::io::render_map_error(&machine.dir, d))?;
    let mut io = crate::drive_io::DriveIo::new(canopen, kernel, cnc)?;
    io.unwire(
        machine
            .script
            .handwheel
            .iter()
            .filter_map(|h| h.counter.parse::<packets::Signal>().ok())
            .map(|s| s.image_byte()),
    );
    if io.drives().is_empty() {
        return Err(format!(
            "error: {}: a part run on --io canopen needs the axes on drives: io.toml has no [[canopen.drive]] (docs/drives.md)",
            runtime::render::user_path(&machine.dir.join("io.toml")).display()
        ));
    }
    run.drives = io.drives().to_vec();
    run.bus_inputs = io.bus_inputs();
    run.drive_samples = Some(io.samples());
    run.nodes_lost = Some(io.nodes_lost());
    Ok((Box::new(io), run))
}

/// Builds the kernel I/O for a part run of `spec` and the part run that drives it.
pub fn start_spec(
    args: &PartSpec,
    machine: &Machine,
    tick_ms: u32,
) -> Result<(Box<dyn PacketIo>, PartRun), String> {
    let (io, cnc) = kernel_io(machine, tick_ms)?;
    let (vars_text, vars_start) = macro_vars(args, machine)?;
    let others = other_programs(args, machine, vars_text.as_deref())?;
    let part = match &args.program {
        Some(p) => Some(load_part(
            &machine.dir,
            p,
            args.dialect.as_deref(),
            vars_text.as_deref(),
        )?),
        None => None,
    };
    // The files the MDI blocks' compile reads (macros, correction table, constants).
    let mdi_files = if args.mdi.is_empty() {
        Vec::new()
    } else {
        let text = mdi_program(&machine.dir, args.dialect.as_deref(), &args.mdi.join("\n"));
        files_read(
            &machine.dir,
            "MDI",
            &text,
            args.dialect.as_deref(),
            vars_text.as_deref(),
        )?
    };
    let run = PartRun {
        mdi_files,
        cnc,
        drives: Vec::new(),
        bus_inputs: Vec::new(),
        drive_samples: None,
        nodes_lost: None,
        process: args.process,
        part,
        // The blocks run as one MDI program: planned together, they share their modal state; it
        // is planned from where the axes stand when it starts (`Cnc::set_mdi_compiler_at`).
        mdi: if args.mdi.is_empty() {
            VecDeque::new()
        } else {
            VecDeque::from([args.mdi.join("\n")])
        },
        mdi_running: false,
        machine: machine.dir.clone(),
        dialect: args.dialect.clone(),
        started: None,
        idle_limit: None,
        idle_since: None,
        finished: None,
        alarms: Vec::new(),
        failed: false,
        program_selected: false,
        homing_started: false,
        others,
        trajectory: None,
        vars_text,
        vars_start,
        vars_mdi: Arc::new(Mutex::new(Vec::new())),
        program_ran: false,
    };
    run.wire_planners(args)?;
    Ok((Box::new(io), run))
}

/// The CNC kernel behind the simulated I/O, with each process's PGCFIL manual axes (MAS) and
/// alternative feed (QFD).
fn kernel_io(machine: &Machine, tick_ms: u32) -> Result<(KernelIo, Arc<Mutex<Cnc>>), String> {
    let facts = Facts::load(&machine.dir).map_err(|e| e.to_string())?;
    let axcfil = &facts.machine.axcfil;
    let complex = sim::machine_view::complex_speed(&machine.dir)?;
    let interp = |cfg: &ProcessConfig, start: &[f64]| make_interp(axcfil, complex, cfg, start);
    let setup = KernelSetup {
        axcfil: &facts.machine.axcfil,
        iocfil: facts.machine.iocfil.as_ref(),
        interface: &machine.interface,
        a_inputs: &machine.config.a_inputs,
        tick_ms,
        make_interp: &interp,
    };
    let sim_path = machine.dir.join("sim.toml");
    let (io, cnc) = KernelIo::new(&setup, machine.script.clone())
        .map_err(|e| format!("{}: {e}", sim_path.display()))?;
    if let Some(pg) = &facts.machine.pgcfil {
        let mut c = cnc.lock().unwrap_or_else(PoisonError::into_inner);
        for n in 1..=5u8 {
            let cfg = pg.process(u32::from(n));
            let mas = cfg.map(|p| p.mas.clone()).filter(|m| !m.is_empty());
            if let Ok(p) = c.process_mut(n) {
                p.set_manual_axes(mas);
                p.set_alternative_feed(cfg.and_then(|p| p.qfd));
                p.set_uep(cfg.and_then(|p| p.assigned("UEP")) == Some(1.0));
            }
        }
    }
    Ok((io, cnc))
}

/// The retained macro variables the run starts from: their text (the machine's file, or the one a
/// trace recorded) and the variables read from it.
fn macro_vars(args: &PartSpec, machine: &Machine) -> Result<(Option<String>, Retained), String> {
    let vars_text = match &args.vars {
        VarsSource::Machine => sim::machine_view::read_macro_vars(&machine.dir).map_err(|e| {
            format!(
                "{}: {e}",
                sim::machine_view::macro_vars_file(&machine.dir).display()
            )
        })?,
        VarsSource::Recorded(t) => t.clone(),
    };
    let vars_start = match &vars_text {
        Some(text) => {
            let name =
                runtime::render::user_path(&sim::machine_view::macro_vars_file(&machine.dir))
                    .display()
                    .to_string();
            let (v, diags) = parse_retained(&name, text);
            if diag::has_errors(&diags) {
                let mut sources = diag::Sources::new();
                sources.add(name, text.clone());
                return Err(diag::render_human(&diags, &sources));
            }
            v
        }
        None => Retained::default(),
    };
    Ok((vars_text, vars_start))
}

/// The programs of the other processes (`sim.toml [cnc] programs`).
fn other_programs(
    args: &PartSpec,
    machine: &Machine,
    vars_text: Option<&str>,
) -> Result<Vec<Other>, String> {
    let sim_path = machine.dir.join("sim.toml");
    let mut others = Vec::new();
    for (k, name) in &machine.script.cnc.programs {
        let process: u8 = k
            .parse()
            .ok()
            .filter(|p| (1..=5).contains(p) && *p != args.process)
            .ok_or_else(|| {
                format!(
                    "{}: [cnc] programs: `{k}` is not a process 1..5 other than --process {}",
                    sim_path.display(),
                    args.process
                )
            })?;
        // `--dialect` is the dialect of the operator's program and MDI; the other processes'
        // programs are the machine's own (nc/DIALECT, else detected from their header).
        let part = load_part(&machine.dir, std::path::Path::new(name), None, vars_text)?;
        others.push(Other {
            process,
            part,
            selected: false,
            started: false,
        });
    }
    Ok(others)
}

impl PartRun {
    /// Gives the kernel the run's MDI compiler (planned from the axes' set points when an MDI
    /// program starts) and the selected program's re-planner (tool-correction requests).
    fn wire_planners(&self, args: &PartSpec) -> Result<(), String> {
        let mut c = self.lock();
        let process = c
            .process_mut(args.process)
            .map_err(|e| format!("error: {e}"))?;
        let _ = process;
        let dir = self.machine.clone();
        let dialect = self.dialect.clone();
        let vars = self.vars_text.clone();
        let vars_mdi = Arc::clone(&self.vars_mdi);
        c.set_mdi_compiler_at(Arc::new(move |_, text, at| {
            let program = mdi_program(&dir, dialect.as_deref(), text);
            let (blocks, end) = plan_text_from(
                &dir,
                "MDI",
                &program,
                dialect.as_deref(),
                vars.as_deref(),
                at,
            )?;
            vars_mdi
                .lock()
                .unwrap_or_else(PoisonError::into_inner)
                .push(end);
            Ok(blocks)
        }));
        if let Some(part) = &self.part {
            let replan = sim::part::replanner(
                &self.machine,
                part,
                self.dialect.clone(),
                args.kor_change.clone(),
                self.vars_text.clone(),
            )?;
            c.process_mut(args.process)
                .map_err(|e| format!("error: {e}"))?
                .set_replanner(replan);
        }
        Ok(())
    }

    /// The kernel (shared with the I/O, an HMI and a replay).
    pub fn cnc(&self) -> Arc<Mutex<Cnc>> {
        Arc::clone(&self.cnc)
    }

    /// The trace header of this run: the programs with their content hashes and the options.
    pub fn header(&self, spec: &PartSpec) -> PartHeader {
        PartHeader {
            kernel: kernel_version(),
            process: spec.process,
            dialect: spec.dialect.clone(),
            program: self.part.as_ref().map(|p| p.name.clone()),
            crc32: self.part.as_ref().map(|p| p.hash.clone()),
            mdi: spec.mdi.clone(),
            kor_change: spec.kor_change.as_ref().map(|p| p.display().to_string()),
            others: self
                .others
                .iter()
                .map(|o| OtherProgram {
                    process: o.process,
                    program: o.part.name.clone(),
                    crc32: o.part.hash.clone(),
                })
                .collect(),
            files: self
                .files()
                .into_iter()
                .map(|(file, crc32)| FileCrc { file, crc32 })
                .collect(),
            macro_vars: self.vars_text.clone(),
            drives: self.drives.clone(),
            bus_inputs: self.bus_inputs.clone(),
        }
    }

    /// The retained macro variables after the run: those it started from, changed by each MDI
    /// program planned and then by the selected program when its cycle started (the plan of the
    /// block-skip setting its START took).
    pub fn macro_vars(&self) -> Retained {
        let mut out = self.vars_start.clone();
        let mdi = self.vars_mdi.lock().unwrap_or_else(PoisonError::into_inner);
        for end in mdi.iter() {
            out.apply_changes(&self.vars_start, end);
        }
        if let Some(part) = self.part.as_ref().filter(|_| self.program_ran) {
            let skip = self
                .lock()
                .process_mut(self.process)
                .is_ok_and(|p| p.skip_selected());
            out.apply_changes(&part.vars_start, &part.vars_end[usize::from(skip)]);
        }
        out
    }

    /// Writes [`PartRun::macro_vars`] to the machine's `nc/MACROVARS` atomically, when they differ
    /// from what the run started from (an unchanged table leaves the file alone).
    pub fn save_macro_vars(&self) -> Result<(), String> {
        let vars = self.macro_vars();
        if vars == self.vars_start {
            return Ok(());
        }
        let path = sim::machine_view::macro_vars_file(&self.machine);
        runtime::atomic_file::write(&path, format_retained(&vars).as_bytes())
            .map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Every other file the programs' compile read, with its CRC-32, in name order.
    pub fn files(&self) -> Vec<(String, String)> {
        let mut v: Vec<(String, String)> = self
            .part
            .iter()
            .chain(self.others.iter().map(|o| &o.part))
            .flat_map(|p| p.files.iter().cloned())
            .chain(self.mdi_files.iter().cloned())
            .collect();
        v.sort();
        v.dedup();
        v
    }

    /// The programs and their paths as (name in the header, file, CRC-32), for a replay's check.
    pub fn programs(&self) -> Vec<(String, std::path::PathBuf, String)> {
        self.part
            .iter()
            .chain(self.others.iter().map(|o| &o.part))
            .map(|p| (p.name.clone(), p.path.clone(), p.hash.clone()))
            .collect()
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Cnc> {
        self.cnc.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Called after every tick; false stops the run (`--until-end`: the end or a stopping alarm).
    pub fn each_tick(&mut self, tick: u64, until_end: bool) -> bool {
        let cnc = Arc::clone(&self.cnc);
        let mut c = cnc.lock().unwrap_or_else(PoisonError::into_inner);
        let n = self.process;
        let Some(st) = self.watch_main(&mut c, tick) else {
            return false;
        };
        self.operate_main(&mut c, &st);
        let others_ended = self.operate_others(&mut c);
        let ended = others_ended
            && match &self.part {
                Some(_) => {
                    self.program_selected && c.process_mut(n).is_ok_and(|p| p.counters().ended >= 1)
                }
                None => self.mdi.is_empty() && !self.mdi_running && st.interp == Interp::Idle,
            };
        if ended && self.finished.is_none() {
            self.finished = Some(tick);
        }
        !(until_end && (ended || self.failed))
    }

    /// The operator watches the main process after a tick: trajectory, refused commands, stopping
    /// alarms, the cycle's start, idle time, whether the selected program ran. None: no process.
    fn watch_main(&mut self, c: &mut Cnc, tick: u64) -> Option<cnc::state::State> {
        let n = self.process;
        let p = c.process_mut(n).ok()?;
        if let Some(w) = self.trajectory.as_mut() {
            use std::io::Write as _;
            if let Err(e) = w.write_all(p.take_trajectory().as_bytes()) {
                eprintln!("error: trajectory: {e}");
                self.trajectory = None;
            }
        }
        for (cmd, why) in p.take_rejected() {
            eprintln!("process {n}: {cmd:?} refused: {why}");
        }
        let st = p.state();
        let stopping: Vec<String> = p
            .alarms()
            .iter()
            .filter(|a| a.stopping)
            .map(|a| a.message.clone())
            .collect();
        for a in stopping {
            if !self.alarms.contains(&a) {
                self.alarms.push(a);
                self.failed = true;
            }
        }
        if st.interp == Interp::Running && st.mode != Mode::Home && self.started.is_none() {
            self.started = Some(tick);
        }
        if st.moving || st.interp == Interp::Running || self.finished.is_some() {
            self.idle_since = None;
        } else {
            let since = *self.idle_since.get_or_insert(tick);
            if let Some(limit) = self.idle_limit
                && tick - since >= limit
                && !self.failed
            {
                self.alarms.push(format!(
                    "nothing moved and no block ran from tick {since} to tick {tick}: in virtual time \
                     only the sim.toml script could press START (or continue after M00), and it \
                     does not; give --ticks N to run a fixed time"
                ));
                self.failed = true;
            }
        }
        if self.program_selected && st.interp == Interp::Running && st.mode == Mode::Auto {
            self.program_ran = true;
        }
        Some(st)
    }

    /// The operator acts on the main process: homes first (HOME, then START), then runs the MDI
    /// program, then selects the program in AUTO (the PLC's START begins its cycle).
    fn operate_main(&mut self, c: &mut Cnc, st: &cnc::state::State) {
        let n = self.process;
        if st.on && st.interp == Interp::Idle && !st.homed {
            // The operator homes first: HOME, then START (the MCZ cycle of every axis).
            if st.mode != Mode::Home {
                let _ = c.mode(n, Mode::Home);
            } else if !self.homing_started {
                self.homing_started = c.start(n).is_ok();
            }
        } else if st.on && st.interp == Interp::Idle {
            if self.mdi_running {
                self.mdi_running = false;
            } else if let Some(text) = self.mdi.front().cloned() {
                if st.mode != Mode::Mdi {
                    let _ = c.mode(n, Mode::Mdi);
                } else {
                    match c.mdi(n, &text) {
                        Ok(()) => {
                            self.mdi.pop_front();
                            self.mdi_running = true;
                        }
                        Err(e) => {
                            eprintln!("error: {e}");
                            self.alarms.push(e.to_string());
                            self.failed = true;
                            self.mdi.clear();
                        }
                    }
                }
            } else if let Some(part) = &self.part
                && !self.program_selected
            {
                let _ = c.mode(n, Mode::Auto);
                if st.mode == Mode::Auto
                    && let Ok(p) = c.process_mut(n)
                {
                    let _ = p.load_with_skip(
                        &part.name,
                        Arc::clone(&part.blocks),
                        Arc::clone(&part.skipped),
                    );
                    self.program_selected = true;
                }
            }
        }
    }

    /// The operator selects the other processes' programs in AUTO and starts them once the main
    /// cycle runs; true when every one of them has ended.
    fn operate_others(&mut self, c: &mut Cnc) -> bool {
        let mut others_ended = true;
        for o in &mut self.others {
            let Ok(p) = c.process_mut(o.process) else {
                continue;
            };
            for (cmd, why) in p.take_rejected() {
                eprintln!("process {}: {cmd:?} refused: {why}", o.process);
            }
            for a in p.alarms().iter().filter(|a| a.stopping) {
                if !self.alarms.contains(&a.message) {
                    self.alarms.push(a.message.clone());
                    self.failed = true;
                }
            }
            let ost = p.state();
            others_ended &= p.counters().ended >= 1;
            if !ost.on {
                continue;
            }
            if !o.selected && ost.interp == Interp::Idle {
                if ost.mode != Mode::Auto {
                    let _ = c.mode(o.process, Mode::Auto);
                } else if let Ok(p) = c.process_mut(o.process) {
                    o.selected = p.load(&o.part.name, Arc::clone(&o.part.blocks)).is_ok();
                }
            } else if o.selected && !o.started && self.started.is_some() {
                // The operator starts the other programs once the main cycle runs.
                o.started = c.start(o.process).is_ok();
            }
        }
        others_ended
    }

    /// Stops a `--until-end` run after `ticks` ticks in which nothing moved and no block ran
    /// (virtual time without an HMI: nobody but the script can act).
    pub fn set_idle_limit(&mut self, ticks: u64) {
        self.idle_limit = Some(ticks);
    }

    /// The outcome of `--until-end` as an exit code: 0 when the program ended, 1 on a stopping
    /// alarm or when the run stopped before the end, 2 when the trajectory could not be written.
    pub fn exit_code(&mut self) -> u8 {
        if let Some(mut w) = self.trajectory.take() {
            use std::io::Write as _;
            if let Err(e) = w.flush() {
                eprintln!("error: trajectory: {e}");
                return 2;
            }
        }
        if self.failed || self.finished.is_none() {
            1
        } else {
            0
        }
    }

    /// The summary printed at the end of the run.
    pub fn summary(&self, tick_ms: u32) -> String {
        let c = self.lock();
        let mut s = String::new();
        if let Some(part) = &self.part {
            s.push_str(&format!(
                "part {} (crc32 {}): {} canonical blocks\n",
                part.name,
                part.hash,
                part.blocks.len()
            ));
            // Contour control: the `nc run` summary line, when the program uses it.
            let contour = contour_blocks(&part.blocks);
            if let Some(line) = c
                .processes()
                .iter()
                .find(|p| p.number() == self.process)
                .and_then(|p| p.contour_summary(contour))
            {
                s.push_str(&format!("{line}\n"));
            }
        }
        let secs = |t: u64| t as f64 * f64::from(tick_ms) / 1000.0;
        match (self.started, self.finished) {
            (Some(a), Some(b)) => s.push_str(&format!(
                "cycle time {:.2} s (ticks {a}..{b}), ended\n",
                secs(b - a)
            )),
            (Some(a), None) => s.push_str(&format!("started at tick {a}, did not end\n")),
            _ => s.push_str("the cycle never started (START from the PLC)\n"),
        }
        for p in c.processes() {
            let k = p.counters();
            s.push_str(&format!(
                "process {}: {} blocks; handshakes M {} S {} T {}; FIN wait M {:.2} s S {:.2} s T {:.2} s; largest following error {}\n",
                p.number(),
                k.blocks,
                k.handshakes[0],
                k.handshakes[1],
                k.handshakes[2],
                secs(k.wait_ticks[0]),
                secs(k.wait_ticks[1]),
                secs(k.wait_ticks[2]),
                cnc::following::summary(&p.following_peaks())
            ));
            if k.corrections > 0 {
                s.push_str(&format!(
                    "process {}: tool-correction requests {} (following blocks re-planned)\n",
                    p.number(),
                    k.corrections
                ));
            }
            if let Some(top) = k.spindle_drive_top {
                s.push_str(&format!(
                    "process {} spindle on its drive: top speed {top:.1} rev/min (606Ch)\n",
                    p.number()
                ));
            }
            if k.css_ticks > 0 || k.gear_changes > 0 {
                s.push_str(&format!(
                    "process {} spindle: G96 (FG96) for {:.2} s; top speed {:.1} rev/min; gear changes {}\n",
                    p.number(),
                    secs(k.css_ticks),
                    k.spindle_top,
                    k.gear_changes
                ));
            }
        }
        for a in &self.alarms {
            s.push_str(&format!("alarm: {a}\n"));
        }
        s
    }
}
