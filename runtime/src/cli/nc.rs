//! `ncplc nc`: check partprograms and plan them into canonical blocks.
//!
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

/// Output format of `nc check` diagnostics.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum CheckFormat {
    /// rustc-style with the source line and the span marked.
    Human,
    /// One JSON object per line per diagnostic.
    Json,
}

/// Output format of `nc plan` blocks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum PlanFormat {
    /// One JSON object per canonical block.
    Json,
    /// One line per canonical block with the same fields.
    Text,
}

/// Options shared by the `nc` subcommands.
#[derive(Debug, clap::Args)]
pub struct Common {
    /// Machine directory (e.g. plc-programs/mill).
    #[arg(value_name = "MACHINE")]
    pub machine: PathBuf,
    /// Partprogram file (a bare name is looked up in <machine>/nc/).
    pub program: PathBuf,
    /// Dialect, overriding the machine's (mefi or fanuc).
    #[arg(long)]
    pub dialect: Option<String>,
    /// Correction table file, instead of the machine's MP0/TAB0.KOR (or MP0/TAB2.KOR).
    #[arg(long, value_name = "FILE")]
    pub kor: Option<PathBuf>,
    /// Diagnostics printed per file; the rest are counted in one `note: N more errors in FILE`
    /// line (0: print all).
    #[arg(long, value_name = "N", default_value_t = diag::DEFAULT_MAX_PER_FILE)]
    pub max_errors: usize,
}

/// `ncplc nc` subcommands.
#[derive(Debug, clap::Subcommand)]
pub enum NcCommand {
    /// Compile a partprogram and report diagnostics.
    #[command(after_help = crate::cli::output::EXIT_CODES_HELP)]
    Check {
        /// Machine and program.
        #[command(flatten)]
        common: Common,
        /// Output format of diagnostics.
        #[arg(long, value_enum, default_value_t = CheckFormat::Human)]
        format: CheckFormat,
    },
    /// Run a partprogram and print its canonical blocks.
    #[command(after_help = crate::cli::output::EXIT_CODES_HELP)]
    Plan {
        /// Machine and program.
        #[command(flatten)]
        common: Common,
        /// Output format of the blocks.
        #[arg(long, value_enum, default_value_t = PlanFormat::Json)]
        format: PlanFormat,
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
    /// Draw a partprogram's tool path (rapids dashed, feeds solid) as SVG or PNG.
    Plot {
        /// Machine and program.
        #[command(flatten)]
        common: Common,
        /// Plot options.
        #[command(flatten)]
        plot: super::nc_plot::PlotArgs,
    },
    /// Plan a partprogram and run it through the motion kernel in virtual time.
    #[command(after_help = crate::cli::output::EXIT_CODES_HELP)]
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
/// The machine's default partprogram dialect: `<dir>/nc/DIALECT`.
pub fn dialect_file(dir: &Path) -> PathBuf {
    dir.join("nc").join("DIALECT")
}

/// The machine constants: `<dir>/nc/CONSTANTS`.
pub fn constants_file(dir: &Path) -> PathBuf {
    dir.join("nc").join("CONSTANTS")
}

/// The zero-offset table: `<dir>/MP0/TAB0.POS`.
pub fn pos_file(dir: &Path) -> PathBuf {
    dir.join("MP0").join("TAB0.POS")
}

/// The retained Fanuc macro variables `#500`–`#999`: `<dir>/nc/MACROVARS` (not in
/// [`machine_view_files`]: a part trace carries its content, not its CRC, because a part run
/// rewrites it).
pub fn macro_vars_file(dir: &Path) -> PathBuf {
    dir.join("nc").join("MACROVARS")
}

/// The text of the machine's retained-variables file; `None` when it does not exist (every
/// variable null).
pub fn read_macro_vars(dir: &Path) -> std::io::Result<Option<String>> {
    match std::fs::read(macro_vars_file(dir)) {
        Ok(b) => Ok(Some(String::from_utf8_lossy(&b).into_owned())),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(e),
    }
}

/// Reads the retained-variables text `text` (the content of [`macro_vars_file`], None: no file)
/// into `spec`; returns the file's name and text for rendering, and its diagnostics.
pub fn load_macro_vars(
    dir: &Path,
    text: Option<&str>,
    spec: &mut MachineSpec,
) -> Option<(String, String, Vec<diag::Diagnostic>)> {
    let text = text?;
    let name = crate::cli::output::user_path(&macro_vars_file(dir))
        .display()
        .to_string();
    let (vars, diags) = partprogram::macro_b::retained::parse_retained(&name, text);
    spec.retained = vars;
    Some((name, text.to_string(), diags))
}

/// [`load_macro_vars`] of the machine's own file, an unreadable file being error 2080.
pub fn load_machine_macro_vars(
    dir: &Path,
    spec: &mut MachineSpec,
) -> Option<(String, String, Vec<diag::Diagnostic>)> {
    match read_macro_vars(dir) {
        Ok(text) => load_macro_vars(dir, text.as_deref(), spec),
        Err(e) => {
            let name = crate::cli::output::user_path(&macro_vars_file(dir))
                .display()
                .to_string();
            Some(unreadable(
                partprogram::codes::VARS_IO,
                name,
                "retained macro variables",
                &e,
            ))
        }
    }
}

/// Every machine file [`machine_spec`] and [`load_corrections`] may read besides the
/// characterization (the machine's own correction table, not a `--kor` one), whether it exists or
/// not: what a part trace's header hashes.
pub fn machine_view_files(dir: &Path) -> Vec<PathBuf> {
    let kor = kor_file(dir, None).map(|(p, _)| p);
    [
        Some(constants_file(dir)),
        Some(dialect_file(dir)),
        Some(pos_file(dir)),
        kor,
    ]
    .into_iter()
    .flatten()
    .collect()
}

/// Machine constants 8, 329 and 341 come from `<dir>/nc/CONSTANTS` when it exists.
pub fn machine_spec(
    dir: &Path,
    dialect: Option<&str>,
    program_text: &str,
) -> Result<MachineSpec, MachineError> {
    let facts = Facts::load(dir)?;
    let option = std::fs::read_to_string(dialect_file(dir)).ok();
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
    match std::fs::read_to_string(constants_file(dir)) {
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
/// value is the file's name in diagnostics (as the user can open it from the current directory).
pub fn kor_file(dir: &Path, kor: Option<&Path>) -> Option<(PathBuf, String)> {
    if let Some(k) = kor {
        return Some((k.to_path_buf(), k.display().to_string()));
    }
    ["TAB0.KOR", "TAB2.KOR"].iter().find_map(|n| {
        let p = dir.join("MP0").join(n);
        p.is_file().then(|| {
            let name = crate::cli::output::user_path(&p).display().to_string();
            (p, name)
        })
    })
}

/// Reads the correction table into `spec` (see [`kor_file`]) and the zero-offset table
/// `MP0/TAB0.POS` when the machine has one; returns each file's name and text for rendering, and
/// its diagnostics (an unreadable file is error 2049 / 2075).
pub fn load_corrections(
    dir: &Path,
    kor: Option<&Path>,
    spec: &mut MachineSpec,
) -> Vec<(String, String, Vec<diag::Diagnostic>)> {
    let mut files = Vec::new();
    if let Some((path, name)) = kor_file(dir, kor) {
        files.push(match std::fs::read(&path) {
            Ok(bytes) => {
                let text = String::from_utf8_lossy(&bytes).into_owned();
                let (table, diags) = partprogram::parse_kor(&name, &text, &spec.axes());
                spec.corrections = table;
                (name, text, diags)
            }
            Err(e) => unreadable(partprogram::codes::KOR_IO, name, "correction table", &e),
        });
    }
    let pos = pos_file(dir);
    if pos.is_file() {
        let name = crate::cli::output::user_path(&pos).display().to_string();
        files.push(match std::fs::read(&pos) {
            Ok(bytes) => {
                let text = String::from_utf8_lossy(&bytes).into_owned();
                let (table, diags) = partprogram::parse_pos(&name, &text, &spec.axes());
                spec.zero_offsets = table;
                (name, text, diags)
            }
            Err(e) => unreadable(partprogram::codes::POS_IO, name, "zero-offset table", &e),
        });
    }
    files
}

fn unreadable(
    code: u32,
    name: String,
    what: &str,
    e: &std::io::Error,
) -> (String, String, Vec<diag::Diagnostic>) {
    let d = diag::Diagnostic::error(
        code,
        name.clone(),
        0..0,
        format!("cannot read the {what}: {e}"),
    )
    .locate("");
    (name, String::new(), vec![d])
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

/// The program file: `program` itself when it exists, else `<machine>/nc/<program>`.
pub fn program_path(machine: &Path, program: &Path) -> PathBuf {
    if program.exists() {
        program.to_path_buf()
    } else {
        machine.join("nc").join(program)
    }
}

/// Runs `ncplc nc`.
pub fn run(args: Args) -> ExitCode {
    let (common, plan_opts, json) = match &args.command {
        NcCommand::Plot { common, plot } => return super::nc_plot::run(common, plot),
        NcCommand::Run(a) => return super::nc_run::run(a),
        NcCommand::Check { common, format } => (common, None, *format == CheckFormat::Json),
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
            *format == PlanFormat::Json,
        ),
    };
    let (name, prog, sources) = match compile_common(common, json) {
        Ok(c) => (c.name, c.prog, c.sources),
        Err(code) => return code,
    };
    let max_errors = common.max_errors;
    let print_diags = |diags: &[diag::Diagnostic], json: bool| {
        print_diags(diags, &sources, json, max_errors);
    };
    let Some(opts) = plan_opts else {
        // The geometric checks need the program executed: an arc whose end point is not on its
        // circle is a mistake of the text, so `check` refuses it as `plan` does (issue 12).
        if let Err((_, d)) = partprogram::plan(&prog, PlanOptions::default())
            && partprogram::codes::is_geometric(d.code)
        {
            print_diags(&[d], json);
            return ExitCode::from(1);
        }
        if !json {
            eprintln!(
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
            out.push_str(&c.to_text_line());
        }
        out.push('\n');
    }
    print!("{out}");
    if let Some(d) = err {
        print_diags(&[d], json);
        return ExitCode::from(1);
    }
    ExitCode::SUCCESS
}

/// A compiled partprogram with the sources its diagnostics are rendered from.
pub struct Compiled {
    /// The program's name in diagnostics (as the user can open it).
    pub name: String,
    /// The compiled program.
    pub prog: partprogram::Program,
    /// Program, macro and correction-table texts.
    pub sources: diag::Sources,
}

/// Prints diagnostics to stderr (at most `max_errors`), as JSON lines or rendered for humans.
pub fn print_diags(
    diags: &[diag::Diagnostic],
    sources: &diag::Sources,
    json: bool,
    max_errors: usize,
) {
    if diags.is_empty() {
        return;
    }
    if json {
        eprint!("{}", diag::json_lines_capped(diags, max_errors));
    } else {
        eprint!(
            "{}",
            super::output::render_diagnostics_capped(diags, sources, max_errors)
        );
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
    // As the user can open it from the current directory.
    let name = super::output::user_path(&path).display().to_string();
    let mut kor = load_corrections(&common.machine, common.kor.as_deref(), &mut spec);
    kor.extend(load_machine_macro_vars(&common.machine, &mut spec));
    let (prog, diags) = partprogram::compile(&spec, &name, &text);
    let mut sources = diag::Sources::new();
    sources.add(name.clone(), text.clone());
    let mut kor_failed = false;
    let mut diags = diags;
    for (kname, ktext, kdiags) in kor.into_iter().rev() {
        kor_failed |= diag::has_errors(&kdiags);
        sources.add(kname, ktext);
        diags.splice(0..0, kdiags);
    }
    if let Some(p) = &prog {
        for f in &p.files {
            sources.add(f.name.clone(), f.text.clone());
        }
    }
    print_diags(&diags, &sources, json, common.max_errors);
    match prog.filter(|_| !kor_failed) {
        Some(prog) => Ok(Compiled {
            name,
            prog,
            sources,
        }),
        None => Err(ExitCode::from(1)),
    }
}
