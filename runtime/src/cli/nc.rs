//! `ncplc nc`: check partprograms and plan them into canonical blocks.
//!
//! `ncplc nc run` (module [`super::nc_run`]) moves the planned blocks through the motion kernel.
//! `ncplc nc check <machine> <program>` compiles a partprogram (with the machine's macro folder) and
//! prints diagnostics; `ncplc nc plan <machine> <program> --format json` runs it and writes one JSON
//! object per canonical block. A program path that does not exist is looked up in `<machine>/nc/`.
//!
//! The correction table at power-up is the machine's `MP0/TAB0.KOR` (else `MP0/TAB2.KOR`, the lathe
//! name of the manual), or the file given with `--kor`; errors in it are reported like program
//! diagnostics and fail both subcommands. The machine constants the planner uses (8: thread
//! run-in/run-out slope; 329 decade 7: MEFI length correction method; 341: the G14–G16 planes) are
//! read from the option file `<machine>/nc/CONSTANTS`, written as in a `TAB0.REK` listing (`R329: 01000.000`).

use crate::machine_facts::Facts;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use partprogram::{Backend, Dialect, MTiming, MachineSpec, PlanOptions, ProcessSpec};

/// Arguments of `ncplc nc`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// What to do.
    #[command(subcommand)]
    pub command: NcCommand,
}

/// Options shared by the `nc` subcommands.
#[derive(Debug, clap::Args)]
pub struct Common {
    /// Machine directory (e.g. plc-programs/mill).
    pub machine: PathBuf,
    /// Partprogram file (a bare name is looked up in <machine>/nc/).
    pub program: PathBuf,
    /// Dialect, overriding the machine's (mefi or fanuc).
    #[arg(long)]
    pub dialect: Option<String>,
    /// Correction table file, instead of the machine's MP0/TAB0.KOR (or MP0/TAB2.KOR).
    #[arg(long, value_name = "FILE")]
    pub kor: Option<PathBuf>,
}

/// `ncplc nc` subcommands.
#[derive(Debug, clap::Subcommand)]
pub enum NcCommand {
    /// Compile a partprogram and report diagnostics.
    Check {
        /// Machine and program.
        #[command(flatten)]
        common: Common,
        /// Output format of diagnostics: human or json.
        #[arg(long, default_value = "human")]
        format: String,
    },
    /// Run a partprogram and print its canonical blocks.
    Plan {
        /// Machine and program.
        #[command(flatten)]
        common: Common,
        /// Output format: json (one object per line) or text.
        #[arg(long, default_value = "json")]
        format: String,
        /// Run parameter arithmetic in the reference interpreter instead of native code.
        #[arg(long)]
        interpreter: bool,
        /// Block-skip mode: skip blocks marked with `/`.
        #[arg(long)]
        block_skip: bool,
        /// Outside corners under radius compensation G41/G42: `arc` (insert an arc, MC 339 decade 8
        /// = 1) or `intersection` (intersection of the equidistants, decade 8 = 0).
        #[arg(long, default_value = "arc")]
        corners: partprogram::radius::Corners,
    },
    /// Plan a partprogram and run it through the motion kernel in virtual time.
    Run(super::nc_run::RunArgs),
}

/// Errors building the machine description.
#[derive(Debug, thiserror::Error)]
pub enum MachineError {
    /// The machine directory cannot be used (missing, or its characterization has errors).
    #[error(transparent)]
    Machine(#[from] crate::machine_facts::MachineError),
    /// A dialect name that is not known.
    #[error("{0}")]
    Dialect(String),
    /// The option file `nc/CONSTANTS` is not valid.
    #[error("nc/CONSTANTS: {0}")]
    Constants(#[from] partprogram::machine::ConstantsError),
    /// The option file `nc/CONSTANTS` exists but cannot be read.
    #[error("nc/CONSTANTS: {0}")]
    ConstantsFile(std::io::Error),
}

/// Builds the partprogram view of the machine in `dir` from its validated characterization.
///
/// Each AXCFIL process gives its axes (spindles excluded) and the M functions IOCFIL section 2
/// declares for it, with their timing. The machine is a lathe when PGCFIL `TOF` says so for process
/// 1 (else when process 1 has no Y axis): X is then programmed in diameter, and in the Fanuc dialect
/// the spindle is addressed as C (cylinder interpolation G7.1). Macros live in `<dir>/macros`.
///
/// The dialect is, in order: `--dialect`; the machine option file `<dir>/nc/DIALECT` (one word, `mefi`
/// or `fanuc`); else detected from the program text (an `O<number>` program header means Fanuc).
/// Machine constants 8, 329 and 341 come from `<dir>/nc/CONSTANTS` when it exists.
pub fn machine_spec(
    dir: &Path,
    dialect: Option<&str>,
    program_text: &str,
) -> Result<MachineSpec, MachineError> {
    let facts = Facts::load(dir)?;
    let option = std::fs::read_to_string(dir.join("nc").join("DIALECT")).ok();
    let dialect: Dialect = match dialect.or(option.as_deref().map(str::trim)) {
        Some(d) => d.parse().map_err(MachineError::Dialect)?,
        None => detect_dialect(program_text),
    };
    let machine = &facts.machine;
    let mut processes: Vec<ProcessSpec> = machine
        .axcfil
        .processes
        .iter()
        .map(|p| ProcessSpec {
            axes: p
                .axes
                .iter()
                .filter(|a| !a.axis_type().spindle())
                .map(|a| a.name)
                .collect(),
            declared_m: facts
                .iocfil()
                .process(p.number)
                .map(|io| {
                    io.m_functions
                        .iter()
                        .map(|f| {
                            let timing = MTiming {
                                m_type: f.m_type,
                                m_request: f.m_request,
                                class: f.class,
                            };
                            (u16::from(f.number), timing)
                        })
                        .collect()
                })
                .unwrap_or_default(),
        })
        .collect();
    let first_axes: Vec<char> = processes
        .first()
        .map(|p| p.axes.clone())
        .unwrap_or_default();
    let tof = machine
        .pgcfil
        .as_ref()
        .and_then(|p| p.process(1))
        .and_then(|p| p.tof.as_ref());
    let lathe = tof.map_or(!first_axes.contains(&'Y'), |t| t.is_lathe());
    let mut axes = first_axes;
    if lathe && dialect == Dialect::Fanuc && !axes.contains(&'C') {
        axes.push('C');
    }
    let mut spec = MachineSpec::new(dialect, &axes);
    if let Some(first) = processes.first_mut() {
        first.axes = axes;
        spec.processes = processes;
    }
    spec.diameter_x = lathe;
    spec.macro_dir = dir.join("macros");
    spec.check_m_declared = true;
    match std::fs::read_to_string(dir.join("nc").join("CONSTANTS")) {
        Ok(text) => {
            for (n, v) in partprogram::machine::parse_constants(&text)? {
                spec.set_constant(n, v)?;
            }
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(MachineError::ConstantsFile(e)),
    }
    Ok(spec)
}

/// The correction table file of the machine in `dir`: `kor` when given, else `MP0/TAB0.KOR`, else
/// `MP0/TAB2.KOR`; `None` when the machine has neither (the table is then all zero). The second
/// value is the file's name in diagnostics (relative to the machine for the default files).
pub fn kor_file(dir: &Path, kor: Option<&Path>) -> Option<(PathBuf, String)> {
    if let Some(k) = kor {
        return Some((k.to_path_buf(), k.display().to_string()));
    }
    ["TAB0.KOR", "TAB2.KOR"].iter().find_map(|n| {
        let p = dir.join("MP0").join(n);
        p.is_file().then(|| (p, format!("MP0/{n}")))
    })
}

/// Reads the correction table into `spec` (see [`kor_file`]); returns the file's name and text for
/// rendering, and its diagnostics (an unreadable file is error 2049).
pub fn load_corrections(
    dir: &Path,
    kor: Option<&Path>,
    spec: &mut MachineSpec,
) -> Option<(String, String, Vec<diag::Diagnostic>)> {
    let (path, name) = kor_file(dir, kor)?;
    match std::fs::read(&path) {
        Ok(bytes) => {
            let text = String::from_utf8_lossy(&bytes).into_owned();
            let (table, diags) = partprogram::parse_kor(&name, &text, &spec.axes());
            spec.corrections = table;
            Some((name, text, diags))
        }
        Err(e) => {
            let d = diag::Diagnostic::error(
                partprogram::codes::KOR_IO,
                name.clone(),
                0..0,
                format!("cannot read the correction table: {e}"),
            )
            .locate("");
            Some((name, String::new(), vec![d]))
        }
    }
}

/// Fanuc when the first word of the program (after `%` lines and comments) is an `O<number>`.
fn detect_dialect(text: &str) -> Dialect {
    for line in text.lines() {
        let t = line.trim();
        if t.is_empty() || t.starts_with('%') || t.starts_with('(') || t.starts_with(';') {
            continue;
        }
        let mut c = t.chars();
        let fanuc = matches!(c.next(), Some('O') | Some('o'))
            && c.next().is_some_and(|d| d.is_ascii_digit());
        return if fanuc { Dialect::Fanuc } else { Dialect::Mefi };
    }
    Dialect::Mefi
}

fn program_path(machine: &Path, program: &Path) -> PathBuf {
    if program.exists() {
        program.to_path_buf()
    } else {
        machine.join("nc").join(program)
    }
}

/// Runs `ncplc nc`.
pub fn run(args: Args) -> ExitCode {
    let (common, plan_opts, format) = match &args.command {
        NcCommand::Run(a) => return super::nc_run::run(a),
        NcCommand::Check { common, format } => (common, None, format.clone()),
        NcCommand::Plan {
            common,
            format,
            interpreter,
            block_skip,
            corners,
        } => (
            common,
            Some(PlanOptions {
                backend: if *interpreter {
                    Backend::Interpreter
                } else {
                    Backend::Native
                },
                block_skip: *block_skip,
                radius: partprogram::radius::RadiusOptions {
                    corners: *corners,
                    ..partprogram::radius::RadiusOptions::default()
                },
                ..PlanOptions::default()
            }),
            format.clone(),
        ),
    };
    let json = format == "json";
    let compiled = match compile_common(common, json) {
        Ok(c) => c,
        Err(code) => return code,
    };
    let Compiled {
        name,
        prog,
        sources,
    } = compiled;
    let Some(opts) = plan_opts else {
        if !json {
            println!(
                "{name}: ok ({} blocks, {} units)",
                prog.blocks.len(),
                prog.units.len()
            );
        }
        return ExitCode::SUCCESS;
    };
    let (blocks, err) = match partprogram::plan(&prog, opts) {
        Ok(p) => (p.blocks, None),
        Err((b, d)) => (b, Some(d)),
    };
    let mut out = String::with_capacity(blocks.len() * 160);
    for c in &blocks {
        if json {
            out.push_str(&c.to_json_line());
        } else {
            let end: Vec<String> = c
                .end
                .iter()
                .map(|(a, v)| format!("{a}{}", partprogram::canon::num(*v)))
                .collect();
            out.push_str(&format!(
                "N{} {} {}",
                c.n.unwrap_or(0),
                c.kind.name(),
                end.join(" ")
            ));
        }
        out.push('\n');
    }
    print!("{out}");
    if let Some(d) = err {
        print_diags(&[d], &sources, json);
        return ExitCode::from(1);
    }
    ExitCode::SUCCESS
}

/// A compiled partprogram with the sources its diagnostics are rendered from.
pub struct Compiled {
    /// The program's name in diagnostics (`nc/NAME`).
    pub name: String,
    /// The compiled program.
    pub prog: partprogram::Program,
    /// Program, macro and correction-table texts.
    pub sources: diag::Sources,
}

/// Prints diagnostics to stderr, as JSON lines or rendered for humans.
pub fn print_diags(diags: &[diag::Diagnostic], sources: &diag::Sources, json: bool) {
    if diags.is_empty() {
        return;
    }
    if json {
        for d in diags {
            eprintln!("{}", d.to_json_line());
        }
    } else {
        eprint!("{}", diag::render_human(diags, sources));
    }
}

/// Reads and compiles the program of `common` for its machine (with the correction table),
/// printing every diagnostic; the exit code when it cannot be planned (2: unreadable input,
/// 1: errors).
pub fn compile_common(common: &Common, json: bool) -> Result<Compiled, ExitCode> {
    let path = program_path(&common.machine, &common.program);
    let text = match std::fs::read(&path) {
        Ok(b) => String::from_utf8_lossy(&b).into_owned(),
        Err(e) => {
            eprintln!("ncplc nc: cannot read {}: {e}", path.display());
            return Err(ExitCode::from(2));
        }
    };
    let mut spec = match machine_spec(&common.machine, common.dialect.as_deref(), &text) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("ncplc nc: {e}");
            return Err(ExitCode::from(2));
        }
    };
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| format!("nc/{}", n.to_string_lossy()),
    );
    let kor = load_corrections(&common.machine, common.kor.as_deref(), &mut spec);
    let (prog, diags) = partprogram::compile(&spec, &name, &text);
    let mut sources = diag::Sources::new();
    sources.add(name.clone(), text.clone());
    let mut kor_failed = false;
    let mut diags = diags;
    if let Some((kname, ktext, kdiags)) = kor {
        kor_failed = diag::has_errors(&kdiags);
        sources.add(kname, ktext);
        diags.splice(0..0, kdiags);
    }
    if let Some(p) = &prog {
        for f in &p.files {
            sources.add(f.name.clone(), f.text.clone());
        }
    }
    print_diags(&diags, &sources, json);
    match prog.filter(|_| !kor_failed) {
        Some(prog) => Ok(Compiled {
            name,
            prog,
            sources,
        }),
        None => Err(ExitCode::from(1)),
    }
}
