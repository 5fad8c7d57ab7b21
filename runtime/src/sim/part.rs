//! The partprogram of a part run: found (a name in `<machine>/nc/`, or a path), compiled with the
//! machine's view (`cli::nc::machine_spec`, its correction table) and planned into canonical
//! blocks, with a content hash for the trace header and the summary, and the CRC-32 of every
//! other file the compile read ([`Part::files`]: macro and cycle files, the correction table,
//! `nc/CONSTANTS`, `nc/DIALECT`), so that a replay names the file that changed.

use std::path::{Path, PathBuf};

use partprogram::{Canon, PlanOptions};

use crate::cli::nc::{load_corrections, machine_spec};

/// A planned partprogram.
#[derive(Debug, Clone)]
pub struct Part {
    /// Its name as given (`O1000.nc`) or its path.
    pub name: String,
    /// CRC-32 of its text, hexadecimal.
    pub hash: String,
    /// The file it was read from.
    pub path: PathBuf,
    /// The canonical blocks in execution order.
    pub blocks: Vec<Canon>,
    /// The same with block skip on (blocks marked `/` left out), for the PLC's BSKIP switch.
    pub skipped: Vec<Canon>,
    /// Every other file the compile read: (path relative to the machine directory, CRC-32), in
    /// name order.
    pub files: Vec<FileCrc>,
}

/// A file the compile read: (path relative to the machine directory, CRC-32).
pub type FileCrc = (String, String);

/// CRC-32 of `bytes`, 8 hex digits.
pub fn crc32_hex(bytes: &[u8]) -> String {
    format!("{:08x}", crc32fast::hash(bytes))
}

/// The machine files every compile reads when they exist: (name, CRC-32).
fn machine_files(dir: &Path) -> Vec<FileCrc> {
    let kor = crate::cli::nc::kor_file(dir, None).map(|(p, _)| p);
    [
        Some(dir.join("nc").join("CONSTANTS")),
        Some(dir.join("nc").join("DIALECT")),
        kor,
    ]
    .into_iter()
    .flatten()
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

/// `program` as a path when it exists, else `<machine>/nc/<program>`.
pub fn program_path(machine: &Path, program: &Path) -> PathBuf {
    if program.exists() {
        program.to_path_buf()
    } else {
        machine.join("nc").join(program)
    }
}

/// Compiles and plans `text` (named `name`) for the machine in `dir`; the error is the rendered
/// diagnostics.
pub fn plan_text(
    dir: &Path,
    name: &str,
    text: &str,
    dialect: Option<&str>,
    block_skip: bool,
) -> Result<Vec<Canon>, String> {
    plan_text_from(dir, name, text, dialect, block_skip, &[])
}

/// [`plan_text`] starting from the axis positions `start` (axis letter, position; MDI blocks
/// start where the axes stand). Letters the machine does not have are ignored.
pub fn plan_text_from(
    dir: &Path,
    name: &str,
    text: &str,
    dialect: Option<&str>,
    block_skip: bool,
    start: &[(char, f64)],
) -> Result<Vec<Canon>, String> {
    plan_with_files(dir, name, text, dialect, block_skip, start).map(|(b, _)| b)
}

/// The files besides `name` that compiling and planning `text` reads (see [`Part::files`]).
pub fn files_read(
    dir: &Path,
    name: &str,
    text: &str,
    dialect: Option<&str>,
) -> Result<Vec<FileCrc>, String> {
    plan_with_files(dir, name, text, dialect, false, &[]).map(|(_, f)| f)
}

/// [`plan_text_from`] that also names the files the compile read besides `name` (see
/// [`Part::files`]).
fn plan_with_files(
    dir: &Path,
    name: &str,
    text: &str,
    dialect: Option<&str>,
    block_skip: bool,
    start: &[(char, f64)],
) -> Result<(Vec<Canon>, Vec<FileCrc>), String> {
    let mut spec = machine_spec(dir, dialect, text).map_err(|e| e.to_string())?;
    let mut sources = diag::Sources::new();
    sources.add(name.to_string(), text.to_string());
    if let Some((kname, ktext, kdiags)) = load_corrections(dir, None, &mut spec)
        && diag::has_errors(&kdiags)
    {
        sources.add(kname, ktext);
        return Err(diag::render_human(&kdiags, &sources));
    }
    let (prog, diags) = partprogram::compile(&spec, name, text);
    if let Some(p) = &prog {
        for f in &p.files {
            sources.add(f.name.clone(), f.text.clone());
        }
    }
    let Some(prog) = prog.filter(|_| !diag::has_errors(&diags)) else {
        return Err(diag::render_human(&diags, &sources));
    };
    let mut at = [0.0; 6];
    for (i, a) in prog.machine.axes().iter().take(6).enumerate() {
        if let Some((_, x)) = start.iter().find(|(c, _)| c == a) {
            at[i] = *x;
        }
    }
    let opts = PlanOptions {
        block_skip,
        start: at,
        ..PlanOptions::default()
    };
    let mut files = machine_files(dir);
    files.extend(
        prog.files
            .iter()
            .skip(1)
            .map(|f| (f.name.clone(), crc32_hex(f.text.as_bytes()))),
    );
    files.sort();
    partprogram::plan(&prog, opts)
        .map(|p| (p.blocks, files))
        .map_err(|(_, d)| diag::render_human(&[d], &sources))
}

/// Reads, compiles and plans the program `program` of the machine in `dir` (with and without
/// block skip).
pub fn load_part(dir: &Path, program: &Path, dialect: Option<&str>) -> Result<Part, String> {
    let path = program_path(dir, program);
    let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let text = String::from_utf8_lossy(&bytes).into_owned();
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| format!("nc/{}", n.to_string_lossy()),
    );
    let (blocks, files) = plan_with_files(dir, &name, &text, dialect, false, &[])?;
    let skipped = plan_text(dir, &name, &text, dialect, true)?;
    Ok(Part {
        name: program.display().to_string(),
        hash: crc32_hex(&bytes),
        path,
        blocks,
        skipped,
        files,
    })
}
