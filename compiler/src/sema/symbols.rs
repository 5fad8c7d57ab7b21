//! The declaration pass (`DEF` lines: names, typed views, internal variables, timers, counters),
//! the SPL limit, and the usage warnings computed after the statements were checked.

use packets::{Packet, Signal};

use super::signals::{Access, check_signal};
use super::types::{Lit, LitError, lit_value, type_by_name};
use super::{Checker, SymKind, Symbol, codes};
use crate::ast::{Expr, ExprKind, Name, Span, Stmt, StmtKind, TypeSpec, UnOp};
use crate::ir::{CounterKind, Place, TimerKind, Ty};
use crate::lexer::RawSignal;

/// Function and block names: they cannot be used as symbolic names.
pub(crate) const FUNCTIONS: &[&str] = &[
    "BCD", "BIN", "MIN", "MAX", "LIMIT", "ABS", "TON", "TOF", "TP", "CTU", "CTD",
];

/// True for packet signals the logic owns: `U` bits and bytes of packet-A output connectors.
fn is_output(sig: &Signal) -> bool {
    match *sig {
        Signal::Bit { dir, .. } => dir == packets::Dir::Out,
        Signal::Byte {
            packet, connector, ..
        } => packet == Packet::A && !packets::is_a_input_connector(connector),
    }
}

/// Two signal names for the same storage (the I/U prefix does not matter).
fn same_storage(a: &Signal, b: &Signal) -> bool {
    a.image_byte() == b.image_byte() && a.bit() == b.bit()
}

/// The value of a constant expression (a literal, possibly negated), if it is one.
pub(crate) fn const_lit(e: &Expr) -> Option<Lit> {
    match &e.kind {
        ExprKind::Int(v) => Some(Lit::Int(i64::from(*v))),
        ExprKind::Real(v) => Some(Lit::Real(*v)),
        ExprKind::Duration(ms) if ms.fract() == 0.0 && *ms <= 9.0e15 => Some(Lit::Int(*ms as i64)),
        ExprKind::Duration(ms) => Some(Lit::Real(*ms)),
        ExprKind::Bool(b) => Some(Lit::Bool(*b)),
        ExprKind::Unary(UnOp::Neg, inner) => match const_lit(inner)? {
            Lit::Int(v) => Some(Lit::Int(-v)),
            Lit::Real(v) => Some(Lit::Real(-v)),
            Lit::Bool(_) => None,
        },
        _ => None,
    }
}

impl Checker<'_> {
    /// Declares every `DEF` in `stmts` (and in nested `IF` blocks), then checks the SPL limit.
    pub(crate) fn declare_all<'s>(&mut self, stmts: impl Iterator<Item = &'s Stmt>) {
        let mut counted: Vec<Span> = Vec::new();
        for s in stmts {
            self.declare(s, &mut counted);
        }
        self.symbolic_names = counted.len();
        let spl = self.ctx.spl as usize;
        if counted.len() > spl {
            let span = counted[spl].clone();
            self.error(
                codes::SPL_EXCEEDED,
                &span,
                format!(
                    "the program defines {} symbolic names, but IOCFIL SPL allows {spl}",
                    counted.len()
                ),
                format!(
                    "set `SPL={}` in IOCFIL (at most 5000), or use signal names directly",
                    counted.len()
                ),
            );
        }
    }

    fn declare(&mut self, s: &Stmt, counted: &mut Vec<Span>) {
        match &s.kind {
            StmtKind::Alias {
                name,
                signal,
                signal_span,
            } => {
                self.declare_alias(name, signal, signal_span, counted);
                self.note_failed(name);
            }
            StmtKind::Var {
                name,
                ty,
                at,
                init,
                retain,
            } => {
                if self.name_available(name, None) {
                    counted.push(name.span.clone());
                    self.declare_var(name, ty, at.as_ref(), init.as_ref(), retain.as_ref());
                }
                self.note_failed(name);
            }
            StmtKind::If {
                then_body,
                else_body,
                ..
            } => {
                for s in then_body.iter().chain(else_body) {
                    self.declare(s, counted);
                }
            }
            StmtKind::Assign { .. } | StmtKind::Error => {}
        }
    }

    /// Reserved words, duplicates and predeclared names. `alias_of` is the signal of a
    /// `DEF name = signal` (a predeclared name may be re-declared to its own address).
    /// Returns true when the name may be defined and counted.
    fn name_available(&mut self, name: &Name, alias_of: Option<&Signal>) -> bool {
        let n = name.text.as_str();
        if type_by_name(n).is_some() || FUNCTIONS.contains(&n) {
            self.error(
                codes::RESERVED_NAME,
                &name.span,
                format!("`{n}` is a type or function name"),
                "choose another name (letters, digits and `_`, starting with a letter)",
            );
            return false;
        }
        if let Some(&i) = self.by_name.get(n) {
            let first = self.syms[i].span.start;
            let at = self.position(first);
            self.error(
                codes::DUPLICATE,
                &name.span,
                format!("`{n}` is already defined"),
                format!("the first definition is at {at}; rename one of them"),
            );
            return false;
        }
        if let Some(entry) = self.ctx.interface.get(n) {
            let entry = entry.clone();
            match alias_of {
                Some(sig) if same_storage(sig, &entry.signal) && entry.width.bytes() <= 1 => {
                    self.warning(
                        codes::PREDECLARED_SAME,
                        &name.span,
                        format!("`{n}` is predeclared as {}; this DEF repeats it", entry.signal),
                        "the interface map already defines it; the DEF can be removed",
                    );
                }
                _ => self.error(
                    codes::PREDECLARED_OTHER,
                    &name.span,
                    format!("`{n}` is a predeclared interface name ({}, {})", entry.signal, entry.meaning),
                    format!("use `{n}` as it is, choose another name, or move it in <machine>/interface.toml"),
                ),
            }
            return false;
        }
        true
    }

    /// A name whose DEF failed is not reported again as undefined where it is used.
    fn note_failed(&mut self, name: &Name) {
        if !self.by_name.contains_key(&name.text) && self.ctx.interface.get(&name.text).is_none() {
            self.failed.insert(name.text.clone());
        }
    }

    fn insert(&mut self, name: &Name, kind: SymKind) {
        self.by_name.insert(name.text.clone(), self.syms.len());
        self.syms.push(Symbol {
            name: name.text.clone(),
            kind,
            span: name.span.clone(),
            predeclared: false,
            cnc_writes: false,
            read: false,
            written: false,
        });
    }

    fn declare_alias(
        &mut self,
        name: &Name,
        raw: &RawSignal,
        span: &Span,
        counted: &mut Vec<Span>,
    ) {
        let mut d = Vec::new();
        let sig = check_signal(raw, span, Access::Read, self.ctx, self.file, &mut d);
        self.diags.append(&mut d);
        let Some(sig) = sig else { return };
        if !self.name_available(name, Some(&sig)) {
            return;
        }
        counted.push(name.span.clone());
        let ty = if sig.bit().is_some() {
            Ty::Bool
        } else {
            Ty::Byte
        };
        self.insert(
            name,
            SymKind::Place {
                place: Place::Signal(sig),
                ty,
                output: is_output(&sig),
            },
        );
    }

    fn declare_var(
        &mut self,
        name: &Name,
        spec: &TypeSpec,
        at: Option<&(RawSignal, Span)>,
        init: Option<&Expr>,
        retain: Option<&Span>,
    ) {
        let tn = spec.name.text.as_str();
        let timer = match tn {
            "TON" => Some(TimerKind::Ton),
            "TOF" => Some(TimerKind::Tof),
            "TP" => Some(TimerKind::Tp),
            _ => None,
        };
        let counter = match tn {
            "CTU" => Some(CounterKind::Ctu),
            "CTD" => Some(CounterKind::Ctd),
            _ => None,
        };
        if timer.is_some() || counter.is_some() {
            for (extra, what) in [
                (at.map(|a| &a.1), "AT"),
                (init.map(|e| &e.span), ":="),
                (retain, "RETAIN"),
            ] {
                if let Some(span) = extra {
                    let code = if what == "RETAIN" {
                        codes::BAD_RETAIN
                    } else {
                        codes::BAD_INIT
                    };
                    self.error(
                        code,
                        span,
                        format!("a {tn} takes no {what}"),
                        format!("write `DEF {} : {tn}(preset)`", name.text),
                    );
                }
            }
            let preset = self.preset(spec, tn, timer.is_some());
            let tick = i64::from(self.ctx.tick_ms);
            if let (Some(_), Some(p)) = (timer, preset)
                && p > 0
                && p < tick
                && let Some(arg) = spec.args.as_ref().and_then(|a| a.first())
            {
                self.warning(
                    codes::SHORT_TIMER,
                    &arg.span,
                    format!(
                        "{tn} preset {p} ms is shorter than the logic tick of {tick} ms: it runs out at the first tick"
                    ),
                    format!("timers count whole ticks; use a preset of at least {tick} ms"),
                );
            }
            if let Some(kind) = timer {
                let id = self
                    .builder
                    .timer(&name.text, kind, preset.unwrap_or(0).max(0) as u64);
                self.insert(name, SymKind::Timer { id, kind });
            } else if let Some(kind) = counter {
                let pv = preset.and_then(|p| i32::try_from(p).ok()).unwrap_or(0);
                let id = self.builder.counter(&name.text, kind, pv);
                self.insert(name, SymKind::Counter { id, kind });
            }
            return;
        }
        let Some(ty) = type_by_name(tn) else {
            self.error(
                codes::UNKNOWN_TYPE,
                &spec.name.span,
                format!("unknown type `{tn}`"),
                "types: BOOL BYTE WORD DWORD INT DINT REAL LREAL; blocks: TON(t) TOF(t) TP(t) CTU(n) CTD(n)",
            );
            return;
        };
        if let Some(args) = &spec.args {
            let span = args.first().map_or(spec.span.clone(), |a| a.span.clone());
            self.error(
                codes::BAD_PRESET,
                &span,
                format!("the type {tn} takes no arguments"),
                format!("write `DEF {} : {tn}`", name.text),
            );
        }
        if let Some((raw, sspan)) = at {
            if let Some(e) = init {
                self.error(
                    codes::BAD_INIT,
                    &e.span,
                    "a typed view takes its value from the packet",
                    "remove the `:=` initial value",
                );
            }
            if let Some(r) = retain {
                self.error(
                    codes::BAD_RETAIN,
                    r,
                    "a typed view cannot be RETAIN",
                    "only internal variables (without AT) are retained",
                );
            }
            let mut d = Vec::new();
            let sig = check_signal(raw, sspan, Access::Read, self.ctx, self.file, &mut d);
            self.diags.append(&mut d);
            let Some(sig) = sig else { return };
            let kind = match (sig, ty) {
                (Signal::Bit { .. }, Ty::Bool) => SymKind::Place {
                    place: Place::Signal(sig),
                    ty,
                    output: is_output(&sig),
                },
                (Signal::Bit { .. }, _) => {
                    self.error(
                        codes::VIEW_BAD_BASE,
                        sspan,
                        format!("a {tn} cannot be AT the bit {sig}"),
                        format!(
                            "a {tn} view starts at a byte: W<c><P><b> (e.g. W{}{}{})",
                            raw.connector,
                            raw.packet.letter(),
                            0
                        ),
                    );
                    return;
                }
                (Signal::Byte { .. }, Ty::Bool) => {
                    self.error(
                        codes::VIEW_BAD_BASE,
                        sspan,
                        "a BOOL cannot be AT a byte",
                        "use a bit signal (I…/U…) or `x.n` for a bit of a byte",
                    );
                    return;
                }
                (Signal::Byte { index, .. }, _) => {
                    if usize::from(index) + ty.size() > 4 {
                        self.error(
                            codes::VIEW_CROSSES_CONNECTOR,
                            sspan,
                            format!("a {tn} at {sig} runs past the end of its connector"),
                            format!(
                                "a {tn} ({} bytes) may start at byte 0..{} of a connector",
                                ty.size(),
                                4 - ty.size()
                            ),
                        );
                        return;
                    }
                    let place = if ty == Ty::Byte {
                        Place::Signal(sig)
                    } else {
                        Place::View { at: sig, ty }
                    };
                    SymKind::Place {
                        place,
                        ty,
                        output: is_output(&sig),
                    }
                }
            };
            self.insert(name, kind);
            return;
        }
        let init_value = init.and_then(|e| match const_lit(e).map(|l| (l, lit_value(l, ty))) {
            Some((_, Ok(v))) => Some(v),
            Some((l, Err(LitError::Range(r)))) => {
                self.error(
                    codes::LITERAL_RANGE,
                    &e.span,
                    format!("{} does not fit {tn}", l.describe()),
                    format!("{tn} holds {r}"),
                );
                None
            }
            _ => {
                self.error(
                    codes::BAD_INIT,
                    &e.span,
                    format!("the initial value of a {tn} must be a constant of that type"),
                    "write a literal, e.g. `:= 0`",
                );
                None
            }
        });
        let id = self
            .builder
            .var(&name.text, ty, init_value, retain.is_some());
        self.insert(name, SymKind::Var { id, ty });
    }

    /// The preset of `DEF t : TON(…)` in ms (timers) or counts (counters).
    fn preset(&mut self, spec: &TypeSpec, tn: &str, timer: bool) -> Option<i64> {
        let valid = if timer {
            "a constant time such as 500ms, 2s or 1.5s (a bare number is ms)"
        } else {
            "a constant whole number"
        };
        let Some(args) = spec.args.as_ref().filter(|a| a.len() == 1) else {
            self.error(
                codes::BAD_PRESET,
                &spec.span,
                format!("{tn} needs exactly one preset"),
                format!("write {tn}(preset) with {valid}"),
            );
            return None;
        };
        let e = &args[0];
        let v = match const_lit(e) {
            Some(Lit::Int(v)) if v >= 0 && (timer || v <= i64::from(i32::MAX)) => Some(v),
            Some(Lit::Int(v)) if !timer && v >= i64::from(i32::MIN) && v <= i64::from(i32::MAX) => {
                Some(v)
            }
            Some(Lit::Real(r)) if timer && (0.0..2.0e9).contains(&r) => Some(r.ceil() as i64),
            _ => None,
        };
        if v.is_none() {
            self.error(
                codes::BAD_PRESET,
                &e.span,
                format!("invalid preset for {tn}"),
                format!("the preset is {valid}"),
            );
        }
        v
    }

    /// Warnings for names never used, outputs and blocks never written, one-shots never set.
    pub(crate) fn usage_warnings(&mut self) {
        let mut warnings = Vec::new();
        for s in self.syms.iter().filter(|s| !s.predeclared) {
            let never_written = match s.kind {
                SymKind::Place { output, .. } => output && !s.written,
                SymKind::Var { .. } | SymKind::Timer { .. } | SymKind::Counter { .. } => !s.written,
            };
            if !s.read && !s.written {
                warnings.push((
                    codes::NEVER_USED,
                    s.span.clone(),
                    format!("`{}` is never used", s.name),
                    "remove the DEF (it counts against SPL)".to_string(),
                ));
            } else if never_written {
                let what = match s.kind {
                    SymKind::Place { .. } => "output",
                    SymKind::Var { .. } => "variable",
                    SymKind::Timer { .. } => "timer",
                    SymKind::Counter { .. } => "counter",
                };
                warnings.push((
                    codes::NEVER_WRITTEN,
                    s.span.clone(),
                    format!("{what} `{}` is read but never written", s.name),
                    format!("assign it somewhere (`{} = …`)", s.name),
                ));
            }
        }
        for (&n, span) in &self.pulses_read {
            if !self.pulses_set.contains(&n) {
                warnings.push((
                    codes::PULSE_NEVER_SET,
                    span.clone(),
                    format!("P{n} is read but never assigned, so it is always 0"),
                    format!("assign it: `P{n} = <edge input>`"),
                ));
            }
        }
        warnings.sort_by_key(|w| w.1.start);
        for (code, span, msg, hint) in warnings {
            self.warning(code, &span, msg, hint);
        }
    }
}
