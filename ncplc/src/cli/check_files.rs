//! The machine files besides the characterization, the maps and sim.toml that `ncplc check` reads:
//! what a part run (`run --program`, `nc run`) and a PLC run read from the machine directory.
//!
//! - `nc/DIALECT`: one word, `mefi` or `fanuc` (3620 otherwise, at the word);
//! - `nc/CONSTANTS`: `R<n>: <value>` lines (3621 at each bad line, every line checked);
//! - `MP0/TAB0.KOR` (else `MP0/TAB2.KOR`), `MP0/TAB0.POS`, `nc/MACROVARS`: the partprogram
//!   readers' own located diagnostics (20xx), read with the machine's axes exactly as a part run
//!   reads them (skipped while the characterization, DIALECT or CONSTANTS have errors, which are
//!   reported);
//! - `macros/`: the macro library every compile of a part or of MDI text loads (MEFI `L<n>` and
//!   `$PC` cycle files, Fanuc `O<n>`), compiled on its own in the machine's dialect (both when
//!   `nc/DIALECT` does not name one), with the compile's own diagnostics (20xx; skipped like the
//!   tables); a file or subfolder of the folder that no compile reads is warning 3624;
//! - the programs of the other processes that sim.toml's `[cnc] programs` names, compiled and
//!   executed as a part run plans them before its first tick (their 20xx codes, any run-time
//!   error; a missing one is sim.toml's 3611);
//! - `retain.bin`: a damaged record is a warning (3622), as `run` warns and starts without it.
//!
//! Every file that exists is added to the sources under its name relative to the machine
//! directory; a missing file is not a problem (each has a default). Each is read with the limit of
//! a machine configuration file (`diag::read_config`: 1 MiB; a larger one is error 3623), but for
//! the library files and the programs, which are read whole as a compile reads them (their
//! diagnostics capped at `--max-errors` per file).

use std::path::Path;

use diag::{Diagnostic, Hidden, Sources};

/// Codes of the machine files checked here (docs/README.md §Diagnostics).
pub mod codes {
    /// `nc/DIALECT` names no dialect.
    pub const DIALECT: u32 = 3620;
    /// A line of `nc/CONSTANTS` is not `R<n>: <value>`, or its value is not valid.
    pub const CONSTANTS: u32 = 3621;
    /// `retain.bin` is damaged (run starts without retained data).
    pub const RETAIN: u32 = 3622;
    /// A machine file exists but cannot be read.
    pub const IO: u32 = 3623;
    /// A file of the macro folder that no compile reads (not a library file of the dialect).
    pub const MACRO_UNREAD: u32 = 3624;
}

fn read(dir: &Path, rel: &str, out: &mut Vec<Diagnostic>) -> Option<String> {
    match diag::read_config_bytes(&dir.join(rel)) {
        Ok(b) => Some(String::from_utf8_lossy(&b).into_owned()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => {
            out.push(Diagnostic::error(
                codes::IO,
                rel,
                0..0,
                format!("cannot read {rel}: {e}"),
            ));
            None
        }
    }
}

/// The diagnostics of every such file of `dir` and of the `programs` sim.toml names, their texts
/// added to `sources` and what the cap of `max` diagnostics per file (0: all) hid added to
/// `hidden`. `machine` is the machine `check` loaded, when its characterization has no errors and
/// it has an IOCFIL (a part run refuses it otherwise): the tables, the library and the programs
/// are read with its axes, without loading it again.
pub fn check(
    dir: &Path,
    machine: Option<&characterization::Machine>,
    programs: &[String],
    max: usize,
    sources: &mut Sources,
    hidden: &mut Vec<Hidden>,
) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let mut dialect = None;
    if let Some(text) = read(dir, "nc/DIALECT", &mut out) {
        let word = text.trim();
        match word.parse::<partprogram::Dialect>() {
            Ok(d) => dialect = Some(d),
            Err(e) => {
                let start = text.find(word).unwrap_or(0);
                out.push(
                    Diagnostic::error(codes::DIALECT, "nc/DIALECT", start..start + word.len(), e)
                        .with_hint("nc/DIALECT holds one word: mefi or fanuc")
                        .locate(&text),
                );
            }
        }
        sources.add("nc/DIALECT", text);
    }
    if let Some(text) = read(dir, "nc/CONSTANTS", &mut out) {
        out.extend(constants(&text));
        sources.add("nc/CONSTANTS", text);
    }
    if let Some(machine) = machine
        && let Some(iocfil) = machine.iocfil.as_ref()
        && !diag::has_errors(&out)
    {
        let table_dialect = dialect.unwrap_or(partprogram::Dialect::Mefi);
        tables(dir, &table_axes(machine, table_dialect), sources, &mut out);
        // Without nc/DIALECT each program's dialect is told from its text: both may load the
        // library.
        let dialects = match dialect {
            Some(d) => vec![d],
            None => vec![partprogram::Dialect::Mefi, partprogram::Dialect::Fanuc],
        };
        library(
            dir,
            (machine, iocfil),
            &dialects,
            max,
            sources,
            hidden,
            &mut out,
        );
        let mut names: Vec<&String> = programs.iter().collect();
        names.sort();
        names.dedup();
        for name in names {
            let program = Path::new(name.as_str());
            if let Some(p) = sim::part::check_program(dir, machine, iocfil, program, max) {
                out.extend(p.diagnostics);
                hidden.extend(p.hidden);
                sources.add(p.name, p.text);
            }
        }
    }
    let retain = dir.join("retain.bin");
    if let Err(e) = runtime::retain::load(&retain) {
        out.push(
            Diagnostic::warning(codes::RETAIN, "retain.bin", 0..0, e.to_string())
                .with_hint("`run` starts without retained data; delete retain.bin to silence this"),
        );
    }
    out
}

/// Every bad line of `nc/CONSTANTS` (each line is read on its own, as `run` reads them all).
fn constants(text: &str) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let mut spec = partprogram::MachineSpec::new(partprogram::Dialect::Mefi, &['X']);
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let span = offset..offset + line.trim_end().len();
        offset += line.len();
        let result = partprogram::machine::parse_constants(line).and_then(|values| {
            values
                .into_iter()
                .try_for_each(|(n, v)| spec.set_constant(n, v))
        });
        if let Err(e) = result {
            let message = match e {
                partprogram::machine::ConstantsError::Syntax { text, .. } => {
                    format!("expected `R<n>: <value>`, found `{text}`")
                }
                other => other.to_string(),
            };
            out.push(
                Diagnostic::error(codes::CONSTANTS, "nc/CONSTANTS", span, message)
                    .with_hint("one constant per line: `R329: 1000000` (a `\"` starts a comment)")
                    .locate(text),
            );
        }
    }
    out
}

/// The axes a part run reads the tables with: those of `sim::machine_view::machine_spec` for
/// `machine` in `dialect` (`sim::machine_view::program_axes`; X, Y, Z when there are none),
/// taken from the machine `check` loaded.
fn table_axes(machine: &characterization::Machine, dialect: partprogram::Dialect) -> Vec<char> {
    let axes = sim::machine_view::program_axes(machine, dialect);
    partprogram::MachineSpec::new(dialect, &axes).axes()
}

/// The correction, zero-offset and retained-variable tables, read with the machine's `axes`.
fn tables(dir: &Path, axes: &[char], sources: &mut Sources, out: &mut Vec<Diagnostic>) {
    let kor = ["MP0/TAB0.KOR", "MP0/TAB2.KOR"]
        .into_iter()
        .find(|n| dir.join(n).is_file());
    if let Some(name) = kor
        && let Some(text) = read(dir, name, out)
    {
        out.extend(partprogram::parse_kor(name, &text, axes).1);
        sources.add(name, text);
    }
    if let Some(text) = read(dir, "MP0/TAB0.POS", out) {
        out.extend(partprogram::parse_pos("MP0/TAB0.POS", &text, axes).1);
        sources.add("MP0/TAB0.POS", text);
    }
    if let Some(text) = read(dir, "nc/MACROVARS", out) {
        let (_, d) = partprogram::macro_b::retained::parse_retained("nc/MACROVARS", &text);
        out.extend(d);
        sources.add("nc/MACROVARS", text);
    }
}

/// The macro library compiled on its own in each of `dialects` as a part run of `machine` (with
/// its IOCFIL) compiles it (`partprogram::library`), and a warning for each file of the folder none of them
/// reads.
fn library(
    dir: &Path,
    (machine, iocfil): (
        &characterization::Machine,
        &characterization::iocfil::Iocfil,
    ),
    dialects: &[partprogram::Dialect],
    max: usize,
    sources: &mut Sources,
    hidden: &mut Vec<Hidden>,
    out: &mut Vec<Diagnostic>,
) {
    for &dialect in dialects {
        // The spec a part run builds (CONSTANTS was checked above: an error there skips this).
        let Ok(spec) = sim::machine_view::spec_of(dir, machine, iocfil, dialect) else {
            continue;
        };
        let checked = partprogram::library::check_library(&spec, max);
        for f in checked.files {
            sources.add(f.name, f.text);
        }
        out.extend(checked.diagnostics);
        hidden.extend(checked.hidden);
    }
    for name in partprogram::library::unread_files(&dir.join("macros"), dialects) {
        let only = match dialects {
            [partprogram::Dialect::Mefi] => " (nc/DIALECT: mefi)",
            [partprogram::Dialect::Fanuc] => " (nc/DIALECT: fanuc)",
            _ => "",
        };
        out.push(
            Diagnostic::warning(
                codes::MACRO_UNREAD,
                name.as_str(),
                0..0,
                if dir.join(&name).is_dir() {
                    format!("{name} is a folder: no compile reads it")
                } else {
                    format!("{name} is not read: no program can call it{only}")
                },
            )
            .with_hint(
                "the macro folder holds MEFI subprograms `L<n>` and cycle files starting with \
                 `$PC`, and Fanuc programs `O<n>`; move other files out of it",
            ),
        );
    }
}
