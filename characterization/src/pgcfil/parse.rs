//! Decodes a read PGCFIL into [`Pgcfil`]: the NEW/OLD word, sections 1–4 here, sections 5 and 6
//! in `sections56`. Every rule that needs no other file is checked while decoding.

use std::collections::BTreeSet;

use diag::{Diagnostic, Sink};

use crate::reader::{Param, ParsedFile, Record, Section};

use super::fields::Emit;
use super::model::{
    Assignment, CodeRename, FileRef, LoadMode, NewName, Npl, PgProcess, Pgcfil, Prf, ProcessFiles,
    SimDecl,
};
use super::sections56 as machine;
use super::structure::{Blocks, not_allowed};
use super::tables;

const S2: &str = "PRO, SIM";
const S4: &str = "PRO, ASS, NPL, NDD, PRF, FIL, FLC, STR, SER, CHN, SCR";

/// Decodes `file` (read with [`crate::reader::read_with`] and [`crate::reader::Grammar::PGCFIL`]) into a [`Pgcfil`] and the diagnostics of every rule
/// that needs no other file; cross-file rules are in [`super::check_against`].
pub fn parse(file: &ParsedFile) -> (Pgcfil, Vec<Diagnostic>) {
    let mut diags = Sink::unbounded();
    let pg = parse_into(file, &mut diags);
    (pg, diags.into_vec())
}

/// [`parse`] pushing the diagnostics into `diags` (a sink that may store only the first of them).
pub fn parse_into(file: &ParsedFile, diags: &mut Sink) -> Pgcfil {
    let mut e = Emit::new(file, diags);
    let mut pg = Pgcfil {
        load_mode: load_mode(&mut e, file),
        ..Pgcfil::default()
    };
    e.diags
        .extend(crate::reader::check_section_count(file, 5, 6));
    let mut done = BTreeSet::new();
    for section in file.sections.iter().filter(|s| (1..=6).contains(&s.number)) {
        if !done.insert(section.number) {
            continue;
        }
        e.section = section.number;
        e.process = None;
        match section.number {
            1 => codes(&mut e, section, &mut pg.tri, true),
            3 => codes(&mut e, section, &mut pg.jcl, false),
            n => per_process(&mut e, section, &mut pg, n),
        }
    }
    pg.processes.sort_by_key(|p| p.number);
    pg
}

/// The NEW/OLD word before `*1` (error 25 when it is missing or something else).
fn load_mode(e: &mut Emit<'_>, file: &ParsedFile) -> LoadMode {
    let hint =
        "write NEW (reset per-process state) or OLD (restore it) on the first line, before *1";
    match &file.header {
        Some(h) if h.text.eq_ignore_ascii_case("NEW") => LoadMode::New,
        Some(h) if h.text.eq_ignore_ascii_case("OLD") => LoadMode::Old,
        Some(h) => {
            e.error(
                25,
                h.span.clone(),
                format!("PGCFIL begins with `{}` instead of NEW or OLD", h.text),
                hint,
            );
            LoadMode::New
        }
        None => {
            let span = file.sections.first().map_or(0..0, |s| s.span.clone());
            e.error(25, span, "PGCFIL does not begin with NEW or OLD", hint);
            LoadMode::New
        }
    }
}

/// Section 1 (TRI) or section 3 (JCL).
fn codes(e: &mut Emit<'_>, section: &Section, out: &mut Vec<CodeRename>, tri: bool) {
    let key = if tri { "TRI" } else { "JCL" };
    let mut olds = BTreeSet::new();
    for rec in &section.records {
        if rec.key != key {
            not_allowed(e, rec, key);
            continue;
        }
        if !e.count(rec, 3, 3) {
            continue;
        }
        let (Some(old), Some(new)) = (e.ascii(&rec.params[0]), e.ascii(&rec.params[1])) else {
            if rec.params[0].text.is_empty() || rec.params[1].text.is_empty() {
                let p = if rec.params[0].text.is_empty() {
                    &rec.params[0]
                } else {
                    &rec.params[1]
                };
                let (code, hint) = if tri {
                    (
                        103,
                        "write an existing code, then a new three-letter name or D",
                    )
                } else {
                    (
                        952,
                        "write an existing JCL code, then a new three-letter name or D",
                    )
                };
                e.error(
                    code,
                    span_or(p, rec),
                    format!("{key} needs an old and a new name"),
                    hint,
                );
            }
            continue;
        };
        let sync = e.hex(&rec.params[2], 2).map(|v| v as u8);
        let known = if tri {
            tables::three_letter_code(&old).is_some()
        } else {
            tables::JCL_CODES.contains(&old.as_str())
        };
        if !known {
            let (code, what) = if tri {
                (102, "Table 5.1")
            } else {
                (952, "Table 5.6")
            };
            e.error(
                code,
                rec.params[0].span.clone(),
                format!("'{old}' is not a three-letter code of {what}"),
                &format!(
                    "name a code of {what}, e.g. {}",
                    if tri { "CLS" } else { "CAO" }
                ),
            );
            continue;
        }
        let new_name = if new == "D" {
            NewName::Delete
        } else if new.len() == 3 && new.bytes().all(|b| b.is_ascii_uppercase()) {
            NewName::Rename(new)
        } else {
            let code = if tri { 103 } else { 952 };
            e.error(
                code,
                rec.params[1].span.clone(),
                format!("'{new}' is neither a three-letter code nor D"),
                "write three capital letters to rename, or D to delete",
            );
            continue;
        };
        if tri {
            if let Some(s) = sync.filter(|s| !(1..=4).contains(s)) {
                e.error(104, rec.params[2].span.clone(), format!("synchronization code {s} is outside 1 ... 4"), "1 = sync without switch, 2 = sync with switch, 3 = no sync with switch, 4 = no sync");
                continue;
            }
        } else if sync.is_some() {
            e.warning(
                953,
                rec.params[2].span.clone(),
                "the synchronization code of a JCL code cannot be changed; it is ignored",
                "leave the third JCL parameter empty",
            );
        }
        if !olds.insert(old.clone()) {
            e.error(
                101,
                rec.key_span.clone(),
                format!("{key} for {old} is duplicated"),
                "personalize each code once",
            );
            continue;
        }
        out.push(CodeRename {
            old_name: old,
            new_name,
            synchro: if tri { sync } else { None },
        });
    }
}

/// The process with `n`, created when first seen.
pub(crate) fn process_mut(pg: &mut Pgcfil, n: u32) -> &mut PgProcess {
    let i = match pg.processes.iter().position(|p| p.number == n) {
        Some(i) => i,
        None => {
            pg.processes.push(PgProcess {
                number: n,
                ..PgProcess::default()
            });
            pg.processes.len() - 1
        }
    };
    &mut pg.processes[i]
}

/// Sections 2, 4, 5 and 6: PRO blocks.
fn per_process(e: &mut Emit<'_>, section: &Section, pg: &mut Pgcfil, number: u32) {
    let mut blocks = Blocks::default();
    let mut scratch = PgProcess::default();
    let mut s5 = machine::BlockState::default();
    let mut sim_names: Vec<String> = Vec::new();
    for rec in &section.records {
        if rec.key == "PRO" {
            if number == 5 {
                s5.finish(e, &blocks, section);
            }
            blocks.open(e, rec);
            s5 = machine::BlockState::default();
            sim_names.clear();
            continue;
        }
        let target = blocks.record(e);
        let proc = match target {
            Some(n) => process_mut(pg, n),
            None => &mut scratch,
        };
        match number {
            2 => section2(e, &mut blocks, rec, proc),
            4 => section4(e, &mut blocks, rec, proc),
            5 => machine::section5(e, &mut blocks, &mut s5, rec, proc),
            _ => machine::section6(e, &mut blocks, rec, proc),
        }
    }
    if number == 5 {
        s5.finish(e, &blocks, section);
    }
}

fn span_or(p: &Param, rec: &Record) -> std::ops::Range<usize> {
    if p.span.is_empty() {
        rec.span.clone()
    } else {
        p.span.clone()
    }
}

/// Section 2: SIM.
fn section2(e: &mut Emit<'_>, _blocks: &mut Blocks, rec: &Record, proc: &mut PgProcess) {
    if rec.key != "SIM" {
        return not_allowed(e, rec, S2);
    }
    if !e.count(rec, 6, 6) {
        return;
    }
    let p = &rec.params;
    let var_name = p[0].text.clone();
    if var_name.is_empty() {
        return e.error(
            128,
            rec.key_span.clone(),
            "SIM names no variable",
            "the first SIM parameter is a Table 5.2 variable or NEW",
        );
    }
    if e.ascii(&p[0]).is_none() {
        return;
    }
    if var_name != "NEW" && proc.sim.iter().any(|s| s.var_name == var_name) {
        return e.error(
            101,
            rec.key_span.clone(),
            format!("SIM for {var_name} is duplicated"),
            "change each variable once per process",
        );
    }
    let var_new = e.ascii(&p[1]);
    let max_num = e.word(&p[2]);
    let def_type = e.hex(&p[3], 2).map(|v| v as u8);
    let amm_type = e.word(&p[4]);
    let synchro = e.hex(&p[5], 2).map(|v| v as u8);
    let mut ok = true;
    let exists = |name: &str, proc: &PgProcess| {
        tables::system_variable(name).is_some()
            || proc
                .sim
                .iter()
                .any(|s| s.var_name == "NEW" && s.var_new.as_deref() == Some(name))
    };
    if var_name == "NEW" {
        let count = proc.sim.iter().filter(|s| s.var_name == "NEW").count();
        match &var_new {
            None => {
                e.error(
                    109,
                    span_or(&p[1], rec),
                    "SIM=NEW needs the name of the new variable",
                    "write SIM=NEW,<name>,max_num,def_type,amm_type,synchro",
                );
                ok = false;
            }
            Some(n) if exists(n, proc) || !valid_name(n) => {
                e.error(109, p[1].span.clone(), format!("new variable '{n}' already exists or is not a valid name"), "a new name starts with a letter, has letters and digits and is not in Table 5.2");
                ok = false;
            }
            Some(_) if count >= 20 => {
                e.error(
                    119,
                    rec.key_span.clone(),
                    "more than 20 new variables in section 2 for this process",
                    "declare at most 20 new variables per process",
                );
                ok = false;
            }
            Some(_) => {}
        }
    } else {
        match tables::system_variable(&var_name) {
            None => {
                e.error(
                    129,
                    p[0].span.clone(),
                    format!("'{var_name}' is not a variable of the symbol table"),
                    "name a Table 5.2 variable (E, p, TMR, USO, ...) or NEW",
                );
                ok = false;
            }
            Some(row) => {
                if let Some(n) = var_new
                    .as_ref()
                    .filter(|n| exists(n, proc) || !valid_name(n))
                {
                    e.error(109, p[1].span.clone(), format!("new name '{n}' already exists or is not a valid name"), "a new name starts with a letter, has letters and digits and is not in Table 5.2");
                    ok = false;
                }
                if let Some(m) = max_num.filter(|_| row.modif != 2) {
                    e.error(
                        105,
                        p[2].span.clone(),
                        format!("the number of elements of {var_name} cannot be changed (to {m})"),
                        "only E, o, p, l and c may change their number of elements",
                    );
                    ok = false;
                }
            }
        }
    }
    if let Some(t) = def_type.filter(|t| !(1..=7).contains(t)) {
        e.error(
            106,
            p[3].span.clone(),
            format!("default type {t} is outside 1 ... 7"),
            "1 boolean, 2 byte, 3 integer, 4 long integer, 5 real, 6 long real, 7 ASCII",
        );
        ok = false;
    }
    if let Some(t) = amm_type.filter(|&t| t > 127) {
        e.error(
            107,
            p[4].span.clone(),
            format!("admissible-type code {t} is above 127"),
            "sum of 1 boolean, 2 byte, 4 integer, 8 long integer, 16 real, 32 long real, 64 ASCII",
        );
        ok = false;
    }
    if let Some(s) = synchro.filter(|s| !(1..=4).contains(s)) {
        e.error(
            108,
            p[5].span.clone(),
            format!("default synchronization code {s} is outside 1 ... 4"),
            "write 1, 2, 3 or 4",
        );
        ok = false;
    }
    if ok {
        proc.sim.push(SimDecl {
            var_name,
            var_new,
            max_num,
            def_type,
            amm_type,
            synchro,
        });
    }
}

fn valid_name(n: &str) -> bool {
    n.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
        && n.chars().all(|c| c.is_ascii_alphanumeric())
}

/// A `name/MPx` reference; `None` (after `code` was reported) when malformed.
fn file_ref(e: &mut Emit<'_>, p: &Param, code: u32, what: &str) -> Option<FileRef> {
    let t = e.ascii(p)?;
    let parsed = t.split_once('/').and_then(|(name, dev)| {
        let ok_name =
            !name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
        let dev = dev.to_ascii_uppercase();
        let d = dev
            .strip_prefix("MP")
            .and_then(|x| x.parse::<u8>().ok())
            .filter(|d| *d <= 6 && dev.len() == 3);
        match (ok_name, d) {
            (true, Some(device)) => Some(FileRef {
                name: name.to_string(),
                device,
            }),
            _ => None,
        }
    });
    if parsed.is_none() {
        e.error(
            code,
            p.span.clone(),
            format!("'{t}' in {what} is not of the form name/MPx"),
            "write a file as NAME/MPx with x = 0 ... 6, e.g. FI1EOR/MP0",
        );
    }
    parsed
}

/// Section 4: library, files, ASSET.
fn section4(e: &mut Emit<'_>, blocks: &mut Blocks, rec: &Record, proc: &mut PgProcess) {
    let known = [
        "ASS", "NPL", "NDD", "PRF", "FIL", "FLC", "STR", "SER", "CHN", "SCR",
    ];
    if !known.contains(&rec.key.as_str()) {
        return not_allowed(e, rec, S4);
    }
    if rec.key != "ASS" && !blocks.first_time(e, rec) {
        return;
    }
    let p = &rec.params;
    match rec.key.as_str() {
        "ASS" => {
            if !e.count(rec, 2, 2) {
                return;
            }
            let name = p[0].text.clone();
            if name.is_empty() {
                return e.error(
                    128,
                    rec.key_span.clone(),
                    "ASS names no variable",
                    "write ASS=<variable>,<value>",
                );
            }
            // The variables 5.8.2 gives the "boolean" format take 0 or 1 only (003:4569-4615;
            // MDF's table type is boolean too, but its text is a coefficient 0 … 1).
            let boolean =
                ["USB", "UVR", "USO", "URL", "RAP", "UAS", "UEP", "VOL"].contains(&name.as_str());
            let value = if boolean {
                e.boolean(&p[1]).map(f64::from)
            } else {
                e.real(&p[1])
            };
            if e.ascii(&p[0]).is_none() {
                return;
            }
            let extra: Vec<String> = proc.sim.iter().filter_map(|s| s.var_new.clone()).collect();
            if !tables::assignable(&name, &extra) {
                return e.error(
                    129,
                    p[0].span.clone(),
                    format!("'{name}' is not a variable of the symbol table"),
                    "assign a Table 5.2 variable such as USO, TMR, SK1023 or a SIM-defined name",
                );
            }
            if proc.ass.iter().any(|a| a.var_name == name) {
                return e.error(
                    101,
                    rec.key_span.clone(),
                    format!("ASS for {name} is duplicated"),
                    "assign each variable once per process",
                );
            }
            if let Some(value) = value {
                proc.ass.push(Assignment {
                    var_name: name,
                    value,
                });
            }
        }
        "NPL" => {
            if !e.count(rec, 2, 2) {
                return;
            }
            let prog_num = e.integer(&p[0]).and_then(|v| u32::try_from(v).ok());
            let label_num = e.integer(&p[1]).and_then(|v| u32::try_from(v).ok());
            if let Some(n) = prog_num.filter(|&n| n > 255) {
                e.error(
                    110,
                    p[0].span.clone(),
                    format!("{n} subprograms declared, at most 255"),
                    "write at most 255 (default 10)",
                );
            }
            if let Some(n) = label_num.filter(|&n| n > 255) {
                e.error(
                    954,
                    p[1].span.clone(),
                    format!("{n} labels declared, at most 255"),
                    "write at most 255 (default 10)",
                );
            }
            proc.npl = Some(Npl {
                prog_num: prog_num.filter(|&n| n <= 255),
                label_num: label_num.filter(|&n| n <= 255),
            });
        }
        "NDD" => {
            if !e.count(rec, 1, 1) {
                return;
            }
            let Some(t) = e.ascii(&p[0]) else { return };
            let up = t.to_ascii_uppercase();
            match up
                .strip_prefix("MP")
                .and_then(|d| d.parse::<u8>().ok())
                .filter(|d| *d <= 6 && up.len() == 3)
            {
                Some(d) => proc.ndd = Some(d),
                None => e.error(
                    112,
                    p[0].span.clone(),
                    format!("device name '{t}' in NDD is wrong"),
                    "write MP0 ... MP6 (default MP1)",
                ),
            }
        }
        "PRF" => {
            if e.count(rec, 2, 2) {
                let prof_num = e.integer(&p[0]).and_then(|v| u32::try_from(v).ok());
                let block_num = e.integer(&p[1]).and_then(|v| u32::try_from(v).ok());
                proc.prf = Some(Prf {
                    prof_num,
                    block_num,
                });
            }
        }
        "FIL" => {
            if e.count(rec, 5, 5) {
                let mut r = p.iter().map(|x| file_ref(e, x, 134, "FIL"));
                let mut next = || r.next().flatten();
                proc.fil = Some(ProcessFiles {
                    origins: next(),
                    offsets: next(),
                    tool_life: next(),
                    random_tool: next(),
                    unused: next(),
                });
            }
        }
        "FLC" => {
            // Semantics line: 4 parameters; format line: 5 (spec §10 item 6): both are accepted.
            if e.count(rec, 4, 5) {
                let refs: Vec<Option<FileRef>> =
                    p.iter().map(|x| file_ref(e, x, 955, "FLC")).collect();
                proc.flc = refs.into_iter().nth(2).flatten();
            }
        }
        "STR" => {
            if e.count(rec, 1, 1)
                && let Some(n) = e.word(&p[0])
            {
                if n > 255 {
                    e.error(
                        135,
                        p[0].span.clone(),
                        format!("{n} structures declared, at most 255"),
                        "write at most 255",
                    );
                } else {
                    proc.structures = Some(n);
                }
            }
        }
        "SER" => {
            if e.count(rec, 1, 1) {
                proc.ser = e.hex(&p[0], 2).map(|v| v as u8);
            }
        }
        "CHN" => {
            if e.count(rec, 1, 1) {
                proc.chn = e.word(&p[0]);
            }
        }
        _ => {
            if e.count(rec, 1, 1) {
                proc.scr = e.word(&p[0]);
            }
        }
    }
}
