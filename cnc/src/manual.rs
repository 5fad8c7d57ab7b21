//! MANU and MANJ: jogging from the PLC's jog signals (JOGP1..8 / JOGM1..8, plc-interface-map
//! project signals) through the interpolator, within the active soft limits
//! (LO1 or LO2 by ZONE2, and the CUB box: [`crate::zones`]).
//!
//! MANU: while a jog bit is 1 the axis moves at its MAN speed towards its soft limit (1000 mm away
//! when it has none); when the bit drops the move is aborted (the fastest in-limit stop). MANJ:
//! each rising edge moves the axis by the JINC step (1 = 1 µm … 4 = 1 mm), clipped at the soft
//! limit. Only one axis jogs at a time (the lowest bit wins); jogs need the machine on and the
//! interpreter idle.

use partprogram::Canon;
use partprogram::canon::{Kind, Plane};

use crate::process::Process;
use crate::signals;
use crate::state::{Command, Interp, Mode, decide};

/// The jog step of a JINC code, mm.
pub fn increment(code: u8) -> Option<f64> {
    match code {
        1 => Some(0.001),
        2 => Some(0.01),
        3 => Some(0.1),
        4 => Some(1.0),
        _ => None,
    }
}

impl Process {
    /// The requested jog: (axis index, direction) of the lowest jog bit that is 1.
    fn jog_request(&self, out: &[u8]) -> Option<(usize, f64)> {
        (0..self.cfg.axes.len().min(8)).find_map(|i| {
            if signals::read(out, self.sig.jog[0][i], 0) == 1 {
                Some((i, 1.0))
            } else if signals::read(out, self.sig.jog[1][i], 0) == 1 {
                Some((i, -1.0))
            } else {
                None
            }
        })
    }

    /// Handles the jog signals of this tick (called before the interpolation ticks).
    pub(crate) fn manual(&mut self, out: &[u8]) {
        let req = self.jog_request(out);
        let edge = req.is_some() && self.jog_last.is_none();
        let was = self.jog_last;
        self.jog_last = req;
        if !matches!(self.mode, Mode::Manu | Mode::Manj) || self.run != Interp::Idle {
            return;
        }
        if self.mode == Mode::Manu && was.is_some() && req != was {
            self.interp.abort();
        }
        let Some((axis, dir)) = req else { return };
        let start = self.mode == Mode::Manu && req != was || self.mode == Mode::Manj && edge;
        if !start {
            return;
        }
        if let Err(r) = decide(&self.state_for_jog(), Command::Jog) {
            self.rejected.push((Command::Jog, r));
            return;
        }
        let a = &self.cfg.axes[axis];
        let here = self.interp.position().get(axis).copied().unwrap_or(0.0);
        let target = match self.mode {
            Mode::Manj => {
                let Some(step) = increment(signals::read(out, self.sig.jog_increment, 0)) else {
                    return;
                };
                here + dir * step
            }
            _ => {
                let (lo, hi) = self.active_limits(axis);
                if dir > 0.0 {
                    hi.unwrap_or(here + 1000.0)
                } else {
                    lo.unwrap_or(here - 1000.0)
                }
            }
        };
        let target = self.clip_single_axis(axis, here, target);
        if (target - here).abs() < 1e-9 {
            return;
        }
        let mut end: Vec<(char, f64)> = self
            .cfg
            .axes
            .iter()
            .enumerate()
            .map(|(i, ax)| {
                (
                    ax.name,
                    self.interp.position().get(i).copied().unwrap_or(0.0),
                )
            })
            .collect();
        end[axis].1 = target;
        let block = Canon {
            n: None,
            unit: None,
            kind: Kind::Linear,
            end,
            center: Vec::new(),
            plane: Plane::XY,
            feed: Some(a.jog_speed),
            m: Vec::new(),
            s: None,
            t: None,
            dwell: None,
            thread: false,
            thread_angle: 0.0,
            // A point-to-point move of the kernel's own ends at rest.
            exact_stop: true,
            tolerance: None,
            css: None,
            feed_g94: false,
            modal: partprogram::canon::BlockModal::default(),
        };
        let name = a.name;
        if let Err(e) = self.interp.push(0, &block) {
            self.raise(format!("jog of axis {name}: {e}"), false);
        }
    }

    /// The state for a jog decision: a jog already moving does not count as "moving".
    fn state_for_jog(&self) -> crate::state::State {
        crate::state::State {
            moving: false,
            ..self.state()
        }
    }
}
