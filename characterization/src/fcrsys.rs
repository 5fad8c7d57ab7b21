//! FCRSYS, the system-level file: logical paths (section 1), logical file names (section 2),
//! hard disks (section 3) and disk/USB drivers (section 4).
//!
//! Section 2 decides which files are AXCFIL, PGCFIL and IOCFIL (logical names `AXCONF`,
//! `PGCONF`, `IOCONF`). ncplc adds the logical name `PLCSRC` for the PLC program (default: file
//! `PLCPRG` in `MP0`). A section-2 value is either `file_name/MPx` (the manual's form) or a DOS
//! path such as `C:\CNC32\MP0\AXCFIL`; [`Fcrsys::resolve`] maps both into the machine directory.
//!
//! The manual numbers FCRSYS errors only as "Сообщение 1__xx" without a table, so every FCRSYS
//! rule has a project code (903–914, see [`crate::codes`]); the grammar errors of Table 7.1 and
//! the section counts (1, 24) keep their numbers.

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

use diag::Diagnostic;
use serde::{Deserialize, Serialize};

use crate::codes;
use crate::reader::{ParsedFile, Record};
use crate::values::Ctx;

/// The fixed logical file names of the manual's Table 3.1, plus ncplc's `PLCSRC`.
pub const LOGICAL_NAMES: [&str; 12] = [
    "FILMS1", "FILMS2", "FILMS3", "FILMS4", "FILMS5", "FORMAT", "AXCONF", "PGCONF", "IOCONF",
    "FILCMD", "FILMAS", "PLCSRC",
];

/// Logical names that section 2 must bind.
pub const MANDATORY_NAMES: [&str; 4] = ["AXCONF", "PGCONF", "IOCONF", "FORMAT"];

/// A section-1 logical path `MPx=path`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct LogicalPath {
    /// x of `MPx`, 0…6.
    pub index: u8,
    /// The path as written (`C:\CNC32\MP0`, `C:/CNC32/MP0`, `A:`, `\\server\share`).
    pub path: String,
    /// Span of the record.
    pub span: Range<usize>,
}

/// Where a section-2 file lives.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub enum FileLocation {
    /// `file_name/MPx`: in logical path x.
    Logical {
        /// The file name.
        file: String,
        /// x of `MPx`.
        mp: u8,
    },
    /// A DOS path such as `C:\CNC32\MP0\AXCFIL`.
    Dos(String),
}

/// A section-2 binding `log_name, file_name/MPx`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct FileBinding {
    /// The fixed logical name (`AXCONF`, …).
    pub logical: String,
    /// The user's file.
    pub location: FileLocation,
    /// Span of the record.
    pub span: Range<usize>,
}

/// The typed content of FCRSYS.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Fcrsys {
    /// Section 1, by x of `MPx`.
    pub paths: BTreeMap<u8, LogicalPath>,
    /// Section 2 in file order.
    pub files: Vec<FileBinding>,
    /// Section 3: drive letters of hard disks kept awake.
    pub hdd: Option<String>,
    /// Section 4 `FLP`: floppy drive names as written.
    pub flp: Option<Vec<String>>,
    /// Section 4 `IDE`: PM, PS, SM, SS as written.
    pub ide: Option<Vec<String>>,
    /// Section 4 `DOC`.
    pub doc: Option<String>,
    /// Section 4 `USB`: one driver name per port as written.
    pub usb: Option<Vec<String>>,
}

impl Fcrsys {
    /// The binding of logical name `logical`, if declared.
    pub fn binding(&self, logical: &str) -> Option<&FileBinding> {
        self.files.iter().find(|b| b.logical == logical)
    }

    /// The machine-directory folder of logical path `MPx`: the last component of its DOS path
    /// (`C:\CNC32\MP0` → `<dir>/MP0`); `None` when x is undeclared or the path is a bare drive.
    pub fn mp_dir(&self, dir: &Path, x: u8) -> Option<PathBuf> {
        let path = &self.paths.get(&x)?.path;
        last_component(path).map(|c| dir.join(c))
    }

    /// The file bound to `logical` inside the machine directory `dir`, if it can be located.
    pub fn resolve(&self, dir: &Path, logical: &str) -> Option<PathBuf> {
        match &self.binding(logical)?.location {
            FileLocation::Logical { file, mp } => Some(self.mp_dir(dir, *mp)?.join(file)),
            FileLocation::Dos(path) => {
                let parts = components(path);
                let file = parts.last()?;
                match parts.len() {
                    1 => Some(dir.join(file)),
                    n => Some(dir.join(parts[n - 2]).join(file)),
                }
            }
        }
    }
}

/// Path components of a DOS or Unix path, without the drive and empty parts.
fn components(path: &str) -> Vec<&str> {
    let no_drive = match path.split_once(':') {
        Some((drive, rest)) if drive.len() == 1 => rest,
        _ => path,
    };
    no_drive
        .split(['\\', '/'])
        .filter(|c| !c.is_empty() && *c != ".")
        .collect()
}

fn last_component(path: &str) -> Option<&str> {
    components(path).last().copied()
}

/// Validates a read FCRSYS and builds its model; all problems go to the returned diagnostics.
pub fn validate(file: &ParsedFile) -> (Fcrsys, Vec<Diagnostic>) {
    let mut model = Fcrsys::default();
    let mut diags = crate::reader::check_section_count(file, 2, 4);
    check_case(file, &mut diags);
    let ctx = Ctx::new(file);
    if file.end_marker.is_none() {
        diags.push(ctx.error(
            codes::FCRSYS_END,
            file.end_span(),
            "FCRSYS does not end with a lone `*`",
            "write a line holding only `*` after the last section",
        ));
    }
    let mut seen: BTreeMap<String, Range<usize>> = BTreeMap::new();
    for section in &file.sections {
        let ctx = ctx.in_section(section.number);
        for r in &section.records {
            let first = seen
                .entry(format!("{}:{}", section.number, r.key))
                .or_insert_with(|| r.span.clone())
                .clone();
            if first != r.span {
                let (line, _) = file.lines.line_column(&file.text, first.start);
                diags.push(ctx.error(
                    codes::FCRSYS_DUPLICATE,
                    r.key_span.clone(),
                    format!("`{}` is declared twice", r.key),
                    format!("keep only one `{}` (the first is on line {line})", r.key),
                ));
                continue;
            }
            let result = match section.number {
                1 => section1(&ctx, r, &mut model),
                2 => section2(&ctx, r, &mut model),
                3 => section3(&ctx, r, &mut model),
                4 => section4(&ctx, r, &mut model),
                _ => Ok(()),
            };
            if let Err(d) = result {
                diags.push(d);
            }
        }
    }
    let ctx1 = ctx.in_section(1);
    if let Some(s1) = file.section(1) {
        for x in [0u8, 1] {
            if !model.paths.contains_key(&x) {
                diags.push(ctx1.error(
                    codes::FCRSYS_MP_MISSING,
                    s1.span.clone(),
                    format!("section 1 lacks the mandatory logical path MP{x}"),
                    format!("add e.g. `MP{x}=C:\\CNC32\\MP{x}`"),
                ));
            }
        }
    }
    if let Some(s2) = file.section(2) {
        let ctx2 = ctx.in_section(2);
        for name in MANDATORY_NAMES {
            if model.binding(name).is_none() {
                let file_name = match name {
                    "AXCONF" => "AXCFIL",
                    "PGCONF" => "PGCFIL",
                    "IOCONF" => "IOCFIL",
                    _ => "FORMAT",
                };
                diags.push(ctx2.error(
                    codes::FCRSYS_NAME_MISSING,
                    s2.span.clone(),
                    format!("section 2 lacks the mandatory logical name {name}"),
                    format!("add e.g. `{name}, {file_name}/MP0`"),
                ));
            }
        }
        for b in model.files.iter().filter(|_| file.section(1).is_some()) {
            if let FileLocation::Logical { mp, .. } = b.location
                && !model.paths.contains_key(&mp)
            {
                diags.push(ctx2.error(
                    codes::FCRSYS_MP_UNDECLARED,
                    b.span.clone(),
                    format!(
                        "{} refers to MP{mp}, which section 1 does not declare",
                        b.logical
                    ),
                    format!("declare `MP{mp}=…` in section 1 or use a declared path"),
                ));
            }
        }
    }
    (model, diags)
}

/// S2: all FCRSYS information is upper case (one diagnostic per offending line).
fn check_case(file: &ParsedFile, diags: &mut Vec<Diagnostic>) {
    let mut offset = 0;
    for line in file.text.split_inclusive('\n') {
        // A `;` starts a comment (whole line or after an instruction); comments may be any case.
        let code = &line[..line.find(';').unwrap_or(line.len())];
        if let Some(i) = code.find(|c: char| c.is_ascii_lowercase()) {
            let at = offset + i;
            diags.push(Ctx::new(file).error(
                codes::FCRSYS_CASE,
                at..at + 1,
                "lower-case letter in FCRSYS",
                "all FCRSYS information must be typed in capital letters",
            ));
        }
        offset += line.len();
    }
}

fn one_param<'r>(ctx: &Ctx, r: &'r Record) -> Result<&'r str, Diagnostic> {
    ctx.arity(r, 1, 1)?;
    Ok(r.params[0].text.as_str())
}

fn section1(ctx: &Ctx, r: &Record, model: &mut Fcrsys) -> Result<(), Diagnostic> {
    let index = r
        .key
        .strip_prefix("MP")
        .and_then(|x| x.parse::<u8>().ok())
        .filter(|&x| x <= 6 && r.key.len() == 3);
    let Some(index) = index else {
        return Err(ctx.error(
            codes::FCRSYS_NOT_ALLOWED,
            r.key_span.clone(),
            format!("`{}` is not allowed in FCRSYS section 1", r.key),
            "section 1 declares logical paths MP0 … MP6, e.g. `MP0=C:\\CNC32\\MP0`",
        ));
    };
    let path = one_param(ctx, r)?;
    let span = r.params[0].span.clone();
    if path.is_empty() {
        return Err(ctx.error(
            codes::FCRSYS_PATH,
            r.end_span(),
            format!("MP{index} has no path"),
            "write a disk and directory, e.g. `C:\\CNC32\\MP0`",
        ));
    }
    if path.chars().count() > 255 {
        return Err(ctx.error(
            codes::FCRSYS_PATH,
            span,
            format!("the path of MP{index} is longer than 255 characters"),
            "a logical path has at most 255 characters",
        ));
    }
    if path.len() > 1 && (path.ends_with('\\') || (path.ends_with('/') && !path.ends_with(":/"))) {
        return Err(ctx.error(
            codes::FCRSYS_PATH,
            span.end - 1..span.end,
            format!("the path of MP{index} ends with a separator"),
            "remove the trailing `\\`",
        ));
    }
    model.paths.insert(
        index,
        LogicalPath {
            index,
            path: path.to_string(),
            span: r.span.clone(),
        },
    );
    Ok(())
}

fn section2(ctx: &Ctx, r: &Record, model: &mut Fcrsys) -> Result<(), Diagnostic> {
    if !LOGICAL_NAMES.contains(&r.key.as_str()) {
        return Err(ctx.warning(
            codes::FCRSYS_UNKNOWN_NAME,
            r.key_span.clone(),
            format!("`{}` is not a known logical file name", r.key),
            format!("known names: {}", LOGICAL_NAMES.join(", ")),
        ));
    }
    let value = one_param(ctx, r)?;
    let span = r.params[0].span.clone();
    let bad = |why: &str| {
        ctx.error(codes::FCRSYS_FILE_REF, span.clone(), format!("`{value}`: {why}"), "write `file_name/MPx` (file name of up to 6 letters and digits, first a letter; x = 0…6) or a DOS path like `C:\\CNC32\\MP0\\AXCFIL`")
    };
    let location = if value.contains('\\') || value.contains(':') {
        if last_component(value).is_none() {
            return Err(bad("the DOS path names no file"));
        }
        FileLocation::Dos(value.to_string())
    } else {
        let Some((name, mp)) = value.split_once('/') else {
            return Err(bad("no `/MPx` after the file name"));
        };
        let name = name.trim();
        let mp = mp.trim();
        let name_ok = (1..=6).contains(&name.len())
            && name.starts_with(|c: char| c.is_ascii_alphabetic())
            && name.bytes().all(|b| b.is_ascii_alphanumeric());
        if !name_ok {
            return Err(bad(
                "the file name must be 1 to 6 letters and digits starting with a letter",
            ));
        }
        let x = mp
            .strip_prefix("MP")
            .and_then(|x| x.parse::<u8>().ok())
            .filter(|&x| x <= 6 && mp.len() == 3);
        let Some(x) = x else {
            return Err(bad("the logical path must be MP0 … MP6"));
        };
        FileLocation::Logical {
            file: name.to_string(),
            mp: x,
        }
    };
    model.files.push(FileBinding {
        logical: r.key.clone(),
        location,
        span: r.span.clone(),
    });
    Ok(())
}

fn section3(ctx: &Ctx, r: &Record, model: &mut Fcrsys) -> Result<(), Diagnostic> {
    if r.key != "HDD" {
        return Err(ctx.error(
            codes::FCRSYS_NOT_ALLOWED,
            r.key_span.clone(),
            format!("`{}` is not allowed in FCRSYS section 3", r.key),
            "section 3 holds only `HDD=` with up to three drive letters",
        ));
    }
    let letters = one_param(ctx, r)?;
    if letters.len() > 3 || !letters.bytes().all(|b| b.is_ascii_alphabetic()) {
        return Err(ctx.error(
            codes::FCRSYS_HDD,
            r.params[0].span.clone(),
            format!("`{letters}` is not a list of up to three drive letters"),
            "write the drive letters together, e.g. `HDD=CDF`",
        ));
    }
    model.hdd = Some(letters.to_string());
    Ok(())
}

fn section4(ctx: &Ctx, r: &Record, model: &mut Fcrsys) -> Result<(), Diagnostic> {
    let names = || r.params.iter().map(|p| p.text.clone()).collect::<Vec<_>>();
    match r.key.as_str() {
        "FLP" => {
            ctx.arity(r, 1, 2)?;
            model.flp = Some(names());
        }
        "IDE" => {
            ctx.arity(r, 1, 4)?;
            if r.params[0].text == "CD" {
                return Err(ctx.error(
                    codes::FCRSYS_IDE_PM,
                    r.params[0].span.clone(),
                    "the IDE Primary Master cannot be a CD drive",
                    "write `HDD` or leave PM empty, e.g. `IDE=HDD,CD`",
                ));
            }
            model.ide = Some(names());
        }
        "DOC" => {
            model.doc = Some(one_param(ctx, r)?.to_string());
        }
        "USB" => {
            ctx.arity(r, 1, 4)?;
            model.usb = Some(names());
        }
        _ => {
            return Err(ctx.error(
                codes::FCRSYS_NOT_ALLOWED,
                r.key_span.clone(),
                format!("`{}` is not allowed in FCRSYS section 4", r.key),
                "section 4 holds FLP, IDE, DOC and USB",
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reader::{Grammar, read_with};

    fn load(src: &str) -> (Fcrsys, Vec<(u32, u32, u32)>) {
        let (f, mut d) = read_with("FCRSYS", src.as_bytes(), Grammar::FCRSYS);
        let (m, d2) = validate(&f);
        d.extend(d2);
        (m, d.iter().map(|d| (d.code, d.line, d.column)).collect())
    }

    #[test]
    fn resolves_logical_and_dos_paths() {
        let (m, d) = load(
            "*1\nMP0=C:\\CNC32\\MP0\nMP1=C:/CNC32/MP1\nMP6=A:\n*2\nAXCONF, AXCFIL/MP0\nPGCONF,C:\\CNC32\\MP1\\PG\nIOCONF,IOCFIL/MP6\nFORMAT,FORMAT/MP0\n*\n",
        );
        assert!(d.is_empty(), "{d:?}");
        let dir = Path::new("/m");
        assert_eq!(
            m.resolve(dir, "AXCONF"),
            Some(PathBuf::from("/m/MP0/AXCFIL"))
        );
        assert_eq!(m.resolve(dir, "PGCONF"), Some(PathBuf::from("/m/MP1/PG")));
        assert_eq!(m.resolve(dir, "IOCONF"), None);
        assert_eq!(m.resolve(dir, "PLCSRC"), None);
    }

    #[test]
    fn rule_violations_are_located() {
        let (_, d) = load(
            "*1\nMP0=C:\\CNC32\\MP0\\\nMP7=C:\nmp1=C:\\X\n*2\nAXCONF, AXCFIL/MP3\nAXCONF, AXCFIL/MP0\nPGCONF, PGCFIL\n*4\nIDE=CD\n",
        );
        assert_eq!(
            d,
            [
                (903, 4, 1),
                (913, 11, 1),
                (906, 2, 17),
                (904, 3, 1),
                (912, 7, 1),
                (909, 8, 9),
                (911, 10, 5),
                (905, 1, 1),
                (908, 5, 1),
                (908, 5, 1),
                (908, 5, 1),
                (910, 6, 1)
            ]
        );
    }

    #[test]
    fn unknown_logical_name_warns_and_bad_hdd_fails() {
        let base = "*1\nMP0=C:\\CNC32\\MP0\nMP1=C:\\CNC32\\MP1\n*2\nAXCONF,AXCFIL/MP0\nPGCONF,PGCFIL/MP0\nIOCONF,IOCFIL/MP0\nFORMAT,FORMAT/MP0\n";
        let (_, d) = load(&format!(
            "{base}FILXYZ,ABC/MP0 ; unknown name\n*3\nHDD=CDFG\n*\n"
        ));
        assert_eq!(d, [(907, 9, 1), (914, 11, 5)]);
        let (f, mut d) = read_with(
            "FCRSYS",
            format!("{base}FILXYZ,ABC/MP0\n*\n").as_bytes(),
            Grammar::FCRSYS,
        );
        d.extend(validate(&f).1);
        assert_eq!(
            d.iter().map(|d| d.severity).collect::<Vec<_>>(),
            [diag::Severity::Warning]
        );
    }
}
