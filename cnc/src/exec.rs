//! The block executor of a process: runs the canonical blocks of the selected program, handing S,
//! T and M to the PLC as IOCFIL section 2 says and moving the axes through the interpolator.
//!
//! A block goes through: the functions before motion (GPS = 0: S, then T, then each before-motion
//! M, one after another; GPS = 1: S, T and the block's first before-motion M strobed together, the
//! rest one after another), its motion (DEN when the interpolator reports the block's tag), the
//! functions after motion one after another, then its requests: `m_request` 08 stops at the end of
//! the block, 02 stops when USO = 1, 20 ends the program (reset to its start). M03/M04/M05 also
//! set the direction of the CNC's spindle reference; an immediate function (`m_type` 10) has no
//! handshake: its BCD code is written to MIMM when the block's motion starts and held until a block
//! without one starts (the canonical blocks do not carry G27/G28, so continuous mode is the run of
//! consecutive blocks with immediate functions).
//!
//! Look-ahead: while a block moves, the following blocks are queued in the interpolator as long as
//! it has room and neither they nor the block before them have functions or requests (so paths
//! blend); the process runs the look-ahead again before every interpolation tick, so the window
//! stays as full as `ncplc nc run` keeps it. Any function is a sequence point, which also makes a
//! calculation-blocking function (`m_request` 04) wait for its FIN. In STEP mode every block ends
//! with a stop.

use std::collections::VecDeque;

use partprogram::canon::Kind as CanonKind;
use partprogram::{Canon, MTiming};

use crate::handshake::Kind;
use crate::process::Process;
use crate::state::{Interp, Mode};

/// Functions issued together (one group waits for all its FINs before the next goes out).
pub type Groups = VecDeque<Vec<(Kind, u32)>>;

/// Where the executor is in the current block.
#[derive(Debug, Clone, PartialEq)]
pub enum Phase {
    /// About to start block `next`.
    Fetch,
    /// Functions before motion: groups still to issue, and whether the front group is out.
    Before(Groups, bool),
    /// Motion of the blocks in `in_motion` (the last one is the current block).
    Motion,
    /// Functions after motion.
    After(Groups, bool),
    /// Block end: requests.
    End,
}

const REQ_OPTIONAL_STOP: u8 = 0x02;
const REQ_STOP: u8 = 0x08;
const REQ_CORRECTION: u8 = 0x10;
const REQ_RESET: u8 = 0x20;
const TYPE_IMMEDIATE: u8 = 0x10;

fn is_motion(b: &Canon) -> bool {
    !matches!(b.kind, CanonKind::Aux)
}

impl Process {
    fn timing(&self, m: u16) -> MTiming {
        self.cfg.m_timing.get(&m).copied().unwrap_or(MTiming {
            m_type: 0x02,
            m_request: 0,
            class: 0,
        })
    }

    /// True when `b` issues no function at all given the S and T already out.
    fn quiet(&self, b: &Canon) -> bool {
        b.m.is_empty() && s_code(b) == self.last_s && b.t == self.last_t && b.css == self.css
    }

    /// The groups of functions of block `b` before and after its motion.
    fn groups(&mut self, b: &Canon) -> (Groups, Groups) {
        let mut first: Vec<(Kind, u32)> = Vec::new();
        let mut before = VecDeque::new();
        let mut after = VecDeque::new();
        if let Some(s) = s_code(b)
            && Some(s) != self.last_s
        {
            self.last_s = Some(s);
            first.push((Kind::S, s));
        }
        if let Some(t) = b.t
            && Some(t) != self.last_t
        {
            self.last_t = Some(t);
            first.push((Kind::T, t.clamp(0, 99_999_999) as u32));
        }
        let mut mimm = 0;
        for f in &b.m {
            let t = self.timing(f.m);
            if t.m_type & TYPE_IMMEDIATE != 0 {
                mimm = crate::handshake::bcd(u32::from(f.m), 2) as u8;
                continue;
            }
            let item = (Kind::M, u32::from(f.m));
            if t.before_motion() {
                if self.cfg.parallel && !first.iter().any(|(k, _)| *k == Kind::M) {
                    first.push(item);
                } else {
                    before.push_back(vec![item]);
                }
            } else {
                after.push_back(vec![item]);
            }
        }
        self.mimm = mimm;
        if self.cfg.parallel {
            if !first.is_empty() {
                before.push_front(first);
            }
        } else {
            for (i, f) in first.into_iter().enumerate() {
                before.insert(i, vec![f]);
            }
        }
        (before, after)
    }

    /// Advances the executor as far as it can go this tick.
    pub(crate) fn advance(&mut self) {
        for _ in 0..8 {
            if self.run != Interp::Running || !self.on || self.mode == Mode::Home {
                return;
            }
            if !self.advance_once() {
                return;
            }
        }
    }

    /// One step of the executor; false when it must wait.
    fn advance_once(&mut self) -> bool {
        match std::mem::replace(&mut self.phase, Phase::Fetch) {
            Phase::Fetch => {
                let Some(b) = self.program.get(self.next).cloned() else {
                    // Ran off the end without M02/M30: the program ends here.
                    self.finish_program();
                    return false;
                };
                let (before, after) = self.groups(&b);
                let s_out = before.iter().flatten().any(|(k, _)| *k == Kind::S);
                if !self.spindle_block(&b, s_out) {
                    return false;
                }
                self.pending_after = after;
                self.phase = Phase::Before(before, false);
                true
            }
            Phase::Before(groups, out) => match self.issue_groups(groups, out) {
                Some((g, o)) => {
                    self.phase = Phase::Before(g, o);
                    false
                }
                None => {
                    let b = self.program[self.next].clone();
                    if is_motion(&b) {
                        if let Err(e) = self.zone_check(&b) {
                            let block = self.block_label();
                            self.raise(format!("{block} refused: {e}"), true);
                            return false;
                        }
                        let alt = crate::alt_feed::apply(&b, self.cfg.qfd, self.qckfd);
                        if let Err(e) = self
                            .interp
                            .push(self.next as u64 + 1, alt.as_ref().unwrap_or(&b))
                        {
                            let block = self.block_label();
                            self.raise(format!("motion of {block}: {e}"), true);
                            return false;
                        }
                        self.queued_end = end_point(&self.cfg.axis_names(), &b, &self.queued_end);
                        self.in_motion.push_back(self.next);
                        self.den = false;
                        self.phase = Phase::Motion;
                    } else {
                        self.phase = Phase::After(std::mem::take(&mut self.pending_after), false);
                    }
                    true
                }
            },
            Phase::Motion => {
                self.look_ahead();
                if self.in_motion.is_empty() {
                    self.den = true;
                    self.phase = Phase::After(std::mem::take(&mut self.pending_after), false);
                    true
                } else {
                    self.phase = Phase::Motion;
                    false
                }
            }
            Phase::After(groups, out) => match self.issue_groups(groups, out) {
                Some((g, o)) => {
                    self.phase = Phase::After(g, o);
                    false
                }
                None => {
                    self.phase = Phase::End;
                    true
                }
            },
            Phase::End => self.end_block(),
        }
    }

    /// Issues the front group when the channels are free; `None` when every group is done.
    fn issue_groups(&mut self, mut groups: Groups, out: bool) -> Option<(Groups, bool)> {
        let busy = self.channels.iter().flatten().any(|c| !c.idle());
        if out {
            if busy {
                return Some((groups, true));
            }
            groups.pop_front();
        }
        let front = groups.front()?.clone();
        if !self.gear_ready(&front) {
            return Some((groups, false));
        }
        for (kind, code) in front {
            if kind == Kind::M {
                match code {
                    3 => self.spindle_dir = 1,
                    4 => self.spindle_dir = -1,
                    5 => self.spindle_dir = 0,
                    _ => {}
                }
            }
            match self.channels[crate::signals::index(kind)].as_mut() {
                Some(ch) => ch.issue(code),
                None => {
                    let block = self.block_label();
                    self.raise(
                        format!(
                            "{} has no {kind:?} handshake in the interface map ({block})",
                            kind.name(code)
                        ),
                        true,
                    );
                    return Some((groups, false));
                }
            }
        }
        Some((groups, true))
    }

    /// Queues following motion-only blocks behind the current one, as long as the interpolator
    /// has room (its look-ahead window). Where the run of such blocks ends (the program's end, a
    /// block with functions or requests, STEP mode) the interpolator is told that nothing more
    /// comes before the path stops ([`crate::interp::Interpolator::end_of_input`]).
    pub(crate) fn look_ahead(&mut self) {
        if self.mode == Mode::Step || !self.pending_after.is_empty() {
            self.end_of_input();
            return;
        }
        while let Some(&last) = self.in_motion.back() {
            if self.interp.space() == 0 {
                return;
            }
            let cur = &self.program[last];
            if self.requests(cur) != 0 {
                self.end_of_input();
                return;
            }
            let Some(next) = self.program.get(last + 1).cloned() else {
                self.end_of_input();
                return;
            };
            if !is_motion(&next) || !self.quiet(&next) {
                self.end_of_input();
                return;
            }
            let alt = crate::alt_feed::apply(&next, self.cfg.qfd, self.qckfd);
            if self.zone_check(&next).is_err()
                || self
                    .interp
                    .push(last as u64 + 2, alt.as_ref().unwrap_or(&next))
                    .is_err()
            {
                // Refused when it becomes the current block (with its alarm); what is queued
                // runs to its end first.
                self.end_of_input();
                return;
            }
            self.queued_end = end_point(&self.cfg.axis_names(), &next, &self.queued_end);
            self.in_motion.push_back(last + 1);
            self.next = last + 1;
        }
    }

    /// The interpolator's held blocks go to its queue; a block it then refuses stops the process
    /// with an alarm naming it.
    fn end_of_input(&mut self) {
        if let Err(e) = self.interp.end_of_input() {
            let block = self.block_label();
            self.raise(format!("motion of {block}: {e}"), true);
        }
    }

    fn requests(&self, b: &Canon) -> u8 {
        b.m.iter()
            .fold(0, |acc, f| acc | self.timing(f.m).m_request)
    }

    /// The interpolator reports the end of the motion tagged `tag`.
    pub(crate) fn motion_finished(&mut self, tag: u64) {
        if let Some(pos) = self.in_motion.iter().position(|&i| i as u64 + 1 == tag) {
            for _ in 0..pos {
                self.in_motion.pop_front();
                self.counters.blocks += 1;
            }
            self.in_motion.pop_front();
            if !self.in_motion.is_empty() {
                self.counters.blocks += 1;
            }
        }
    }

    /// Applies the block's requests; true when execution goes on at once.
    fn end_block(&mut self) -> bool {
        let b = &self.program[self.next];
        let req = self.requests(b);
        self.counters.blocks += 1;
        self.next += 1;
        self.phase = Phase::Fetch;
        if req & REQ_CORRECTION != 0 {
            self.correction_request();
            if self.run != Interp::Running {
                return false;
            }
        }
        if req & REQ_RESET != 0 {
            self.counters.ended += 1;
            self.finish_program();
            return false;
        }
        let stop = req & REQ_STOP != 0 || (req & REQ_OPTIONAL_STOP != 0 && self.uso);
        if stop || self.mode == Mode::Step {
            self.run = Interp::Paused;
            return false;
        }
        if self.next >= self.program.len() {
            self.finish_program();
            return false;
        }
        true
    }

    /// End of the program: back to its start, interpreter idle.
    fn finish_program(&mut self) {
        self.run = Interp::Idle;
        self.next = 0;
        self.phase = Phase::Fetch;
        self.mimm = 0;
        self.den = true;
        self.css = None;
    }
}

/// The S code of a block (rounded rev/min).
fn s_code(b: &Canon) -> Option<u32> {
    b.s.map(|s| s.round().clamp(0.0, u32::MAX as f64) as u32)
}

/// Where block `b` leaves the axes (`before` for the axes it does not name).
fn end_point(axes: &[char], b: &Canon, before: &[f64]) -> Vec<f64> {
    axes.iter()
        .enumerate()
        .map(|(i, a)| {
            b.end_of(*a)
                .unwrap_or_else(|| before.get(i).copied().unwrap_or(0.0))
        })
        .collect()
}

impl Process {
    /// The active limits' check of motion block `b` from where the queued motion ends.
    fn zone_check(&self, b: &Canon) -> Result<(), crate::zones::ZoneError> {
        let start = if self.interp.is_idle() {
            self.interp.position()
        } else {
            &self.queued_end
        };
        self.check_zones(start, b)
    }
}
