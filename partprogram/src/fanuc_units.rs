//! Fanuc program units built block by block as the parser hands the blocks on: the main file's
//! main program and every further `O<n>` program of the file, then the `O<n>` files of the macro
//! folder (each a program, with every further `O<n>` in it another), the static checks of each
//! block ([`crate::fanuc::check_block`]), `M97 P`/`M98 P`/`G65 P` targets, recursion through
//! `M98`, and the Macro B control flow ([`crate::macro_b::flow`]).
//!
//! Invariants (issue 23): a block is kept only while the compile has no error ([`UnitTable`]);
//! what a rejected program holds per block is its number in its unit's bitmap, and only for the
//! blocks that need it: an `M97 P` or a `GOTO` whose line has not come (until it comes, or the
//! unit ends), an `M98 P` or `G65 P` call (until every program is loaded) and an open `DO`. The
//! diagnostics go to the phases' sinks: units (duplicate `N` and `O`, the macro files' parse
//! errors), block checks, `M97`/`M98` targets, recursion, control flow; merged in that order they
//! are what checking the whole block list phase after phase gave.

use std::collections::BTreeMap;

use diag::{Diagnostic, Sink};

use crate::ast::Block;
use crate::codes;
use crate::machine::Dialect;
use crate::macro_b::flow::{MacroCall, UnitFlow, check_calls};
use crate::parse::Piece;
use crate::program::{BlockIndex, CBlock, Program, Unit, UnitKind};
use crate::unit_table::UnitTable;

/// An `M98 P` call, linked once every program is loaded.
struct Call {
    unit: usize,
    file: usize,
    span: (usize, usize),
    p: u32,
}

/// An `M97 P` whose line was not in the unit when the call was read.
struct Line {
    file: usize,
    span: (usize, usize),
    n: u32,
}

/// The unit being built.
struct Cur {
    unit: usize,
    file: usize,
    /// The `M97 P` calls whose line has not come (yet), by line number.
    m97: BTreeMap<u32, Vec<Line>>,
    flow: UnitFlow,
}

/// The building state of a Fanuc compile.
pub(crate) struct FanucUnits {
    table: UnitTable,
    axes: Vec<char>,
    cur: Option<Cur>,
    calls: Vec<Call>,
    macro_calls: Vec<MacroCall>,
}

impl FanucUnits {
    /// Building state for `prog`'s compile keeping `max` diagnostics per file and phase (0: all);
    /// starts the main program of file 0.
    pub(crate) fn new(prog: &mut Program, max: usize) -> Self {
        let mut f = FanucUnits {
            table: UnitTable::new(max),
            axes: prog.machine.axes(),
            cur: None,
            calls: Vec::new(),
            macro_calls: Vec::new(),
        };
        f.start_unit(prog, 0, UnitKind::Main, 0);
        f
    }

    fn start_unit(&mut self, prog: &mut Program, file: usize, kind: UnitKind, l: u32) {
        let unit = Unit {
            kind,
            l,
            file,
            start: 0,
            end: 0,
            index: BlockIndex::default(),
        };
        let unit = self.table.push_unit(prog, unit);
        self.cur = Some(Cur {
            unit,
            file,
            m97: BTreeMap::new(),
            flow: UnitFlow::default(),
        });
    }

    fn end_unit(&mut self, prog: &mut Program) {
        let Some(cur) = self.cur.take() else {
            return;
        };
        let u = cur.unit;
        let kept = !self.table.failed();
        if kept {
            // Of a number written twice the last block is the target (it replaced the first).
            prog.units[u].index.finish();
        }
        let numbers = &self.table.numbers[u];
        // Every line that came was taken out: these never came.
        for m in cur.m97.into_values().flatten() {
            let n = m.n;
            self.table.phases.link.push(crate::program::err(
                codes::MISSING_BLOCK,
                &prog.files[m.file].name,
                "",
                m.span,
                format!("M97 P{n}: no block N{n} in this program"),
                "M97 calls a line number of the same program",
            ));
        }
        cur.flow
            .end(prog, u, kept, numbers, &mut self.table.phases.flow);
    }

    /// Takes a piece of file `file` from the parser; `parse_failed`: the parse has an error.
    fn piece(&mut self, prog: &mut Program, file: usize, p: Piece, parse_failed: bool) {
        match p {
            Piece::Block(b) => self.block(prog, b, parse_failed),
            Piece::Number(n) => {
                // The main program's number; a macro file's program is named by the file.
                if file == 0 {
                    prog.units[0].l = n;
                }
            }
            Piece::Program(n) => {
                self.end_unit(prog);
                let lib = self.register(prog, file, n);
                self.start_unit(prog, file, UnitKind::Library, n);
                if lib {
                    prog.library.insert(n, prog.units.len() - 1);
                }
            }
        }
    }

    /// True when program O`num` is new; a number already loaded keeps its first program.
    fn register(&mut self, prog: &Program, file: usize, num: u32) -> bool {
        if prog.library.contains_key(&num)
            || (prog.units.first().is_some_and(|u| u.l == num && num != 0))
        {
            let f = &prog.files[file];
            self.table.phases.units.push(
                Diagnostic::warning(
                    codes::DUPLICATE_N,
                    f.name.clone(),
                    0..0,
                    format!("program O{num} is loaded twice: the first one is called"),
                )
                .with_hint("every O number names one program (the main file's programs load first)")
                .locate(&f.text),
            );
            return false;
        }
        true
    }

    fn block(&mut self, prog: &mut Program, b: Block, parse_failed: bool) {
        let Some(cur) = self.cur.as_mut() else {
            return;
        };
        let (u, file) = (cur.unit, cur.file);
        let idx = prog.blocks.len();
        if let Some(n) = b.n {
            if !self.table.number(u, n) {
                self.table
                    .phases
                    .units
                    .push(crate::program::to_locate(Diagnostic::warning(
                        codes::DUPLICATE_N,
                        prog.files[file].name.clone(),
                        b.span.0..b.span.1,
                        format!("block number N{n} is used twice"),
                    )));
            }
            self.table.index(prog, u, n, idx);
            if !cur.m97.is_empty() {
                cur.m97.remove(&n);
            }
            cur.flow.arrived(n);
        }
        let mut cb = CBlock {
            n: b.n,
            file,
            unit: u,
            span: b.span,
            skip: b.skip,
            words: b.words.into_boxed_slice(),
            decls: b.decls.into_boxed_slice(),
            arith_ops: 0,
            native: None,
            mac: b.mac,
            jump: None,
        };
        let kept = !self.table.failed();
        let numbers = &self.table.numbers[u];
        for (m, p) in crate::fanuc::check_block(prog, &cb, &self.axes, &mut self.table.phases.check)
        {
            match (m, p) {
                (97, Some(n)) if !numbers.contains(n) => cur.m97.entry(n).or_default().push(Line {
                    file,
                    span: cb.span,
                    n,
                }),
                (98, Some(p)) => self.calls.push(Call {
                    unit: u,
                    file,
                    span: cb.span,
                    p,
                }),
                _ => {}
            }
        }
        if let Some(mac) = cb.mac.take() {
            if let Some(stmt) = &mac.stmt {
                cur.flow.block(
                    prog,
                    &mut cb,
                    stmt,
                    idx,
                    kept,
                    numbers,
                    &mut self.macro_calls,
                    &mut self.table.phases.flow,
                );
            }
            cb.mac = Some(mac);
        }
        if self.table.keep(prog, u, cb, parse_failed) {
            cur.flow.dropped(&self.table.numbers[u]);
        }
    }

    /// Streams the main file `name` (text `src`) into its units; the parser's diagnostics go to
    /// `sink`. Returns the program number of its header.
    pub(crate) fn main_file(
        &mut self,
        prog: &mut Program,
        name: &str,
        src: &str,
        sink: &mut Sink,
    ) -> Option<u32> {
        let parsed =
            crate::parse::parse_streaming(Dialect::Fanuc, name, src, true, sink, &mut |p, s| {
                self.piece(prog, 0, p, s.has_errors())
            });
        self.end_unit(prog);
        parsed.number
    }

    /// Loads the `O<n>` programs of the macro folder for M98 and G65 (`main_failed`: the main
    /// file's parse had an error).
    pub(crate) fn load_library(&mut self, prog: &mut Program, main_failed: bool) {
        let dir = prog.machine.macro_dir.clone();
        for (path, fname, stem) in crate::program::macro_folder_files(&dir) {
            let Some(num) = crate::library::fanuc_library_number(&stem) else {
                continue;
            };
            let Some(text) = self.table.read_macro(&path, &fname) else {
                continue;
            };
            let name = crate::library::file_name(&fname);
            let file = prog.add_macro_file(&name);
            let lib = self.register(prog, file, num);
            self.start_unit(prog, file, UnitKind::Library, num);
            if lib {
                prog.library.insert(num, prog.units.len() - 1);
            }
            // The file's parse errors come after what the units phase holds so far and before the
            // file's own units diagnostics (its units were built after it was parsed).
            let mut parse = self.table.begin_file_parse();
            crate::parse::parse_streaming(
                Dialect::Fanuc,
                &name,
                &text,
                true,
                &mut parse,
                &mut |p, s| self.piece(prog, file, p, main_failed || s.has_errors()),
            );
            self.end_unit(prog);
            self.table.end_file_parse(parse);
            prog.files[file].text = text;
        }
    }

    /// Links the `M98 P` and `G65 P` calls, finds recursion through `M98` and pushes every
    /// phase's diagnostics into `sink`.
    pub(crate) fn finish(mut self, prog: &mut Program, sink: &mut Sink) {
        let n = prog.units.len();
        // Per unit, the calls out of it: (callee, index of the call).
        let mut edges: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
        for (ci, c) in self.calls.iter().enumerate() {
            match prog.library.get(&c.p) {
                Some(&u) => edges[c.unit].push((u, ci)),
                None if prog.units[0].l == c.p && c.p != 0 => edges[c.unit].push((0, ci)),
                None => self.table.phases.link.push(crate::program::err(
                    codes::MISSING_SUBPROGRAM,
                    &prog.files[c.file].name,
                    "",
                    c.span,
                    format!("M98 P{}: program O{} not found", c.p, c.p),
                    "store subprograms as files O<n> in the machine's macro folder",
                )),
            }
        }
        // Recursion through M98: a cycle in the static call graph never terminates.
        let hits = crate::unit_table::back_edges(&edges);
        for ci in hits {
            let c = &self.calls[ci];
            self.table.phases.rec.push(crate::program::err(
                codes::RECURSION,
                &prog.files[c.file].name,
                "",
                c.span,
                "M98 call leads back to its own program: unbounded recursion",
                "a subprogram must not call itself",
            ));
        }
        check_calls(prog, &self.macro_calls, &mut self.table.phases.flow);
        self.table.phases.merge_into(sink);
    }
}
