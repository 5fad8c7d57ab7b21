//! Compiled program: files, blocks, program units (main program, subprograms, macrocycles, fixed
//! cycles) and the static checks of the MEFI dialect.
//!
//! A main file holds the main program up to its M02/M30 block followed by subprograms `G79 L … G70`.
//! The machine's macro folder holds macro files `L<n>` and `$PC` fixed-cycle files whose units
//! `G79 L8x … G70` implement G81–G89. All of them are parsed, checked and linked here; jump and call
//! targets written literally are resolved at compile time, computed ones at run time.

use std::collections::HashMap;

use diag::{Diagnostic, Hidden, Sink};

use crate::ast::{Decl, Val, Word};
use crate::codes;
use crate::fanuc_units::FanucUnits;
use crate::lexer::Lit;
use crate::machine::{Dialect, MachineSpec};
use crate::parse::Piece;
use crate::units::Units;

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
    pub index: BlockIndex,
}

/// The blocks of a unit by number: pairs (number, block index) sorted by number, 8 bytes per
/// numbered block (a hash map took 20 to 40). Filled by [`BlockIndex::push`] in any order and
/// sorted once by [`BlockIndex::finish`]; looked up by binary search.
#[derive(Debug, Clone, Default)]
pub struct BlockIndex {
    entries: Vec<(u32, u32)>,
    /// True while `entries` is sorted by number without repeats.
    sorted: bool,
}

impl BlockIndex {
    /// An index of the pairs (number, block index) in file order; of a number written twice the
    /// last block is kept.
    pub fn from_pairs(pairs: impl IntoIterator<Item = (u32, usize)>) -> Self {
        let mut ix = BlockIndex::default();
        for (n, b) in pairs {
            ix.push(n, b);
        }
        ix.finish();
        ix
    }

    /// Adds block `block` under number `n` (a later push of the same number replaces it once
    /// [`BlockIndex::finish`] ran).
    pub fn push(&mut self, n: u32, block: usize) {
        // A program of more than 4 G blocks would need more than 8 GB of text and blocks.
        let block = u32::try_from(block).unwrap_or(u32::MAX);
        self.sorted =
            self.entries.is_empty() || (self.sorted && self.entries[self.entries.len() - 1].0 < n);
        self.entries.push((n, block));
    }

    /// Sorts the pairs by number (stable: of equal numbers the last pushed is kept) and drops the
    /// spare room.
    pub fn finish(&mut self) {
        if !self.sorted {
            self.entries.sort_by_key(|e| e.0);
            let mut out: Vec<(u32, u32)> = Vec::with_capacity(self.entries.len());
            for e in self.entries.drain(..) {
                match out.last_mut() {
                    Some(last) if last.0 == e.0 => *last = e,
                    _ => out.push(e),
                }
            }
            self.entries = out;
            self.sorted = true;
        }
        self.entries.shrink_to_fit();
    }

    /// The block numbered `n`.
    pub fn get(&self, n: u32) -> Option<usize> {
        debug_assert!(
            self.sorted || self.entries.is_empty(),
            "BlockIndex read before finish"
        );
        let i = self.entries.binary_search_by_key(&n, |e| e.0).ok()?;
        Some(self.entries[i].1 as usize)
    }

    /// True when a block is numbered `n`.
    pub fn contains(&self, n: u32) -> bool {
        self.get(n).is_some()
    }

    /// The pairs (number, block index) by number.
    pub fn iter(&self) -> impl Iterator<Item = (u32, usize)> + '_ {
        self.entries.iter().map(|&(n, b)| (n, b as usize))
    }

    /// Numbered blocks.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True when no block has a number.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
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
    pub words: Box<[Word]>,
    /// Declarations.
    pub decls: Box<[Decl]>,
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
            .any(|w| w.addr == 'G' && matches!(w.val, Val::Lit(l) if l.milli() == g * 1000))
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

impl Program {
    /// Adds the macro file `name` (its text is set once it is read through) and returns its index.
    pub(crate) fn add_macro_file(&mut self, name: &str) -> usize {
        self.files.push(SourceFile {
            name: name.to_string(),
            text: String::new(),
        });
        self.files.len() - 1
    }
}

/// Integer value of a literal written for a count address (None when it has a fraction).
pub fn lit_int(l: &Lit) -> Option<i64> {
    if l.milli() % 1000 != 0 {
        None
    } else {
        Some(l.milli() / 1000)
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

/// The text of a macro file's `bytes`, taking them over when they are UTF-8 (no copy of a large
/// file) and replacing invalid sequences otherwise.
pub fn text_of(bytes: Vec<u8>) -> String {
    String::from_utf8(bytes).unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned())
}

/// The files of a machine's macro folder in name order, each with its file name and its
/// upper-case stem (the name before the first `.`): what MEFI's `L<n>`/`$PC` and Fanuc's `O<n>`
/// loaders both walk. An empty path or an unreadable folder has none.
pub(crate) fn macro_folder_files(
    dir: &std::path::Path,
) -> Vec<(std::path::PathBuf, String, String)> {
    if dir.as_os_str().is_empty() {
        return Vec::new();
    }
    let Ok(rd) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut paths: Vec<_> = rd
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.is_file())
        .collect();
    paths.sort();
    paths
        .into_iter()
        .map(|path| {
            let fname = path
                .file_name()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            let stem = fname.split('.').next().unwrap_or("").to_ascii_uppercase();
            (path, fname, stem)
        })
        .collect()
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
    if machine.dialect == Dialect::Fanuc {
        // Like MEFI: each block is built into its unit and checked as the parser hands it on.
        let mut units = FanucUnits::new(&mut prog, max);
        prog.number = units.main_file(&mut prog, name, src, &mut sink);
        units.load_library(&mut prog, sink.has_errors());
        units.finish(&mut prog, &mut sink);
    } else {
        // Each block is built into its unit and checked as the parser hands it on, and kept only
        // while the program has no error (`units`).
        let mut units = Units::new(max);
        let mut f = units.start_file(&mut prog, 0);
        let parsed = crate::parse::parse_streaming(
            machine.dialect,
            name,
            src,
            true,
            &mut sink,
            &mut |p, parse| {
                if let Piece::Block(b) = p {
                    units.block(&mut prog, &mut f, b, parse.has_errors())
                }
            },
        );
        prog.number = parsed.number;
        units.end_file(&mut prog, f, src);
        units.load_library(&mut prog, &machine.macro_dir, sink.has_errors());
        crate::link::link(&prog, &mut units);
        units.table.phases.merge_into(&mut sink);
    }
    let failed = sink.has_errors();
    let (mut diags, mut hidden) = sink.finish();
    // Diagnostics, and the notes of what the cap hid, in file order: the main file first, then the
    // other files by name (the phases are merged at the end, so the order in which files first
    // overflowed is not the order the checks found their diagnostics in); within a file by place.
    // The files are ranked once (comparing names at every step of the sort was a tenth of a
    // compile of error-dense text): the program's, and a macro file that could not be read (2031).
    let mut files: Vec<String> = prog.files.iter().map(|f| f.name.clone()).collect();
    for d in &diags {
        if !files.contains(&d.file) {
            files.push(d.file.clone());
        }
    }
    files.sort_by(|a, b| (a != name, a).cmp(&(b != name, b)));
    let rank = |file: &str| files.iter().position(|f| f == file).unwrap_or(usize::MAX);
    hidden.sort_by_key(|h| rank(&h.file));
    locate_pending(&prog.files, src, &mut diags);
    diags.sort_by_cached_key(|d| (rank(&d.file), d.line, d.column));
    if failed {
        return (None, diags, hidden);
    }
    prog.files[0].text = src.to_string();
    // Without the spare room of the last doubling: the blocks live as long as the program.
    prog.blocks.shrink_to_fit();
    for u in &mut prog.units {
        u.index.finish();
    }
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
