//! The names and signals of one parsed program: every `DEF`, and every place a name, a signal or a
//! one-shot is written, read or declared, sorted by position.
//!
//! Built from the syntax tree ([`compiler::ast`]), so it exists also for a program with errors
//! (the lines the parser could read). A name that stands for a signal — a `DEF name = signal`
//! alias, a typed view `AT` a byte, or a name of the interface map — carries the signal's
//! [`Addr`], so that the references of `FOLD` include every `U10K5` and the other way round.

use std::collections::HashMap;

use compiler::MachineContext;
use compiler::ast::{Expr, ExprKind, Program, Span, Stmt, StmtKind, Target, TargetKind, TypeSpec};
use compiler::lexer::{RawSignal, SignalKind};
use packets::{Packet, Signal};

/// A storage place, normalised: `I`/`U` of one address are one bit, `S<P><B>` is a `W` byte.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Addr {
    /// A bit: packet, connector, contact.
    Bit(Packet, u32, u32),
    /// A byte: packet, connector, byte of the connector.
    Byte(Packet, u32, u32),
    /// A one-shot `P<n>`.
    Pulse(u32),
}

impl Addr {
    /// The address of a signal as written.
    pub fn of_raw(s: &RawSignal) -> Addr {
        match s.kind {
            SignalKind::I | SignalKind::U => Addr::Bit(s.packet, s.connector, s.number),
            SignalKind::W => Addr::Byte(s.packet, s.connector, s.number),
            SignalKind::S => Addr::Byte(s.packet, s.number / 4, s.number % 4),
        }
    }

    /// The address of an interface-map signal.
    pub fn of_signal(s: &Signal) -> Addr {
        match *s {
            Signal::Bit {
                packet,
                connector,
                contact,
                ..
            } => Addr::Bit(packet, u32::from(connector), u32::from(contact)),
            Signal::Byte {
                packet,
                connector,
                index,
            } => Addr::Byte(packet, u32::from(connector), u32::from(index)),
        }
    }
}

/// How a place of the text uses what it names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Use {
    /// Read in an expression.
    Read,
    /// Written: the target of an assignment (coil, SET, RES, `c.R`, a bit of it).
    Write,
    /// The name of a `DEF`, or the signal a `DEF` aliases.
    Decl,
}

/// One place in the text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Ref {
    /// Where.
    pub span: Span,
    /// The name written there (upper case), when it is a name.
    pub name: Option<String>,
    /// The place it stands for, when known.
    pub addr: Option<Addr>,
    /// Read, written or declared.
    pub usage: Use,
}

/// What a `DEF` declares.
#[derive(Debug, Clone, PartialEq)]
pub enum DefKind {
    /// `DEF name = signal`.
    Alias(RawSignal),
    /// `DEF name : TYPE [AT signal] [:= init] [RETAIN]`, or a timer/counter with its preset text.
    Var {
        /// The type or function block (`DINT`, `TON`, …).
        ty: String,
        /// The preset's text of a timer or counter.
        preset: Option<String>,
        /// The byte it is a view of.
        at: Option<RawSignal>,
    },
}

/// One `DEF`.
#[derive(Debug, Clone, PartialEq)]
pub struct Def {
    /// The name, upper case.
    pub name: String,
    /// Where the name is written.
    pub name_span: Span,
    /// The whole statement.
    pub span: Span,
    /// What it declares.
    pub kind: DefKind,
    /// In the SLOW part.
    pub slow: bool,
}

/// The index of one program.
#[derive(Debug, Clone, Default)]
pub struct Index {
    /// Every `DEF`, in source order.
    pub defs: Vec<Def>,
    /// Every place, sorted by start.
    pub refs: Vec<Ref>,
    /// The separating `$` line.
    pub separator: Option<Span>,
    by_name: HashMap<String, usize>,
}

impl Index {
    /// Indexes `program` checked against `ctx` (for the interface names).
    pub fn new(program: &Program, ctx: &MachineContext) -> Index {
        let mut ix = Index {
            separator: program.separator.clone(),
            ..Index::default()
        };
        for (slow, stmts) in [(false, &program.fast), (true, &program.slow)] {
            for s in stmts {
                ix.collect_defs(s, slow);
            }
        }
        for (i, d) in ix.defs.iter().enumerate() {
            ix.by_name.entry(d.name.clone()).or_insert(i);
        }
        for s in program.fast.iter().chain(&program.slow) {
            ix.stmt(s);
        }
        // Resolve names to places: aliases, views, then the interface map.
        for r in &mut ix.refs {
            if r.addr.is_some() {
                continue;
            }
            let Some(n) = &r.name else { continue };
            r.addr = match ix.by_name.get(n).map(|&i| &ix.defs[i].kind) {
                Some(DefKind::Alias(s)) => Some(Addr::of_raw(s)),
                Some(DefKind::Var { at: Some(s), .. }) => Some(Addr::of_raw(s)),
                Some(DefKind::Var { .. }) => None,
                None => ctx.interface.get(n).map(|e| Addr::of_signal(&e.signal)),
            };
        }
        ix.refs.sort_by_key(|r| (r.span.start, r.span.end));
        ix
    }

    /// The `DEF` of `name` (upper case).
    pub fn def(&self, name: &str) -> Option<&Def> {
        self.by_name.get(name).map(|&i| &self.defs[i])
    }

    /// The place at byte `offset` (its span contains it or ends there).
    pub fn at(&self, offset: usize) -> Option<&Ref> {
        let i = self.refs.partition_point(|r| r.span.start <= offset);
        self.refs[..i]
            .iter()
            .rev()
            .take(4)
            .find(|r| r.span.start <= offset && offset <= r.span.end)
    }

    /// Every place that stands for the same thing as `r`: the same address, or the same name.
    pub fn same_as<'a>(&'a self, r: &'a Ref) -> impl Iterator<Item = &'a Ref> + 'a {
        self.refs.iter().filter(move |o| match (&r.addr, &r.name) {
            (Some(a), _) => o.addr.as_ref() == Some(a),
            (None, Some(n)) => o.name.as_ref() == Some(n),
            (None, None) => false,
        })
    }

    fn collect_defs(&mut self, s: &Stmt, slow: bool) {
        match &s.kind {
            StmtKind::Alias { name, signal, .. } => self.defs.push(Def {
                name: name.text.clone(),
                name_span: name.span.clone(),
                span: s.span.clone(),
                kind: DefKind::Alias(*signal),
                slow,
            }),
            StmtKind::Var { name, ty, at, .. } => self.defs.push(Def {
                name: name.text.clone(),
                name_span: name.span.clone(),
                span: s.span.clone(),
                kind: DefKind::Var {
                    ty: ty.name.text.clone(),
                    preset: preset(ty),
                    at: at.as_ref().map(|(s, _)| *s),
                },
                slow,
            }),
            StmtKind::If {
                then_body,
                else_body,
                ..
            } => {
                for s in then_body.iter().chain(else_body) {
                    self.collect_defs(s, slow);
                }
            }
            StmtKind::Assign { .. } | StmtKind::Error => {}
        }
    }

    fn push_name(&mut self, span: &Span, name: &str, usage: Use) {
        self.refs.push(Ref {
            span: span.clone(),
            name: Some(name.to_string()),
            addr: None,
            usage,
        });
    }

    fn push_addr(&mut self, span: &Span, addr: Addr, usage: Use) {
        self.refs.push(Ref {
            span: span.clone(),
            name: None,
            addr: Some(addr),
            usage,
        });
    }

    fn stmt(&mut self, s: &Stmt) {
        match &s.kind {
            StmtKind::Assign { target, value, .. } => {
                self.target(target);
                self.expr(value);
            }
            StmtKind::Alias {
                name,
                signal,
                signal_span,
            } => {
                self.push_name(&name.span, &name.text, Use::Decl);
                self.push_addr(signal_span, Addr::of_raw(signal), Use::Decl);
            }
            StmtKind::Var {
                name, ty, at, init, ..
            } => {
                self.push_name(&name.span, &name.text, Use::Decl);
                for a in ty.args.iter().flatten() {
                    self.expr(a);
                }
                if let Some((sig, span)) = at {
                    self.push_addr(span, Addr::of_raw(sig), Use::Decl);
                }
                if let Some(e) = init {
                    self.expr(e);
                }
            }
            StmtKind::If {
                cond,
                then_body,
                else_body,
            } => {
                self.expr(cond);
                for s in then_body.iter().chain(else_body) {
                    self.stmt(s);
                }
            }
            StmtKind::Error => {}
        }
    }

    fn target(&mut self, t: &Target) {
        match &t.kind {
            TargetKind::Signal(s) => self.push_addr(&t.span, Addr::of_raw(s), Use::Write),
            TargetKind::Pulse(n) => self.push_addr(&t.span, Addr::Pulse(*n), Use::Write),
            TargetKind::Name(n) => self.push_name(&n.span, &n.text, Use::Write),
            TargetKind::Member(n, _) => self.push_name(&n.span, &n.text, Use::Write),
            TargetKind::Bit(inner, _) => self.target_bit(inner),
        }
    }

    /// The object of `x.n = …`: its span is the whole `x.n`, so the name's own span is kept.
    fn target_bit(&mut self, t: &Target) {
        self.target(t);
    }

    fn expr(&mut self, e: &Expr) {
        match &e.kind {
            ExprKind::Signal(s) => self.push_addr(&e.span, Addr::of_raw(s), Use::Read),
            ExprKind::Pulse(n) => self.push_addr(&e.span, Addr::Pulse(*n), Use::Read),
            ExprKind::Name(n) => self.push_name(&e.span, n, Use::Read),
            ExprKind::Member(inner, _)
            | ExprKind::BitOf(inner, _, _)
            | ExprKind::Unary(_, inner) => self.expr(inner),
            ExprKind::Binary(_, a, b) | ExprKind::Compare(_, a, b) => {
                self.expr(a);
                self.expr(b);
            }
            ExprKind::Call(_, args) => {
                for a in args {
                    self.expr(a);
                }
            }
            ExprKind::Bool(_)
            | ExprKind::Int(_)
            | ExprKind::Real(_)
            | ExprKind::Duration(_)
            | ExprKind::Error => {}
        }
    }
}

/// A signal as written, in canonical upper case (`U10K5`, `W3K0`, `SK57`).
pub fn signal_text(s: &RawSignal) -> String {
    let p = s.packet.letter();
    match s.kind {
        SignalKind::I => format!("I{}{p}{}", s.connector, s.number),
        SignalKind::U => format!("U{}{p}{}", s.connector, s.number),
        SignalKind::W => format!("W{}{p}{}", s.connector, s.number),
        SignalKind::S => format!("S{p}{}", s.number),
    }
}

/// A timer's or counter's preset as written, in milliseconds for a timer.
fn preset(ty: &TypeSpec) -> Option<String> {
    let arg = ty.args.as_ref()?.first()?;
    Some(match arg.kind {
        ExprKind::Duration(ms) => format!("{ms} ms"),
        ExprKind::Int(n) if matches!(ty.name.text.as_str(), "TON" | "TOF" | "TP") => {
            format!("{n} ms")
        }
        ExprKind::Int(n) => n.to_string(),
        _ => "(an expression)".to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn index(src: &str) -> Index {
        let (p, _) = compiler::parser::parse("t", src);
        Index::new(&p, &MachineContext::lathe_like())
    }

    #[test]
    fn writes_reads_and_declarations_resolve_to_one_place() {
        let src = "DEF FEED = U10K5\nFOLD = I0A0\nU10K5 = FEED * I0A1\nDEF t : TON(2s)\nt = I0A2\nU4A0 = t\n";
        let ix = index(src);
        let at = |s: &str| src.find(s).expect("in the source");
        let fold = ix.at(at("FOLD") + 1).expect("FOLD").clone();
        assert_eq!(fold.usage, Use::Write);
        let same: Vec<_> = ix
            .same_as(&fold)
            .map(|r| (&src[r.span.clone()], r.usage))
            .collect();
        assert_eq!(
            same,
            vec![
                ("FEED", Use::Decl),
                ("U10K5", Use::Decl),
                ("FOLD", Use::Write),
                ("U10K5", Use::Write),
                ("FEED", Use::Read)
            ]
        );
        let t = ix.def("T").expect("the timer");
        assert_eq!(
            t.kind,
            DefKind::Var {
                ty: "TON".into(),
                preset: Some("2000 ms".into()),
                at: None
            }
        );
        let uses: Vec<_> = ix
            .refs
            .iter()
            .filter(|r| r.name.as_deref() == Some("T"))
            .map(|r| r.usage)
            .collect();
        assert_eq!(uses, vec![Use::Decl, Use::Write, Use::Read]);
    }
}
