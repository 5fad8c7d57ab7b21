//! The HMI's static facts of a machine: the interface-map names, the PLC program's `DEF` aliases,
//! and the source lines with the packet signals each statement reads and writes (parsed with the
//! compiler's own parser, so the Program page shows the image's values of exactly those signals).

use std::collections::BTreeMap;

use compiler::ast::{Expr, ExprKind, Stmt, StmtKind, Target, TargetKind};
use hmi::{Catalog, NamedSignal, SourceLine};
use packets::Signal;

use crate::machine::Machine;

/// Builds the catalog of `machine` running `source` (the PLC program's bytes).
pub fn build(machine: &Machine, source: &[u8]) -> Catalog {
    let text = compiler::lexer::decode_source(source);
    let file = machine.source_name();
    let (program, _diags) = compiler::parser::parse(&file, &text);
    let mut names: Vec<NamedSignal> = machine
        .interface
        .iter()
        .map(|s| NamedSignal {
            name: s.name.clone(),
            signal: s.signal,
            origin: "interface",
            meaning: s.meaning.clone(),
        })
        .collect();
    let mut aliases: BTreeMap<String, Signal> = BTreeMap::new();
    let stmts: Vec<&Stmt> = program.fast.iter().chain(&program.slow).collect();
    for s in &stmts {
        if let StmtKind::Alias {
            name, signal_span, ..
        } = &s.kind
            && let Some(sig) = signal_at(&text, signal_span)
        {
            aliases.insert(name.text.clone(), sig);
            names.push(NamedSignal {
                name: name.text.clone(),
                signal: sig,
                origin: "program",
                meaning: String::new(),
            });
        }
    }
    names.sort_by(|a, b| {
        (a.signal.image_byte(), a.signal.bit(), &a.name).cmp(&(
            b.signal.image_byte(),
            b.signal.bit(),
            &b.name,
        ))
    });
    let starts: Vec<usize> = std::iter::once(0)
        .chain(text.match_indices('\n').map(|(i, _)| i + 1))
        .collect();
    let mut lines: Vec<SourceLine> = text
        .lines()
        .enumerate()
        .map(|(i, l)| SourceLine {
            line: i + 1,
            text: l.to_string(),
            writes: Vec::new(),
            reads: Vec::new(),
        })
        .collect();
    let ctx = Lookup {
        text: &text,
        aliases: &aliases,
        interface: machine,
    };
    let mut walk = Vec::new();
    walk.extend(stmts.iter().copied());
    while let Some(s) = walk.pop() {
        let line = starts
            .partition_point(|&st| st <= s.span.start)
            .saturating_sub(1);
        let Some(entry) = lines.get_mut(line) else {
            continue;
        };
        match &s.kind {
            StmtKind::Assign { target, value, .. } => {
                if let Some(sig) = ctx.target(target) {
                    push_unique(&mut entry.writes, sig.to_string());
                }
                ctx.reads(value, &mut entry.reads);
            }
            StmtKind::If {
                cond,
                then_body,
                else_body,
            } => {
                ctx.reads(cond, &mut entry.reads);
                walk.extend(then_body.iter().chain(else_body));
            }
            _ => {}
        }
    }
    Catalog {
        machine: machine
            .dir
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
        names,
        source_name: file,
        source: lines,
    }
}

fn push_unique(list: &mut Vec<String>, s: String) {
    if !list.contains(&s) {
        list.push(s);
    }
}

fn signal_at(text: &str, span: &std::ops::Range<usize>) -> Option<Signal> {
    text.get(span.clone())?.trim().parse().ok()
}

/// Resolves names and signal texts of the program.
struct Lookup<'a> {
    text: &'a str,
    aliases: &'a BTreeMap<String, Signal>,
    interface: &'a Machine,
}

impl Lookup<'_> {
    fn name(&self, name: &str) -> Option<Signal> {
        self.aliases
            .get(name)
            .copied()
            .or_else(|| self.interface.interface.signal(name))
    }

    fn target(&self, t: &Target) -> Option<Signal> {
        match &t.kind {
            TargetKind::Signal(_) => signal_at(self.text, &t.span),
            TargetKind::Name(n) => self.name(&n.text),
            _ => None,
        }
    }

    fn reads(&self, e: &Expr, out: &mut Vec<String>) {
        match &e.kind {
            ExprKind::Signal(_) => {
                if let Some(s) = signal_at(self.text, &e.span) {
                    push_unique(out, s.to_string());
                }
            }
            ExprKind::Name(n) => {
                if let Some(s) = self.name(n) {
                    push_unique(out, s.to_string());
                }
            }
            ExprKind::Member(inner, _)
            | ExprKind::BitOf(inner, _, _)
            | ExprKind::Unary(_, inner) => self.reads(inner, out),
            ExprKind::Binary(_, a, b) | ExprKind::Compare(_, a, b) => {
                self.reads(a, out);
                self.reads(b, out);
            }
            ExprKind::Call(_, args) => {
                for a in args {
                    self.reads(a, out);
                }
            }
            _ => {}
        }
    }
}
