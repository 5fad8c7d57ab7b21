//! Loading a machine directory: FCRSYS first, then the files its section 2 names.
//!
//! `<dir>/FCRSYS` decides where AXCFIL, PGCFIL and IOCFIL are (logical names AXCONF, PGCONF,
//! IOCONF) and where the PLC program is (ncplc's logical name PLCSRC, default `MP0/PLCPRG`).
//! Logical paths `MPx` map into the machine directory by their last component
//! (`C:\CNC32\MP0` → `<dir>/MP0`). Diagnostics name files relative to the machine directory
//! (`FCRSYS`, `MP0/AXCFIL`), and [`MachineLoad::sources`] holds their decoded text for rendering.
//!
//! All files are read and checked in one run: a broken FCRSYS still lets the other files be found
//! when their bindings are readable, and errors of every file are reported together.

use std::path::{Path, PathBuf};

use diag::{Diagnostic, Hidden, Sink, Sources};
use serde::{Deserialize, Serialize};

use crate::axcfil::{self, Axcfil, FileRef};
use crate::codes;
use crate::fcrsys::{self, Fcrsys};
use crate::iocfil::{self, Iocfil};
use crate::messages::{self, MessageFile, PlcMessages};
use crate::pgcfil::{self, Pgcfil};
use crate::reader::{self, Grammar, ParsedFile};

/// Where the files of a machine are.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct MachinePaths {
    /// `<dir>/FCRSYS`.
    pub fcrsys: PathBuf,
    /// The directory of logical path MP0.
    pub mp0: PathBuf,
    /// AXCFIL (logical name AXCONF), when FCRSYS names it.
    pub axcfil: Option<PathBuf>,
    /// PGCFIL (logical name PGCONF), when FCRSYS names it.
    pub pgcfil: Option<PathBuf>,
    /// IOCFIL (logical name IOCONF), when FCRSYS names it.
    pub iocfil: Option<PathBuf>,
    /// The PLC program (logical name PLCSRC, default `MP0/PLCPRG`).
    pub plc_source: PathBuf,
}

/// A loaded machine: its paths and typed characterization.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Machine {
    /// The machine directory.
    pub dir: PathBuf,
    /// Where its files are.
    pub paths: MachinePaths,
    /// FCRSYS.
    pub fcrsys: Fcrsys,
    /// AXCFIL.
    pub axcfil: Axcfil,
    /// PGCFIL, when FCRSYS names an existing file.
    pub pgcfil: Option<Pgcfil>,
    /// IOCFIL, when FCRSYS names an existing file.
    pub iocfil: Option<Iocfil>,
    /// The PLC message texts (FCRSYS FILMS5, PGCFIL FLC).
    #[serde(default)]
    pub messages: PlcMessages,
}

/// The result of [`load_machine`]: the machine (when its FCRSYS and AXCFIL could be read),
/// every diagnostic of every file, and the sources to render them with.
#[derive(Debug, Clone)]
pub struct MachineLoad {
    /// The machine, `None` when FCRSYS or AXCFIL could not be read at all.
    pub machine: Option<Machine>,
    /// Diagnostics of all files, FCRSYS first, each file's in source order (with
    /// [`load_machine_capped`], at most its `max` per file).
    pub diagnostics: Vec<Diagnostic>,
    /// Per file, the diagnostics [`load_machine_capped`] counted but did not keep.
    pub hidden: Vec<Hidden>,
    /// The decoded text of every file read, by diagnostic file name.
    pub sources: Sources,
    /// PGCFIL as read by the common grammar (for its validator).
    pub pgcfil_file: Option<ParsedFile>,
    /// IOCFIL as read by the common grammar (for its validator).
    pub iocfil_file: Option<ParsedFile>,
}

impl MachineLoad {
    /// True when any diagnostic is an error.
    pub fn has_errors(&self) -> bool {
        diag::has_errors(&self.diagnostics) || self.hidden.iter().any(|h| h.errors > 0)
    }
}

/// The section-2 bindings whose files ncplc does not read, when the file exists (never silently
/// ignored input): FILMS1–FILMS4 and FORMAT are a warning (ncplc words its own messages and reads
/// its tables in its own formats: a missing file is the manual's normal fallback, 003:665), FILCMD
/// and FILMAS an error (programs and blocks started on PLC request are not implemented).
fn unread_bindings(dir: &Path, fcrsys: &Fcrsys, ctx: &crate::values::Ctx, diags: &mut Sink) {
    const WHY: [(&str, &str); 7] = [
        (
            "FILMS1",
            "the system's messages are ncplc's own (its diagnostics and alarms)",
        ),
        (
            "FILMS2",
            "the system's messages are ncplc's own (its diagnostics and alarms)",
        ),
        (
            "FILMS3",
            "the system's messages are ncplc's own (its diagnostics and alarms)",
        ),
        (
            "FILMS4",
            "the system's messages are ncplc's own (its diagnostics and alarms)",
        ),
        (
            "FORMAT",
            "ncplc reads its zero-offset and correction tables in their own formats (TAB0.POS, TAB0.KOR)",
        ),
        (
            "FILCMD",
            "part programs started on PLC request are not implemented",
        ),
        (
            "FILMAS",
            "blocks executed on PLC request are not implemented",
        ),
    ];
    for (logical, why) in WHY {
        let Some(path) = fcrsys.resolve(dir, logical).filter(|p| p.is_file()) else {
            continue;
        };
        let span = fcrsys.binding(logical).map_or(0..0, |b| b.span.clone());
        let name = display_name(dir, &path);
        let message = format!("{logical} binds {name}, which ncplc does not read: {why}");
        diags.push(if logical.starts_with("FIL") && !logical.starts_with("FILMS") {
            ctx.error(
                codes::FILE_NOT_IMPLEMENTED,
                span,
                message,
                format!("remove the {logical} line (and the PLC requests that rely on it)"),
            )
        } else {
            ctx.warning(
                codes::FILE_NOT_READ,
                span,
                message,
                format!("remove the {logical} line or the file; nothing in {name} changes what ncplc does"),
            )
        });
    }
}

/// The name a file gets in diagnostics: its path relative to `dir`, with `/` separators.
pub fn display_name(dir: &Path, path: &Path) -> String {
    let rel = path.strip_prefix(dir).unwrap_or(path);
    rel.components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect::<Vec<_>>()
        .join("/")
}

struct Loader<'a> {
    dir: &'a Path,
    /// Diagnostics kept per file (0: all).
    max: usize,
    diagnostics: Vec<Diagnostic>,
    hidden: Vec<Hidden>,
    sources: Sources,
}

impl Loader<'_> {
    /// Reads `path` with `grammar`; reports 902 (`missing_code` when given) if it cannot be read.
    /// The file's diagnostics go into a sink of `max`; its text goes to the sources (a copy, or
    /// moved when the file is abandoned: use [`Loader::keep_text`] for a file not kept).
    fn read(&mut self, path: &Path, grammar: Grammar) -> Option<(ParsedFile, Sink)> {
        let name = display_name(self.dir, path);
        let mut diags = Sink::new(self.max);
        match reader::read_path(path, &name, grammar, &mut diags) {
            Ok(file) => {
                if file.abandoned {
                    // Not a characterization file: validating it would only add follow-on errors.
                    self.sources.add(name, file.text);
                    self.add(diags);
                    return None;
                }
                Some((file, diags))
            }
            Err(e) => {
                let d = Diagnostic::error(
                    codes::FILE_UNREADABLE,
                    name.clone(),
                    0..0,
                    format!("cannot read {name}: {e}"),
                )
                .with_hint(format!(
                    "create {name} in the machine directory {}",
                    self.dir.display()
                ));
                self.diagnostics.push(d);
                None
            }
        }
    }

    /// Reads the PLC message file at `path` (at most [`reader::MAX_BYTES`]); its diagnostics
    /// and text go to the load's; 902 when it cannot be read.
    fn read_messages(&mut self, path: &Path) -> Option<MessageFile> {
        use std::io::Read;
        let name = display_name(self.dir, path);
        let mut bytes = Vec::new();
        let read = std::fs::File::open(path)
            .and_then(|f| f.take(reader::MAX_BYTES as u64).read_to_end(&mut bytes));
        if let Err(e) = read {
            self.diagnostics.push(Diagnostic::error(
                codes::FILE_UNREADABLE,
                name.clone(),
                0..0,
                format!("cannot read {name}: {e}"),
            ));
            return None;
        }
        let text = crate::decode::decode(&bytes);
        let mut diags = Sink::new(self.max);
        let file = messages::parse_into(&name, &text, &mut diags);
        self.sources.add(name, text);
        self.add(diags);
        Some(file)
    }

    /// Error 949 at the `FLC` record of `process` in PGCFIL: the file it names does not exist.
    fn flc_missing(&mut self, pgcfil: &ParsedFile, process: u32, flc: &pgcfil::FileRef) {
        let record = crate::pgcfil::locate::records(pgcfil, &[4])
            .into_iter()
            .find(|r| r.process == process && r.record.key == "FLC");
        let span = record.map_or(0..0, |r| r.record.span.clone());
        let d = Diagnostic::error(
            codes::MESSAGE_FILE_MISSING,
            pgcfil.name.clone(),
            span,
            format!(
                "FLC of process {process} names the PLC message file {}/MP{}, which does not exist",
                flc.name, flc.device
            ),
        )
        .with_hint(format!(
            "create MP{}/{} (one `nnn text` line per message, docs/plc-messages.md) or remove FLC",
            flc.device, flc.name
        ))
        .with_section(4)
        .with_process(process)
        .locate(&pgcfil.text);
        self.diagnostics.push(d);
    }

    /// Moves the text of a file that is not kept into the sources (no copy of a large file).
    fn keep_text(&mut self, file: ParsedFile) {
        self.sources.add(file.name, file.text);
    }

    /// Adds a file's diagnostics in source order, and what its sink only counted.
    fn add(&mut self, diags: Sink) {
        let (mut kept, dropped) = diags.finish();
        kept.sort_by_key(|d| (d.span.start, d.code));
        self.diagnostics.extend(kept);
        diag::merge_hidden(&mut self.hidden, &dropped);
    }
}

/// Loads the machine in `dir`: FCRSYS, then AXCFIL, PGCFIL and IOCFIL; never panics.
pub fn load_machine(dir: &Path) -> MachineLoad {
    load_machine_capped(dir, 0)
}

/// [`load_machine`] keeping at most `max` diagnostics per characterization file (0: all), the
/// first in source order, and counting the rest in [`MachineLoad::hidden`]: the memory a file's
/// diagnostics take is bounded whatever their number (`ncplc check --max-errors`).
pub fn load_machine_capped(dir: &Path, max: usize) -> MachineLoad {
    let mut l = Loader {
        dir,
        max,
        diagnostics: Vec::new(),
        hidden: Vec::new(),
        sources: Sources::new(),
    };
    let fcrsys_path = dir.join("FCRSYS");
    let mut pgcfil_file = None;
    let mut iocfil_file = None;
    let Some((fc_file, mut fc_diags)) = l.read(&fcrsys_path, Grammar::FCRSYS) else {
        return MachineLoad {
            machine: None,
            diagnostics: l.diagnostics,
            hidden: l.hidden,
            sources: l.sources,
            pgcfil_file,
            iocfil_file,
        };
    };
    l.sources.add(fc_file.name.clone(), fc_file.text.clone());
    let (fcrsys, d) = fcrsys::validate(&fc_file);
    fc_diags.extend(d);
    let mp0 = fcrsys.mp_dir(dir, 0).unwrap_or_else(|| dir.join("MP0"));
    let ctx = crate::values::Ctx::new(&fc_file).in_section(2);
    let resolve = |logical: &str, diags: &mut Sink| -> Option<PathBuf> {
        let path = fcrsys.resolve(dir, logical)?;
        if !path.is_file() {
            let span = fcrsys.binding(logical).map_or(0..0, |b| b.span.clone());
            let name = display_name(dir, &path);
            diags.push(ctx.error(
                codes::FILE_MISSING,
                span,
                format!("{logical} names {name}, which does not exist"),
                format!("create {name} or bind {logical} to an existing file"),
            ));
            return None;
        }
        Some(path)
    };
    let axcfil_path = resolve("AXCONF", &mut fc_diags);
    let pgcfil_path = resolve("PGCONF", &mut fc_diags);
    let iocfil_path = resolve("IOCONF", &mut fc_diags);
    let films5_path = resolve("FILMS5", &mut fc_diags);
    let plc_source = match fcrsys.binding("PLCSRC") {
        Some(_) => fcrsys
            .resolve(dir, "PLCSRC")
            .unwrap_or_else(|| mp0.join("PLCPRG")),
        None => mp0.join("PLCPRG"),
    };
    if !plc_source.is_file() {
        let span = fcrsys.binding("PLCSRC").map_or(0..0, |b| b.span.clone());
        let name = display_name(dir, &plc_source);
        let (message, hint) = (
            format!("the PLC program {name} does not exist"),
            "write the PLC program there, or bind PLCSRC in FCRSYS section 2, e.g. `PLCSRC, PLCPRG/MP0`",
        );
        fc_diags.push(match fcrsys.binding("PLCSRC") {
            Some(_) => ctx.warning(codes::PLC_SOURCE_MISSING, span, message, hint),
            // No binding: the default location is meant, a problem of the machine, not of a line.
            None => Diagnostic::warning(
                codes::PLC_SOURCE_MISSING,
                fc_file.name.as_str(),
                0..0,
                message,
            )
            .with_hint(hint),
        });
    }
    unread_bindings(dir, &fcrsys, &ctx, &mut fc_diags);
    l.add(fc_diags);
    let mut axcfil = None;
    if let Some(path) = &axcfil_path
        && let Some((file, mut diags)) = l.read(path, Grammar::FUNCTIONAL)
    {
        let side = |f: &FileRef| -> Option<Vec<u8>> {
            std::fs::read(fcrsys.mp_dir(dir, f.mp)?.join(&f.file)).ok()
        };
        let model = axcfil::validate_into(&file, &side, true, &mut diags);
        l.add(diags);
        l.keep_text(file);
        axcfil = Some(model);
    }
    let mut pgcfil = None;
    if let Some(path) = &pgcfil_path
        && let Some((file, mut diags)) = l.read(path, Grammar::PGCFIL)
    {
        let model = pgcfil::parse_into(&file, &mut diags);
        if let Some(ax) = &axcfil {
            pgcfil::check_against_into(&model, &file, ax, &mut diags);
        }
        l.add(diags);
        l.sources.add(file.name.clone(), file.text.clone());
        pgcfil = Some(model);
        pgcfil_file = Some(file);
    }
    let mut iocfil = None;
    if let Some(path) = &iocfil_path
        && let Some((file, mut diags)) = l.read(path, Grammar::FUNCTIONAL)
    {
        let model = iocfil::parse_into(&file, &mut diags);
        if let Some(ax) = &axcfil {
            iocfil::check_against_into(&model, &file, ax, &mut diags);
        }
        l.add(diags);
        l.sources.add(file.name.clone(), file.text.clone());
        iocfil = Some(model);
        iocfil_file = Some(file);
    }
    let mut plc_messages = PlcMessages {
        common: films5_path.and_then(|p| l.read_messages(&p)),
        ..PlcMessages::default()
    };
    if let (Some(pg), Some(file)) = (&pgcfil, &pgcfil_file) {
        for proc in &pg.processes {
            let (Some(flc), Ok(number)) = (&proc.flc, u8::try_from(proc.number)) else {
                continue;
            };
            let path = fcrsys.mp_dir(dir, flc.device).map(|d| d.join(&flc.name));
            match path.filter(|p| p.is_file()) {
                Some(p) => {
                    if let Some(m) = l.read_messages(&p) {
                        plc_messages.processes.insert(number, m);
                    }
                }
                None => l.flc_missing(file, proc.number, flc),
            }
        }
    }
    let paths = MachinePaths {
        fcrsys: fcrsys_path,
        mp0,
        axcfil: axcfil_path,
        pgcfil: pgcfil_path,
        iocfil: iocfil_path,
        plc_source,
    };
    let machine = axcfil.map(|axcfil| Machine {
        dir: dir.to_path_buf(),
        paths,
        fcrsys,
        axcfil,
        pgcfil,
        iocfil,
        messages: plc_messages,
    });
    MachineLoad {
        machine,
        diagnostics: l.diagnostics,
        hidden: l.hidden,
        sources: l.sources,
        pgcfil_file,
        iocfil_file,
    }
}
