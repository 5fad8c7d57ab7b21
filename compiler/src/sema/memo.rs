//! Incremental checking for an editor: the check of each top-level statement is kept from one
//! version of a text to the next, so that a one-character edit checks one statement again and
//! *replays* the recorded effects of all the others.
//!
//! A statement's check is a pure function of its text, the program's declarations and the
//! machine, except for what it does to the checker's shared state, which the checker records as
//! [`Event`]s while a statement is checked: the names it reads and writes (replayed through
//! [`Checker::lookup`], so predeclared names are entered in the same order), the one-shots it
//! reads and sets, the stateful inputs it drives (replayed through the same `drive`, so "already
//! driven at L:C" is computed against the current text, never stored), and its diagnostics in
//! the order they were made. A statement whose check asked for a "did you mean" hint depends on
//! the hint budget and on the names entered before it: it is never memoized, always checked.
//!
//! Invariants: a memo is keyed by the statement's text from its first token to the end of its
//! last nested statement, and holds spans relative to the statement's start; all memos are
//! dropped when the machine context or the text of any `DEF` changes (the declarations
//! fingerprint); only the memos of the latest check are kept, so memory stays proportional to
//! the text. Replaying every statement gives exactly the diagnostics of [`super::check`]
//! (property-tested against it on random edits in `compiler/tests/it/front_incremental.rs`).
//! No program is produced: the editor's diagnostics need none.

use std::collections::HashMap;
use std::hash::{Hash, Hasher};

use diag::Diagnostic;

use super::{Checker, Driven};
use crate::ast::{Program, Span, Stmt, StmtKind};
use crate::context::MachineContext;

/// One effect of a statement's check on the shared state, in the order it happened.
#[derive(Debug, Clone)]
pub(crate) enum Event {
    /// A diagnostic of the statement itself.
    Diag(Diagnostic),
    /// A name read.
    Read(String),
    /// A name written.
    Written(String),
    /// A one-shot, timer or counter input driven (the key, the target, what it is called).
    Drive(Driven, Span, String),
    /// A one-shot read.
    PulseRead(u16, Span),
    /// A one-shot assigned.
    PulseSet(u16),
}

/// The events of the statement being checked.
#[derive(Debug, Default)]
pub(crate) struct Recording {
    /// Recorded so far.
    pub events: Vec<Event>,
    /// The checker's diagnostics before this index are already among `events` (or not the
    /// statement's own).
    pub flushed: usize,
    /// The check depended on more than the statement, declarations and machine.
    pub volatile: bool,
}

/// The kept check of one statement.
#[derive(Debug)]
struct Memo {
    events: Vec<Event>,
    /// Executable statements it counts.
    statements: usize,
    generation: u64,
}

/// Statement checks of the previous texts, for [`super::check_incremental`].
#[derive(Debug, Default)]
pub struct CheckCache {
    memos: HashMap<String, Memo>,
    /// The machine context and declarations fingerprint the memos were made for.
    made_for: Option<(MachineContext, u64)>,
    generation: u64,
    /// Statements replayed in the latest check.
    pub reused: usize,
    /// Statements checked in the latest check.
    pub checked: usize,
}

impl CheckCache {
    /// An empty cache.
    pub fn new() -> Self {
        CheckCache::default()
    }

    /// Starts a check; forgets every memo when the machine or the declarations changed.
    fn begin(&mut self, ctx: &MachineContext, decls: u64) {
        let same = matches!(&self.made_for, Some((c, d)) if *d == decls && c == ctx);
        if !same {
            self.memos.clear();
            self.made_for = Some((ctx.clone(), decls));
        }
        self.generation += 1;
        self.reused = 0;
        self.checked = 0;
    }

    /// Ends a check: only the memos it used are kept.
    fn end(&mut self) {
        let g = self.generation;
        self.memos.retain(|_, m| m.generation == g);
    }
}

/// The fingerprint of a program's declarations: the text of every `DEF`, in order.
pub(crate) fn declarations(text: &str, program: &Program) -> u64 {
    fn walk(text: &str, stmts: &[Stmt], h: &mut std::collections::hash_map::DefaultHasher) {
        for s in stmts {
            match &s.kind {
                StmtKind::Alias { .. } | StmtKind::Var { .. } => {
                    text.get(s.span.clone()).hash(h);
                    s.span.len().hash(h);
                }
                StmtKind::If {
                    then_body,
                    else_body,
                    ..
                } => {
                    walk(text, then_body, h);
                    walk(text, else_body, h);
                }
                StmtKind::Assign { .. } | StmtKind::Error => {}
            }
        }
    }
    let mut h = std::collections::hash_map::DefaultHasher::new();
    walk(text, &program.fast, &mut h);
    program.separator.is_some().hash(&mut h);
    walk(text, &program.slow, &mut h);
    h.finish()
}

/// Where a statement ends: its own span's end, or its last nested statement's.
fn stmt_end(s: &Stmt) -> usize {
    match &s.kind {
        StmtKind::If {
            then_body,
            else_body,
            ..
        } => then_body
            .iter()
            .chain(else_body)
            .map(stmt_end)
            .fold(s.span.end, usize::max),
        _ => s.span.end,
    }
}

fn shifted(s: &Span, start: usize) -> Span {
    s.start + start..s.end + start
}

fn unshifted(s: &Span, start: usize) -> Span {
    s.start.saturating_sub(start)..s.end.saturating_sub(start)
}

impl Event {
    /// The event with its spans moved by `start` (`back`: made relative to `start`).
    fn moved(mut self, start: usize, back: bool) -> Event {
        let m = |s: &Span| {
            if back {
                unshifted(s, start)
            } else {
                shifted(s, start)
            }
        };
        match &mut self {
            Event::Diag(d) => d.span = m(&d.span),
            Event::Drive(_, s, _) | Event::PulseRead(_, s) => *s = m(s),
            Event::Read(_) | Event::Written(_) | Event::PulseSet(_) => {}
        }
        self
    }
}

impl Checker<'_> {
    /// Moves the checker's diagnostics made since the last flush into the recording.
    pub(crate) fn flush_recorded_diags(&mut self) {
        if let Some(r) = &mut self.rec {
            let new = self.diags.get(r.flushed..).unwrap_or_default();
            r.events.extend(new.iter().cloned().map(Event::Diag));
            r.flushed = self.diags.len();
        }
    }

    /// Checks the top-level statements of one part, replaying the memos of unchanged ones.
    pub(crate) fn block_incremental(&mut self, stmts: &[Stmt], cache: &mut CheckCache) {
        for s in stmts {
            let start = s.span.start;
            let Some(key) = self.text.get(start..stmt_end(s)) else {
                self.stmt(s, &mut Vec::new());
                continue;
            };
            if let Some(m) = cache.memos.get_mut(key) {
                m.generation = cache.generation;
                cache.reused += 1;
                self.statements += m.statements;
                for e in &m.events {
                    self.replay(e.clone().moved(start, false));
                }
                continue;
            }
            cache.checked += 1;
            let before = self.statements;
            self.rec = Some(Recording {
                flushed: self.diags.len(),
                ..Recording::default()
            });
            self.stmt(s, &mut Vec::new());
            self.flush_recorded_diags();
            let Some(rec) = self.rec.take().filter(|r| !r.volatile) else {
                continue;
            };
            let memo = Memo {
                events: rec
                    .events
                    .into_iter()
                    .map(|e| e.moved(start, true))
                    .collect(),
                statements: self.statements - before,
                generation: cache.generation,
            };
            cache.memos.insert(key.to_string(), memo);
        }
    }

    /// Applies one recorded event (spans already in the current text).
    fn replay(&mut self, e: Event) {
        match e {
            Event::Diag(d) => self.diags.push(d),
            Event::Read(n) => {
                if let Some(i) = self.lookup(&n) {
                    self.syms[i].read = true;
                }
            }
            Event::Written(n) => {
                if let Some(i) = self.lookup(&n) {
                    self.syms[i].written = true;
                }
            }
            Event::Drive(key, span, what) => self.drive(key, &span, &what),
            Event::PulseRead(n, span) => {
                self.pulses_read.entry(n).or_insert(span);
            }
            Event::PulseSet(n) => {
                self.pulses_set.insert(n);
            }
        }
    }
}

/// What an error-free incremental check counts (for the empty-program warning).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Counts {
    /// Executable statements.
    pub statements: usize,
    /// Symbolic names defined.
    pub symbolic_names: usize,
}

/// [`super::check`]'s diagnostics for `program`, replaying the statements `cache` holds checks
/// of; the counts when there is no error. Builds no program.
pub fn check_incremental(
    file: &str,
    text: &str,
    program: &Program,
    ctx: &MachineContext,
    cache: &mut CheckCache,
) -> (Option<Counts>, Vec<Diagnostic>) {
    let mut c = Checker::new(file, text, ctx);
    c.declare_all(program.fast.iter().chain(&program.slow));
    cache.begin(ctx, declarations(text, program));
    c.block_incremental(&program.fast, cache);
    c.block_incremental(&program.slow, cache);
    cache.end();
    c.usage_warnings();
    let diags: Vec<Diagnostic> = std::mem::take(&mut c.diags)
        .into_iter()
        .map(|d| c.lines.locate(d))
        .collect();
    if diag::has_errors(&diags) {
        return (None, diags);
    }
    let counts = Counts {
        statements: c.statements,
        symbolic_names: c.symbolic_names,
    };
    (Some(counts), diags)
}
