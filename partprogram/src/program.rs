//! Compiled program: files, blocks, program units (main program, subprograms, macrocycles, fixed
//! cycles) and the static checks of the MEFI dialect.
//!
//! A main file holds the main program up to its M02/M30 block followed by subprograms `G79 L … G70`.
//! The machine's macro folder holds macro files `L<n>` and `$PC` fixed-cycle files whose units
//! `G79 L8x … G70` implement G81–G89. All of them are parsed, checked and linked here; jump and call
//! targets written literally are resolved at compile time, computed ones at run time.

use std::collections::HashMap;
use std::path::Path;

use diag::{Diagnostic, Hidden, Sink};

use crate::ast::{Block, Decl, ParsedFile, Val, Word};
use crate::codes;
use crate::lexer::Lit;
use crate::machine::{Dialect, MachineSpec};

/// What a program unit is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnitKind {
    /// The main program.
    Main,
    /// A subprogram of the main file (`G71 L`).
    Sub,
    /// A library unit from the macro folder (`G72 L`, fixed cycles `G8x` → `L8x`).
    Library,
}

/// One program unit: a contiguous range of blocks with its own block-number index.
#[derive(Debug, Clone)]
pub struct Unit {
    /// Kind of unit.
    pub kind: UnitKind,
    /// Unit number (`G79 L<n>`), 0 for the main program.
    pub l: u32,
    /// Index of the file the unit is in.
    pub file: usize,
    /// First block (index into [`Program::blocks`]).
    pub start: usize,
    /// One past the last block.
    pub end: usize,
    /// Block number → block index.
    pub index: HashMap<u32, usize>,
}

/// A block ready to run.
#[derive(Debug, Clone)]
pub struct CBlock {
    /// Block number.
    pub n: Option<u32>,
    /// File index.
    pub file: usize,
    /// Unit index.
    pub unit: usize,
    /// Byte range in the file.
    pub span: (usize, usize),
    /// Block skip `/`.
    pub skip: bool,
    /// Words (not N, not declarations).
    pub words: Vec<Word>,
    /// Declarations.
    pub decls: Vec<Decl>,
    /// Number of arithmetic operations when G26..G29 is written literally (1..4), else 0.
    pub arith_ops: u8,
    /// Index of the native function for this block's arithmetic, when compiled.
    pub native: Option<usize>,
    /// Fanuc Macro B: the block's statement or the expressions of its words.
    pub mac: Option<Box<crate::macro_b::Macro>>,
    /// Fanuc Macro B: for `WHILE … DO m` the block of its `END m`, for `END m` the `DO` block, for a
    /// `GOTO`/`IF … GOTO` with a literal target the target block (resolved by `macro_b::flow`).
    pub jump: Option<usize>,
}

impl CBlock {
    /// The first word with address `a`.
    pub fn word(&self, a: char) -> Option<&Word> {
        self.words.iter().find(|w| w.addr == a)
    }

    /// True when a literal `G<g>` is written.
    pub fn has_g(&self, g: i64) -> bool {
        self.words
            .iter()
            .any(|w| w.addr == 'G' && matches!(w.val, Val::Lit(l) if l.milli == g * 1000))
    }
}

/// A source file of the program.
#[derive(Debug, Clone)]
pub struct SourceFile {
    /// Name used in diagnostics.
    pub name: String,
    /// Text.
    pub text: String,
}

/// A compiled partprogram with its subprograms and the machine's library units.
#[derive(Debug)]
pub struct Program {
    /// Dialect.
    pub dialect: Dialect,
    /// Program number from the header.
    pub number: Option<u32>,
    /// Files: 0 is the main file.
    pub files: Vec<SourceFile>,
    /// All blocks.
    pub blocks: Vec<CBlock>,
    /// All units; unit 0 is the main program.
    pub units: Vec<Unit>,
    /// Subprograms of the main file by number.
    pub subs: HashMap<u32, usize>,
    /// Library units by number (macros and fixed cycles).
    pub library: HashMap<u32, usize>,
    /// The machine.
    pub machine: MachineSpec,
    /// Native code for arithmetic blocks (None when not compiled or not available).
    pub native: Option<crate::jit::NativeCode>,
    /// Native code of the Fanuc Macro B runs (None when the program has none).
    pub macro_native: Option<crate::macro_b::native::MacroCode>,
}

/// Integer value of a literal written for a count address (None when it has a fraction).
pub fn lit_int(l: &Lit) -> Option<i64> {
    if l.milli % 1000 != 0 {
        None
    } else {
        Some(l.milli / 1000)
    }
}

/// Column of a diagnostic made by [`err`] that [`compile`] has still to locate.
const TO_LOCATE: u32 = u32::MAX;

/// An error of the static checks at `span` of `file`. It is located by [`compile`] in one pass per
/// file at the end (locating each one by scanning `src` is quadratic: issue 12, a one-block program
/// with 200,001 errors took 117 s), so `src` is not read here.
pub(crate) fn err(
    code: u32,
    file: &str,
    _src: &str,
    span: (usize, usize),
    msg: impl Into<String>,
    hint: &str,
) -> Diagnostic {
    to_locate(Diagnostic::error(code, file, span.0..span.1, msg).with_hint(hint))
}

/// Marks `d` (about one of the program's files) to be located by [`compile`] at the end.
pub(crate) fn to_locate(mut d: Diagnostic) -> Diagnostic {
    d.column = TO_LOCATE;
    d
}

/// Fills line and column of the diagnostics [`err`] made, with one walk over each file's text
/// (`main`: the text of file 0, which the program holds only once it compiled).
fn locate_pending(files: &[SourceFile], main: &str, diags: &mut [Diagnostic]) {
    for (i, f) in files.iter().enumerate() {
        let text = if i == 0 { main } else { f.text.as_str() };
        let pending: Vec<usize> = (0..diags.len())
            .filter(|&d| diags[d].column == TO_LOCATE && diags[d].file == f.name)
            .collect();
        if pending.is_empty() {
            continue;
        }
        let offsets: Vec<usize> = pending.iter().map(|&d| diags[d].span.start).collect();
        for (d, lc) in pending.into_iter().zip(diag::line_columns(text, &offsets)) {
            (diags[d].line, diags[d].column) = lc;
        }
    }
    for d in diags.iter_mut().filter(|d| d.column == TO_LOCATE) {
        // A file not among the program's (cannot happen): whole-file position.
        (d.line, d.column) = (0, 0);
    }
}

/// Compiles the main file `name` (text `src`) for `machine`, loading library units from
/// `machine.macro_dir`. Returns the program (None when errors prevent running it) and diagnostics.
pub fn compile(machine: &MachineSpec, name: &str, src: &str) -> (Option<Program>, Vec<Diagnostic>) {
    let (prog, diags, _) = compile_capped(machine, name, src, 0);
    (prog, diags)
}

/// [`compile`] keeping at most `max` diagnostics per file (0: all), the first in source order,
/// and counting the others (the returned [`Hidden`] per file): the memory an error-dense program's
/// diagnostics take is bounded whatever their number (`ncplc nc check --max-errors`, issue 23).
pub fn compile_capped(
    machine: &MachineSpec,
    name: &str,
    src: &str,
    max: usize,
) -> (Option<Program>, Vec<Diagnostic>, Vec<Hidden>) {
    let mut prog = Program {
        dialect: machine.dialect,
        number: None,
        // The main file's text is copied in once the program compiled: a rejected file is not
        // copied at all (its diagnostics are located in `src`).
        files: vec![SourceFile {
            name: name.to_string(),
            text: String::new(),
        }],
        blocks: Vec::new(),
        units: Vec::new(),
        subs: HashMap::new(),
        library: HashMap::new(),
        machine: machine.clone(),
        native: None,
        macro_native: None,
    };
    let mut sink = Sink::new(max);
    let parsed = crate::parse::parse_into(machine.dialect, name, src, &mut sink);
    prog.number = parsed.number;
    if machine.dialect == Dialect::Fanuc {
        crate::fanuc::build_units(&mut prog, parsed, &mut sink);
        crate::fanuc::check(&mut prog, &mut sink);
        crate::macro_b::flow::link(&mut prog, &mut sink);
    } else {
        build_main_units(&mut prog, 0, parsed, src, &mut sink);
        load_library(&mut prog, &machine.macro_dir, &mut sink);
        for b in 0..prog.blocks.len() {
            crate::check::check_block(&prog, b, &mut sink);
        }
        crate::link::link(&mut prog, &mut sink);
    }
    let failed = sink.has_errors();
    let (mut diags, hidden) = sink.finish();
    locate_pending(&prog.files, src, &mut diags);
    diags.sort_by(|a, b| {
        (a.file != name, &a.file, a.line, a.column).cmp(&(
            b.file != name,
            &b.file,
            b.line,
            b.column,
        ))
    });
    if failed {
        return (None, diags, hidden);
    }
    prog.files[0].text = src.to_string();
    if machine.dialect == Dialect::Fanuc {
        match crate::macro_b::native::compile(&prog) {
            Ok(code) => prog.macro_native = code,
            Err(e) => diags.push(Diagnostic::warning(
                codes::RUN_MACRO,
                name,
                0..0,
                format!("native code generation failed, the interpreter runs the macros: {e}"),
            )),
        }
    }
    if machine.dialect == Dialect::Mefi {
        match crate::jit::compile_program(&prog) {
            Ok(native) => {
                for (bi, fi) in &native.block_fn {
                    prog.blocks[*bi].native = Some(*fi);
                }
                prog.native = Some(native);
            }
            Err(e) => diags.push(Diagnostic::warning(
                codes::RUN_ARITH,
                name,
                0..0,
                format!("native code generation failed, the interpreter runs the arithmetic: {e}"),
            )),
        }
    }
    (Some(prog), diags, hidden)
}

fn g_lits(b: &Block) -> impl Iterator<Item = i64> + '_ {
    b.words
        .iter()
        .filter(|w| w.addr == 'G')
        .filter_map(|w| match w.val {
            Val::Lit(l) => lit_int(&l),
            Val::Param(_) | Val::Expr(_) => None,
        })
}

fn m_lits(b: &Block) -> impl Iterator<Item = i64> + '_ {
    b.words
        .iter()
        .filter(|w| w.addr == 'M')
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

fn push_block(prog: &mut Program, file: usize, unit: usize, b: Block) {
    let arith_ops = g_lits(&b)
        .find(|g| (26..=29).contains(g))
        .map_or(0, |g| (g - 25) as u8);
    prog.blocks.push(CBlock {
        n: b.n,
        file,
        unit,
        span: b.span,
        skip: b.skip,
        words: b.words,
        decls: b.decls,
        arith_ops,
        native: None,
        mac: None,
        jump: None,
    });
}

/// Splits a parsed MEFI file into units. `file` 0 is the main file (main program + subprograms);
/// other files are library files (units only).
fn build_main_units(
    prog: &mut Program,
    file: usize,
    parsed: ParsedFile,
    src: &str,
    diags: &mut Sink,
) {
    let fname = prog.files[file].name.clone();
    let library = file != 0;
    let mut cur: Option<usize> = None;
    let mut main_ended = false;
    if !library {
        prog.units.push(Unit {
            kind: UnitKind::Main,
            l: 0,
            file,
            start: prog.blocks.len(),
            end: prog.blocks.len(),
            index: HashMap::new(),
        });
        cur = Some(prog.units.len() - 1);
    }
    prog.blocks.reserve_exact(parsed.blocks.len());
    let mut subs = 0;
    let first_unit = prog.units.len();
    let mut closed = std::collections::HashSet::new();
    for b in parsed.blocks {
        let is_entry = g_lits(&b).any(|g| g == 79);
        if is_entry {
            if let Some(u) = cur
                && prog.units[u].kind == UnitKind::Main
                && !main_ended
            {
                diags.push(err(
                    codes::AFTER_END,
                    &fname,
                    src,
                    b.span,
                    "subprogram before the end of the main program",
                    "subprograms follow the block with M02 or M30",
                ));
            }
            let l = lit_of(&b, 'L').unwrap_or(0);
            let kind = if library {
                UnitKind::Library
            } else {
                UnitKind::Sub
            };
            if !library {
                subs += 1;
                if subs == 100 {
                    diags.push(err(
                        codes::TOO_MANY_SUBPROGRAMS,
                        &fname,
                        src,
                        b.span,
                        "more than 99 subprograms",
                        "a partprogram holds at most 99 subprograms",
                    ));
                }
            }
            let map = if library {
                &mut prog.library
            } else {
                &mut prog.subs
            };
            if l > 0 && map.insert(l as u32, prog.units.len()).is_some() {
                diags.push(err(
                    codes::DUPLICATE_N,
                    &fname,
                    src,
                    b.span,
                    format!("unit L{l} is defined twice"),
                    "every G79 L<n> number must be unique",
                ));
            }
            prog.units.push(Unit {
                kind,
                l: l as u32,
                file,
                start: prog.blocks.len(),
                end: prog.blocks.len(),
                index: HashMap::new(),
            });
            cur = Some(prog.units.len() - 1);
        }
        let Some(u) = cur else {
            diags.push(err(
                codes::NO_BLOCK_NUMBER,
                &fname,
                src,
                b.span,
                "block outside a G79 … G70 unit",
                "a macro file holds units that start with `G79 L<n>` and end with G70",
            ));
            continue;
        };
        if prog.units[u].kind == UnitKind::Main && main_ended {
            diags.push(err(
                codes::AFTER_END,
                &fname,
                src,
                b.span,
                "block after the end of the main program",
                "only subprograms (G79 L<n> … G70) may follow M02/M30",
            ));
            continue;
        }
        let ends_main =
            prog.units[u].kind == UnitKind::Main && m_lits(&b).any(|m| m == 2 || m == 30);
        let ends_unit = prog.units[u].kind != UnitKind::Main && g_lits(&b).any(|g| g == 70);
        let idx = prog.blocks.len();
        if let Some(n) = b.n {
            let dup = if library {
                prog.units[u].index.contains_key(&n)
            } else {
                prog.units
                    .iter()
                    .filter(|x| x.file == file)
                    .any(|x| x.index.contains_key(&n))
            };
            if dup {
                diags.push(err(codes::DUPLICATE_N, &fname, src, b.span, format!("block number N{n} is used twice"), "block numbers must be unique within a partprogram file (within a unit of a macro file)"));
            } else {
                prog.units[u].index.insert(n, idx);
            }
        }
        push_block(prog, file, u, b);
        prog.units[u].end = prog.blocks.len();
        if ends_main {
            main_ended = true;
        }
        if ends_unit {
            // A unit runs until the next G79 (the cycle files put blocks after an inner G70), but it
            // must contain at least one G70.
            closed.insert(u);
        }
    }
    for (u, unit) in prog.units.iter().enumerate().skip(first_unit) {
        if unit.kind != UnitKind::Main && !closed.contains(&u) {
            let span = prog.blocks.get(unit.start).map_or((0, 0), |b| b.span);
            diags.push(err(
                codes::UNIT_NOT_CLOSED,
                &fname,
                src,
                span,
                format!("unit L{} has no G70", unit.l),
                "end the unit with a block containing G70",
            ));
        }
    }
    // An empty file has one error saying so; "no M02/M30" would only repeat it.
    if !library && !main_ended && !src.trim().is_empty() {
        diags.push(
            Diagnostic::warning(
                codes::NO_END,
                &fname,
                0..0,
                "the main program has no M02/M30 block",
            )
            .with_hint("end the main program with M02 or M30")
            .locate(src),
        );
    }
}

/// Loads every macro file `L<n>` and every `$PC` cycle file of `dir`.
fn load_library(prog: &mut Program, dir: &Path, diags: &mut Sink) {
    if dir.as_os_str().is_empty() {
        return;
    }
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    let mut paths: Vec<_> = rd
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.is_file())
        .collect();
    paths.sort();
    for path in paths {
        let fname = path
            .file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let stem = fname.split('.').next().unwrap_or("").to_ascii_uppercase();
        let is_l = stem.len() > 1
            && stem.starts_with('L')
            && stem[1..].bytes().all(|c| c.is_ascii_digit());
        let text = match std::fs::read(&path) {
            Ok(bytes) => String::from_utf8_lossy(&bytes).into_owned(),
            Err(e) => {
                diags.push(Diagnostic::error(
                    codes::MACRO_IO,
                    format!("macros/{fname}"),
                    0..0,
                    format!("cannot read: {e}"),
                ));
                continue;
            }
        };
        let is_cycle = text.trim_start().starts_with("$PC");
        if !is_l && !is_cycle {
            continue;
        }
        let name = format!("macros/{fname}");
        let (parsed, d) = crate::parse::parse_library(Dialect::Mefi, &name, &text);
        diags.extend(d);
        prog.files.push(SourceFile {
            name,
            text: String::new(),
        });
        let file = prog.files.len() - 1;
        build_main_units(prog, file, parsed, &text, diags);
        prog.files[file].text = text;
    }
}
