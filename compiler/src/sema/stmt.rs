//! Statement checking: assignment targets (signals, names, bits, one-shots, timer and counter
//! inputs), `SET`/`RES`, `IF` zones; produces the IR statements of one part (FAST or SLOW).

use packets::{Dir, Packet, Signal};

use super::signals::{Access, check_signal};
use super::{Checker, Driven, SymKind, codes, memo};
use crate::ast::{AssignKind, Expr, Span, Stmt, StmtKind, Target, TargetKind};
use crate::ir::{self, CounterId, CounterKind, Place, PulseId, TimerId, Ty};

/// A resolved assignment target.
enum Tgt {
    /// A place of type `Ty`.
    Place(Place, Ty),
    /// One-shot `P<n>`.
    Pulse(PulseId, u16),
    /// A timer's input.
    Timer(TimerId),
    /// A counter's count input.
    Count(CounterId),
    /// A counter's R (CTU) or LD (CTD) input.
    Reset(CounterId),
}

impl Checker<'_> {
    /// Checks a list of statements.
    pub(crate) fn block(&mut self, stmts: &[Stmt]) -> Vec<ir::Stmt> {
        let mut out = Vec::with_capacity(stmts.len());
        for s in stmts {
            self.stmt(s, &mut out);
        }
        out
    }

    pub(crate) fn stmt(&mut self, s: &Stmt, out: &mut Vec<ir::Stmt>) {
        self.pending.clear();
        match &s.kind {
            StmtKind::Alias { .. } | StmtKind::Var { .. } | StmtKind::Error => {}
            StmtKind::If {
                cond,
                then_body,
                else_body,
            } => {
                self.statements += 1;
                let cond = self.expr_to(cond, Ty::Bool);
                let pending = std::mem::take(&mut self.pending);
                let mark = self.stmt_lines.len();
                let then_ = self.block(then_body);
                let else_ = self.block(else_body);
                if let Some(cond) = cond {
                    // Pre-order: the inline timers and the IF itself before its branches.
                    let line = self.line_of(&s.span);
                    let own = std::iter::repeat_n(line, pending.len() + 1);
                    self.stmt_lines.splice(mark..mark, own);
                    out.extend(pending);
                    out.push(ir::Stmt::If { cond, then_, else_ });
                } else {
                    self.stmt_lines.truncate(mark);
                }
            }
            StmtKind::Assign {
                kind,
                target,
                value,
            } => {
                self.statements += 1;
                if let Some(st) = self.assign(*kind, target, value, &s.span) {
                    let line = self.line_of(&s.span);
                    let n = self.pending.len() + 1;
                    self.stmt_lines.extend(std::iter::repeat_n(line, n));
                    out.append(&mut self.pending);
                    out.push(st);
                }
            }
        }
    }

    /// The 1-based line a statement starts on.
    fn line_of(&self, span: &Span) -> u32 {
        self.lines.line_column(span.start).0
    }

    fn assign(
        &mut self,
        kind: AssignKind,
        target: &Target,
        value: &Expr,
        stmt_span: &Span,
    ) -> Option<ir::Stmt> {
        let tgt = self.target(target);
        let stateful = |c: &mut Self, what: &str| {
            if kind != AssignKind::Coil {
                c.error(
                    codes::BAD_STATEFUL_USE,
                    &target.span,
                    format!("SET/RES cannot drive {what}"),
                    format!(
                        "drive {what} with a plain assignment: `{} = <input>`",
                        c.text.get(target.span.clone()).unwrap_or("target")
                    ),
                );
                return false;
            }
            true
        };
        match tgt? {
            Tgt::Place(place, ty) => {
                if kind == AssignKind::Coil {
                    let value = self.expr_to(value, ty)?;
                    return Some(ir::Stmt::Assign { place, value });
                }
                if ty != Ty::Bool {
                    self.error(
                        codes::SET_RES_NOT_BOOL,
                        &target.span,
                        format!("SET/RES needs a BOOL target, found {}", ty.name()),
                        "SET/RES write bits; assign numbers with `=`",
                    );
                    return None;
                }
                let cond = self.expr_to(value, Ty::Bool)?;
                Some(if kind == AssignKind::Set {
                    ir::Stmt::Set { place, cond }
                } else {
                    ir::Stmt::Res { place, cond }
                })
            }
            Tgt::Pulse(pulse, n) => {
                if !stateful(self, "a one-shot") {
                    return None;
                }
                self.drive(Driven::Pulse(n), &target.span, &format!("P{n}"));
                self.pulses_set.insert(n);
                if let Some(r) = &mut self.rec {
                    r.events.push(memo::Event::PulseSet(n));
                }
                let input = self.expr_to(value, Ty::Bool)?;
                Some(ir::Stmt::Pulse { pulse, input })
            }
            Tgt::Timer(timer) => {
                if !stateful(self, "a timer") {
                    return None;
                }
                self.drive(Driven::Timer(timer.0), &target.span, "this timer's input");
                let input = self.expr_to(value, Ty::Bool)?;
                Some(ir::Stmt::Timer { timer, input })
            }
            Tgt::Count(counter) => {
                if !stateful(self, "a counter") {
                    return None;
                }
                self.drive(
                    Driven::Count(counter.0),
                    &target.span,
                    "this counter's count input",
                );
                let input = self.expr_to(value, Ty::Bool)?;
                Some(ir::Stmt::CounterCount { counter, input })
            }
            Tgt::Reset(counter) => {
                if !stateful(self, "a counter input") {
                    return None;
                }
                let _ = stmt_span;
                self.drive(
                    Driven::Reset(counter.0),
                    &target.span,
                    "this counter's R/LD input",
                );
                let input = self.expr_to(value, Ty::Bool)?;
                Some(ir::Stmt::CounterReset { counter, input })
            }
        }
    }

    /// Records that `key` is driven here; a second driver is an error.
    pub(crate) fn drive(&mut self, key: Driven, span: &Span, what: &str) {
        // The error depends on the other statements: recorded as the drive, never as its error.
        self.flush_recorded_diags();
        if let Some(r) = &mut self.rec {
            r.events
                .push(memo::Event::Drive(key, span.clone(), what.to_string()));
        }
        self.drive_now(key, span, what);
        if let Some(r) = &mut self.rec {
            r.flushed = self.diags.len();
        }
    }

    fn drive_now(&mut self, key: Driven, span: &Span, what: &str) {
        if let Some(first) = self.driven.get(&key) {
            let at = self.position(first.start);
            self.error(codes::DRIVEN_TWICE, span, format!("{what} is already driven at {at}"), "a one-shot, timer or counter input has exactly one assignment; combine the conditions with + (OR)");
        } else {
            self.driven.insert(key, span.clone());
        }
    }

    /// The write rules for a signal reached through a name or a bit of a byte.
    fn check_write(&mut self, sig: &Signal, span: &Span) -> bool {
        if sig.packet() == Packet::A && packets::is_a_input_connector(sig.packet_byte() as u16 / 4)
        {
            self.error(
                codes::WRITE_INPUT,
                span,
                format!("{sig} is a physical input; the logic cannot write it"),
                "write an output connector or a free K/N signal instead",
            );
            return false;
        }
        true
    }

    fn target(&mut self, t: &Target) -> Option<Tgt> {
        match &t.kind {
            TargetKind::Signal(raw) => {
                let mut d = Vec::new();
                let sig = check_signal(raw, &t.span, Access::Write, self.ctx, self.file, &mut d);
                self.diags.append(&mut d);
                let sig = sig?;
                let ty = if sig.bit().is_some() {
                    Ty::Bool
                } else {
                    Ty::Byte
                };
                Some(Tgt::Place(Place::Signal(sig), ty))
            }
            TargetKind::Pulse(n) => {
                let n = self.pulse_number(*n, &t.span)?;
                Some(Tgt::Pulse(self.builder.pulse(n), n))
            }
            TargetKind::Name(name) => {
                let i = self.target_symbol(&name.text, &t.span)?;
                match self.syms[i].kind.clone() {
                    SymKind::Place { place, ty, .. } => {
                        if let Place::Signal(sig) = place
                            && !self.check_write(&sig, &t.span)
                        {
                            return None;
                        }
                        Some(Tgt::Place(place, ty))
                    }
                    SymKind::Var { id, ty } => Some(Tgt::Place(Place::Var(id), ty)),
                    SymKind::Timer { id, .. } => Some(Tgt::Timer(id)),
                    SymKind::Counter { id, .. } => Some(Tgt::Count(id)),
                }
            }
            TargetKind::Member(name, member) => {
                let i = self.target_symbol(&name.text, &t.span)?;
                let m = member.text.as_str();
                match (self.syms[i].kind.clone(), m) {
                    (
                        SymKind::Counter {
                            id,
                            kind: CounterKind::Ctu,
                        },
                        "R",
                    ) => Some(Tgt::Reset(id)),
                    (
                        SymKind::Counter {
                            id,
                            kind: CounterKind::Ctd,
                        },
                        "LD",
                    ) => Some(Tgt::Reset(id)),
                    (SymKind::Timer { id, .. }, "IN") => Some(Tgt::Timer(id)),
                    (SymKind::Counter { kind, .. }, _) => {
                        let valid = if kind == CounterKind::Ctu {
                            "`c = x` counts, `c.R = x` resets"
                        } else {
                            "`c = x` counts down, `c.LD = x` loads"
                        };
                        self.error(
                            codes::NOT_ASSIGNABLE,
                            &member.span,
                            format!("`.{m}` of this counter cannot be assigned"),
                            valid,
                        );
                        None
                    }
                    (SymKind::Timer { .. }, _) => {
                        self.error(
                            codes::NOT_ASSIGNABLE,
                            &member.span,
                            format!("`.{m}` of a timer cannot be assigned"),
                            "drive the timer's input: `t = x`",
                        );
                        None
                    }
                    _ => {
                        self.error(
                            codes::BAD_MEMBER,
                            &member.span,
                            format!("`{}` has no member `.{m}`", name.text),
                            "members exist on counters (`.R`, `.LD`) and timers; `x.n` is bit n",
                        );
                        None
                    }
                }
            }
            TargetKind::Bit(base, bit) => self.bit_target(base, *bit, &t.span),
        }
    }

    /// Looks up a target name, marks it written and warns when the CNC owns it.
    fn target_symbol(&mut self, name: &str, span: &Span) -> Option<usize> {
        let Some(i) = self.lookup(name) else {
            if !self.failed.contains(name) {
                let hint = self.suggest_name(
                    name,
                    format!("define it first: `DEF {name} = <signal>` or `DEF {name} : <type>`"),
                );
                self.error(
                    codes::UNDEFINED,
                    span,
                    format!("`{name}` is not defined"),
                    hint,
                );
            }
            return None;
        };
        self.mark_written(i);
        if self.syms[i].cnc_writes {
            self.warning(
                codes::WRITE_I_PREFIX,
                span,
                format!("`{name}` is written by the CNC (interface map direction CNC→PLC)"),
                "the CNC overwrites it; the logic normally only reads it",
            );
        }
        Some(i)
    }

    fn bit_target(&mut self, base: &Target, bit: u32, span: &Span) -> Option<Tgt> {
        let (place, ty) = match &base.kind {
            TargetKind::Signal(raw) => {
                let mut d = Vec::new();
                let sig = check_signal(raw, &base.span, Access::Write, self.ctx, self.file, &mut d);
                self.diags.append(&mut d);
                let sig = sig?;
                if sig.bit().is_some() {
                    self.error(
                        codes::BAD_OPERATOR,
                        span,
                        format!("{sig} is already a bit"),
                        "`.n` takes a bit of a byte or an integer",
                    );
                    return None;
                }
                (Place::Signal(sig), Ty::Byte)
            }
            TargetKind::Name(name) => {
                let i = self.target_symbol(&name.text, &base.span)?;
                match self.syms[i].kind.clone() {
                    SymKind::Place { place, ty, .. } => (place, ty),
                    SymKind::Var { id, ty } => (Place::Var(id), ty),
                    _ => {
                        self.error(
                            codes::BAD_OPERATOR,
                            span,
                            format!("`{}` has no bits", name.text),
                            "`.n` takes a bit of a byte or an integer",
                        );
                        return None;
                    }
                }
            }
            _ => return None,
        };
        if !ty.is_int() {
            self.error(
                codes::BAD_OPERATOR,
                span,
                format!("`.{bit}` needs an integer, found {}", ty.name()),
                "bits can be taken of BYTE, WORD, DWORD, INT, DINT",
            );
            return None;
        }
        if bit >= ty.bits() {
            self.error(
                codes::BIT_RANGE,
                span,
                format!("{} has no bit {bit}", ty.name()),
                format!("bits of a {} are 0..{}", ty.name(), ty.bits() - 1),
            );
            return None;
        }
        let bit = bit as u8;
        let sig_bit = |at: Signal| match at {
            Signal::Byte {
                packet,
                connector,
                index,
            } => {
                let contact = index * 8 + bit;
                Some(Signal::Bit {
                    dir: Dir::Out,
                    packet,
                    connector,
                    contact,
                })
            }
            Signal::Bit { .. } => None,
        };
        let sig = match place {
            Place::Var(var) => return Some(Tgt::Place(Place::VarBit { var, bit }, Ty::Bool)),
            Place::Signal(at) | Place::View { at, .. } => sig_bit(at)?,
            Place::VarBit { .. } => return None,
        };
        if !self.check_write(&sig, span) {
            return None;
        }
        Some(Tgt::Place(Place::Signal(sig), Ty::Bool))
    }
}
