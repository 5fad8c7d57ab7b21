//! Axes on bus drives (CiA 402 over CANopen): the kernel's half of the exchange.
//!
//! A process with axes on drives ([`Process::attach_bus`]) no longer moves those axes with the
//! plant model: per interpolation tick it records the set point ([`Process::bus_set_points`],
//! what the master sends as the target of that tick's SYNC) and takes the drive's actual
//! position from the feedback the caller installed before the step ([`Process::bus_feedback`]).
//! The master answers a logic tick's SYNCs after the scan published, so the feedback a step
//! takes is the answer to an earlier logic tick's set points (the previous one's, or older when
//! the master is late in real time; the caller says which): the following-error monitor
//! pairs each answer with the set point it answers (kept for a few steps, with its
//! feed-forward state), and the axis's actual position (DRO, summary, trace) is the drive's
//! last healthy one. An interpolation tick without a healthy answer (faulted, silent, no answer
//! yet) leaves the actual position where it was and is not checked: nothing from such a drive
//! is taken as a position. The spindle on a `csv` drive is commanded with the speed the
//! spindle model ramps to (revolutions per second); the drive's velocity actual (`606Ch`, the
//! last answer of a step) gives the spindle's at-speed and zero-speed contacts and the speed
//! the status shows ([`Process::bus_spindle_rpm`]): within POM's max deviation of the reference,
//! as the model's; no healthy answer is neither at speed nor stopped. The model keeps the
//! spindle's encoder position (threading).
//!
//! Homing a bus axis (the MCZ cycle, `homing.rs`) takes the home switch from the drive's digital
//! inputs (`60FDh` bit 2, [`Process::bus_home`]) and the reference mark from its touch probe:
//! while the cycle waits for the mark, [`Process::bus_probe`] asks the master to arm the probe
//! on the encoder's zero impulse, and the latched drive position becomes the axis's 0. The
//! drive keeps its own scale: the axis keeps an origin (the drive position of coordinate 0), so
//! the drive is sent set point + origin and its actual position − origin is the axis's.
//! Following errors are checked on the drive's scale, which homing does not move.
//!
//! Invariant: a process without a bus behaves exactly as before (no field of this module is
//! read on its path).

use std::collections::VecDeque;

use crate::process::Process;

/// How many earlier steps' set points a bus axis keeps for pairing answers with them.
const HISTORY: usize = 4;

/// One bus axis's exchange.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct BusAxis {
    /// This step's set points, one per interpolation tick.
    set_points: Vec<f64>,
    /// The set points of the last [`HISTORY`] steps, newest last.
    history: VecDeque<Vec<f64>>,
    /// The drive's answers (`None`: no healthy answer).
    feedback: Vec<Option<f64>>,
    /// Which step's set points `feedback` answers: 1 = the previous step's.
    age: usize,
    /// The drive position of the axis's coordinate 0 (moved by homing).
    origin: f64,
    /// The home switch (`60FDh` bit 2) of the drive's last answer.
    switch: bool,
    /// The touch probe's latched position (drive scale) while the drive says it stored one.
    probe: Option<f64>,
    /// The last answer of the installed feedback, when healthy.
    last: Option<f64>,
}

/// The bus side of a process.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Bus {
    /// Per coordinated axis (process order): on a drive or not.
    axes: Vec<Option<BusAxis>>,
    /// The spindle's drive.
    spindle: Option<BusAxis>,
    /// Feed-forward per interpolation tick of the last [`HISTORY`] steps, newest last.
    vff_history: VecDeque<Vec<bool>>,
    /// This step's feed-forward per interpolation tick.
    vff: Vec<bool>,
    /// A RESET was applied in this step (the drives get a fault reset).
    pub(crate) fault_reset: bool,
    /// Per axis, this interpolation tick's answer to check: (set point, actual, feed-forward).
    checks: Vec<Option<(f64, f64, bool)>>,
}

impl Bus {
    /// Axis `i`'s answer to check in this interpolation tick: `None` for an axis not on the
    /// bus, `Some(None)` when there is nothing healthy to check.
    pub(crate) fn check(&self, i: usize) -> Option<Option<(f64, f64, bool)>> {
        self.axes.get(i)?.as_ref()?;
        Some(self.checks.get(i).copied().flatten())
    }
}

/// What the drives of a process are told for the next SYNCs.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BusCommand {
    /// Power the drives (the process is on: CONP).
    pub enable: bool,
    /// Quick stop (the e-stop chain is open).
    pub quick_stop: bool,
    /// Fault reset (a RESET was applied in this step).
    pub fault_reset: bool,
}

/// The simulated machine behind a drive axis (for a simulated drive), in axis units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BusMachine {
    /// The machine position where the axis's coordinate 0 (the drive's position 0) stands.
    pub start: f64,
    /// The home switch's edge on the machine's scale, and true when it is pressed below it.
    pub home_switch: Option<(f64, bool)>,
    /// The reference marks' pitch on the machine's scale (PAS), 0 without an MCZ cycle.
    pub mark_pitch: f64,
}

impl Process {
    /// The simulated machine behind coordinated axis `axis` (`sim.toml [[axis]]` start and
    /// home switch, AXCFIL MCZ direction and PAS pitch), for a simulated drive; `None` for an
    /// axis the process does not have.
    pub fn bus_machine(&self, axis: char) -> Option<BusMachine> {
        let i = self.axis_index(axis)?;
        let d = self.drives.get(i)?;
        let home = self.cfg.axes.get(i)?.home;
        let below = home.is_some_and(|h| h.negative);
        Some(BusMachine {
            start: d.machine_position() - d.actual(),
            home_switch: d.home_switch().map(|e| (e, below)),
            mark_pitch: home.map_or(0.0, |h| h.mark_pitch),
        })
    }

    /// Puts the coordinated axes `axes` (and the spindle when `spindle`) on bus drives; an axis
    /// this process does not have is an error naming it.
    pub fn attach_bus(&mut self, axes: &[char], spindle: bool) -> Result<(), String> {
        let mut bus = Bus {
            axes: vec![None; self.cfg.axes.len()],
            checks: vec![None; self.cfg.axes.len()],
            ..Bus::default()
        };
        for &a in axes {
            let i = self
                .axis_index(a)
                .ok_or_else(|| format!("process {}: no coordinated axis {a}", self.cfg.number))?;
            bus.axes[i] = Some(BusAxis::default());
        }
        if spindle {
            if self.spindle.is_none() {
                return Err(format!("process {}: no spindle", self.cfg.number));
            }
            bus.spindle = Some(BusAxis::default());
        }
        self.bus = Some(bus);
        Ok(())
    }

    /// The interpolation tick in seconds and the interpolation ticks per logic tick (the SYNC
    /// period and the SYNCs per logic tick of its drives).
    pub fn interpolation(&self) -> (f64, usize) {
        (self.cfg.int_tick_s, self.ticks_per_logic)
    }

    /// True when the process has axes on bus drives.
    pub fn on_bus(&self) -> bool {
        self.bus.is_some()
    }

    /// Installs the drive's answers for axis `axis` (`S`: the spindle, in revolutions per
    /// second), for the next step: the answers to the SYNCs of the set points of `age` steps
    /// before it (1: the previous step's; in real time a late master makes it 2 or more); false
    /// when the axis is not on the bus.
    pub fn bus_feedback(&mut self, axis: char, values: &[Option<f64>], age: usize) -> bool {
        match self.bus_axis_mut(axis) {
            Some(b) => {
                b.feedback.clear();
                b.feedback.extend_from_slice(values);
                b.age = age;
                b.last = values.last().copied().flatten();
                if axis == 'S'
                    && let Some(rps) = b.last
                {
                    let top = self.counters.spindle_drive_top.get_or_insert(0.0);
                    *top = top.max((rps * 60.0).abs());
                }
                true
            }
            None => false,
        }
    }

    /// The spindle's speed from its `csv` drive (rev/min, signed, the last answer): `None`
    /// when the spindle is not on a drive, `Some(None)` without a healthy answer.
    pub fn bus_spindle_rpm(&self) -> Option<Option<f64>> {
        let b = self.bus.as_ref()?.spindle.as_ref()?;
        Some(b.last.map(|rps| rps * 60.0))
    }

    /// The spindle's (at speed, stopped) contacts from its drive's speed, as the model's are
    /// made: at speed within `cfg.max_deviation` of the reference `sp.target()` (never at a
    /// reference of 0), stopped below `cfg.limit_speed`; `None` when the spindle is not on a
    /// drive. Without a healthy answer it is neither.
    pub(crate) fn bus_spindle_contacts(
        &self,
        sp: &crate::plant::Spindle,
        cfg: &crate::config::SpindleConfig,
    ) -> Option<(bool, bool)> {
        let rpm = self.bus_spindle_rpm()?;
        let target = sp.target();
        Some(rpm.map_or((false, false), |r| {
            let at = target != 0.0 && (r - target).abs() <= cfg.max_deviation * target.abs();
            (at, r.abs() < cfg.limit_speed)
        }))
    }

    /// Installs the homing inputs of drive axis `axis` for the next step: the home switch
    /// (`60FDh` bit 2) and the touch probe's latched position (axis units on the drive's scale,
    /// `None` while it stored none); false when the axis is not on the bus.
    pub fn bus_home(&mut self, axis: char, switch: bool, probe: Option<f64>) -> bool {
        match self.bus_axis_mut(axis) {
            Some(b) => {
                b.switch = switch;
                b.probe = probe;
                true
            }
            None => false,
        }
    }

    /// True while the homing cycle of `axis` waits for its reference mark: the drive's touch
    /// probe is to be armed on the encoder's zero impulse.
    pub fn bus_probe(&self, axis: char) -> bool {
        let i = self.axis_index(axis);
        i.is_some_and(|i| self.bus_homing(i).is_some())
            && matches!(self.home_stage, Some((j, crate::homing::Stage::Probe)) if Some(j) == i)
    }

    /// Bus axis `i`'s homing state: (home switch, latched probe position in the axis's
    /// coordinates); `None` when axis `i` is not on the bus.
    pub(crate) fn bus_homing(&self, i: usize) -> Option<(bool, Option<f64>)> {
        let b = self.bus.as_ref()?.axes.get(i)?.as_ref()?;
        Some((b.switch, b.probe.map(|p| p - b.origin)))
    }

    /// Homing moved bus axis `i`'s coordinates by −`shift`: its origin moves by +`shift`.
    pub(crate) fn bus_shift(&mut self, i: usize, shift: f64) {
        if let Some(b) = self.bus.as_mut().and_then(|b| b.axes.get_mut(i)?.as_mut()) {
            b.origin += shift;
        }
    }

    /// The set points of `axis` this step produced, one per interpolation tick, on the drive's
    /// scale (`S`: the spindle's speed in revolutions per second).
    pub fn bus_set_points(&self, axis: char) -> Option<&[f64]> {
        let bus = self.bus.as_ref()?;
        let b = if axis == 'S' && bus.spindle.is_some() {
            bus.spindle.as_ref()
        } else {
            self.axis_index(axis)
                .and_then(|i| bus.axes.get(i))
                .and_then(Option::as_ref)
        };
        b.map(|b| b.set_points.as_slice())
    }

    /// What the drives are told with this step's set points.
    pub fn bus_command(&self) -> BusCommand {
        BusCommand {
            enable: self.on,
            quick_stop: self.estop_open,
            fault_reset: self.bus.as_ref().is_some_and(|b| b.fault_reset),
        }
    }

    /// A drive fault, lost drive or refused enable: a stopping alarm that switches the process
    /// off (as a following-error alarm does).
    pub fn drive_alarm(&mut self, message: String) {
        self.raise(message, true);
        self.fault = true;
        self.on = false;
    }

    fn bus_axis_mut(&mut self, axis: char) -> Option<&mut BusAxis> {
        let i = self.axis_index(axis);
        let bus = self.bus.as_mut()?;
        if axis == 'S' && bus.spindle.is_some() {
            return bus.spindle.as_mut();
        }
        bus.axes.get_mut(i?).and_then(Option::as_mut)
    }

    /// Start of a step's interpolation: the last step's set points go into the history, this
    /// step's begin empty (the oldest history's buffer is reused: no allocation once full).
    pub(crate) fn bus_begin(&mut self) {
        let Some(bus) = self.bus.as_mut() else { return };
        for b in bus.axes.iter_mut().flatten().chain(bus.spindle.as_mut()) {
            push_history(&mut b.history, &mut b.set_points);
        }
        push_history(&mut bus.vff_history, &mut bus.vff);
    }

    /// Interpolation tick `k`: records axis `i`'s set point `sp` and returns the drive's answer
    /// to the previous step's tick `k` in the axis's coordinates (the set point it answers and
    /// its feed-forward state go to the following-error check, on the drive's scale); `None` for
    /// an axis not on the bus. `Some(None)`: on the bus, no healthy answer.
    pub(crate) fn bus_axis_tick(&mut self, i: usize, k: usize, sp: f64) -> Option<Option<f64>> {
        let bus = self.bus.as_mut()?;
        let b = bus.axes.get_mut(i)?.as_mut()?;
        b.set_points.push(sp + b.origin);
        let older = |len: usize| len.checked_sub(b.age.max(1));
        let answered = older(b.history.len()).and_then(|j| b.history.get(j)?.get(k));
        let vff = older(bus.vff_history.len()).and_then(|j| bus.vff_history.get(j)?.get(k));
        let answer = match (answered, b.feedback.get(k).copied().flatten()) {
            (Some(&cmd), Some(actual)) => Some((cmd, actual, vff == Some(&true))),
            _ => None,
        };
        if let Some(c) = bus.checks.get_mut(i) {
            *c = answer;
        }
        Some(answer.map(|(_, actual, _)| actual - b.origin))
    }

    /// Interpolation tick: the feed-forward state of this tick, and the spindle's speed.
    pub(crate) fn bus_tick_end(&mut self, vff: bool) {
        let rps = self.spindle.as_ref().map(|s| s.actual() / 60.0);
        let Some(bus) = self.bus.as_mut() else { return };
        bus.vff.push(vff);
        if let (Some(b), Some(v)) = (bus.spindle.as_mut(), rps) {
            b.set_points.push(v);
        }
    }
}

/// Moves `current` to the end of `history` (at most [`HISTORY`] long) and leaves it empty.
fn push_history<T>(history: &mut VecDeque<Vec<T>>, current: &mut Vec<T>) {
    let mut recycled = if history.len() >= HISTORY {
        history.pop_front().unwrap_or_default()
    } else {
        Vec::new()
    };
    recycled.clear();
    std::mem::swap(&mut recycled, current);
    history.push_back(recycled);
}
