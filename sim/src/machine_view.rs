//! The partprogram view of a machine: its `MachineSpec` (axes, declared M functions, lathe or
//! mill, dialect, machine constants), the correction and zero-offset tables, the retained macro
//! variables, and the names of every machine file that view reads.
//!
//! Shared by `ncplc nc`, the part run's planning ([`crate::part`]) and a part replay's file check.
//! **Invariant:** a file the view may read is listed by [`machine_view_files`] (or is the
//! retained-variables file, whose text a part trace carries), so a replay notices any change.

use std::path::{Path, PathBuf};

use partprogram::{Dialect, MTiming, MachineSpec, ProcessSpec};
use runtime::machine_facts::Facts;

/// Errors building the machine description.
#[derive(Debug, thiserror::Error)]
pub enum MachineError {
    /// The machine directory cannot be used (missing, or its characterization has errors).
    #[error(transparent)]
    Machine(#[from] runtime::machine_facts::MachineError),
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

/// The motion kernel's complex-speed constants (R39, R384, R385, R386, R236) from
/// [`constants_file`], the manual's defaults when it does not exist; an unreadable file or a value
/// out of range is an error naming the file (and the line).
pub fn complex_speed(dir: &Path) -> Result<motion::complex::ComplexSpeed, String> {
    let path = constants_file(dir);
    match diag::read_config(&path) {
        Ok(text) => motion::complex::from_constants(&text)
            .map_err(|e| format!("{}: {e}", runtime::render::user_path(&path).display())),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Default::default()),
        Err(e) => Err(format!(
            "{}: {e}",
            runtime::render::user_path(&path).display()
        )),
    }
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
    match diag::read_config_bytes(&macro_vars_file(dir)) {
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
    let name = runtime::render::user_path(&macro_vars_file(dir))
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
            let name = runtime::render::user_path(&macro_vars_file(dir))
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

/// The axes a partprogram of `dialect` is compiled with on `machine`: process 1's axes without
/// its spindles, and C for a Fanuc lathe (PGCFIL's TOF says lathe; without TOF, no Y axis) whose
/// process 1 has none (the cylinder interpolation G7.1 names it).
pub fn program_axes(machine: &characterization::Machine, dialect: Dialect) -> Vec<char> {
    let mut axes: Vec<char> = machine
        .axcfil
        .processes
        .first()
        .map(|p| {
            p.axes
                .iter()
                .filter(|a| !a.axis_type().spindle())
                .map(|a| a.name)
                .collect()
        })
        .unwrap_or_default();
    if is_lathe(machine, &axes) && dialect == Dialect::Fanuc && !axes.contains(&'C') {
        axes.push('C');
    }
    axes
}

/// PGCFIL's TOF of process 1 says lathe; without TOF, a machine whose `axes` have no Y is one.
fn is_lathe(machine: &characterization::Machine, axes: &[char]) -> bool {
    let tof = machine
        .pgcfil
        .as_ref()
        .and_then(|p| p.process(1))
        .and_then(|p| p.tof.as_ref());
    tof.map_or(!axes.contains(&'Y'), |t| t.is_lathe())
}

/// Machine constants 8, 329 and 341 come from `<dir>/nc/CONSTANTS` when it exists.
pub fn machine_spec(
    dir: &Path,
    dialect: Option<&str>,
    program_text: &str,
) -> Result<MachineSpec, MachineError> {
    let facts = Facts::load(dir)?;
    let dialect = program_dialect(dir, dialect, program_text)?;
    spec_of(dir, &facts.machine, facts.iocfil(), dialect)
}

/// The dialect a program of the machine in `dir` is compiled in: `dialect` when given (a
/// `--dialect` option), else `nc/DIALECT`, else the one its text `program_text` starts in.
pub fn program_dialect(
    dir: &Path,
    dialect: Option<&str>,
    program_text: &str,
) -> Result<Dialect, MachineError> {
    let option = diag::read_config(&dialect_file(dir)).ok();
    match dialect.or(option.as_deref().map(str::trim)) {
        Some(d) => d.parse().map_err(MachineError::Dialect),
        None => Ok(detect_dialect(program_text)),
    }
}

/// The [`MachineSpec`] of the machine in `dir`, loaded as `machine` with its `iocfil`, for
/// programs in `dialect` (what [`machine_spec`] builds once it has loaded the machine).
pub fn spec_of(
    dir: &Path,
    machine: &characterization::Machine,
    iocfil: &characterization::iocfil::Iocfil,
    dialect: Dialect,
) -> Result<MachineSpec, MachineError> {
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
            declared_m: iocfil
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
    let axes = program_axes(machine, dialect);
    let lathe = is_lathe(machine, &axes);
    let mut spec = MachineSpec::new(dialect, &axes);
    if let Some(first) = processes.first_mut() {
        first.axes = axes;
        spec.processes = processes;
    }
    spec.diameter_x = lathe;
    spec.macro_dir = dir.join("macros");
    spec.check_m_declared = true;
    match diag::read_config(&constants_file(dir)) {
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
            let name = runtime::render::user_path(&p).display().to_string();
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
        files.push(match diag::read_config_bytes(&path) {
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
        let name = runtime::render::user_path(&pos).display().to_string();
        files.push(match diag::read_config_bytes(&pos) {
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
