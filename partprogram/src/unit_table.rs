//! What both dialects' unit builders share ([`crate::units`] for MEFI, [`crate::fanuc_units`] for
//! Fanuc): the diagnostics of each compile phase after parsing ([`Phases`]) and the unit table
//! ([`UnitTable`]): the units, the block numbers of each unit in a compressed bitmap, and the rule
//! that keeps blocks.
//!
//! Invariants (issue 23): a block is kept in [`Program::blocks`] (and in its unit's
//! [`BlockIndex`]) only while the compile has no error; at the first error the blocks kept so far
//! and the indexes are dropped, and from then on a block leaves only its number in its unit's
//! bitmap ([`RoaringBitmap`]: at most 2 bytes per number, at most 12.5 MB per bitmap since numbers
//! are below 10^8). Numbers are never removed from a bitmap, so a target found there stays found.
//! The phases' diagnostics are merged at the end in the order the phases ran when the whole block
//! list was checked phase after phase: the kept diagnostics and their order are the same as then.

use diag::{Diagnostic, Sink};
use roaring::RoaringBitmap;

use crate::program::{BlockIndex, CBlock, Program, Unit};

/// The diagnostics of each compile phase after parsing, each capped like the compile's sink.
pub(crate) struct Phases {
    /// Units, block numbers, library files.
    pub(crate) units: Sink,
    /// The static checks of each block.
    pub(crate) check: Sink,
    /// Jump and call targets.
    pub(crate) link: Sink,
    /// M functions not declared in IOCFIL.
    pub(crate) m: Sink,
    /// Recursion.
    pub(crate) rec: Sink,
    /// Fanuc Macro B control flow (`DO`/`END` pairs, `GOTO` targets, `G65 P`).
    pub(crate) flow: Sink,
}

impl Phases {
    fn new(max: usize) -> Self {
        Phases {
            units: Sink::new(max),
            check: Sink::new(max),
            link: Sink::new(max),
            m: Sink::new(max),
            rec: Sink::new(max),
            flow: Sink::new(max),
        }
    }

    fn all(self) -> [Sink; 6] {
        [
            self.units, self.check, self.link, self.m, self.rec, self.flow,
        ]
    }

    fn has_errors(&self) -> bool {
        [
            &self.units,
            &self.check,
            &self.link,
            &self.m,
            &self.rec,
            &self.flow,
        ]
        .iter()
        .any(|s| s.has_errors())
    }

    /// Pushes the kept diagnostics of every phase into `sink`, phase after phase, and counts the
    /// rest: `sink` keeps what it would have kept had every diagnostic been pushed in that order.
    pub(crate) fn merge_into(self, sink: &mut Sink) {
        for s in self.all() {
            let (kept, hidden) = s.finish();
            for d in kept {
                sink.push(d);
            }
            sink.count_hidden(&hidden);
        }
    }
}

/// The units of a compile being built block by block, what is kept of their blocks, and the
/// diagnostics of the phases.
pub(crate) struct UnitTable {
    /// True once the compile has an error: blocks are no longer kept.
    failed: bool,
    /// Per unit: the block numbers of the unit.
    pub(crate) numbers: Vec<RoaringBitmap>,
    /// The diagnostics of the phases after parsing.
    pub(crate) phases: Phases,
    /// Diagnostics kept per file and phase (0: all).
    max: usize,
}

impl UnitTable {
    /// An empty table for a compile keeping `max` diagnostics per file and phase (0: all).
    pub(crate) fn new(max: usize) -> Self {
        UnitTable {
            failed: false,
            numbers: Vec::new(),
            phases: Phases::new(max),
            max,
        }
    }

    /// The text of macro file `path` (`fname` in the macro folder), or `None` after an error
    /// (2031) in the units phase: a file that cannot be read is never skipped in silence.
    pub(crate) fn read_macro(&mut self, path: &std::path::Path, fname: &str) -> Option<String> {
        match std::fs::read(path) {
            Ok(bytes) => Some(crate::program::text_of(bytes)),
            Err(e) => {
                self.phases.units.push(Diagnostic::error(
                    crate::codes::MACRO_IO,
                    crate::library::file_name(fname),
                    0..0,
                    format!("cannot read: {e}"),
                ));
                None
            }
        }
    }

    /// Starts the streamed parse of a macro file: returns the units phase's sink for the
    /// parser's diagnostics and collects the units diagnostics of the file's blocks apart, so
    /// that [`UnitTable::end_file_parse`] puts the parse errors first, as when a file was parsed
    /// whole before its blocks were built.
    pub(crate) fn begin_file_parse(&mut self) -> Sink {
        std::mem::replace(&mut self.phases.units, Sink::new(self.max))
    }

    /// Ends what [`UnitTable::begin_file_parse`] began: `parse` (holding the parse errors)
    /// becomes the units phase's sink again, followed by the file's units diagnostics.
    pub(crate) fn end_file_parse(&mut self, parse: Sink) {
        let units = std::mem::replace(&mut self.phases.units, parse);
        let (kept, hidden) = units.finish();
        for d in kept {
            self.phases.units.push(d);
        }
        self.phases.units.count_hidden(&hidden);
    }

    /// True once the compile has an error (blocks are dropped).
    pub(crate) fn failed(&self) -> bool {
        self.failed
    }

    /// Adds `unit` to `prog` (its blocks start at the next kept block) and returns its index.
    pub(crate) fn push_unit(&mut self, prog: &mut Program, mut unit: Unit) -> usize {
        unit.start = prog.blocks.len();
        unit.end = prog.blocks.len();
        unit.index = BlockIndex::default();
        prog.units.push(unit);
        self.numbers.push(RoaringBitmap::new());
        prog.units.len() - 1
    }

    /// Notes number `n` in unit `u`'s bitmap: false when the unit had it already.
    pub(crate) fn number(&mut self, u: usize, n: u32) -> bool {
        self.numbers[u].insert(n)
    }

    /// Enters the block that will be `prog.blocks[idx]` under number `n` in unit `u`'s index,
    /// while blocks are kept.
    pub(crate) fn index(&self, prog: &mut Program, u: usize, n: u32, idx: usize) {
        if !self.failed {
            prog.units[u].index.push(n, idx);
        }
    }

    /// Ends block `cb` of unit `u`: once the compile has an error (now, or the parser's when
    /// `parse_failed`) every kept block is dropped and `cb` is not kept; otherwise it is pushed.
    /// Returns true when this call dropped the blocks.
    pub(crate) fn keep(
        &mut self,
        prog: &mut Program,
        u: usize,
        cb: CBlock,
        parse_failed: bool,
    ) -> bool {
        let mut dropped = false;
        if !self.failed && (parse_failed || self.phases.has_errors()) {
            // The program will not run: what is left to do needs no block.
            self.failed = true;
            dropped = true;
            prog.blocks = Vec::new();
            for unit in &mut prog.units {
                unit.index = BlockIndex::default();
            }
        }
        if !self.failed {
            prog.blocks.push(cb);
            prog.units[u].end = prog.blocks.len();
        }
        dropped
    }
}

/// The calls that close a cycle in the static call graph `edges` (per unit, its calls in block
/// order: callee and the call's index), found by a depth-first walk from every unit in order: each
/// call to a unit still on the walk's path, in the order the walk meets them. Iterative, so a long
/// chain of calls cannot exhaust the stack.
pub(crate) fn back_edges(edges: &[Vec<(usize, usize)>]) -> Vec<usize> {
    // 0: not visited, 1: on the path, 2: done.
    let mut state = vec![0u8; edges.len()];
    let mut hits = Vec::new();
    let mut path: Vec<(usize, usize)> = Vec::new();
    for root in 0..edges.len() {
        if state[root] != 0 {
            continue;
        }
        state[root] = 1;
        path.push((root, 0));
        while let Some((u, next)) = path.last_mut() {
            let u = *u;
            match edges[u].get(*next) {
                Some(&(v, call)) => {
                    *next += 1;
                    match state[v] {
                        1 => hits.push(call),
                        0 => {
                            state[v] = 1;
                            path.push((v, 0));
                        }
                        _ => {}
                    }
                }
                None => {
                    state[u] = 2;
                    path.pop();
                }
            }
        }
    }
    hits
}

#[cfg(test)]
mod tests {
    use super::back_edges;

    #[test]
    fn back_edges_are_the_calls_that_close_a_cycle_in_walk_order() {
        // 0 → 1 (call 0), 1 → 2 (call 1), 2 → 1 (call 2: back to the path), 1 → 1 (call 3: itself),
        // 0 → 2 (call 4: done already, no cycle), 3 → 0 (call 5: 0 is done, no cycle).
        let edges = vec![
            vec![(1, 0), (2, 4)],
            vec![(2, 1), (1, 3)],
            vec![(1, 2)],
            vec![(0, 5)],
        ];
        assert_eq!(back_edges(&edges), [2, 3]);
    }

    #[test]
    fn a_chain_of_a_million_calls_does_not_exhaust_the_stack() {
        let n = 1_000_000;
        let mut edges: Vec<Vec<(usize, usize)>> = (0..n).map(|u| vec![(u + 1, u)]).collect();
        // The last unit calls the first: one cycle through every unit.
        edges[n - 1] = vec![(0, n - 1)];
        assert_eq!(back_edges(&edges), [n - 1]);
    }
}
