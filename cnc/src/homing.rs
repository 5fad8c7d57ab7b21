//! HOME mode: the MCZ homing cycle of every axis that has one, in process axis order, started by
//! START (characterization-system-axes.md §10.11).
//!
//! Stage 1: towards the home switch at the MAN speed in the MCZ direction (skipped when the switch
//! is already pressed). Stage 2: on the switch, stop, reverse at the MCZ speed and leave it.
//! Stage 3: go on to the next encoder reference mark (every PAS mechanical pitch on the machine's
//! scale); stop there; that point becomes coordinate 0 and the axis is homed. The switch is read
//! from the simulated machine (`sim.toml [[axis]] home_switch`), and also written to the MCZ input.
//!
//! An axis on a CiA 402 drive (`bus.rs`) is homed the way masters home CSP drives: the switch is
//! the drive's digital input (`60FDh` bit 2), and stage 3 arms the drive's touch probe on the
//! encoder's zero impulse once the switch is left; the position the drive latched at the mark
//! (exact, not the position of a later tick) becomes 0.

use partprogram::Canon;
use partprogram::canon::{Kind, Plane};

use crate::process::Process;
use crate::state::{Interp, Mode};

/// Where the cycle of one axis is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stage {
    /// About to start.
    Begin,
    /// Stage 1: moving towards the switch.
    Seek,
    /// Stage 2: stopping on the switch.
    Stop,
    /// Stage 2: moving back until the switch releases.
    Leave,
    /// Stage 3: moving to the reference mark at this machine position.
    Mark(f64),
    /// Stage 3 on a drive: moving with the touch probe armed until the drive latches a mark.
    Probe,
    /// Stopping after the mark at this coordinate.
    Settle(f64),
}

impl Process {
    /// The home switch of axis `i` is pressed (machine position beyond its edge in the search
    /// direction); `None` when the machine does not simulate it.
    pub(crate) fn home_pressed(&self, i: usize) -> Option<bool> {
        if let Some((switch, _)) = self.bus_homing(i) {
            return Some(switch);
        }
        let d = &self.drives[i];
        let edge = d.home_switch()?;
        let negative = self.cfg.axes[i].home.is_some_and(|h| h.negative);
        let p = d.machine_position();
        Some(if negative { p <= edge } else { p >= edge })
    }

    fn home_move(&mut self, i: usize, dir: f64, feed: f64) {
        let mut end: Vec<(char, f64)> = self
            .cfg
            .axes
            .iter()
            .enumerate()
            .map(|(k, a)| {
                (
                    a.name,
                    self.interp.position().get(k).copied().unwrap_or(0.0),
                )
            })
            .collect();
        end[i].1 += dir * 1000.0;
        let block = Canon {
            n: None,
            unit: None,
            kind: Kind::Linear,
            end,
            center: Vec::new(),
            plane: Plane::XY,
            feed: Some(feed),
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
        if let Err(e) = self.interp.push(0, &block) {
            let name = self.cfg.axes[i].name;
            self.raise(format!("homing of axis {name}: {e}"), true);
        }
    }

    /// One tick of the homing cycle (after the interpolation ticks).
    pub(crate) fn homing(&mut self) {
        if self.mode != Mode::Home || self.run != Interp::Running || !self.on {
            return;
        }
        let (i, stage) = match self.home_stage {
            Some(s) => s,
            None => match (0..self.cfg.axes.len()).find(|&i| !self.homed_axes[i]) {
                Some(i) => (i, Stage::Begin),
                None => {
                    self.homed = true;
                    self.run = Interp::Idle;
                    if let Err(e) = self.interp.set_soft_limits(true) {
                        self.raise(format!("homing: {e}"), true);
                    }
                    return;
                }
            },
        };
        let Some(home) = self.cfg.axes[i].home else {
            self.homed_axes[i] = true;
            self.home_stage = None;
            return;
        };
        let name = self.cfg.axes[i].name;
        let Some(pressed) = self.home_pressed(i) else {
            self.raise(
                format!("axis {name} has no simulated home switch (sim.toml [[axis]] home_switch)"),
                true,
            );
            self.home_stage = None;
            return;
        };
        let search = if home.negative { -1.0 } else { 1.0 };
        let next = match stage {
            Stage::Begin if pressed && self.interp.set_soft_limits(false).is_ok() => {
                self.home_move(i, -search, home.speed);
                Stage::Leave
            }
            Stage::Begin if self.interp.set_soft_limits(false).is_err() => {
                self.raise(
                    format!("homing of axis {name}: cannot lift the soft limits"),
                    true,
                );
                return;
            }
            Stage::Begin => {
                let fast = self.cfg.axes[i].jog_speed;
                self.home_move(i, search, fast);
                Stage::Seek
            }
            Stage::Seek if pressed => {
                self.interp.abort();
                Stage::Stop
            }
            Stage::Stop if self.interp.is_idle() => {
                self.home_move(i, -search, home.speed);
                Stage::Leave
            }
            Stage::Leave if !pressed && self.bus_homing(i).is_some() => Stage::Probe,
            Stage::Probe => match self.bus_homing(i) {
                Some((_, Some(mark))) => {
                    self.interp.abort();
                    Stage::Settle(mark)
                }
                _ if self.interp.is_idle() => {
                    // The search move ended without a latch: no reference mark on its way.
                    self.raise(
                        format!(
                            "homing of axis {name}: the drive latched no reference mark (touch probe 60B9h) within the search move"
                        ),
                        true,
                    );
                    self.home_stage = None;
                    return;
                }
                _ => Stage::Probe,
            },
            Stage::Leave if !pressed => {
                let p = self.drives[i].machine_position();
                let pitch = home.mark_pitch;
                // The next mark beyond p, moving in −search.
                let mark = if search > 0.0 {
                    ((p / pitch).ceil() - 1.0) * pitch
                } else {
                    ((p / pitch).floor() + 1.0) * pitch
                };
                Stage::Mark(mark)
            }
            Stage::Mark(mark) => {
                let p = self.drives[i].machine_position();
                if (search > 0.0 && p <= mark) || (search < 0.0 && p >= mark) {
                    self.interp.abort();
                    let coord = self.drives[i].actual() - (p - mark);
                    Stage::Settle(coord)
                } else {
                    Stage::Mark(mark)
                }
            }
            Stage::Settle(coord) if self.interp.is_idle() => {
                let mut pos = self.interp.position().to_vec();
                if let Some(v) = pos.get_mut(i) {
                    *v -= coord;
                }
                if let Err(e) = self.interp.set_position(&pos) {
                    self.raise(format!("homing of axis {name}: {e}"), true);
                    return;
                }
                self.drives[i].shift(coord);
                if self.bus_homing(i).is_some() {
                    // The drive's scale (where following errors are checked) does not move.
                    self.bus_shift(i, coord);
                } else {
                    self.monitors[i].shift(coord);
                }
                self.homed_axes[i] = true;
                self.home_stage = None;
                return;
            }
            s => s,
        };
        self.home_stage = Some((i, next));
    }
}
