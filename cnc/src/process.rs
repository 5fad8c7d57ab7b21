//! One CNC process: its state ([`crate::state`]), its M, S and T handshake channels, its
//! interpolator, its simulated drives and spindle, and the program it runs ([`crate::exec`] holds
//! the block executor's half of the `impl`).
//!
//! Order inside [`Process::step`] (one logic tick; `out` are the PLC's last published outputs):
//! 1. read the PLC→CNC levels and edges (FOLD, RABI, overrides, START, ERS, mode request, USO);
//! 2. apply queued commands (operator channel first, then the PLC's edges) through [`decide`];
//! 3. step the handshake channels with the FINs; advance the block executor; strobe what it issued;
//! 4. run the interpolation ticks that fit the logic tick: each sets the spindle reference from
//!    the law at the last set points ([`crate::spindle`]: G96 follows the radius), the drives
//!    follow each set point with the velocity feed-forward of [`crate::servo`] (on for a
//!    programmed move in MDI/AUTO/STEP while UEP = 0), [`crate::following`] checks each axis's
//!    error against the SRV limit in force, DEN tags are collected; before each of these ticks the
//!    executor's look-ahead queues what fits (as `ncplc nc run` does); advance the executor again
//!    so that the next block starts without a gap;
//! 5. write the CNC→PLC signals into `image`.

use std::collections::VecDeque;
use std::sync::Arc;

use packets::Signal;
use partprogram::Canon;

use crate::config::ProcessConfig;
use crate::exec::Phase;
use crate::following::{AxisMonitor, Peak};
use crate::handshake::{Channel, Kind, Note, bcd};
use crate::interp::{Interpolator, TickOut};
use crate::plant::{Drive, PlantSignals, Spindle};
use crate::signals::{self, ProcessSignals};
use crate::state::{Command, Interp, Mode, Reject, State, decide};
use crate::status::{AxisStatus, ProcessStatus};

/// A planned program's canonical blocks, shared between the part run that planned them and the
/// process that runs them (the plan of a 50 MB program is hundreds of megabytes: never copied).
pub type Blocks = Arc<Vec<Canon>>;

/// An alarm of a process.
#[derive(Debug, Clone, PartialEq)]
pub struct Alarm {
    /// The message (names the process, the function and the block where they matter).
    pub message: String,
    /// The alarm stopped the program (e-stop, following error, timeouts).
    pub stopping: bool,
}

/// Per-process counters for the run summary.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Counters {
    /// Blocks executed.
    pub blocks: u64,
    /// Completed functions per channel (M, S, T).
    pub handshakes: [u64; 3],
    /// Logic ticks spent waiting for FIN per channel (strobe up).
    pub wait_ticks: [u64; 3],
    /// Programs that ended with M02/M30.
    pub ended: u64,
    /// Logic ticks with CYCLE = 1.
    pub cycle_ticks: u64,
    /// Logic ticks with constant surface speed (FG96 = 1).
    pub css_ticks: u64,
    /// Highest spindle speed reached (rev/min, unsigned).
    pub spindle_top: f64,
    /// Gear range changes engaged for an S function.
    pub gear_changes: u64,
    /// Tool-correction requests that re-planned the following blocks.
    pub corrections: u64,
    /// A spindle on a `csv` drive: the highest speed its `606Ch` reported (rev/min, unsigned).
    pub spindle_drive_top: Option<f64>,
}

/// One process.
pub struct Process {
    pub(crate) cfg: ProcessConfig,
    pub(crate) sig: ProcessSignals,
    pub(crate) channels: [Option<Channel>; 3],
    pub(crate) interp: Box<dyn Interpolator>,
    pub(crate) drives: Vec<Drive>,
    /// The controller's velocity feed-forward per axis.
    servo: Vec<crate::servo::FeedForward>,
    /// The following-error monitor per axis.
    pub(crate) monitors: Vec<AxisMonitor>,
    /// The system variable UEP: 1 = no velocity feed-forward (PGCFIL `ASS=UEP`, 0 by default).
    uep: bool,
    pub(crate) spindle: Option<Spindle>,
    pub(crate) plant: PlantSignals,
    pub(crate) mode: Mode,
    pub(crate) run: Interp,
    pub(crate) on: bool,
    pub(crate) fault: bool,
    /// The e-stop chain opened while the machine was on and has not closed since.
    pub(crate) estop_open: bool,
    pub(crate) reset_pulse: bool,
    pub(crate) homed: bool,
    /// The selected program's blocks, shared with the part run that planned them (a planned
    /// program of a 50 MB file is hundreds of megabytes: it is never copied).
    pub(crate) program: Blocks,
    pub(crate) program_name: String,
    /// The program planned without and with block skip, when selected with both.
    pub(crate) programs: Option<(Blocks, Blocks)>,
    pub(crate) block_skip: bool,
    pub(crate) phase: Phase,
    pub(crate) next: usize,
    pub(crate) in_motion: VecDeque<usize>,
    pub(crate) pending_after: VecDeque<Vec<(Kind, u32)>>,
    pub(crate) last_s: Option<u32>,
    pub(crate) last_t: Option<i64>,
    pub(crate) spindle_dir: i8,
    pub(crate) css: Option<partprogram::Css>,
    pub(crate) gear: crate::spindle::Gear,
    pub(crate) mimm: u8,
    pub(crate) uso: bool,
    pub(crate) qckfd: bool,
    pub(crate) replanner: Option<crate::correction::Replanner>,
    pub(crate) skip_selected: bool,
    pub(crate) op_hold: bool,
    pub(crate) rabi_wait: u64,
    pub(crate) den: bool,
    pub(crate) held: bool,
    pub(crate) jog_last: Option<(usize, f64)>,
    pub(crate) home_stage: Option<(usize, crate::homing::Stage)>,
    pub(crate) homed_axes: Vec<bool>,
    pub(crate) alarms: Vec<Alarm>,
    pub(crate) new_alarms: Vec<Alarm>,
    pub(crate) commands: VecDeque<Command>,
    pub(crate) rejected: Vec<(Command, Reject)>,
    pub(crate) last_plc: (u8, u8, Option<u8>),
    /// The feed and rapid overrides last given to the interpolator (None: none yet).
    last_overrides: Option<(u8, u8)>,
    pub(crate) counters: Counters,
    pub(crate) rabi_timeout_ticks: u64,
    pub(crate) ticks_per_logic: usize,
    pub(crate) hand: crate::handwheel::Handwheels,
    pub(crate) zone2: bool,
    pub(crate) cub_on: bool,
    pub(crate) queued_end: Vec<f64>,
    pub(crate) manual_axes: Option<Vec<char>>,
    tick_out: TickOut,
    trajectory: Option<(u64, String)>,
    /// Axes on bus drives ([`crate::bus`]); None: the plant moves every axis.
    pub(crate) bus: Option<crate::bus::Bus>,
}

/// Settings shared by every process.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Timing {
    /// Logic tick in seconds.
    pub logic_tick_s: f64,
    /// Strobe timeout in logic ticks (0: none).
    pub strobe_timeout_ticks: u64,
    /// A disabled axis may hold a block this long before the alarm (logic ticks; 0: never).
    pub rabi_timeout_ticks: u64,
}

impl Process {
    /// A process at rest at `start` (process axis order), machine off until ESTOP reads 1.
    pub fn new(
        cfg: ProcessConfig,
        sig: ProcessSignals,
        interp: Box<dyn Interpolator>,
        start: &[f64],
        timing: Timing,
    ) -> Process {
        let channels = [Kind::M, Kind::S, Kind::T].map(|k| {
            sig.channels[signals::index(k)].map(|_| Channel::new(k, timing.strobe_timeout_ticks))
        });
        let drives = cfg
            .axes
            .iter()
            .enumerate()
            .map(|(i, a)| Drive::new(a.kv, start.get(i).copied().unwrap_or(0.0)))
            .collect();
        let monitors = cfg
            .axes
            .iter()
            .enumerate()
            .map(|(i, a)| {
                AxisMonitor::new(a.name, a.srv, a.kv, start.get(i).copied().unwrap_or(0.0))
            })
            .collect();
        let servo = vec![crate::servo::FeedForward::default(); cfg.axes.len()];
        let spindle = cfg.spindle.as_ref().map(|s| Spindle::new(s.accel));
        let gear = crate::spindle::Gear {
            engaged: u8::from(cfg.spindle.as_ref().is_some_and(|s| s.ranges.len() == 1)),
            timeout: timing.strobe_timeout_ticks,
            ..Default::default()
        };
        let ticks_per_logic = (timing.logic_tick_s / cfg.int_tick_s).round().max(1.0) as usize;
        let homed = cfg.axes.iter().all(|a| !a.needs_homing);
        let homed_axes = cfg.axes.iter().map(|a| !a.needs_homing).collect();
        Process {
            cfg,
            sig,
            channels,
            interp,
            drives,
            servo,
            monitors,
            uep: false,
            spindle,
            plant: PlantSignals::default(),
            mode: Mode::Idle,
            run: Interp::Idle,
            on: false,
            fault: false,
            estop_open: false,
            reset_pulse: false,
            homed,
            program: Arc::default(),
            program_name: String::new(),
            programs: None,
            block_skip: false,
            phase: Phase::Fetch,
            next: 0,
            in_motion: VecDeque::new(),
            pending_after: VecDeque::new(),
            last_s: None,
            last_t: None,
            spindle_dir: 0,
            css: None,
            gear,
            mimm: 0,
            uso: false,
            qckfd: false,
            replanner: None,
            skip_selected: false,
            op_hold: false,
            rabi_wait: 0,
            den: true,
            held: false,
            jog_last: None,
            home_stage: None,
            homed_axes,
            alarms: Vec::new(),
            new_alarms: Vec::new(),
            commands: VecDeque::new(),
            rejected: Vec::new(),
            last_plc: (0, 0, None),
            last_overrides: None,
            counters: Counters::default(),
            rabi_timeout_ticks: timing.rabi_timeout_ticks,
            ticks_per_logic,
            hand: Default::default(),
            zone2: false,
            cub_on: false,
            queued_end: start.to_vec(),
            manual_axes: None,
            tick_out: TickOut::default(),
            bus: None,
            trajectory: None,
        }
    }

    /// The process number.
    pub fn number(&self) -> u8 {
        self.cfg.number
    }

    /// Selects the program (canonical blocks) and its name; the interpreter must be idle.
    pub fn load(&mut self, name: &str, blocks: impl Into<Blocks>) -> Result<(), Reject> {
        if self.run != Interp::Idle {
            return Err(Reject::ProgramActive);
        }
        self.program = blocks.into();
        self.programs = None;
        self.program_name = name.to_string();
        self.next = 0;
        self.phase = Phase::Fetch;
        Ok(())
    }

    /// Selects a program planned twice: without and with block skip (blocks marked `/`); START
    /// from the program's start takes the one the PLC's BSKIP switch selects.
    pub fn load_with_skip(
        &mut self,
        name: &str,
        plain: Blocks,
        skipped: Blocks,
    ) -> Result<(), Reject> {
        self.load(name, Arc::clone(&plain))?;
        self.programs = Some((plain, skipped));
        Ok(())
    }

    /// True when the last START from the program's start took the block-skip plan.
    pub fn skip_selected(&self) -> bool {
        self.skip_selected
    }

    /// Sets the alternative feed PGCFIL QFD (mm/min) that QCKFD selects.
    pub fn set_alternative_feed(&mut self, qfd: Option<f64>) {
        self.cfg.qfd = qfd;
    }

    /// Marks every axis referenced (an absolute-encoder machine, or a test without homing).
    pub fn set_homed(&mut self) {
        self.homed = true;
        self.homed_axes.iter_mut().for_each(|h| *h = true);
    }

    /// The index of axis `name` in the process.
    pub fn axis_index(&self, name: char) -> Option<usize> {
        self.cfg.axes.iter().position(|a| a.name == name)
    }

    /// Places axis `i` of the simulated machine: its position on the machine's scale at power-on
    /// and its home switch edge (see [`crate::homing`]).
    pub fn place_axis(&mut self, i: usize, start: f64, home_switch: Option<f64>) {
        if let Some(d) = self.drives.get_mut(i) {
            d.place(start, home_switch);
        }
    }

    /// Wires the simulated spindle drive's contacts and contactors.
    pub fn set_plant(&mut self, plant: PlantSignals) {
        self.plant = plant;
    }

    /// Queues an operator command; it is decided at the next tick.
    pub fn command(&mut self, c: Command) {
        self.commands.push_back(c);
    }

    /// The state [`decide`] sees.
    pub fn state(&self) -> State {
        State {
            on: self.on,
            mode: self.mode,
            interp: self.run,
            moving: !self.interp.is_idle() || self.hand.moving(),
            homed: self.homed,
            program: !self.program.is_empty(),
        }
    }

    /// Counters for the summary.
    pub fn counters(&self) -> &Counters {
        &self.counters
    }

    /// Active alarms.
    pub fn alarms(&self) -> &[Alarm] {
        &self.alarms
    }

    /// Alarms raised since the last call.
    pub fn take_new_alarms(&mut self) -> Vec<Alarm> {
        std::mem::take(&mut self.new_alarms)
    }

    /// Commands refused since the last call, with the reason.
    pub fn take_rejected(&mut self) -> Vec<(Command, Reject)> {
        std::mem::take(&mut self.rejected)
    }

    pub(crate) fn raise(&mut self, message: String, stopping: bool) {
        let prefix = format!("process {}: ", self.cfg.number);
        let a = Alarm {
            message: format!("{prefix}{message}"),
            stopping,
        };
        if !self.alarms.contains(&a) {
            self.alarms.push(a.clone());
            self.new_alarms.push(a);
        }
        if stopping {
            self.stop_everything();
        }
    }

    /// Abort motion, clear strobes and the program position (reset and stopping alarms).
    pub(crate) fn stop_everything(&mut self) {
        self.interp.abort();
        for ch in self.channels.iter_mut().flatten() {
            ch.step(0, false, true);
        }
        self.run = Interp::Idle;
        self.phase = Phase::Fetch;
        self.next = 0;
        self.in_motion.clear();
        self.pending_after.clear();
        self.den = true;
        self.mimm = 0;
        self.home_stage = None;
        self.css = None;
        self.gear.pending = false;
        self.stop_handwheels();
        self.op_hold = false;
        self.rabi_wait = 0;
    }

    /// A reset: stop, clear strobes and alarms, back to the program start.
    pub(crate) fn reset(&mut self) {
        self.stop_everything();
        self.alarms.clear();
        self.fault = false;
        self.reset_pulse = true;
        if let Some(b) = self.bus.as_mut() {
            b.fault_reset = true;
        }
        self.last_s = None;
        self.last_t = None;
        if self.estop_open {
            // The cause is still there: the alarm stays (raised again, as new).
            self.raise("emergency stop".into(), true);
        }
    }

    /// The machine's e-stop chain opened (`on` = false) or closed again. While it stays open
    /// after it opened on a running machine, its stopping alarm is raised again after a RESET.
    pub(crate) fn set_power(&mut self, estop_ok: bool) {
        let on = estop_ok && !self.fault;
        if estop_ok {
            self.estop_open = false;
        } else if self.on || self.estop_open {
            self.estop_open = true;
            if !self
                .alarms
                .iter()
                .any(|a| a.message.ends_with(": emergency stop"))
            {
                self.raise("emergency stop".into(), true);
            }
        }
        self.on = on;
    }

    /// One logic tick (see the module docs for the order).
    pub fn step(&mut self, tick: u64, out: &[u8], image: &mut [u8]) {
        if let Some(b) = self.bus.as_mut() {
            b.fault_reset = false;
        }
        self.read_plc(out);
        self.read_gear(out);
        while let Some(c) = self.commands.pop_front() {
            self.apply(c);
        }
        self.step_channels(tick, out, false);
        self.advance();
        self.step_channels(tick, out, true);
        self.manual(out);
        self.handwheels(out, image);
        self.run_interpolation(out);
        self.watch_limit_switches();
        self.watch_thread_wait();
        self.homing();
        self.advance();
        self.step_channels(tick, out, true);
        if self.run == Interp::Running {
            self.counters.cycle_ticks += 1;
        }
        if self.css.is_some() {
            self.counters.css_ticks += 1;
        }
        self.watch_gear();
        self.write_plc(image);
    }

    fn read_plc(&mut self, out: &[u8]) {
        let s = &self.sig;
        let start = signals::read(out, s.start, 0);
        let ers = signals::read(out, s.ers, 0);
        let modereq = s.mode_request.map(|m| m.read(out));
        let (last_start, last_ers, last_req) = self.last_plc;
        self.uso = signals::read(out, s.uso, 0) == 1;
        self.qckfd = signals::read(out, s.qckfd, 0) == 1;
        self.block_skip = signals::read(out, s.block_skip, 0) == 1;
        self.zone2 = signals::read(out, s.zone2, 0) == 1;
        self.cub_on = signals::read(out, s.cub, 0) == 1;
        let fov = signals::read(out, s.overrides[0], 100);
        let rov = signals::read(out, s.overrides[2], 100);
        // Only a changed override reaches the interpolator (a change replans its look-ahead).
        if self.last_overrides != Some((fov, rov)) {
            self.interp.set_feed_override(u16::from(fov));
            self.interp.set_rapid_override(u16::from(rov));
            self.last_overrides = Some((fov, rov));
        }
        // plc-interface-map.md: ACC1 ACC2 = 00 linear, 01 S-shaped, 10 exponential.
        let law = (signals::read(out, s.acc[0], 0) << 1) | signals::read(out, s.acc[1], 0);
        self.interp.set_law(law);
        if ers == 1 && last_ers == 0 {
            self.commands.push_back(Command::Reset);
        }
        if let Some(m) = modereq
            && Some(m) != last_req
            && last_req.is_some()
            && let Some(mode) = Mode::from_code(m)
        {
            self.commands.push_back(Command::SetMode(mode));
        }
        if start == 1 && last_start == 0 {
            self.commands.push_back(Command::Start);
        }
        self.last_plc = (start, ers, modereq);
    }

    fn apply(&mut self, c: Command) {
        if let Err(r) = decide(&self.state(), c) {
            self.rejected.push((c, r));
            return;
        }
        match c {
            Command::Reset => self.reset(),
            Command::SetMode(m) => self.mode = m,
            Command::Start => {
                self.op_hold = false;
                if self.run == Interp::Idle
                    && self.next == 0
                    && let Some((plain, skipped)) = &self.programs
                {
                    self.skip_selected = self.block_skip;
                    self.program = Arc::clone(if self.block_skip { skipped } else { plain });
                }
                if self.run != Interp::Running {
                    self.run = Interp::Running;
                }
            }
            Command::Hold => self.op_hold = true,
            Command::Mdi | Command::Jog => {}
        }
    }

    /// Steps every channel; `only_new`: only the idle ones with a queued function (issued
    /// within this tick, so that the code goes out at once).
    fn step_channels(&mut self, tick: u64, out: &[u8], only_new: bool) {
        for i in 0..3 {
            let Some(ch) = self.channels[i].as_mut() else {
                continue;
            };
            if only_new && (ch.phase() != crate::handshake::Phase::Idle || ch.idle()) {
                continue;
            }
            let fin = self.sig.channels[i].is_some_and(|c| c.fin.read(out) == 1);
            let done_before = ch.done;
            let (_, note) = ch.step(tick, fin, false);
            if matches!(ch.phase(), crate::handshake::Phase::Strobe { .. }) && !only_new {
                self.counters.wait_ticks[i] += 1;
            }
            self.counters.handshakes[i] += ch.done - done_before;
            if let Some(Note::Timeout(f)) = note {
                let block = self.block_label();
                self.raise(
                    format!("{f} not acknowledged (FIN) within the strobe timeout ({block})"),
                    true,
                );
            }
        }
    }

    /// `block 12 (N40)` for the block being executed.
    pub(crate) fn block_label(&self) -> String {
        let i = self.in_motion.front().copied().unwrap_or(self.next);
        match self.program.get(i).and_then(|b| b.n) {
            Some(n) => format!("block {} (N{n})", i + 1),
            None => format!("block {}", i + 1),
        }
    }

    fn run_interpolation(&mut self, out: &[u8]) {
        let fold = signals::read(out, self.sig.fold, 0) == 1;
        let rabi_ok = self.rabi_ok(out);
        if !rabi_ok && !self.interp.is_idle() {
            self.rabi_wait += 1;
            if self.rabi_timeout_ticks > 0 && self.rabi_wait == self.rabi_timeout_ticks {
                let block = self.block_label();
                self.raise(
                    format!("axis enable (RABI) missing for a moving axis ({block})"),
                    true,
                );
            }
        } else {
            self.rabi_wait = 0;
        }
        let sov = f64::from(signals::read(out, self.sig.overrides[1], 100)) / 100.0;
        let hold_request = fold || self.op_hold;
        self.interp.set_hold(hold_request || !rabi_ok || !self.on);
        let powered = self.plant.run.is_empty() || self.plant.run.iter().any(|s| s.read(out) == 1);
        let dir = if powered {
            f64::from(self.spindle_dir)
        } else {
            0.0
        };
        let dt = self.cfg.int_tick_s;
        self.held = false;
        self.bus_begin();
        for k in 0..self.ticks_per_logic {
            if self.spindle.is_some() {
                // The law at the set points of the last tick (G96 follows the radius).
                let vmax = self.range_vmax();
                let target = self.law_rpm(self.interp.position()) * sov * dir;
                if let Some(sp) = self.spindle.as_mut() {
                    sp.set_target(target.clamp(-vmax, vmax));
                }
            }
            if let Some(sp) = self.spindle.as_mut() {
                sp.tick(dt);
                let top = &mut self.counters.spindle_top;
                *top = top.max(sp.actual().abs());
                self.interp.set_spindle_position(sp.position());
            }
            // Blocks are queued before every interpolation tick, as `ncplc nc run` queues them:
            // the same program gives the same look-ahead window and the same set points.
            if self.run == Interp::Running
                && self.on
                && self.mode != Mode::Home
                && self.phase == Phase::Motion
            {
                self.look_ahead();
            }
            self.tick_out.finished.clear();
            self.interp.tick(&mut self.tick_out);
            // A programmed block's motion, including the tick in which the last one ends (the
            // interpolator's tag is None from that tick on).
            let programmed = self.tick_out.tag.is_some_and(|t| t > 0)
                || self.tick_out.finished.iter().any(|t| *t > 0);
            self.tick_handwheels();
            self.held |= self.tick_out.held && hold_request;
            for tag in std::mem::take(&mut self.tick_out.finished) {
                self.motion_finished(tag);
            }
            let pos = self.interp.position().to_vec();
            if let Some((t, buf)) = self.trajectory.as_mut() {
                use std::fmt::Write as _;
                let p: Vec<String> = pos.iter().map(|v| partprogram::canon::num(*v)).collect();
                let block = self.tick_out.tag.map_or("null".to_string(), |g| {
                    g.checked_sub(1)
                        .map_or("null".to_string(), |b| b.to_string())
                });
                let _ = writeln!(
                    buf,
                    "{{\"t\":{t},\"p\":[{}],\"block\":{block},\"feed\":{}}}",
                    p.join(","),
                    partprogram::canon::num(self.tick_out.feed_mm_min)
                );
                *t += 1;
            }
            let vff = crate::servo::vff_active(self.mode, self.uep, programmed);
            for i in 0..self.drives.len() {
                let sp = pos.get(i).copied().unwrap_or(0.0);
                if let Some(answer) = self.bus_axis_tick(i, k, sp) {
                    self.drives[i].follow_bus(sp, answer);
                    continue;
                }
                let (d, ff) = (&mut self.drives[i], &mut self.servo[i]);
                let g = self.cfg.axes[i].gains();
                let w = ff.step(&g, vff, sp - d.command(), d.error(), dt);
                d.tick(sp, w, dt);
            }
            self.check_following(vff, dt);
            self.bus_tick_end(vff);
        }
    }

    fn rabi_ok(&self, out: &[u8]) -> bool {
        self.cfg
            .axes
            .iter()
            .enumerate()
            .all(|(i, _)| signals::read(out, self.sig.rabi.get(i).copied().flatten(), 1) == 1)
    }

    /// Every axis's error against its SRV limit in force; the first one beyond it stops the
    /// process (machine off) with an alarm naming the axis, the limit and why it applies.
    fn check_following(&mut self, vff: bool, dt: f64) {
        let mut first = None;
        for (i, (d, m)) in self.drives.iter().zip(&mut self.monitors).enumerate() {
            // A bus axis: the drive's answer with the set point it answers, when healthy.
            let (command, actual, vff) = match self.bus.as_ref().and_then(|b| b.check(i)) {
                Some(Some(answer)) => answer,
                Some(None) => continue,
                None => (d.command(), d.actual(), vff),
            };
            let e = m.check(command, actual, vff, dt);
            first = first.or(e);
        }
        if let Some(e) = first
            && self.on
        {
            self.raise(e.to_string(), true);
            self.fault = true;
            self.on = false;
        }
    }

    /// UEP (1 = no velocity feed-forward), as PGCFIL `ASS=UEP` or the operator sets it.
    pub fn set_uep(&mut self, on: bool) {
        self.uep = on;
    }

    /// The system variable UEP.
    pub fn uep(&self) -> bool {
        self.uep
    }

    /// Per axis: its letter and the largest following error seen with the limit it was checked
    /// against (None before the first interpolation tick).
    pub fn following_peaks(&self) -> Vec<(char, Option<Peak>)> {
        self.monitors.iter().map(|m| (m.name(), m.peak())).collect()
    }

    fn write_plc(&self, image: &mut [u8]) {
        let s = &self.sig;
        let standby = self.interp.is_idle() && !self.hand.moving();
        signals::write(image, s.conp, u8::from(self.on));
        signals::write(image, s.den, u8::from(self.den));
        signals::write(image, s.alarm, u8::from(!self.alarms.is_empty()));
        signals::write(image, s.cycle, u8::from(self.run == Interp::Running));
        signals::write(image, s.hold, u8::from(self.held));
        signals::write(image, s.standby, u8::from(standby));
        signals::write(image, s.mode, self.mode.code());
        signals::write(image, s.mimm, self.mimm);
        self.write_spindle(image);
        for (i, ch) in self.channels.iter().enumerate() {
            let (Some(ch), Some(cs)) = (ch, self.sig.channels[i]) else {
                continue;
            };
            let (code, strobe) = match ch.phase() {
                crate::handshake::Phase::CodeWritten { code } => (Some(code), false),
                crate::handshake::Phase::Strobe { code, .. } => (Some(code), true),
                _ => (None, false),
            };
            if let Some(code) = code {
                let bytes = match i {
                    0 => vec![bcd(code, 2) as u8],
                    1 => code.to_le_bytes().to_vec(),
                    _ => bcd(code, 8).to_le_bytes().to_vec(),
                };
                signals::write_bytes(image, cs.code, &bytes);
            }
            cs.strobe.write(image, u8::from(strobe));
        }
        self.write_limit_switches(image);
        for (i, a) in self.cfg.axes.iter().enumerate() {
            if let (Some(input), Some(pressed)) =
                (a.home.and_then(|h| h.input), self.home_pressed(i))
            {
                input.write(image, u8::from(!pressed));
            }
        }
        if let (Some(sp), Some(cfg)) = (&self.spindle, &self.cfg.spindle) {
            // A spindle on a drive: its contacts come from the drive's speed (bus.rs).
            let (at, stopped) = self.bus_spindle_contacts(sp, cfg).unwrap_or_else(|| {
                (
                    sp.at_speed(cfg.max_deviation),
                    sp.actual().abs() < cfg.limit_speed,
                )
            });
            write_opt(image, cfg.at_speed_signal, u8::from(at));
            write_opt(image, cfg.stopped_signal, u8::from(stopped));
            write_opt(image, self.plant.at_speed, u8::from(at));
            write_opt(image, self.plant.stopped, u8::from(stopped));
        }
    }

    /// A status snapshot for an HMI.
    pub fn status(&self) -> ProcessStatus {
        let mut out = ProcessStatus {
            process: self.cfg.number,
            mode: self.mode,
            interp: self.run,
            on: self.on,
            homed: self.homed,
            program: String::new(),
            block: 0,
            block_n: None,
            axes: Vec::new(),
            feed_mm_min: 0.0,
            spindle_rpm: 0.0,
            alarms: Vec::new(),
        };
        self.status_into(&mut out);
        out
    }

    /// Overwrites `out` with this process's status, reusing its strings and vectors: no
    /// allocation once `out` has held a status of this process (an HMI's copy on the scan thread).
    pub fn status_into(&self, out: &mut ProcessStatus) {
        let cmd = self.interp.position();
        let i = self.in_motion.front().copied().unwrap_or(self.next);
        out.process = self.cfg.number;
        out.mode = self.mode;
        out.interp = self.run;
        out.on = self.on;
        out.homed = self.homed;
        out.program.clone_from(&self.program_name);
        out.block = i;
        out.block_n = self.program.get(i).and_then(|b| b.n);
        out.axes.truncate(self.cfg.axes.len());
        for (k, ((a, d), m)) in self
            .cfg
            .axes
            .iter()
            .zip(&self.drives)
            .zip(&self.monitors)
            .enumerate()
        {
            let limit = m.limit();
            let axis = AxisStatus {
                name: a.name,
                command: cmd.get(k).copied().unwrap_or(0.0),
                actual: d.actual(),
                following_error: d.error(),
                limit,
                limit_mm: limit.of(&a.srv),
                largest: m.peak().map_or(0.0, |p| p.error),
            };
            match out.axes.get_mut(k) {
                Some(slot) => *slot = axis,
                None => out.axes.push(axis),
            }
        }
        out.feed_mm_min = self.tick_out.feed_mm_min;
        out.spindle_rpm = match self.bus_spindle_rpm() {
            Some(drive) => drive.unwrap_or(0.0),
            None => self.spindle.as_ref().map_or(0.0, |s| s.actual()),
        };
        out.alarms.truncate(self.alarms.len());
        for (k, a) in self.alarms.iter().enumerate() {
            match out.alarms.get_mut(k) {
                Some(slot) => slot.clone_from(&a.message),
                None => out.alarms.push(a.message.clone()),
            }
        }
    }

    /// Starts recording the trajectory; returns its header line (None: no interpolator header).
    /// `contour_blocks`: the program's blocks under contour control (for the header).
    pub fn record_trajectory(&mut self, contour_blocks: usize) -> Option<String> {
        let h = self.interp.trajectory_header(contour_blocks)?;
        self.trajectory = Some((0, String::new()));
        Some(h)
    }

    /// The summary line about contour control for a program with `contour_blocks` blocks under
    /// it (None when it has none).
    pub fn contour_summary(&self, contour_blocks: usize) -> Option<String> {
        self.interp.contour_summary(contour_blocks)
    }

    /// The trajectory lines recorded since the last call (one per interpolation tick:
    /// `{"t":0,"p":[x,z],"block":3,"feed":500}`).
    pub fn take_trajectory(&mut self) -> String {
        self.trajectory
            .as_mut()
            .map(|(_, s)| std::mem::take(s))
            .unwrap_or_default()
    }

    /// Set points of every axis (for `--trajectory`).
    pub fn set_points(&self) -> &[f64] {
        self.interp.position()
    }

    /// The loaded program's canonical blocks (for an HMI's tool path and block display).
    pub fn program(&self) -> &[Canon] {
        &self.program
    }

    /// The loaded program's name.
    pub fn program_name(&self) -> &str {
        &self.program_name
    }

    /// The axis letters of the process, in set-point order.
    pub fn axis_names(&self) -> Vec<char> {
        self.cfg.axes.iter().map(|a| a.name).collect()
    }

    /// True while a feed hold (operator, FOLD) keeps the path stopped.
    pub fn held(&self) -> bool {
        self.held
    }
}

fn write_opt(image: &mut [u8], s: Option<Signal>, v: u8) {
    if let Some(s) = s {
        s.write(image, v);
    }
}
