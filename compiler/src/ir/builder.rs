//! [`ProgramBuilder`]: how the front end creates a [`Program`] — it declares state, gets ids back,
//! and `finish` lays out the image, rounds timer presets to ticks and cuts the SLOW part into slices.

use super::{
    COUNTER_LEN, CounterDecl, CounterId, CounterKind, HEADER_LEN, HEADER_OFFSET, IrError, Program,
    PulseDecl, PulseId, Stmt, TIMER_LEN, TimerDecl, TimerId, TimerKind, Ty, Value, VarDecl, VarId,
};

/// Cost units (see [`Stmt::cost`]) the SLOW part may spend per ms of `time_slow`.
pub const COST_UNITS_PER_MS: u32 = 10_000;

/// Collects declarations while the front end lowers statements.
#[derive(Debug, Clone, Default)]
pub struct ProgramBuilder {
    tick_ms: u32,
    time_slow_ms: u32,
    vars: Vec<(String, Ty, Value, bool)>,
    timers: Vec<(String, TimerKind, u64)>,
    counters: Vec<(String, CounterKind, i32)>,
    pulses: Vec<u16>,
}

impl ProgramBuilder {
    /// A builder for a program with logic tick `tick_ms` (0 counts as 1) and SLOW budget `time_slow_ms`.
    pub fn new(tick_ms: u32, time_slow_ms: u32) -> Self {
        ProgramBuilder {
            tick_ms: tick_ms.max(1),
            time_slow_ms,
            ..Default::default()
        }
    }

    /// Declares a variable; `init` defaults to zero (it must have type `ty`, checked by `finish`).
    pub fn var(&mut self, name: &str, ty: Ty, init: Option<Value>, retain: bool) -> VarId {
        self.vars.push((
            name.to_string(),
            ty,
            init.unwrap_or(Value::zero(ty)),
            retain,
        ));
        VarId(self.vars.len() as u32 - 1)
    }

    /// Declares a timer with a preset in ms (rounded up to whole ticks by `finish`).
    pub fn timer(&mut self, name: &str, kind: TimerKind, preset_ms: u64) -> TimerId {
        self.timers.push((name.to_string(), kind, preset_ms));
        TimerId(self.timers.len() as u32 - 1)
    }

    /// Declares a counter with preset PV.
    pub fn counter(&mut self, name: &str, kind: CounterKind, preset: i32) -> CounterId {
        self.counters.push((name.to_string(), kind, preset));
        CounterId(self.counters.len() as u32 - 1)
    }

    /// The pulse `P<n>`, created at its first mention.
    pub fn pulse(&mut self, n: u16) -> PulseId {
        if let Some(i) = self.pulses.iter().position(|&p| p == n) {
            return PulseId(i as u32);
        }
        self.pulses.push(n);
        PulseId(self.pulses.len() as u32 - 1)
    }

    /// The rounded preset of a timer: up to whole ticks, at most the largest tick multiple ≤ i32::MAX.
    pub fn round_preset(&self, preset_ms: u64) -> i32 {
        let tick = u64::from(self.tick_ms);
        let max = (i32::MAX as u64 / tick) * tick;
        let up = preset_ms.div_ceil(tick).saturating_mul(tick);
        up.min(max) as i32
    }

    /// Lays out the image, cuts `slow` into slices and validates the program.
    pub fn finish(self, fast: Vec<Stmt>, slow: Vec<Stmt>) -> Result<Program, IrError> {
        let mut at = HEADER_OFFSET + HEADER_LEN;
        let align = |at: usize, a: usize| at.div_ceil(a) * a;
        let mut vars = Vec::with_capacity(self.vars.len());
        // Non-RETAIN variables by decreasing size keep the padding small; ids keep declaration order.
        let mut order: Vec<usize> = (0..self.vars.len()).collect();
        order.sort_by_key(|&i| std::cmp::Reverse(self.vars[i].1.size()));
        let mut offsets = vec![0usize; self.vars.len()];
        for &i in order.iter().filter(|&&i| !self.vars[i].3) {
            let size = self.vars[i].1.size();
            at = align(at, size);
            offsets[i] = at;
            at += size;
        }
        let mut pulses = Vec::with_capacity(self.pulses.len());
        for &n in &self.pulses {
            pulses.push(PulseDecl { n, offset: at });
            at += 1;
        }
        at = align(at, 4);
        let mut timers = Vec::with_capacity(self.timers.len());
        for (name, kind, preset) in &self.timers {
            let preset_ms = self.round_preset(*preset);
            timers.push(TimerDecl {
                name: name.clone(),
                kind: *kind,
                preset_ms,
                offset: at,
            });
            at += TIMER_LEN;
        }
        let mut counters = Vec::with_capacity(self.counters.len());
        for (name, kind, preset) in &self.counters {
            counters.push(CounterDecl {
                name: name.clone(),
                kind: *kind,
                preset: *preset,
                offset: at,
            });
            at += COUNTER_LEN;
        }
        at = align(at, 8);
        let retain_start = at;
        for &i in order.iter().filter(|&&i| self.vars[i].3) {
            let size = self.vars[i].1.size();
            at = align(at, size);
            offsets[i] = at;
            at += size;
        }
        let retain = (retain_start, at);
        for (i, (name, ty, init, retain)) in self.vars.into_iter().enumerate() {
            vars.push(VarDecl {
                name,
                ty,
                init,
                retain,
                offset: offsets[i],
            });
        }
        let budget = self.time_slow_ms.saturating_mul(COST_UNITS_PER_MS);
        let program = Program {
            tick_ms: self.tick_ms,
            time_slow_ms: self.time_slow_ms,
            vars,
            timers,
            counters,
            pulses,
            fast,
            slow: split_slices(slow, budget),
            retain,
            image_len: at,
            lines: Vec::new(),
        };
        program.validate()?;
        Ok(program)
    }
}

/// The summed cost of a slice.
pub fn slice_cost(slice: &[Stmt]) -> u32 {
    slice.iter().map(Stmt::cost).fold(0, u32::saturating_add)
}

/// Cuts statements greedily into slices of at most `budget` cost units (a statement costlier than
/// the budget gets a slice of its own). Deterministic: depends only on the statements.
pub fn split_slices(stmts: Vec<Stmt>, budget: u32) -> Vec<Vec<Stmt>> {
    let mut slices = Vec::new();
    let mut cur = Vec::new();
    let mut cost = 0u32;
    for s in stmts {
        let c = s.cost();
        if !cur.is_empty() && cost.saturating_add(c) > budget {
            slices.push(std::mem::take(&mut cur));
            cost = 0;
        }
        cost = cost.saturating_add(c);
        cur.push(s);
    }
    if !cur.is_empty() {
        slices.push(cur);
    }
    slices
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ir::{Expr, Place};

    #[test]
    fn layout_follows_the_documented_order() {
        let mut b = ProgramBuilder::new(10, 5);
        let x = b.var("x", Ty::Byte, None, false);
        let y = b.var("y", Ty::Dint, Some(Value::Dint(7)), false);
        let r = b.var("r", Ty::Lreal, None, true);
        let p = b.pulse(2);
        assert_eq!(b.pulse(2), p);
        let t = b.timer("t", TimerKind::Ton, 45);
        let c = b.counter("c", CounterKind::Ctu, 3);
        let prog = b.finish(vec![], vec![]).expect("valid");
        assert_eq!(prog.vars[y.0 as usize].offset, 2256);
        assert_eq!(prog.vars[x.0 as usize].offset, 2260);
        assert_eq!(prog.pulses[p.0 as usize].offset, 2261);
        assert_eq!(prog.timers[t.0 as usize].offset, 2264);
        assert_eq!(prog.timers[t.0 as usize].preset_ms, 50);
        assert_eq!(prog.counters[c.0 as usize].offset, 2272);
        assert_eq!(prog.vars[r.0 as usize].offset, 2280);
        assert_eq!(prog.retain_range(), 2280..2288);
        assert_eq!(prog.image_len(), 2288);
        let image = prog.new_image();
        assert_eq!(&image[2256..2260], &[7, 0, 0, 0]);
    }

    #[test]
    fn slow_part_is_cut_by_cost() {
        let s = |n: u16| Stmt::Assign {
            place: Place::Signal(format!("U10K{n}").parse().expect("signal")),
            value: Expr::Const(Value::Bool(true)),
        };
        // Each statement costs 2; a budget of 5 holds two.
        let slices = split_slices((0..5).map(s).collect(), 5);
        assert_eq!(
            slices.iter().map(Vec::len).collect::<Vec<_>>(),
            vec![2, 2, 1]
        );
        let slices = split_slices((0..3).map(s).collect(), 0);
        assert_eq!(slices.len(), 3);
    }

    #[test]
    fn presets_round_up_to_ticks() {
        let b = ProgramBuilder::new(10, 5);
        assert_eq!(b.round_preset(0), 0);
        assert_eq!(b.round_preset(1), 10);
        assert_eq!(b.round_preset(50), 50);
        assert_eq!(b.round_preset(u64::MAX), 2_147_483_640);
    }
}
