//! The laid-out program: declarations with their image offsets, the statement lists, and what
//! the runtime asks of a program (image length, initial image, written signals, state slots).

use packets::Signal;
use serde::{Deserialize, Serialize};

use super::{COUNTER_LEN, Place, Stmt, TIMER_LEN, Ty, Value};

/// An internal variable.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VarDecl {
    /// The declared name.
    pub name: String,
    /// The type.
    pub ty: Ty,
    /// Value written at start (ignored for RETAIN variables).
    pub init: Value,
    /// Kept across restarts (lives in the retain area).
    pub retain: bool,
    /// Image offset.
    pub offset: usize,
}

/// Timer kinds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum TimerKind {
    /// On-delay.
    Ton,
    /// Off-delay.
    Tof,
    /// Pulse.
    Tp,
}

/// A timer instance (named or inline).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct TimerDecl {
    /// The declared name; inline timers get a unique name from the front end (e.g. `TON@12:9`).
    pub name: String,
    /// The kind.
    pub kind: TimerKind,
    /// The preset in ms, rounded up to whole ticks (at most `i32::MAX` rounded down to ticks).
    pub preset_ms: i32,
    /// Image offset of the state.
    pub offset: usize,
}

/// Counter kinds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum CounterKind {
    /// Up counter.
    Ctu,
    /// Down counter.
    Ctd,
}

/// A counter instance.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct CounterDecl {
    /// The declared name.
    pub name: String,
    /// The kind.
    pub kind: CounterKind,
    /// The preset PV.
    pub preset: i32,
    /// Image offset of the state.
    pub offset: usize,
}

/// A one-shot `P<n>`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct PulseDecl {
    /// The number n (0..1023).
    pub n: u16,
    /// Image offset of the state byte.
    pub offset: usize,
}

/// What a state slot holds (for online change: a slot migrates when name and kind match).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum SlotKind {
    /// An internal variable.
    Var,
    /// A timer of that kind.
    Timer(TimerKind),
    /// A counter of that kind.
    Counter(CounterKind),
    /// A pulse.
    Pulse,
}

/// A named piece of state in the image.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct StateSlot {
    /// The name (`P2` for pulses).
    pub name: String,
    /// What it is.
    pub kind: SlotKind,
    /// The value type (variables; DINT for timers and counters; BOOL for pulses).
    pub ty: Ty,
    /// Image offset.
    pub offset: usize,
    /// Length in bytes.
    pub len: usize,
}

/// A lowered, laid-out and validated PLC program.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Program {
    /// The logic tick in ms (timers advance by it per execution).
    pub tick_ms: u32,
    /// The SLOW budget in ms the slices were cut for.
    pub time_slow_ms: u32,
    /// Variables.
    pub vars: Vec<VarDecl>,
    /// Timers.
    pub timers: Vec<TimerDecl>,
    /// Counters.
    pub counters: Vec<CounterDecl>,
    /// Pulses.
    pub pulses: Vec<PulseDecl>,
    /// The FAST part.
    pub fast: Vec<Stmt>,
    /// The SLOW part, cut into slices (one runs per tick, round robin).
    pub slow: Vec<Vec<Stmt>>,
    /// Start and end of the retain area.
    pub retain: (usize, usize),
    /// Total image length.
    pub image_len: usize,
    /// The 1-based source line of every statement in pre-order (FAST, then the SLOW slices in
    /// order; an IF before its branches); empty for a program built without a source. Read by
    /// [`super::flow::instrument`] only.
    #[serde(default)]
    pub lines: Vec<u32>,
}

impl Program {
    /// Total length of the image the engines need.
    pub fn image_len(&self) -> usize {
        self.image_len
    }
    /// The retain area (RETAIN variables), as an image byte range.
    pub fn retain_range(&self) -> std::ops::Range<usize> {
        self.retain.0..self.retain.1
    }
    /// The type of a place.
    pub fn place_ty(&self, place: &Place) -> Ty {
        match place {
            Place::Signal(Signal::Bit { .. }) | Place::VarBit { .. } => Ty::Bool,
            Place::Signal(Signal::Byte { .. }) => Ty::Byte,
            Place::View { ty, .. } => *ty,
            Place::Var(v) => self.vars.get(v.0 as usize).map_or(Ty::Bool, |d| d.ty),
        }
    }
    /// Writes the initial values of the non-RETAIN variables (the rest of the image is zero at start).
    pub fn init_image(&self, image: &mut [u8]) {
        for v in self.vars.iter().filter(|v| !v.retain) {
            let bytes = v.init.to_bits().to_le_bytes();
            let n = v.ty.size();
            if let Some(dst) = image.get_mut(v.offset..v.offset + n) {
                dst.copy_from_slice(&bytes[..n]);
            }
        }
    }
    /// A fresh image: zeroes plus initial values.
    pub fn new_image(&self) -> Vec<u8> {
        let mut image = vec![0u8; self.image_len];
        self.init_image(&mut image);
        image
    }
    /// Every packet signal the program writes (bits and bytes, sorted, without duplicates); a
    /// typed view contributes each of its bytes. Used by traces.
    pub fn written_signals(&self) -> Vec<Signal> {
        fn walk(stmts: &[Stmt], out: &mut Vec<Signal>) {
            for s in stmts {
                match s {
                    Stmt::Assign { place, .. }
                    | Stmt::Set { place, .. }
                    | Stmt::Res { place, .. } => match *place {
                        Place::Signal(Signal::Bit {
                            packet,
                            connector,
                            contact,
                            ..
                        }) => out.push(Signal::Bit {
                            dir: packets::Dir::Out,
                            packet,
                            connector,
                            contact,
                        }),
                        Place::Signal(sig @ Signal::Byte { .. }) => out.push(sig),
                        Place::View {
                            at:
                                Signal::Byte {
                                    packet,
                                    connector,
                                    index,
                                },
                            ty,
                        } => {
                            for i in 0..ty.size() as u8 {
                                out.push(Signal::Byte {
                                    packet,
                                    connector,
                                    index: index + i,
                                });
                            }
                        }
                        _ => {}
                    },
                    Stmt::If { then_, else_, .. } => {
                        walk(then_, out);
                        walk(else_, out);
                    }
                    _ => {}
                }
            }
        }
        let mut out = Vec::new();
        walk(&self.fast, &mut out);
        for s in &self.slow {
            walk(s, &mut out);
        }
        out.sort();
        out.dedup();
        out
    }
    /// The named state slots (variables, timers, counters, pulses) for online change.
    pub fn state_slots(&self) -> Vec<StateSlot> {
        let mut out = Vec::new();
        for v in &self.vars {
            out.push(StateSlot {
                name: v.name.clone(),
                kind: SlotKind::Var,
                ty: v.ty,
                offset: v.offset,
                len: v.ty.size(),
            });
        }
        for t in &self.timers {
            let kind = SlotKind::Timer(t.kind);
            out.push(StateSlot {
                name: t.name.clone(),
                kind,
                ty: Ty::Dint,
                offset: t.offset,
                len: TIMER_LEN,
            });
        }
        for c in &self.counters {
            let kind = SlotKind::Counter(c.kind);
            out.push(StateSlot {
                name: c.name.clone(),
                kind,
                ty: Ty::Dint,
                offset: c.offset,
                len: COUNTER_LEN,
            });
        }
        for p in &self.pulses {
            let name = format!("P{}", p.n);
            out.push(StateSlot {
                name,
                kind: SlotKind::Pulse,
                ty: Ty::Bool,
                offset: p.offset,
                len: 1,
            });
        }
        out
    }
    /// Number of statements (recursively) in the program.
    pub fn statement_count(&self) -> usize {
        fn count(s: &[Stmt]) -> usize {
            s.iter()
                .map(|s| match s {
                    Stmt::If { then_, else_, .. } => 1 + count(then_) + count(else_),
                    _ => 1,
                })
                .sum()
        }
        count(&self.fast) + self.slow.iter().map(|s| count(s)).sum::<usize>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ir::{Expr, ProgramBuilder};

    fn sig(s: &str) -> Signal {
        s.parse().expect("signal")
    }

    #[test]
    fn written_signals_list_bits_bytes_and_view_bytes_once() {
        let mut b = ProgramBuilder::new(10, 5);
        let t = b.timer("t", TimerKind::Tp, 10);
        let one = || Expr::Const(Value::Bool(true));
        let fast = vec![
            Stmt::Assign {
                place: Place::Signal(sig("I4A3")),
                value: one(),
            },
            Stmt::Set {
                place: Place::Signal(sig("U4A3")),
                cond: one(),
            },
            Stmt::Timer {
                timer: t,
                input: one(),
            },
        ];
        let zone = Stmt::If {
            cond: one(),
            then_: vec![Stmt::Assign {
                place: Place::View {
                    at: sig("W20K1"),
                    ty: Ty::Word,
                },
                value: Expr::Const(Value::Word(1)),
            }],
            else_: vec![Stmt::Res {
                place: Place::Signal(sig("U100N7")),
                cond: one(),
            }],
        };
        let p = b.finish(fast, vec![zone]).expect("valid");
        let names: Vec<String> = p.written_signals().iter().map(|s| s.to_string()).collect();
        // `Signal` order: bits (by packet, connector, contact) before bytes.
        assert_eq!(names, vec!["U4A3", "U100N7", "W20K1", "W20K2"]);
        let slots = p.state_slots();
        assert_eq!(slots.len(), 1);
        assert_eq!(slots[0].kind, SlotKind::Timer(TimerKind::Tp));
        assert_eq!(
            (slots[0].offset, slots[0].len),
            (p.timers[0].offset, TIMER_LEN)
        );
    }
}
