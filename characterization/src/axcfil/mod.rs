//! AXCFIL, the axis characterization file: reading into [`Axcfil`] and applying the manual's rules.
//!
//! [`validate`] takes a file read with [`crate::reader::read`] and returns the model together with
//! every diagnostic (Table 7.2 numbers where the manual gives one, project numbers 917–944
//! otherwise). Side files named by FTP and FEG are read through a loader callback
//! ([`validate_with`]), so the machine loader can resolve `file/MPx` in the machine directory.

pub mod axis_type;
pub mod model;

mod axis_pairs;
mod axis_rules;
mod rules;
mod section1;
mod section2;
mod section3;

pub use model::*;
pub use section1::decode_extension;
pub use section3::point_number;

use diag::{Diagnostic, Sink};

use crate::codes;
use crate::reader::{ParsedFile, Record, check_section_count};
use crate::values::{self, Ctx};

/// Loads a side file (FTP, FEG) by reference; `None` when it does not exist.
pub type SideFiles<'a> = &'a dyn Fn(&FileRef) -> Option<Vec<u8>>;

/// Validates AXCFIL without side files (FTP and FEG files are not checked).
pub fn validate(file: &ParsedFile) -> (Axcfil, Vec<Diagnostic>) {
    validate_with(file, &|_| None, false)
}

/// Validates AXCFIL; `side` loads FTP/FEG files and `check_side` says whether missing ones are errors.
pub fn validate_with(
    file: &ParsedFile,
    side: SideFiles,
    check_side: bool,
) -> (Axcfil, Vec<Diagnostic>) {
    let mut diags = Sink::unbounded();
    let model = validate_into(file, side, check_side, &mut diags);
    (model, diags.into_vec())
}

/// [`validate_with`] into `diags`, a sink that may store only the first of them (`--max-errors`).
pub fn validate_into(
    file: &ParsedFile,
    side: SideFiles,
    check_side: bool,
    diags: &mut Sink,
) -> Axcfil {
    let mut model = Axcfil::default();
    diags.extend(check_section_count(file, 3, 3));
    let ctx = Ctx::new(file);
    for section in &file.sections {
        let c = ctx.in_section(section.number);
        match section.number {
            1 => section1::read(c, section, &mut model, diags),
            2 => section2::read(c, section, &mut model, diags),
            3 => section3::read(c, section, &mut model, diags),
            _ => {}
        }
    }
    if file.section(1).is_none() && !file.sections.is_empty() {
        // Section 1 is missing altogether: check_section_count reported it.
    }
    rules::check(file, &model, diags);
    if check_side {
        side_files(file, &mut model, side, diags);
    }
    model
}

/// Reads `PRO=n` (errors 10/11, 13/14, 187, 184); `None` when unusable.
pub(crate) fn pro_number(ctx: &Ctx, r: &Record, nbp: u32, diags: &mut Sink) -> Option<u32> {
    if let Err(d) = ctx.arity(r, 1, 1) {
        diags.push(d);
        return None;
    }
    let p = &r.params[0];
    match values::integer(ctx, p) {
        Err(d) => {
            diags.push(d);
            None
        }
        Ok(None) => {
            diags.push(ctx.error(
                codes::PRO_EMPTY,
                r.span.clone(),
                "PRO gives no process number",
                "write the process number, e.g. `PRO=1`",
            ));
            None
        }
        Ok(Some(n)) => {
            let limit = if nbp == 0 { 5 } else { nbp };
            if n < 1 || n as u32 > limit {
                diags.push(ctx.error(
                    codes::PRO_ABOVE_NBP,
                    p.span.clone(),
                    format!("process {n} is outside 1…{limit} (NBP)"),
                    format!("PRO is 1 to {limit}, the number of processes set by NBP"),
                ));
                return None;
            }
            Some(n as u32)
        }
    }
}

/// FTP (errors 213, 214) and FEG (943) side files.
fn side_files(file: &ParsedFile, model: &mut Axcfil, side: SideFiles, diags: &mut Sink) {
    let ctx = Ctx::new(file);
    for p in &mut model.processes {
        let c2 = ctx.in_section(2).in_process(Some(p.number));
        for axis in &p.axes {
            let (Some(ftp), Some(pas)) = (&axis.ftp, axis.pas) else {
                continue;
            };
            let span = axis.span_of("FTP").unwrap_or(axis.span.clone());
            let Some(bytes) = side(ftp) else {
                diags.push(c2.error(
                    codes::FTP_MISSING,
                    span,
                    format!("FTP file {}/MP{} does not exist", ftp.file, ftp.mp),
                    "create the position-correction file in the MPx directory",
                ));
                continue;
            };
            let first = if model.extension.ecdf {
                pas.start_point.unwrap_or(0.0) as i64
            } else {
                0
            };
            if let Err(why) = check_ftp(&crate::reader::decode(&bytes), pas.mec_pitch, first) {
                diags.push(c2.error(codes::FTP_FILE, span, format!("FTP file {}/MP{}: {why}", ftp.file, ftp.mp), "one line per position: number, coordinate, optional comment; numbers consecutive from the first position"));
            }
        }
        let c3 = ctx.in_section(3).in_process(Some(p.number));
        for t in &mut p.compensation {
            let Some(f) = &t.file else { continue };
            let Some(bytes) = side(f) else {
                diags.push(c3.error(
                    codes::FEG_FILE,
                    t.span.clone(),
                    format!("FEG file {}/MP{} does not exist", f.file, f.mp),
                    "create the correction file with lines `Ennn = value`",
                ));
                continue;
            };
            let text = crate::reader::decode(&bytes);
            for (i, line) in text
                .lines()
                .enumerate()
                .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with(';'))
            {
                let point = line.split_once('=').and_then(|(k, v)| {
                    Some((point_number(k.trim())?, v.trim().parse::<f64>().ok()?))
                });
                match point {
                    Some(pt) if t.points.last().is_none_or(|l| l.0 < pt.0) => t.points.push(pt),
                    _ => {
                        diags.push(c3.error(codes::FEG_FILE, t.span.clone(), format!("FEG file {}/MP{} line {}: `{}` is not an increasing `Ennn = value`", f.file, f.mp, i + 1, line.trim()), "write one `Ennn = value` per line, numbers increasing"));
                        break;
                    }
                }
            }
            if let Some(n) = t.reference
                && !t.points.iter().any(|p| p.0 == n)
            {
                diags.push(c3.error(
                    codes::NM0_UNKNOWN,
                    t.span.clone(),
                    format!(
                        "NM0 names E{n:03}, which FEG file {} does not define",
                        f.file
                    ),
                    "name a point of the table",
                ));
            }
        }
    }
}

/// Checks an FTP side file's lines: count = positions, numbers consecutive from `first`, the first
/// coordinate equal to its number, each coordinate within ±1 of its number.
fn check_ftp(text: &str, positions: f64, first: i64) -> Result<(), String> {
    let lines: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.eq_ignore_ascii_case("EOF") && *l != "\u{1a}")
        .collect();
    if lines.len() as f64 != positions.abs() {
        return Err(format!(
            "{} lines for {} positions",
            lines.len(),
            positions.abs()
        ));
    }
    for (i, line) in lines.iter().enumerate() {
        let mut parts = line.split_whitespace();
        let n = parts
            .next()
            .and_then(|t| t.parse::<i64>().ok())
            .ok_or(format!("line {}: no position number", i + 1))?;
        let c = parts
            .next()
            .and_then(|t| t.parse::<f64>().ok())
            .ok_or(format!("line {}: no coordinate", i + 1))?;
        if n != first + i as i64 {
            return Err(format!(
                "line {}: position {n}, expected {}",
                i + 1,
                first + i as i64
            ));
        }
        if (i == 0 && c != n as f64) || (c - n as f64).abs() > 1.0 {
            return Err(format!(
                "line {}: coordinate {c} does not fit position {n}",
                i + 1
            ));
        }
    }
    Ok(())
}
