//! MEFI program units built block by block as the parser hands the blocks on: the split of a file
//! into main program, subprograms `G79 L … G70` and library units, the block-number tables, the
//! static checks of each block and what linking needs of it later ([`LinkRef`]).
//!
//! Invariants (issue 23): a block is checked as soon as it is complete and kept only while the
//! compile has no error ([`UnitTable`]: a program with an error never runs). What a rejected
//! program holds per block is its number in two compressed bitmaps (file-wide for duplicates, per
//! unit for jump targets; [`RoaringBitmap`]) and, for a block with a literal jump forward (a jump
//! back is resolved at once), a call or a fixed cycle, one [`LinkRef`] until linking. The
//! diagnostics of each phase go to their own capped sink ([`crate::unit_table::Phases`]), merged
//! at the end in the order the phases ran (units, block checks, links, M functions, recursion).

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use diag::Diagnostic;
use roaring::RoaringBitmap;

use crate::ast::{Block, Val};
use crate::codes;
use crate::link::LinkRef;
use crate::machine::Dialect;
use crate::parse::Piece;
use crate::program::{BlockIndex, CBlock, Program, Unit, UnitKind, err, lit_int};
use crate::unit_table::UnitTable;

/// An M function of a library block not declared in IOCFIL: reported when a program reaches the
/// unit (known once every call is linked).
pub(crate) struct PendingM {
    pub(crate) unit: usize,
    pub(crate) diagnostic: Diagnostic,
}

/// The building state of a MEFI compile: every file's units, block by block.
pub(crate) struct Units {
    /// The units, their block numbers, the kept blocks and the phases' diagnostics.
    pub(crate) table: UnitTable,
    /// Per unit: the span of its `G79` block (the main program: none).
    entry: Vec<(usize, usize)>,
    /// Per unit: true once a block with G70 was seen in it.
    closed: Vec<bool>,
    /// The blocks with a literal jump, call or fixed cycle still to link, by block order (a
    /// forward jump leaves once its target arrives: a record per jump still waiting, not per
    /// jump). [`Units::take_refs`] hands them to linking.
    refs: BTreeMap<u64, LinkRef>,
    /// Forward jumps waiting for their target: (unit, number) → their keys in `refs`.
    waiting: HashMap<(usize, u32), Vec<u64>>,
    /// The key of the next entry of `refs`.
    next_ref: u64,
    /// Undeclared M functions of library blocks.
    pub(crate) lib_m: Vec<PendingM>,
}

/// The building state of one file.
pub(crate) struct FileUnits {
    file: usize,
    name: String,
    library: bool,
    cur: Option<usize>,
    main_ended: bool,
    subs: usize,
    first_unit: usize,
    /// The block numbers of the file (a main file's numbers are unique in the file).
    numbers: RoaringBitmap,
}

fn g_lits(b: &Block) -> impl Iterator<Item = i64> + '_ {
    lits(b, 'G')
}

fn lits(b: &Block, a: char) -> impl Iterator<Item = i64> + '_ {
    b.words
        .iter()
        .filter(move |w| w.addr == a)
        .filter_map(|w| match w.val {
            Val::Lit(l) => lit_int(&l),
            Val::Param(_) | Val::Expr(_) => None,
        })
}

fn lit_of(b: &Block, a: char) -> Option<i64> {
    b.words
        .iter()
        .find(|w| w.addr == a)
        .and_then(|w| match w.val {
            Val::Lit(l) => lit_int(&l),
            Val::Param(_) | Val::Expr(_) => None,
        })
}

fn cblock(file: usize, unit: usize, b: Block) -> CBlock {
    let arith_ops = g_lits(&b)
        .find(|g| (26..=29).contains(g))
        .map_or(0, |g| (g - 25) as u8);
    CBlock {
        n: b.n,
        file,
        unit,
        span: b.span,
        skip: b.skip,
        words: b.words.into_boxed_slice(),
        decls: b.decls.into_boxed_slice(),
        arith_ops,
        native: None,
        mac: None,
        jump: None,
    }
}

impl Units {
    /// Building state for a compile keeping `max` diagnostics per file and phase (0: all).
    pub(crate) fn new(max: usize) -> Self {
        Units {
            table: UnitTable::new(max),
            entry: Vec::new(),
            closed: Vec::new(),
            refs: BTreeMap::new(),
            waiting: HashMap::new(),
            next_ref: 0,
            lib_m: Vec::new(),
        }
    }

    /// Block number `n` arrived in unit `u`: the forward jumps to it are resolved, and those with
    /// nothing else to link leave.
    fn arrived(&mut self, u: usize, n: u32) {
        for key in self.waiting.remove(&(u, n)).unwrap_or_default() {
            if let Some(r) = self.refs.get_mut(&key) {
                r.resolve_jump(&self.table.numbers[u]);
                if !r.pending() {
                    self.refs.remove(&key);
                }
            }
        }
    }

    /// What linking checks, in block order: the calls, the fixed cycles and the jumps whose
    /// target never arrived.
    pub(crate) fn take_refs(&mut self) -> Vec<LinkRef> {
        self.waiting = HashMap::new();
        std::mem::take(&mut self.refs).into_values().collect()
    }

    fn push_unit(&mut self, prog: &mut Program, unit: Unit, entry: (usize, usize)) -> usize {
        self.entry.push(entry);
        self.closed.push(false);
        self.table.push_unit(prog, unit)
    }

    /// Starts file `file` of `prog`: 0 is the main file (main program, then subprograms), others
    /// are library files (units only).
    pub(crate) fn start_file(&mut self, prog: &mut Program, file: usize) -> FileUnits {
        let library = file != 0;
        let mut f = FileUnits {
            file,
            name: prog.files[file].name.clone(),
            library,
            cur: None,
            main_ended: false,
            subs: 0,
            first_unit: prog.units.len(),
            numbers: RoaringBitmap::new(),
        };
        if !library {
            let unit = Unit {
                kind: UnitKind::Main,
                l: 0,
                file,
                start: prog.blocks.len(),
                end: prog.blocks.len(),
                index: BlockIndex::default(),
            };
            f.cur = Some(self.push_unit(prog, unit, (0, 0)));
            f.first_unit = prog.units.len();
        }
        f
    }

    /// Takes the next block of file `f`; `parse_failed`: the parser reported an error.
    pub(crate) fn block(
        &mut self,
        prog: &mut Program,
        f: &mut FileUnits,
        b: Block,
        parse_failed: bool,
    ) {
        let diags = &mut self.table.phases.units;
        let fname = f.name.as_str();
        if g_lits(&b).any(|g| g == 79) {
            if let Some(u) = f.cur
                && prog.units[u].kind == UnitKind::Main
                && !f.main_ended
            {
                diags.push(err(
                    codes::AFTER_END,
                    fname,
                    "",
                    b.span,
                    "subprogram before the end of the main program",
                    "subprograms follow the block with M02 or M30",
                ));
            }
            let l = lit_of(&b, 'L').unwrap_or(0);
            let kind = if f.library {
                UnitKind::Library
            } else {
                f.subs += 1;
                if f.subs == 100 {
                    diags.push(err(
                        codes::TOO_MANY_SUBPROGRAMS,
                        fname,
                        "",
                        b.span,
                        "more than 99 subprograms",
                        "a partprogram holds at most 99 subprograms",
                    ));
                }
                UnitKind::Sub
            };
            let map = if f.library {
                &mut prog.library
            } else {
                &mut prog.subs
            };
            if l > 0 && map.insert(l as u32, prog.units.len()).is_some() {
                diags.push(err(
                    codes::DUPLICATE_N,
                    fname,
                    "",
                    b.span,
                    format!("unit L{l} is defined twice"),
                    "every G79 L<n> number must be unique",
                ));
            }
            let unit = Unit {
                kind,
                l: l as u32,
                file: f.file,
                start: prog.blocks.len(),
                end: prog.blocks.len(),
                index: BlockIndex::default(),
            };
            f.cur = Some(self.push_unit(prog, unit, b.span));
        }
        let diags = &mut self.table.phases.units;
        let Some(u) = f.cur else {
            diags.push(err(
                codes::NO_BLOCK_NUMBER,
                fname,
                "",
                b.span,
                "block outside a G79 … G70 unit",
                "a macro file holds units that start with `G79 L<n>` and end with G70",
            ));
            return;
        };
        let kind = prog.units[u].kind;
        if kind == UnitKind::Main && f.main_ended {
            diags.push(err(
                codes::AFTER_END,
                fname,
                "",
                b.span,
                "block after the end of the main program",
                "only subprograms (G79 L<n> … G70) may follow M02/M30",
            ));
            return;
        }
        let ends_main = kind == UnitKind::Main && lits(&b, 'M').any(|m| m == 2 || m == 30);
        let ends_unit = kind != UnitKind::Main && g_lits(&b).any(|g| g == 70);
        let idx = prog.blocks.len();
        if let Some(n) = b.n {
            // A library unit's numbers are unique in the unit, a main file's in the file.
            let fresh = if f.library {
                self.table.number(u, n)
            } else {
                f.numbers.insert(n) && self.table.number(u, n)
            };
            if !fresh {
                self.table.phases.units.push(err(codes::DUPLICATE_N, fname, "", b.span, format!("block number N{n} is used twice"), "block numbers must be unique within a partprogram file (within a unit of a macro file)"));
            } else {
                self.table.index(prog, u, n, idx);
                self.arrived(u, n);
            }
        }
        let cb = cblock(f.file, u, b);
        crate::check::check_block(prog, &cb, &mut self.table.phases.check);
        if let Some(mut r) = LinkRef::of(&cb) {
            // A jump back to a block of the unit is resolved now: numbers are never removed.
            r.resolve_jump(&self.table.numbers[u]);
            if r.pending() {
                let key = self.next_ref;
                self.next_ref += 1;
                if let Some(target) = r.jump_target() {
                    self.waiting.entry((u, target)).or_default().push(key);
                }
                self.refs.insert(key, r);
            }
        }
        if prog.machine.check_m_declared {
            for d in crate::link::undeclared_m(prog, &cb) {
                if kind == UnitKind::Library {
                    self.lib_m.push(PendingM {
                        unit: u,
                        diagnostic: d,
                    });
                } else {
                    // A unit of the main file always runs or may be called: it is reached.
                    self.table.phases.m.push(d);
                }
            }
        }
        if ends_main {
            f.main_ended = true;
        }
        if ends_unit {
            // A unit runs until the next G79 (the cycle files put blocks after an inner G70), but
            // it must contain at least one G70.
            self.closed[u] = true;
        }
        self.table.keep(prog, u, cb, parse_failed);
    }

    /// Ends file `f` (text `src`): units without G70, a main program without M02/M30.
    pub(crate) fn end_file(&mut self, prog: &mut Program, f: FileUnits, src: &str) {
        let diags = &mut self.table.phases.units;
        for u in f.first_unit..prog.units.len() {
            if prog.units[u].kind != UnitKind::Main && !self.closed[u] {
                diags.push(err(
                    codes::UNIT_NOT_CLOSED,
                    &f.name,
                    "",
                    self.entry[u],
                    format!("unit L{} has no G70", prog.units[u].l),
                    "end the unit with a block containing G70",
                ));
            }
        }
        // An empty file has one error saying so; "no M02/M30" would only repeat it.
        if !f.library && !f.main_ended && !src.trim().is_empty() {
            diags.push(
                Diagnostic::warning(
                    codes::NO_END,
                    &f.name,
                    0..0,
                    "the main program has no M02/M30 block",
                )
                .with_hint("end the main program with M02 or M30")
                .locate(src),
            );
        }
    }

    /// Loads every macro file `L<n>` and every `$PC` cycle file of `dir`; `parse_failed`: the
    /// main file's parse had an error.
    pub(crate) fn load_library(&mut self, prog: &mut Program, dir: &Path, parse_failed: bool) {
        for (path, fname, stem) in crate::program::macro_folder_files(dir) {
            let Some(text) = self.table.read_macro(&path, &fname) else {
                continue;
            };
            if !crate::library::is_mefi_library(&stem, &text) {
                continue;
            }
            let name = crate::library::file_name(&fname);
            let file = prog.add_macro_file(&name);
            let mut f = self.start_file(prog, file);
            // Each block is built as the parser hands it on (an error-dense macro file is held
            // no more than a main file). The file's parse errors come after what the units phase
            // holds so far and before the units diagnostics of its blocks, as when it was parsed
            // whole first.
            let mut parse = self.table.begin_file_parse();
            // A macro file without `%` header starts at its first byte.
            let header = false;
            crate::parse::parse_streaming(
                Dialect::Mefi,
                &name,
                &text,
                header,
                &mut parse,
                &mut |p, s| {
                    if let Piece::Block(b) = p {
                        self.block(prog, &mut f, b, parse_failed || s.has_errors())
                    }
                },
            );
            self.table.end_file_parse(parse);
            self.end_file(prog, f, &text);
            prog.files[file].text = text;
        }
    }
}
