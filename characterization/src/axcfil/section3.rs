//! AXCFIL section 3: geometric error compensation tables (`NAS`/`NAC`, `PAS`, `Ennn`, `FEG`, `NM0`).
//!
//! The tables are collected per process. Numeric rules that need section-2 data (formulas 4.13 to
//! 4.15, rotary pitch) are checked in [`super::rules`].

use diag::Sink;

use super::model::{Axcfil, Compensation};
use crate::codes;
use crate::reader::{Record, Section};
use crate::values::{self, Ctx};

/// Reads section 3 into the processes of `model`.
pub fn read(ctx: Ctx, section: &Section, model: &mut Axcfil, diags: &mut Sink) {
    let mut process: Option<usize> = None;
    let mut seen = Vec::new();
    for r in &section.records {
        let pctx = ctx.in_process(
            process
                .and_then(|i| model.processes.get(i))
                .map(|p| p.number),
        );
        match r.key.as_str() {
            "PRO" => {
                finish(
                    &pctx,
                    process.map(|i| &model.processes[i].compensation),
                    diags,
                );
                process = None;
                let Some(n) = super::pro_number(&ctx, r, model.nbp, diags) else {
                    continue;
                };
                let c = ctx.in_process(Some(n));
                if seen.contains(&n) {
                    diags.push(c.error(
                        codes::PROCESS_TWICE,
                        r.span.clone(),
                        format!("process {n} is opened twice in section 3"),
                        "write each process's PRO once per section",
                    ));
                }
                seen.push(n);
                process = model.processes.iter().position(|p| p.number == n);
                if process.is_none() {
                    diags.push(c.error(
                        codes::PRO_ABOVE_NBP,
                        r.span.clone(),
                        format!("process {n} is not configured in section 1"),
                        "declare the process in section 1 first",
                    ));
                }
            }
            _ => {
                let Some(i) = process else {
                    diags.push(pctx.error(
                        codes::NO_PROCESS,
                        r.key_span.clone(),
                        format!("{} before any PRO in section 3", r.key),
                        "open the process with `PRO=n` first",
                    ));
                    continue;
                };
                let p = &mut model.processes[i];
                record(&pctx, r, &mut p.compensation, diags);
            }
        }
    }
    finish(
        &ctx.in_process(
            process
                .and_then(|i| model.processes.get(i))
                .map(|p| p.number),
        ),
        process.map(|i| &model.processes[i].compensation),
        diags,
    );
}

/// Checks the table just completed (the last one of `tables`): at least 2 points unless in a file.
fn finish(ctx: &Ctx, tables: Option<&Vec<Compensation>>, diags: &mut Sink) {
    let Some(t) = tables.and_then(|t| t.last()) else {
        return;
    };
    if t.file.is_none() && t.points.len() < 2 {
        diags.push(ctx.error(
            codes::S3_TOO_FEW,
            t.span.clone(),
            format!(
                "the compensation table of axis {} has {} value(s)",
                t.axis,
                t.points.len()
            ),
            "a table needs at least 2 Ennn values (or a FEG file)",
        ));
    }
    if t.points.len() > 1000 {
        diags.push(ctx.error(
            codes::SECTION3,
            t.span.clone(),
            format!(
                "the compensation table of axis {} has {} points",
                t.axis,
                t.points.len()
            ),
            "at most 1000 correction points per axis",
        ));
    }
}

fn letter(ctx: &Ctx, r: &Record, i: usize, diags: &mut Sink) -> Option<char> {
    let p = r.param(i)?;
    match values::ascii(ctx, p) {
        Ok(Some(s)) if s.len() == 1 => s.chars().next(),
        Ok(_) => {
            diags.push(ctx.error(
                codes::SECTION3,
                p.span.clone(),
                format!("`{}` is not an axis name", p.text),
                "write one axis letter",
            ));
            None
        }
        Err(d) => {
            diags.push(d);
            None
        }
    }
}

/// Parses the `E` number of `Ennn` or of NM0's `Ennn` parameter (1 to 3 digits).
pub fn point_number(text: &str) -> Option<u32> {
    let digits = text.strip_prefix(['E', 'e'])?;
    (1..=3).contains(&digits.len()).then_some(())?;
    digits
        .bytes()
        .all(|b| b.is_ascii_digit())
        .then(|| digits.parse().ok())?
}

fn record(ctx: &Ctx, r: &Record, tables: &mut Vec<Compensation>, diags: &mut Sink) {
    let key = r.key.as_str();
    match key {
        "NAS" | "NAC" => {
            finish(ctx, Some(tables), diags);
            let n = if key == "NAS" { 1 } else { 2 };
            if let Err(d) = ctx.arity(r, n, n) {
                diags.push(d);
                return;
            }
            let Some(axis) = letter(ctx, r, 0, diags) else {
                return;
            };
            let master = if key == "NAC" {
                letter(ctx, r, 1, diags)
            } else {
                None
            };
            if key == "NAC" && master.is_none() {
                return;
            }
            tables.push(Compensation {
                axis,
                master,
                span: r.span.clone(),
                ..Compensation::default()
            });
        }
        "PAS" => {
            let Some(t) = tables.last_mut() else {
                diags.push(ctx.error(
                    codes::S3_NO_NAS,
                    r.key_span.clone(),
                    "PAS without a preceding NAS or NAC in section 3",
                    "open the table with `NAS=<axis>` first",
                ));
                return;
            };
            if t.pitch.is_some() || !t.points.is_empty() {
                diags.push(ctx.error(
                    codes::DUPLICATE_INSTRUCTION,
                    r.key_span.clone(),
                    format!("second PAS in the table of axis {}", t.axis),
                    "one PAS per table; start a new table with NAS",
                ));
                return;
            }
            if let Err(d) = ctx.arity(r, 1, 1) {
                diags.push(d);
                return;
            }
            match values::real(ctx, &r.params[0]) {
                Ok(Some(v)) if v > 0.0 => t.pitch = Some(v),
                Ok(_) => diags.push(ctx.error(
                    codes::SECTION3,
                    r.params[0].span.clone().start..r.span.end,
                    "the correction pitch is not positive",
                    "write the distance between two correction points, > 0",
                )),
                Err(d) => diags.push(d),
            }
        }
        "FEG" => {
            let Some(t) = tables.last_mut() else {
                diags.push(ctx.error(
                    codes::S3_NO_NAS,
                    r.key_span.clone(),
                    "FEG without a preceding NAS or NAC",
                    "write FEG after NAS (or NAC) and PAS",
                ));
                return;
            };
            if let Err(d) = ctx.arity(r, 1, 1) {
                diags.push(d);
                return;
            }
            match super::section2::file_ref(ctx, &r.params[0]) {
                Ok(f) => t.file = Some(f),
                Err(d) => diags.push(d),
            }
        }
        "NM0" => {
            let ready = tables.last().is_some_and(|t| t.pitch.is_some());
            if !ready {
                diags.push(ctx.error(
                    codes::S3_NO_NAS,
                    r.key_span.clone(),
                    "NM0 without a preceding NAS and PAS",
                    "write NM0 after NAS, PAS and the Ennn values",
                ));
                return;
            }
            if let Err(d) = ctx.arity(r, 1, 1) {
                diags.push(d);
                return;
            }
            let p = &r.params[0];
            let Some(n) = point_number(&p.text) else {
                diags.push(ctx.error(
                    codes::NM0_SYNTAX,
                    p.span.clone().start..r.span.end,
                    format!("`{}` is not a correction point", p.text),
                    "write NM0=Ennn with the point at the absolute home, e.g. `NM0=E004`",
                ));
                return;
            };
            if let Some(t) = tables.last_mut() {
                if t.file.is_none() && !t.points.iter().any(|(k, _)| *k == n) {
                    diags.push(ctx.error(
                        codes::NM0_UNKNOWN,
                        p.span.clone(),
                        format!("NM0 names {}, which the table does not define", p.text),
                        "name one of the Ennn points of this table",
                    ));
                }
                t.reference = Some(n);
            }
        }
        k if k.starts_with('E') => {
            let Some(n) = point_number(k) else {
                diags.push(ctx.error(
                    codes::NOT_ALLOWED,
                    r.key_span.clone(),
                    format!("`{k}` is not a correction point name"),
                    "correction points are E followed by up to three digits, e.g. E010",
                ));
                return;
            };
            let Some(t) = tables.last_mut().filter(|t| t.pitch.is_some()) else {
                diags.push(ctx.error(
                    codes::S3_NO_NAS,
                    r.key_span.clone(),
                    format!("{k} without a preceding NAS and PAS"),
                    "write the Ennn values after NAS (or NAC) and PAS",
                ));
                return;
            };
            if let Err(d) = ctx.arity(r, 1, 1) {
                diags.push(d);
                return;
            }
            if t.points.last().is_some_and(|(last, _)| n <= *last) {
                diags.push(ctx.error(
                    codes::S3_ORDER,
                    r.key_span.clone(),
                    format!(
                        "{k} does not follow E{:03} in increasing order",
                        t.points.last().map_or(0, |p| p.0)
                    ),
                    "number the correction points in increasing order",
                ));
                return;
            }
            match values::real(ctx, &r.params[0]) {
                Ok(v) => t.points.push((n, v.unwrap_or(0.0))),
                Err(d) => diags.push(d),
            }
        }
        k => {
            let hint = if k == "NMO" {
                "`NMO` is a misspelling of `NM0` (digit zero)".to_string()
            } else {
                let allowed = "section 3 allows PRO, NAS, NAC, PAS, Ennn, FEG and NM0";
                crate::values::suggest_key(k, allowed, allowed)
            };
            diags.push(ctx.error(
                codes::NOT_ALLOWED,
                r.key_span.clone(),
                format!("instruction {k} is not allowed in AXCFIL section 3"),
                hint,
            ));
        }
    }
}
