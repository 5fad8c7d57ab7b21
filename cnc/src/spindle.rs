//! The spindle speed law of a process — direct rev/min (G97, MEFI G94/G95) or constant surface
//! speed (G96, MEFI KŘR) — and its gear ranges (GMxx).
//!
//! Under G96 the reference is recomputed every interpolation tick from the set point of the
//! controlling axis (ASM of the spindle, X when not given): n = v·1000 / (2π·r) rev/min, r measured
//! from the program zero carried by the block (half the distance for a diameter X), clamped by
//! Fanuc G50 S and by the engaged range's Vmax (the manual: the range cannot change within a
//! block, 000:1231). FG96 is 1 while the executing block has G96; the S function handed to the PLC
//! is the programmed word (the cutting speed), as SCODE.
//!
//! Gear ranges: an S function in rev/min needs the lowest-numbered range whose Vmax reaches it;
//! M41..M44 in the block fix range 1..4 and M40 returns to the automatic choice (000:405-410);
//! under G96 the range is the one for the speed at the radius where the block starts. An S above
//! every range (or above the fixed one) is a stopping alarm naming the block, never a silent clamp.
//! With more than one range, the kernel writes the range it needs to GEARREQ before the S strobe
//! and waits until the PLC reports the same number in GEARACK (the strobe timeout applies); the
//! spindle turns only in the engaged range, up to its Vmax. Without GEARACK in the map the kernel
//! engages the range itself; a spindle with one range has no gear handshake at all.

use partprogram::{Canon, Css};

use crate::handshake::Kind;
use crate::process::Process;
use crate::signals;
use crate::state::Mode;

/// The gear state of a process.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Gear {
    /// Range fixed by M41..M44 (None: chosen from S, M40).
    pub fixed: Option<u8>,
    /// Range engaged (GEARACK, or the kernel's own without it; 1 for a one-range spindle).
    pub engaged: u8,
    /// Range requested in GEARREQ (0: none yet).
    pub request: u8,
    /// The S function waits for the range (`request` not yet engaged).
    pub pending: bool,
    /// Logic ticks waited for GEARACK.
    pub waited: u64,
    /// The S function was held back for the range in this tick.
    pub waiting: bool,
    /// Timeout in logic ticks (the strobe timeout; 0: none).
    pub timeout: u64,
}

/// The lowest-numbered range (1-based) of `ranges` (Vmax per GM1, GM2, …) that reaches `rpm`.
pub fn range_for(ranges: &[f64], rpm: f64) -> Option<u8> {
    ranges
        .iter()
        .position(|v| *v >= rpm)
        .and_then(|i| u8::try_from(i + 1).ok())
}

impl Process {
    fn ranges(&self) -> &[f64] {
        self.cfg.spindle.as_ref().map_or(&[], |s| &s.ranges)
    }

    /// The engaged range's top speed (rev/min; 0 when no range is engaged).
    pub(crate) fn range_vmax(&self) -> f64 {
        let r = usize::from(self.gear.engaged);
        r.checked_sub(1)
            .and_then(|i| self.ranges().get(i))
            .copied()
            .unwrap_or(0.0)
    }

    /// The controlling axis of G96 and its index among the process axes.
    fn master(&self) -> Option<(char, usize)> {
        let name = self.cfg.spindle.as_ref().map_or('X', |s| s.master);
        self.axis_index(name).map(|i| (name, i))
    }

    /// G96 of the executing block, outside the manual modes (they do not perform it, 000:1231).
    fn css_active(&self) -> Option<&Css> {
        self.css
            .as_ref()
            .filter(|_| matches!(self.mode, Mode::Auto | Mode::Step | Mode::Mdi))
    }

    /// The spindle speed (rev/min, unsigned, before the override) the law asks for at the set
    /// points `pos`: G96 from the radius, else the last S.
    pub(crate) fn law_rpm(&self, pos: &[f64]) -> f64 {
        match (self.css_active(), self.master()) {
            (Some(c), Some((name, i))) => {
                let rpm = c.rpm_at(name, pos.get(i).copied().unwrap_or(0.0));
                rpm.min(c.max_rpm.unwrap_or(f64::INFINITY))
            }
            _ => f64::from(self.last_s.unwrap_or(0)),
        }
    }

    /// The block starts: its G96 state and M40..M44 range selection; with a new S (`s_out`), the
    /// range it needs. False (with a stopping alarm) when no range reaches the speed.
    pub(crate) fn spindle_block(&mut self, b: &Canon, s_out: bool) -> bool {
        self.css = b.css.clone();
        for f in &b.m {
            match f.m {
                40 => self.gear.fixed = None,
                41..=44 => self.gear.fixed = Some((f.m - 40) as u8),
                _ => {}
            }
        }
        let n = self.ranges().len();
        if !s_out || n == 0 {
            return true;
        }
        let rpm = match &self.css {
            Some(c) => self.css_start_rpm(c),
            None => f64::from(self.last_s.unwrap_or(0)),
        };
        if rpm == 0.0 {
            // S0 stops the spindle in whatever range is engaged.
            return true;
        }
        let top = |r: u8| self.ranges().get(usize::from(r) - 1).copied();
        let need = match self.gear.fixed {
            Some(r) => match top(r) {
                Some(v) if v >= rpm || self.css.is_some() => Some(r),
                Some(v) => return self.no_range(format!("beyond range {r} (GM{r} {v} rev/min)")),
                None => return self.no_range(format!("M{}: the spindle has no range {r}", 40 + r)),
            },
            None if self.css.is_some() => Some(range_for(self.ranges(), rpm).unwrap_or(n as u8)),
            None => match range_for(self.ranges(), rpm) {
                Some(r) => Some(r),
                None => {
                    let v = self.ranges().iter().copied().fold(0.0, f64::max);
                    return self.no_range(format!("beyond every gear range (top {v} rev/min)"));
                }
            },
        };
        if let Some(r) = need
            && n > 1
        {
            self.gear.request = r;
            self.gear.pending = r != self.gear.engaged;
            self.gear.waited = 0;
        }
        true
    }

    fn css_start_rpm(&self, c: &Css) -> f64 {
        let pos = self.interp.position().to_vec();
        let rpm = match self.master() {
            Some((name, i)) => c.rpm_at(name, pos.get(i).copied().unwrap_or(0.0)),
            None => 0.0,
        };
        rpm.min(c.max_rpm.unwrap_or(f64::INFINITY))
    }

    fn no_range(&mut self, why: String) -> bool {
        let block = self.block_label();
        let s = self.last_s.unwrap_or(0);
        self.raise(format!("S{s} {why} ({block})"), true);
        false
    }

    /// True when `group` may go out: an S in it waits for its gear range.
    pub(crate) fn gear_ready(&mut self, group: &[(Kind, u32)]) -> bool {
        if !self.gear.pending || !group.iter().any(|(k, _)| *k == Kind::S) {
            return true;
        }
        if self.sig.gear_ack.is_none() {
            self.gear.engaged = self.gear.request;
        }
        if self.gear.engaged == self.gear.request {
            self.gear.pending = false;
            self.counters.gear_changes += 1;
            return true;
        }
        self.gear.waiting = true;
        false
    }

    /// Once per logic tick: counts a tick the S function waited for GEARACK; the strobe timeout
    /// raises a stopping alarm naming the range and the block.
    pub(crate) fn watch_gear(&mut self) {
        if !std::mem::take(&mut self.gear.waiting) || !self.gear.pending {
            return;
        }
        self.gear.waited += 1;
        if self.gear.timeout > 0 && self.gear.waited == self.gear.timeout {
            let block = self.block_label();
            let r = self.gear.request;
            self.raise(
                format!("gear range {r} not engaged (GEARACK) within the strobe timeout ({block})"),
                true,
            );
        }
    }

    /// Reads GEARACK (multi-range spindles only).
    pub(crate) fn read_gear(&mut self, out: &[u8]) {
        if self.ranges().len() > 1
            && let Some(s) = self.sig.gear_ack
        {
            self.gear.engaged = s.read(out);
        }
    }

    /// Writes GEARREQ and FG96.
    pub(crate) fn write_spindle(&self, image: &mut [u8]) {
        signals::write(image, self.sig.fg96, u8::from(self.css_active().is_some()));
        if self.ranges().len() > 1 {
            signals::write(image, self.sig.gear_request, self.gear.request);
        }
    }
}
