//! Jumping over idle ticks in a replay, exactly.
//!
//! A tick is a pure function of the image. The skipper snapshots the image at the start of a
//! quiet stretch (no inputs applied, no output changed) and, one SLOW cycle later, compares:
//! - the image is unchanged: every further cycle without input is the same, so the replay jumps
//!   whole cycles up to the next trace record;
//! - only the ET of steady timers grew, each by its full gain with its flags unchanged: the
//!   next cycles repeat that growth (see [`compiler::ir::IdleFacts`]), so the replay adds the
//!   gain per skipped cycle and stops one cycle short of the first ET that would reach its preset.
//!   The timer then expires at the very tick it would have tick by tick.
//!
//! Anything else (a counter moving, a variable drifting, an oscillating output) disarms the
//! skipper; after repeated misses it waits a little longer before snapshotting again, so a busy
//! program pays a copy and a compare of its image at most every [`MAX_COOLDOWN`] ticks.

use std::ops::Range;

use compiler::ir::{IdleFacts, SteadyTimer};

/// Longest wait, in quiet ticks, between two snapshots after misses.
pub const MAX_COOLDOWN: u64 = 64;

/// Decides when a replay may jump and how far (see the module docs).
#[derive(Debug, Clone)]
pub struct IdleSkipper {
    period: u64,
    timers: Vec<SteadyTimer>,
    /// Image ranges compared byte for byte: everything except the steady timers' ETs.
    exact: Vec<Range<usize>>,
    base: Vec<u8>,
    armed: bool,
    quiet: u64,
    wait: u64,
    cooldown: u64,
    skipped: u64,
}

impl IdleSkipper {
    /// A skipper for a program with `facts` over an image of `image_len` bytes.
    pub fn new(facts: &IdleFacts, image_len: usize) -> IdleSkipper {
        let timers: Vec<SteadyTimer> = facts
            .timers
            .iter()
            .copied()
            .filter(|t| t.offset + 4 <= image_len)
            .collect();
        let mut exact = Vec::with_capacity(timers.len() + 1);
        let mut at = 0;
        for t in &timers {
            if t.offset > at {
                exact.push(at..t.offset);
            }
            at = at.max(t.offset + 4);
        }
        if at < image_len {
            exact.push(at..image_len);
        }
        IdleSkipper {
            period: u64::from(facts.period.max(1)),
            timers,
            exact,
            base: vec![0; image_len],
            armed: false,
            quiet: 0,
            wait: 0,
            cooldown: 0,
            skipped: 0,
        }
    }

    /// Ticks jumped over so far.
    pub fn skipped(&self) -> u64 {
        self.skipped
    }

    /// Something happened in a tick (inputs applied or an output changed): start over.
    pub fn disturbed(&mut self) {
        self.armed = false;
        self.wait = 0;
        self.cooldown = 0;
    }

    /// Called before a tick that applies no input, with the image as the previous tick left it.
    pub fn before_quiet_tick(&mut self, image: &[u8]) {
        if self.armed {
            return;
        }
        if self.wait > 0 {
            self.wait -= 1;
            return;
        }
        if let Some(src) = image.get(..self.base.len()) {
            self.base.copy_from_slice(src);
            self.armed = true;
            self.quiet = 0;
        }
    }

    /// Called after a quiet tick that changed no output. `room` is the number of following ticks
    /// that carry no trace record. Returns how many of them the replay may skip; the image has
    /// then been advanced over them.
    pub fn after_quiet_tick(&mut self, image: &mut [u8], room: u64) -> u64 {
        if !self.armed {
            return 0;
        }
        self.quiet += 1;
        if self.quiet < self.period {
            return 0;
        }
        self.armed = false;
        let cycles = match self.cycles_left(image) {
            Some(n) => n.min(room / self.period),
            None => {
                self.cooldown = (self.cooldown * 2).clamp(1, MAX_COOLDOWN);
                self.wait = self.cooldown;
                return 0;
            }
        };
        self.cooldown = 0;
        if cycles == 0 {
            return 0;
        }
        for t in &self.timers {
            let et = read_i32(image, t.offset);
            if et != read_i32(&self.base, t.offset) {
                // cycles × gain < preset − ET: no overflow (checked by `cycles_left`).
                let add = i64::from(t.gain_ms) * cycles as i64;
                write_i32(image, t.offset, (i64::from(et) + add) as i32);
            }
        }
        let ticks = cycles * self.period;
        self.skipped += ticks;
        ticks
    }

    /// How many further cycles repeat the one just observed (`u64::MAX` for an unchanged image),
    /// or `None` when the image changed in a way that may not repeat.
    fn cycles_left(&self, image: &[u8]) -> Option<u64> {
        for r in &self.exact {
            if image.get(r.clone())? != self.base.get(r.clone())? {
                return None;
            }
        }
        let mut left = u64::MAX;
        for t in &self.timers {
            let (before, now) = (read_i32(&self.base, t.offset), read_i32(image, t.offset));
            if before == now {
                continue;
            }
            if before < 0 || i64::from(now) - i64::from(before) != i64::from(t.gain_ms) {
                return None;
            }
            // The last skipped cycle must end with ET ≤ PT − 1, as the observed one did.
            let room = i64::from(t.preset_ms) - 1 - i64::from(now);
            if room < 0 {
                return None;
            }
            left = left.min((room / i64::from(t.gain_ms)) as u64);
        }
        Some(left)
    }
}

fn read_i32(image: &[u8], at: usize) -> i32 {
    let mut b = [0u8; 4];
    if let Some(src) = image.get(at..at + 4) {
        b.copy_from_slice(src);
    }
    i32::from_le_bytes(b)
}

fn write_i32(image: &mut [u8], at: usize, v: i32) {
    if let Some(dst) = image.get_mut(at..at + 4) {
        dst.copy_from_slice(&v.to_le_bytes());
    }
}
