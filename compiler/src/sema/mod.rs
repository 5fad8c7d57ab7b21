//! Semantic analysis: checks a parsed program against the language rules and the machine, and
//! produces typed IR statements (the lowering of expressions happens here, where the types are
//! known; [`crate::lower`] finishes the program).
//!
//! Passes: [`symbols`] declares every `DEF` of the program first (so a name may be used above its
//! `DEF`), then [`stmt`] checks the statements top to bottom, typing expressions with [`expr`] and
//! the rules of [`types`]; finally the usage warnings are computed. Every problem becomes a
//! [`Diagnostic`] with a stable code ([`codes`]); checking never stops at the first error.

mod calls;
pub mod codes;
mod expr;
pub mod memo;
pub mod signals;
mod stmt;
mod symbols;
pub mod types;

use std::collections::{BTreeMap, HashMap, HashSet};

use diag::Diagnostic;

use crate::ast::{self, Span};
use crate::context::MachineContext;
use crate::interface_map::Direction;
use crate::ir::{
    self, CounterId, CounterKind, Place, ProgramBuilder, TimerId, TimerKind, Ty, VarId,
};

/// What a name stands for.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum SymKind {
    /// A signal, a typed view or a predeclared interface name.
    Place {
        /// Where the value lives.
        place: Place,
        /// Its type.
        ty: Ty,
        /// True when it is an output of the logic (warn when never written).
        output: bool,
    },
    /// An internal variable.
    Var {
        /// The IR variable.
        id: VarId,
        /// Its type.
        ty: Ty,
    },
    /// A named timer.
    Timer {
        /// The IR timer.
        id: TimerId,
        /// Its kind.
        kind: TimerKind,
    },
    /// A named counter.
    Counter {
        /// The IR counter.
        id: CounterId,
        /// Its kind.
        kind: CounterKind,
    },
}

/// A declared or predeclared name and how the program uses it.
#[derive(Debug, Clone)]
pub(crate) struct Symbol {
    pub name: String,
    pub kind: SymKind,
    /// Where it is defined (empty for a predeclared name).
    pub span: Span,
    /// From the interface map rather than a `DEF`.
    pub predeclared: bool,
    /// The CNC writes it (predeclared `in` entries).
    pub cnc_writes: bool,
    pub read: bool,
    pub written: bool,
}

/// A stateful input that only one statement may drive.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum Driven {
    Pulse(u16),
    Timer(u32),
    Count(u32),
    Reset(u32),
}

/// The checked program, ready for [`crate::lower::lower`].
#[derive(Debug, Clone)]
pub struct Checked {
    /// Declarations collected so far (variables, timers, counters, pulses).
    pub builder: ProgramBuilder,
    /// The FAST statements.
    pub fast: Vec<ir::Stmt>,
    /// The SLOW statements (not yet sliced).
    pub slow: Vec<ir::Stmt>,
    /// Executable statements in the source (assignments and `IF`s, nested ones included).
    pub statements: usize,
    /// Symbolic names the program defines (what counts against SPL).
    pub symbolic_names: usize,
    /// The source line of every IR statement in pre-order ([`ir::Program::lines`]).
    pub lines: Vec<u32>,
}

/// The state of one check.
pub(crate) struct Checker<'a> {
    pub file: &'a str,
    pub text: &'a str,
    pub ctx: &'a MachineContext,
    pub diags: Vec<Diagnostic>,
    pub builder: ProgramBuilder,
    pub syms: Vec<Symbol>,
    pub by_name: HashMap<String, usize>,
    /// Inline timer statements produced while checking the current statement's expressions.
    pub pending: Vec<ir::Stmt>,
    /// The source line of every IR statement produced so far, in pre-order ([`ir::Program::lines`]).
    pub stmt_lines: Vec<u32>,
    pub driven: HashMap<Driven, Span>,
    pub pulses_read: BTreeMap<u16, Span>,
    pub pulses_set: HashSet<u16>,
    pub statements: usize,
    pub symbolic_names: usize,
    /// Names whose `DEF` was rejected (uses are not reported as undefined).
    pub failed: HashSet<String>,
    /// Line starts of `text`, for positions in messages and for locating diagnostics.
    pub lines: crate::lexer::LineIndex<'a>,
    /// "Did you mean" searches still allowed: each scans every name, so only the first
    /// [`SUGGESTIONS`] undefined names get one (bounded work on any input).
    pub suggestions_left: usize,
    /// What the statement being checked does, when [`memo`] is recording it.
    pub rec: Option<memo::Recording>,
}

/// Undefined names per check that get a "did you mean" search.
const SUGGESTIONS: usize = 100;

impl<'a> Checker<'a> {
    /// `hint` prefixed with "did you mean `X`? " for the defined, predeclared or function name
    /// nearest to the undefined `name`.
    pub(crate) fn suggest_name(&mut self, name: &str, hint: String) -> String {
        if let Some(r) = &mut self.rec {
            // The hint depends on the budget and the names entered so far: not memoizable.
            r.volatile = true;
        }
        if self.suggestions_left == 0 {
            return hint;
        }
        self.suggestions_left -= 1;
        let defined = self.syms.iter().map(|s| s.name.as_str());
        let predeclared = self.ctx.interface.iter().map(|e| e.name.as_str());
        let functions = symbols::FUNCTIONS.iter().copied();
        match diag::did_you_mean(name, defined.chain(predeclared).chain(functions)) {
            Some(s) => format!("{s} {hint}"),
            None => hint,
        }
    }

    fn new(file: &'a str, text: &'a str, ctx: &'a MachineContext) -> Self {
        Checker {
            file,
            text,
            ctx,
            diags: Vec::new(),
            builder: ProgramBuilder::new(ctx.tick_ms, ctx.time_slow_ms),
            syms: Vec::new(),
            by_name: HashMap::new(),
            pending: Vec::new(),
            stmt_lines: Vec::new(),
            driven: HashMap::new(),
            pulses_read: BTreeMap::new(),
            pulses_set: HashSet::new(),
            statements: 0,
            symbolic_names: 0,
            suggestions_left: SUGGESTIONS,
            failed: HashSet::new(),
            lines: crate::lexer::LineIndex::new(text),
            rec: None,
        }
    }

    /// Records an error.
    pub fn error(
        &mut self,
        code: u32,
        span: &Span,
        msg: impl Into<String>,
        hint: impl Into<String>,
    ) {
        self.diags
            .push(Diagnostic::error(code, self.file, span.clone(), msg).with_hint(hint));
    }

    /// Records a warning.
    pub fn warning(
        &mut self,
        code: u32,
        span: &Span,
        msg: impl Into<String>,
        hint: impl Into<String>,
    ) {
        self.diags
            .push(Diagnostic::warning(code, self.file, span.clone(), msg).with_hint(hint));
    }

    /// `line:column` of a byte offset, for messages.
    pub fn position(&self, at: usize) -> String {
        let (l, c) = self.lines.line_column(at);
        format!("{l}:{c}")
    }

    /// The symbol named `name`: a `DEF`, else a predeclared interface name (entered on first use).
    pub fn lookup(&mut self, name: &str) -> Option<usize> {
        if let Some(&i) = self.by_name.get(name) {
            return Some(i);
        }
        let entry = self.ctx.interface.get(name)?.clone();
        let (place, ty) = interface_place(&entry);
        let output = entry.dir == Direction::PlcToCnc;
        let i = self.syms.len();
        self.syms.push(Symbol {
            name: name.to_string(),
            kind: SymKind::Place { place, ty, output },
            span: 0..0,
            predeclared: true,
            cnc_writes: entry.dir == Direction::CncToPlc,
            read: false,
            written: false,
        });
        self.by_name.insert(name.to_string(), i);
        Some(i)
    }

    /// Marks symbol `i` read (recorded for [`memo`]).
    pub fn mark_read(&mut self, i: usize) {
        self.syms[i].read = true;
        if let Some(r) = &mut self.rec {
            r.events.push(memo::Event::Read(self.syms[i].name.clone()));
        }
    }

    /// Marks symbol `i` written (recorded for [`memo`]).
    pub fn mark_written(&mut self, i: usize) {
        self.syms[i].written = true;
        if let Some(r) = &mut self.rec {
            r.events
                .push(memo::Event::Written(self.syms[i].name.clone()));
        }
    }
}

/// The IR place and type of an interface-map entry.
pub(crate) fn interface_place(entry: &crate::interface_map::InterfaceSignal) -> (Place, Ty) {
    use crate::interface_map::Width;
    match entry.width {
        Width::Bit => (Place::Signal(entry.signal), Ty::Bool),
        Width::Byte => (Place::Signal(entry.signal), Ty::Byte),
        Width::Word => (
            Place::View {
                at: entry.signal,
                ty: Ty::Word,
            },
            Ty::Word,
        ),
        Width::Dword => (
            Place::View {
                at: entry.signal,
                ty: Ty::Dword,
            },
            Ty::Dword,
        ),
    }
}

/// Checks `program` (parsed from `text`, the decoded source of `file`) against `ctx`. Returns the
/// checked program when there is no error, and all diagnostics (located) either way.
pub fn check(
    file: &str,
    text: &str,
    program: &ast::Program,
    ctx: &MachineContext,
) -> (Option<Checked>, Vec<Diagnostic>) {
    let mut c = Checker::new(file, text, ctx);
    c.declare_all(program.fast.iter().chain(&program.slow));
    let fast = c.block(&program.fast);
    let slow = c.block(&program.slow);
    c.usage_warnings();
    let diags: Vec<Diagnostic> = std::mem::take(&mut c.diags)
        .into_iter()
        .map(|d| c.lines.locate(d))
        .collect();
    if diag::has_errors(&diags) {
        return (None, diags);
    }
    let checked = Checked {
        builder: c.builder,
        fast,
        slow,
        statements: c.statements,
        symbolic_names: c.symbolic_names,
        lines: c.stmt_lines,
    };
    (Some(checked), diags)
}
