//! Static checks of Macro B control flow, per program unit, block by block as the unit is built:
//! `WHILE … DO m` / `DO m` pair with the next `END m` (m = 1..3; loops nest at most three deep, an
//! inner loop may not reuse an open number and loops may not overlap), literal `GOTO n` targets
//! must be block numbers of the unit, and `G65 P` must name a loaded program. Pairs and targets are
//! stored in [`CBlock::jump`] while the program's blocks are kept.
//!
//! Invariants (issue 23): a pair is linked when its `END` arrives; a `GOTO` is checked against the
//! unit's number bitmap, at once when its target is already there (numbers are never removed) and
//! otherwise when the unit ends, and it is linked when the unit ends (of a number written twice the
//! last block is the target). Once the compile has an error ([`UnitFlow::dropped`]) a `GOTO` waits
//! only until its target arrives ([`UnitFlow::arrived`]): what a rejected unit holds is its open
//! loops and the `GOTO`s whose target has not come (yet).
//! `G65 P` targets are checked when every program is loaded ([`check_calls`]).

use std::collections::BTreeMap;

use diag::{Diagnostic, Sink};
use roaring::RoaringBitmap;

use super::{Expr, Stmt};
use crate::codes;
use crate::program::{CBlock, Program};

fn err(
    prog: &Program,
    file: usize,
    span: (usize, usize),
    code: u32,
    msg: String,
    hint: &str,
) -> Diagnostic {
    crate::program::err(code, &prog.files[file].name, "", span, msg, hint)
}

/// A literal block number of a `GOTO` (None when computed).
pub fn literal_target(e: &Expr) -> Option<f64> {
    match e {
        Expr::Num(v) => Some(*v),
        _ => None,
    }
}

/// Where a block is: its file and its span there.
#[derive(Clone, Copy)]
struct At {
    file: usize,
    span: (usize, usize),
}

/// A literal `GOTO` of the unit being built.
struct Goto {
    at: At,
    /// The block, while blocks are kept.
    block: usize,
    /// The target as written.
    v: f64,
    /// The target number.
    n: u32,
}

/// An open `DO m`.
struct Open {
    m: u8,
    block: usize,
    at: At,
}

/// A `G65 P` call, checked once every program is loaded.
pub(crate) struct MacroCall {
    at: At,
    p: u32,
}

/// The control flow of the unit being built.
#[derive(Default)]
pub(crate) struct UnitFlow {
    open: Vec<Open>,
    /// While blocks are kept: every literal `GOTO`, to link.
    gotos: Vec<Goto>,
    /// Once the compile has an error: the `GOTO`s whose target has not come, by target.
    waiting: BTreeMap<u32, Vec<Goto>>,
}

impl UnitFlow {
    /// Takes block `b` with statement `stmt`, to be `prog.blocks[idx]` when `kept` (the compile has
    /// no error so far); `numbers`: the unit's block numbers up to `b`'s. `G65 P` calls go to
    /// `calls`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn block(
        &mut self,
        prog: &mut Program,
        b: &mut CBlock,
        stmt: &Stmt,
        idx: usize,
        kept: bool,
        numbers: &RoaringBitmap,
        calls: &mut Vec<MacroCall>,
        diags: &mut Sink,
    ) {
        let at = At {
            file: b.file,
            span: b.span,
        };
        let link = |prog: &mut Program, b: &mut CBlock, d: usize| {
            if kept && let Some(db) = prog.blocks.get_mut(d) {
                db.jump = Some(idx);
                b.jump = Some(d);
            }
        };
        match stmt {
            Stmt::While(_, m) => {
                if self.open.iter().any(|o| o.m == *m) {
                    diags.push(err(
                        prog,
                        at.file,
                        at.span,
                        codes::MACRO_NESTING,
                        format!("DO {m} inside an open DO {m}"),
                        "nested loops need different numbers 1..3",
                    ));
                } else if self.open.len() >= 3 {
                    diags.push(err(
                        prog,
                        at.file,
                        at.span,
                        codes::MACRO_NESTING,
                        "loops nested deeper than 3".into(),
                        "WHILE … DO loops nest at most three levels",
                    ));
                }
                self.open.push(Open {
                    m: *m,
                    block: idx,
                    at,
                });
            }
            Stmt::End(m) => {
                match self.open.last() {
                    Some(o) if o.m == *m => {
                        let d = o.block;
                        self.open.pop();
                        link(prog, b, d);
                    }
                    _ if self.open.iter().any(|o| o.m == *m) => {
                        diags.push(err(
                        prog,
                        at.file,
                        at.span,
                        codes::MACRO_NESTING,
                        format!("END {m} closes an outer loop while an inner one is open: loops overlap"),
                        "close the inner loop first",
                    ));
                        while self.open.last().is_some_and(|o| o.m != *m) {
                            self.open.pop();
                        }
                        if let Some(o) = self.open.pop() {
                            link(prog, b, o.block);
                        }
                    }
                    _ => diags.push(err(
                        prog,
                        at.file,
                        at.span,
                        codes::MACRO_NESTING,
                        format!("END {m} without WHILE … DO {m}"),
                        "every END m closes the last open DO m",
                    )),
                }
            }
            Stmt::Goto(t) | Stmt::IfGoto(_, t) => {
                if let Some(v) = literal_target(t) {
                    let n = (v >= 0.0 && v.fract() == 0.0 && v <= 99_999_999.0).then_some(v as u32);
                    match n {
                        // Linked, or checked, when the unit ends.
                        Some(n) if kept => self.gotos.push(Goto {
                            at,
                            block: idx,
                            v,
                            n,
                        }),
                        Some(n) if !numbers.contains(n) => {
                            self.waiting.entry(n).or_default().push(Goto {
                                at,
                                block: idx,
                                v,
                                n,
                            })
                        }
                        Some(_) => {}
                        None => diags.push(missing_goto(prog, at, v)),
                    }
                }
            }
            Stmt::Call { p, .. } => calls.push(MacroCall { at, p: *p }),
            Stmt::Assign(..) | Stmt::IfThen(..) => {}
        }
    }

    /// The compile got an error: blocks are no longer kept, a `GOTO` whose target is among
    /// `numbers` needs nothing more, the others wait for theirs.
    pub(crate) fn dropped(&mut self, numbers: &RoaringBitmap) {
        for g in std::mem::take(&mut self.gotos) {
            if !numbers.contains(g.n) {
                self.waiting.entry(g.n).or_default().push(g);
            }
        }
    }

    /// Block number `n` came: the `GOTO`s waiting for it are resolved.
    pub(crate) fn arrived(&mut self, n: u32) {
        if !self.waiting.is_empty() {
            self.waiting.remove(&n);
        }
    }

    /// Ends unit `u` (its block numbers `numbers`): checks and, while blocks are kept, links its
    /// `GOTO`s (`prog.units[u].index` finished), and reports its loops left open.
    pub(crate) fn end(
        self,
        prog: &mut Program,
        u: usize,
        kept: bool,
        numbers: &RoaringBitmap,
        diags: &mut Sink,
    ) {
        for g in self.waiting.into_values().flatten() {
            diags.push(missing_goto(prog, g.at, g.v));
        }
        for g in self.gotos {
            if !numbers.contains(g.n) {
                diags.push(missing_goto(prog, g.at, g.v));
            } else if kept
                && let Some(t) = prog.units[u].index.get(g.n)
                && let Some(b) = prog.blocks.get_mut(g.block)
            {
                b.jump = Some(t);
            }
        }
        for o in self.open {
            diags.push(err(
                prog,
                o.at.file,
                o.at.span,
                codes::MACRO_NESTING,
                format!("DO {} without END {}", o.m, o.m),
                "close the loop with END m in the same program",
            ));
        }
    }
}

fn missing_goto(prog: &Program, at: At, v: f64) -> Diagnostic {
    err(
        prog,
        at.file,
        at.span,
        codes::MISSING_BLOCK,
        format!("GOTO {v}: no block N{v} in this program"),
        "GOTO jumps to a block number of the same program",
    )
}

/// Checks the `G65 P` calls once every program is loaded.
pub(crate) fn check_calls(prog: &Program, calls: &[MacroCall], diags: &mut Sink) {
    for c in calls {
        let p = c.p;
        if !(prog.library.contains_key(&p) || (prog.units[0].l == p && p != 0)) {
            diags.push(err(
                prog,
                c.at.file,
                c.at.span,
                codes::MISSING_SUBPROGRAM,
                format!("G65 P{p}: program O{p} not found"),
                "store macro programs as files O<n> in the machine's macro folder or after the main program",
            ));
        }
    }
}
