//! The partprogram of a part run: found (a name in `<machine>/nc/`, or a path), compiled with the
//! machine's view (`machine_view::machine_spec`, its correction table) and planned into canonical
//! blocks, with a content hash for the trace header and the summary, and the CRC-32 of every
//! other file the compile read ([`Part::files`]: macro and cycle files, the correction table,
//! `nc/CONSTANTS`, `nc/DIALECT`), so that a replay names the file that changed.
//!
//! The retained Fanuc macro variables `#500`–`#999` are given as the text of `nc/MACROVARS` (read
//! once when a part run starts, or taken from a trace header by a replay): every plan of the run
//! starts from the same values, and [`Part::vars_end`] holds each plan's final ones.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use partprogram::macro_b::retained::Retained;
use partprogram::{Canon, PlanOptions};

use crate::machine_view::{load_corrections, load_macro_vars, machine_spec};

/// A planned partprogram.
#[derive(Debug, Clone)]
pub struct Part {
    /// Its name as given (`O1000.nc`) or its path.
    pub name: String,
    /// CRC-32 of its text, hexadecimal.
    pub hash: String,
    /// The file it was read from.
    pub path: PathBuf,
    /// The canonical blocks in execution order, shared with the CNC process that runs them (the
    /// plan of a 50 MB program is hundreds of megabytes: it is held once).
    pub blocks: cnc::Blocks,
    /// The same with block skip on (blocks marked `/` left out), for the PLC's BSKIP switch; the
    /// same vector as `blocks` when no block is marked.
    pub skipped: cnc::Blocks,
    /// Every other file the compile read: (path relative to the machine directory, CRC-32), in
    /// name order.
    pub files: Vec<FileCrc>,
    /// The retained macro variables at the start of both plans.
    pub vars_start: Retained,
    /// The retained macro variables at the end of the plan without and with block skip.
    pub vars_end: [Retained; 2],
}

/// A file the compile read: (path relative to the machine directory, CRC-32).
pub type FileCrc = (String, String);

/// CRC-32 of `bytes`, 8 hex digits.
pub fn crc32_hex(bytes: &[u8]) -> String {
    format!("{:08x}", crc32fast::hash(bytes))
}

/// The machine files every compile reads, those that exist: (name, CRC-32).
fn machine_files(dir: &Path) -> Vec<FileCrc> {
    crate::machine_view::machine_view_files(dir)
        .into_iter()
        .filter_map(|p| {
            let bytes = std::fs::read(&p).ok()?;
            let name = p
                .strip_prefix(dir)
                .unwrap_or(&p)
                .to_string_lossy()
                .into_owned();
            Some((name, crc32_hex(&bytes)))
        })
        .collect()
}

/// The files besides `name` that compiling and planning `text` reads (see [`Part::files`]).
pub fn files_read(
    dir: &Path,
    name: &str,
    text: &str,
    dialect: Option<&str>,
    vars: Option<&str>,
) -> Result<Vec<FileCrc>, String> {
    Ok(compile_text(dir, name, text, dialect, None, vars)?.files(dir))
}

/// `program` as a path when it exists, else `<machine>/nc/<program>`.
pub fn program_path(machine: &Path, program: &Path) -> PathBuf {
    if program.exists() {
        program.to_path_buf()
    } else {
        machine.join("nc").join(program)
    }
}

/// Compiles and plans `text` (named `name`) for the machine in `dir` with its retained macro
/// variables; the error is the rendered diagnostics.
pub fn plan_text(
    dir: &Path,
    name: &str,
    text: &str,
    dialect: Option<&str>,
    block_skip: bool,
) -> Result<Vec<Canon>, String> {
    let vars = crate::machine_view::read_macro_vars(dir).map_err(|e| {
        format!(
            "{}: {e}",
            crate::machine_view::macro_vars_file(dir).display()
        )
    })?;
    compile_text(dir, name, text, dialect, None, vars.as_deref())?
        .plan(block_skip, &[])
        .map(|(blocks, _)| blocks)
}

/// The re-planner of `part` for the kernel's tool-correction request: the same text planned with
/// the correction table `kor` (the machine's own when None), read again at each request.
pub fn replanner(
    dir: &Path,
    part: &Part,
    dialect: Option<String>,
    kor: Option<PathBuf>,
    vars: Option<String>,
) -> Result<cnc::correction::Replanner, String> {
    let bytes = std::fs::read(&part.path).map_err(|e| format!("{}: {e}", part.path.display()))?;
    let text = String::from_utf8_lossy(&bytes).into_owned();
    let dir = dir.to_path_buf();
    let selected = part.name.clone();
    let name = source_name(&part.path);
    Ok(Box::new(move |program: &str, skip: bool| {
        (program == selected).then(|| {
            compile_text(
                &dir,
                &name,
                &text,
                dialect.as_deref(),
                kor.as_deref(),
                vars.as_deref(),
            )
            .and_then(|c| c.plan(skip, &[]))
            .map(|(blocks, _)| blocks)
        })
    }))
}

/// Compiles and plans `text` with the retained-variables text `vars`, starting from the axis
/// positions `start` (axis letter, position; MDI blocks start where the axes stand; letters the
/// machine does not have are ignored); the blocks and the retained variables at the end.
pub fn plan_text_from(
    dir: &Path,
    name: &str,
    text: &str,
    dialect: Option<&str>,
    vars: Option<&str>,
    start: &[(char, f64)],
) -> Result<(Vec<Canon>, Retained), String> {
    compile_text(dir, name, text, dialect, None, vars)?.plan(false, start)
}

/// A partprogram compiled with the machine's view, ready to be planned (once per block-skip
/// setting: compiling reads the machine and compiles its macro library, planning does not).
pub struct Compiled {
    prog: partprogram::Program,
    sources: diag::Sources,
}

/// Compiles `text` (named `name`) for the machine in `dir` with the correction table `kor` (the
/// machine's own when None) and the retained-variables text `vars` (None: all null); the error is
/// the rendered diagnostics.
pub fn compile_text(
    dir: &Path,
    name: &str,
    text: &str,
    dialect: Option<&str>,
    kor: Option<&Path>,
    vars: Option<&str>,
) -> Result<Compiled, String> {
    let mut spec = machine_spec(dir, dialect, text).map_err(|e| e.to_string())?;
    let mut sources = diag::Sources::new();
    sources.add(name.to_string(), text.to_string());
    let mut tables = load_corrections(dir, kor, &mut spec);
    tables.extend(load_macro_vars(dir, vars, &mut spec));
    for (kname, ktext, kdiags) in tables {
        if diag::has_errors(&kdiags) {
            sources.add(kname, ktext);
            return Err(diag::render_human(&kdiags, &sources));
        }
    }
    // At most diag::DEFAULT_MAX_PER_FILE diagnostics per file are kept, the rest counted, so an
    // error-dense program is refused in memory bounded by the cap (issue 23).
    let (prog, mut diags, hidden) =
        partprogram::compile_capped(&spec, name, text, diag::DEFAULT_MAX_PER_FILE);
    if name == "MDI" {
        // MDI blocks are not a main program: they need no M02/M30.
        diags.retain(|d| d.code != partprogram::codes::NO_END);
    }
    if let Some(p) = &prog {
        for f in p.files.iter().filter(|f| f.name != name) {
            sources.add(f.name.clone(), f.text.clone());
        }
    }
    let failed = diag::has_errors(&diags) || hidden.iter().any(|h| h.errors > 0);
    match prog.filter(|_| !failed) {
        Some(prog) => Ok(Compiled { prog, sources }),
        None => Err(diag::render_human_capped_with(
            &diags,
            &hidden,
            &sources,
            diag::DEFAULT_MAX_PER_FILE,
        )
        // `run` has no --max-errors: the note names the command that lists everything.
        .replace(
            "(--max-errors 0 shows all)",
            "(`ncplc nc check --max-errors 0` lists all)",
        )),
    }
}

impl Compiled {
    /// Every file besides the main one that the compile of the machine in `dir` read, in name
    /// order (see [`Part::files`]).
    pub fn files(&self, dir: &Path) -> Vec<FileCrc> {
        let mut files = machine_files(dir);
        files.extend(
            self.prog
                .files
                .iter()
                .skip(1)
                .map(|f| (f.name.clone(), crc32_hex(f.text.as_bytes()))),
        );
        files.sort();
        files
    }

    /// Plans the program from the axis positions `start` (axis letter, position; letters the
    /// machine does not have are ignored), with or without block skip: the blocks and the
    /// retained macro variables at the end.
    pub fn plan(
        &self,
        block_skip: bool,
        start: &[(char, f64)],
    ) -> Result<(Vec<Canon>, Retained), String> {
        let mut at = [0.0; 6];
        for (i, a) in self.prog.machine.axes().iter().take(6).enumerate() {
            if let Some((_, x)) = start.iter().find(|(c, _)| c == a) {
                at[i] = *x;
            }
        }
        let opts = PlanOptions {
            block_skip,
            start: at,
            ..PlanOptions::default()
        };
        partprogram::plan(&self.prog, opts)
            .map(|p| {
                let vars = if p.macro_vars.is_empty() {
                    self.prog.machine.retained.clone()
                } else {
                    Retained::from_slots(&p.macro_vars)
                };
                (p.blocks, vars)
            })
            .map_err(|(_, d)| diag::render_human(&[d], &self.sources))
    }
}

/// The name a program's diagnostics give its file: `nc/<file name>`.
fn source_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| format!("nc/{}", n.to_string_lossy()),
    )
}

/// A program of the machine checked as a part run compiles it ([`check_program`]).
#[derive(Debug)]
pub struct ProgramCheck {
    /// The program's name in diagnostics (`nc/<file name>`).
    pub name: String,
    /// Its text, for rendering.
    pub text: String,
    /// The diagnostics of the program's own file (compile and geometry), at most the cap.
    pub diagnostics: Vec<diag::Diagnostic>,
    /// What the cap hid.
    pub hidden: Vec<diag::Hidden>,
}

/// Compiles `program` of the machine in `dir` (loaded as `machine` with its `iocfil`) as a part
/// run does, with the machine's tables, and executes it as [`load_part`] plans it (its run-time
/// errors refuse a run), keeping at most `max` compile diagnostics (0: all): for `ncplc check` of
/// the programs sim.toml names. `None` when the program or a table it needs cannot be read or has
/// errors, which the checks of those files report (sim.toml 3611, nc/DIALECT 3620, the tables'
/// 20xx); of the compile only the program's own diagnostics are kept (the library is checked on
/// its own).
pub fn check_program(
    dir: &Path,
    machine: &characterization::Machine,
    iocfil: &characterization::iocfil::Iocfil,
    program: &Path,
    max: usize,
) -> Option<ProgramCheck> {
    let path = program_path(dir, program);
    let text = partprogram::text_of(std::fs::read(&path).ok()?);
    let name = source_name(&path);
    let dialect = crate::machine_view::program_dialect(dir, None, &text).ok()?;
    let mut spec = crate::machine_view::spec_of(dir, machine, iocfil, dialect).ok()?;
    let mut tables = load_corrections(dir, None, &mut spec);
    tables.extend(crate::machine_view::load_machine_macro_vars(dir, &mut spec));
    if tables.iter().any(|(_, _, d)| diag::has_errors(d)) {
        return None;
    }
    let (prog, mut diagnostics, mut hidden) = partprogram::compile_capped(&spec, &name, &text, max);
    diagnostics.retain(|d| d.file == name);
    hidden.retain(|h| h.file == name);
    // A part run plans the program before its first tick, without and (when a block has `/`)
    // with block skip, and refuses any run-time error of either, wherever it arises (a library
    // unit the program calls included).
    if let Some(prog) = &prog
        && !diag::has_errors(&diagnostics)
    {
        let skips: &[bool] = if prog.blocks.iter().any(|b| b.skip) {
            &[false, true]
        } else {
            &[false]
        };
        let planned = skips.iter().try_for_each(|&block_skip| {
            let opts = PlanOptions {
                block_skip,
                ..PlanOptions::default()
            };
            partprogram::check_plan(prog, opts).map(|_| ())
        });
        diagnostics.extend(planned.err());
    }
    Some(ProgramCheck {
        name,
        text,
        diagnostics,
        hidden,
    })
}

/// Reads, compiles and plans the program `program` of the machine in `dir` (with and without
/// block skip) from the retained-variables text `vars`.
pub fn load_part(
    dir: &Path,
    program: &Path,
    dialect: Option<&str>,
    vars: Option<&str>,
) -> Result<Part, String> {
    let path = program_path(dir, program);
    let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let hash = crc32_hex(&bytes);
    // The bytes become the text (a copy only when they are not UTF-8): the run holds one.
    let text = partprogram::text_of(bytes);
    let name = source_name(&path);
    let compiled = compile_text(dir, &name, &text, dialect, None, vars)?;
    let (blocks, end_plain) = compiled.plan(false, &[])?;
    let blocks = Arc::new(blocks);
    // Block skip changes only the blocks marked `/`: without one the second plan is the first
    // (planning it again would hold a third plan's growing vector at the peak).
    let (skipped, end_skipped) = if compiled.prog.blocks.iter().any(|b| b.skip) {
        let (skipped, end) = compiled.plan(true, &[])?;
        (Arc::new(skipped), end)
    } else {
        (Arc::clone(&blocks), end_plain.clone())
    };
    Ok(Part {
        name: program.display().to_string(),
        hash,
        path,
        blocks,
        skipped,
        files: compiled.files(dir),
        vars_start: compiled.prog.machine.retained.clone(),
        vars_end: [end_plain, end_skipped],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn machine(name: &str) -> PathBuf {
        PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../plc-programs")
            .join(name)
    }

    /// The two plans of a part are those planned without and with block skip, whether the
    /// second is planned (a program with `/` blocks) or taken from the first (one without).
    #[test]
    fn a_part_holds_the_plans_without_and_with_block_skip() {
        for (m, program, has_skip) in [("mill", "O00023.nc", true), ("lathe", "PART1", false)] {
            let dir = machine(m);
            let part = load_part(&dir, Path::new(program), None, None).expect("part");
            let text =
                std::fs::read_to_string(program_path(&dir, Path::new(program))).expect("program");
            let name = source_name(&program_path(&dir, Path::new(program)));
            let compiled = compile_text(&dir, &name, &text, None, None, None).expect("compiled");
            assert_eq!(
                compiled.prog.blocks.iter().any(|b| b.skip),
                has_skip,
                "{program}"
            );
            let (plain, _) = compiled.plan(false, &[]).expect("plan");
            let (skipped, _) = compiled.plan(true, &[]).expect("plan with skip");
            assert_eq!(*part.blocks, plain, "{program}");
            assert_eq!(*part.skipped, skipped, "{program}");
            assert_eq!(part.blocks != part.skipped, has_skip, "{program}");
            // Without a `/` block the part holds one plan, shared by both selections.
            assert_eq!(
                Arc::ptr_eq(&part.blocks, &part.skipped),
                !has_skip,
                "{program}"
            );
        }
    }
}
