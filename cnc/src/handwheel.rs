//! Handwheels under external (PLC) control, IOCFIL `ADV` (characterization-process-logic.md
//! §2.4.6 and §3.5).
//!
//! A channel declared by ADV counts the pulses of its handwheel from a packet-A input byte (a
//! modulo-256 counter; the simulated machine turns it, `sim.toml [[handwheel]]`). Every logic
//! tick the kernel reads the counter's change (−128 … 127 pulses) and moves the selected axis by
//! pulses × step, where:
//! - the axis is HW_AXIS1/HW_AXIS2 (W15N0/W15N1; 1-based process axis, 0 = none), the step the
//!   channel's nibble of HW_SCALE (W15N2: low nibble channel 1, high nibble channel 2; 0 = 1 µm,
//!   1 = 10 µm, 2 = 100 µm);
//! - pulses count only while HW_ON1/HW_ON2 (U15N24/U15N25) = 1, COMU = 1, FOLD = 0, the machine
//!   is on, the process's interpreter is IDLE (any mode but HOME) and no program or jog motion
//!   runs (STANDBY); pulses turned at any other time are dropped, and a handwheel move under way
//!   stops (the fastest in-limit stop) when a condition drops.
//! - The move is point-to-point (`motion::PtpAxis`, rsruckig; MAN speed and acceleration, no
//!   jerk limit), its target is the position at activation + pulses × step (exact: the pulses are
//!   counted in whole micrometres), clipped to the active zone and the CUB box ([`crate::zones`]).
//!
//! A scale code above 2, an axis number beyond the process's axes or an axis PGCFIL MAS does not
//! list raises a (non-stopping) alarm naming the channel and the value; the channel then does
//! nothing.

use motion::PtpAxis;

use crate::process::Process;
use crate::signals;
use crate::state::{Interp, Mode};

/// The step of HW_SCALE code `code`, µm.
pub fn step_um(code: u8) -> Option<u32> {
    match code {
        0 => Some(1),
        1 => Some(10),
        2 => Some(100),
        _ => None,
    }
}

/// One handwheel channel's move of one axis.
struct HandMove {
    axis: usize,
    ptp: PtpAxis,
    origin: f64,
    pulses: i64,
    step_um: u32,
    stopping: bool,
}

/// The handwheel channels of a process.
#[derive(Default)]
pub struct Handwheels {
    /// The packet-A counter byte of each channel (from the machine's wiring).
    pub(crate) counters: [Option<packets::Signal>; 2],
    last: [Option<u8>; 2],
    moves: [Option<HandMove>; 2],
}

impl Handwheels {
    /// A handwheel move is under way.
    pub fn moving(&self) -> bool {
        self.moves.iter().flatten().any(|m| !m.ptp.is_idle())
    }
}

impl Process {
    /// PGCFIL MAS: the axes that manual moves may use (None: every axis); a handwheel that
    /// selects another raises an alarm and does nothing.
    pub fn set_manual_axes(&mut self, axes: Option<Vec<char>>) {
        self.manual_axes = axes;
    }

    /// Wires the packet-A pulse counters of handwheel channels 1 and 2.
    pub fn set_handwheel_counters(&mut self, counters: [Option<packets::Signal>; 2]) {
        self.hand.counters = counters;
    }

    /// Reads the handwheels of this tick (`image`: the inputs the scan reads; `out`: the PLC's
    /// last outputs) and sets the targets of their moves.
    pub(crate) fn handwheels(&mut self, out: &[u8], image: &[u8]) {
        if self.hand.counters == [None, None] {
            return;
        }
        let s = &self.sig;
        let common = self.on
            && self.run == Interp::Idle
            && self.mode != Mode::Home
            && self.interp.is_idle()
            && signals::read(out, s.comu, 0) == 1
            && signals::read(out, s.fold, 0) == 0;
        let scale = signals::read(out, s.hw_scale, 0);
        for c in 0..2 {
            let Some(counter) = self.hand.counters[c].filter(|_| self.cfg.handwheels[c]) else {
                continue;
            };
            let now = counter.read(image);
            let delta = self.hand.last[c].map_or(0, |l| now.wrapping_sub(l) as i8);
            self.hand.last[c] = Some(now);
            let on = signals::read(out, self.sig.hw_on[c], 0) == 1;
            let axis = signals::read(out, self.sig.hw_axis[c], 0);
            let code = if c == 0 { scale & 0x0F } else { scale >> 4 };
            let enabled = common && on && axis > 0;
            if !enabled {
                if let Some(m) = self.hand.moves[c].as_mut()
                    && !m.stopping
                {
                    m.ptp.stop();
                    m.stopping = true;
                }
                continue;
            }
            let i = usize::from(axis) - 1;
            if i >= self.cfg.axes.len() {
                self.raise(
                    format!(
                        "handwheel channel {}: HW_AXIS{} = {axis}, the process has {} axes",
                        c + 1,
                        c + 1,
                        self.cfg.axes.len()
                    ),
                    false,
                );
                continue;
            }
            let name = self.cfg.axes[i].name;
            if self
                .manual_axes
                .as_ref()
                .is_some_and(|mas| !mas.contains(&name))
            {
                self.raise(
                    format!(
                        "handwheel channel {}: axis {name} is not in PGCFIL MAS (the axes of manual moves)",
                        c + 1
                    ),
                    false,
                );
                continue;
            }
            let Some(step) = step_um(code) else {
                self.raise(
                    format!(
                        "handwheel channel {}: scale code {code} in HW_SCALE is not 0, 1 or 2",
                        c + 1
                    ),
                    false,
                );
                continue;
            };
            let other = self.hand.moves[1 - c].as_ref().map(|m| m.axis);
            if other == Some(i) && c == 1 {
                continue;
            }
            let here = self.interp.position().get(i).copied().unwrap_or(0.0);
            let fresh = self.hand.moves[c]
                .as_ref()
                .is_none_or(|m| m.axis != i || m.step_um != step || m.stopping);
            if fresh {
                if delta == 0 {
                    self.hand.moves[c] = None;
                    continue;
                }
                let a = &self.cfg.axes[i];
                let ptp =
                    PtpAxis::new(a.jog_speed / 60.0, a.accel, None, self.cfg.int_tick_s, here);
                self.hand.moves[c] = Some(HandMove {
                    axis: i,
                    ptp,
                    origin: here,
                    pulses: 0,
                    step_um: step,
                    stopping: false,
                });
            }
            if delta == 0 {
                continue;
            }
            let v = self.cfg.axes[i].jog_speed / 60.0;
            let Some(want) = self.hand.moves[c].as_mut().map(|m| {
                m.pulses += i64::from(delta);
                m.origin + (m.pulses * i64::from(m.step_um)) as f64 / 1000.0
            }) else {
                continue;
            };
            let target = self.clip_single_axis(i, here, want);
            if let Some(m) = self.hand.moves[c].as_mut() {
                if target != want {
                    // Pulses beyond the limit are dropped: count on from the limit.
                    m.origin = target;
                    m.pulses = 0;
                }
                m.ptp.move_to(target, v);
            }
        }
    }

    /// One interpolation tick of the handwheel moves: their axes' set points.
    pub(crate) fn tick_handwheels(&mut self) {
        if self.hand.moves[0].is_none() && self.hand.moves[1].is_none() {
            return;
        }
        if !self.interp.is_idle() {
            // Another motion took the axes (it could only start once the handwheel rested).
            self.stop_handwheels();
            return;
        }
        let mut pos = self.interp.position().to_vec();
        for m in self.hand.moves.iter_mut().flatten() {
            if let Some(p) = pos.get_mut(m.axis) {
                *p = m.ptp.tick();
            }
        }
        if let Err(e) = self.interp.set_position(&pos) {
            self.raise(format!("handwheel: {e}"), true);
        }
        for slot in &mut self.hand.moves {
            if slot.as_ref().is_some_and(|m| m.stopping && m.ptp.is_idle()) {
                *slot = None;
            }
        }
    }

    /// Drops the handwheel moves (reset, stopping alarm).
    pub(crate) fn stop_handwheels(&mut self) {
        self.hand.moves = [None, None];
    }
}
