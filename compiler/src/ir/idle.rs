//! What a replay needs to know to jump over idle ticks: the SLOW cycle length and the timers whose
//! elapsed time may be advanced arithmetically.
//!
//! A tick is a pure function of the image. When `period` ticks without input leave the image
//! exactly as it was, every further such cycle does too, so a replay may jump to the next input.
//! When the only difference is the ET of *steady* timers (ET read by no expression, driven by one
//! `Stmt::Timer`), each of which gained exactly `executions × tick` with its flags unchanged, every
//! execution took the counting branch; the next cycles repeat it, shifted by that gain, until the
//! first ET would reach its preset. The replay may advance those ETs and jump that far.

use super::{Expr, Program, Stmt, TimerId};

/// A timer whose ET a replay may advance arithmetically.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SteadyTimer {
    /// Image offset of the timer state (i32 ET at +0, flags at +4).
    pub offset: usize,
    /// The preset PT in ms.
    pub preset_ms: i32,
    /// ET gained per cycle when every execution counts: executions per cycle × tick.
    pub gain_ms: i32,
}

/// Facts for skipping idle ticks (see the module docs).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct IdleFacts {
    /// Ticks per cycle: the number of SLOW slices (1 without a SLOW part).
    pub period: u32,
    /// Timers whose ET may be advanced, by ascending offset.
    pub timers: Vec<SteadyTimer>,
}

/// Where a timer is driven and whether its ET is read.
#[derive(Debug, Clone, Copy, Default)]
struct Use {
    drives_fast: u32,
    drives_slow: u32,
    et_read: bool,
}

impl Program {
    /// The facts a replay needs to skip idle ticks of this program.
    pub fn idle_facts(&self) -> IdleFacts {
        let mut uses = vec![Use::default(); self.timers.len()];
        walk(&self.fast, &mut uses, true);
        for slice in &self.slow {
            walk(slice, &mut uses, false);
        }
        let period = u32::try_from(self.slow.len().max(1)).unwrap_or(u32::MAX);
        let tick = i32::try_from(self.tick_ms).unwrap_or(0);
        let mut timers: Vec<SteadyTimer> = self
            .timers
            .iter()
            .zip(&uses)
            .filter_map(|(d, u)| {
                let execs = match (u.drives_fast, u.drives_slow, u.et_read) {
                    (1, 0, false) => i32::try_from(period).ok()?,
                    (0, 1, false) => 1,
                    _ => return None,
                };
                let gain_ms = execs.checked_mul(tick).filter(|g| *g > 0)?;
                Some(SteadyTimer {
                    offset: d.offset,
                    preset_ms: d.preset_ms,
                    gain_ms,
                })
            })
            .collect();
        timers.sort_by_key(|t| t.offset);
        IdleFacts { period, timers }
    }
}

fn walk(stmts: &[Stmt], uses: &mut [Use], fast: bool) {
    for s in stmts {
        match s {
            Stmt::Assign { value: e, .. }
            | Stmt::Set { cond: e, .. }
            | Stmt::Res { cond: e, .. }
            | Stmt::Pulse { input: e, .. }
            | Stmt::CounterCount { input: e, .. }
            | Stmt::CounterReset { input: e, .. } => reads(e, uses),
            Stmt::Timer { timer, input } => {
                reads(input, uses);
                if let Some(u) = uses.get_mut(timer.0 as usize) {
                    if fast {
                        u.drives_fast += 1;
                    } else {
                        u.drives_slow += 1;
                    }
                }
            }
            Stmt::If { cond, then_, else_ } => {
                reads(cond, uses);
                walk(then_, uses, fast);
                walk(else_, uses, fast);
            }
        }
    }
}

fn reads(e: &Expr, uses: &mut [Use]) {
    match e {
        Expr::TimerEt(TimerId(t)) => {
            if let Some(u) = uses.get_mut(*t as usize) {
                u.et_read = true;
            }
        }
        Expr::Const(_)
        | Expr::Load(_)
        | Expr::Pulse(_)
        | Expr::TimerQ(_)
        | Expr::CounterQ(_)
        | Expr::CounterCv(_) => {}
        Expr::BitOf { value: a, .. }
        | Expr::Not(a)
        | Expr::Unary { arg: a, .. }
        | Expr::Convert { arg: a, .. }
        | Expr::Bcd { arg: a, .. }
        | Expr::Bin { arg: a, .. } => reads(a, uses),
        Expr::Binary { lhs, rhs, .. } | Expr::Cmp { lhs, rhs, .. } => {
            reads(lhs, uses);
            reads(rhs, uses);
        }
        Expr::Limit { lo, x, hi, .. } => {
            reads(lo, uses);
            reads(x, uses);
            reads(hi, uses);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ir::{Place, ProgramBuilder, TimerKind, Value};

    fn input(name: &str) -> Expr {
        Expr::Load(Place::Signal(name.parse().expect("signal")))
    }

    #[test]
    fn steady_timers_are_driven_once_and_never_read_for_et() {
        // tick 10 ms, SLOW budget 0: every SLOW statement is a slice of its own (a cycle of 2).
        let mut b = ProgramBuilder::new(10, 0);
        let fast_t = b.timer("F", TimerKind::Ton, 95);
        let slow_t = b.timer("S", TimerKind::Tp, 30);
        let read_t = b.timer("R", TimerKind::Ton, 50);
        let twice_t = b.timer("W", TimerKind::Tof, 50);
        let timer = |t, i: &str| Stmt::Timer {
            timer: t,
            input: input(i),
        };
        let fast = vec![
            timer(fast_t, "I0A0"),
            timer(read_t, "I0A1"),
            Stmt::Assign {
                place: Place::Signal("U4A0".parse().expect("signal")),
                value: Expr::Cmp {
                    op: crate::ir::CmpOp::Gt,
                    ty: crate::ir::Ty::Dint,
                    lhs: Box::new(Expr::TimerEt(read_t)),
                    rhs: Box::new(Expr::Const(Value::Dint(20))),
                },
            },
            timer(twice_t, "I0A2"),
        ];
        let slow = vec![
            Stmt::If {
                cond: input("I0A3"),
                then_: vec![timer(slow_t, "I0A4")],
                else_: vec![timer(twice_t, "I0A5")],
            },
            Stmt::Assign {
                place: Place::Signal("U4A1".parse().expect("signal")),
                value: input("I0A6"),
            },
        ];
        let p = b.finish(fast, slow).expect("valid");
        let facts = p.idle_facts();
        assert_eq!(p.slow.len(), 2);
        assert_eq!(facts.period, 2);
        assert_eq!(
            facts.timers,
            vec![
                SteadyTimer {
                    offset: p.timers[0].offset,
                    preset_ms: 100,
                    gain_ms: 20,
                },
                SteadyTimer {
                    offset: p.timers[1].offset,
                    preset_ms: 30,
                    gain_ms: 10,
                },
            ]
        );
    }
}
