//! `ncplc nc`: check partprograms and plan them into canonical blocks.
//!
//! `ncplc nc check <machine> <program>` compiles a partprogram (with the machine's macro folder) and
//! prints diagnostics; `ncplc nc plan <machine> <program> --format json` runs it and writes one JSON
//! object per canonical block. A program path that does not exist is looked up in `<machine>/nc/`.

use std::collections::BTreeMap;
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
    },
}

/// Errors building the machine description.
#[derive(Debug, thiserror::Error)]
pub enum MachineError {
    /// The machine directory does not exist.
    #[error("machine directory {0} does not exist")]
    NoMachine(PathBuf),
    /// A dialect name that is not known.
    #[error("{0}")]
    Dialect(String),
}

/// Builds the partprogram view of the machine in `dir`.
///
/// TEMPORARY (to be replaced by the lead with `characterization::Machine`): reads only the `Mxx=` lines
/// of `<dir>/MP0/IOCFIL` section 2 for process 1, and takes the axes from a default per dialect: a
/// machine whose directory name contains "lathe" has X, Z (MEFI) or X, Z, C (Fanuc, for G7.1) with
/// diameter programming, any other X, Y, Z. Macros live in `<dir>/macros`.
///
/// The dialect is, in order: `--dialect`; the machine option file `<dir>/nc/DIALECT` (one word, `mefi`
/// or `fanuc`); else detected from the program text (an `O<number>` program header means Fanuc).
pub fn machine_spec(
    dir: &Path,
    dialect: Option<&str>,
    program_text: &str,
) -> Result<MachineSpec, MachineError> {
    if !dir.is_dir() {
        return Err(MachineError::NoMachine(dir.to_path_buf()));
    }
    let option = std::fs::read_to_string(dir.join("nc").join("DIALECT")).ok();
    let dialect: Dialect = match dialect.or(option.as_deref().map(str::trim)) {
        Some(d) => d.parse().map_err(MachineError::Dialect)?,
        None => detect_dialect(program_text),
    };
    let name = dir.canonicalize().unwrap_or_else(|_| dir.to_path_buf());
    let lathe = name
        .file_name()
        .is_some_and(|n| n.to_string_lossy().to_ascii_lowercase().contains("lathe"));
    let axes: &[char] = match (lathe, dialect) {
        (true, Dialect::Mefi) => &['X', 'Z'],
        (true, Dialect::Fanuc) => &['X', 'Z', 'C'],
        (false, _) => &['X', 'Y', 'Z'],
    };
    let mut spec = MachineSpec::new(dialect, axes);
    spec.diameter_x = lathe;
    spec.macro_dir = dir.join("macros");
    if let Some(declared) = read_iocfil_m(&dir.join("MP0").join("IOCFIL")) {
        spec.processes = vec![ProcessSpec {
            declared_m: declared,
            axes: axes.to_vec(),
        }];
        spec.check_m_declared = true;
    }
    Ok(spec)
}

/// TEMPORARY minimal reader of IOCFIL section 2: `PRO=n` selects the process, `Mxx=t,r,c` (hex) declares
/// an M function. Returns the declarations of process 1, or None when the file cannot be read.
fn read_iocfil_m(path: &Path) -> Option<BTreeMap<u16, MTiming>> {
    let text = String::from_utf8_lossy(&std::fs::read(path).ok()?).into_owned();
    let mut section = 0;
    let mut process = 1;
    let mut out = BTreeMap::new();
    for line in text.lines() {
        let line = line
            .split(';')
            .next()
            .unwrap_or("")
            .trim()
            .trim_start_matches('\\');
        if let Some(s) = line.strip_prefix('*') {
            section = s.trim().parse().unwrap_or(0);
            continue;
        }
        if section != 2 {
            continue;
        }
        let Some((key, value)) = line.split_once('=') else {
            continue;
        };
        let key = key.trim().to_ascii_uppercase();
        if key == "PRO" {
            process = value.trim().parse().unwrap_or(1);
        } else if let Some(num) = key.strip_prefix('M') {
            let (Ok(m), true) = (num.parse::<u16>(), process == 1) else {
                continue;
            };
            let f: Vec<u8> = value
                .split(',')
                .map(|x| u8::from_str_radix(x.trim(), 16).unwrap_or(0))
                .collect();
            out.insert(
                m,
                MTiming {
                    m_type: f.first().copied().unwrap_or(0),
                    m_request: f.get(1).copied().unwrap_or(0),
                    class: f.get(2).copied().unwrap_or(0),
                },
            );
        }
    }
    Some(out)
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
        NcCommand::Check { common, format } => (common, None, format.clone()),
        NcCommand::Plan {
            common,
            format,
            interpreter,
            block_skip,
        } => (
            common,
            Some(PlanOptions {
                backend: if *interpreter {
                    Backend::Interpreter
                } else {
                    Backend::Native
                },
                block_skip: *block_skip,
                ..PlanOptions::default()
            }),
            format.clone(),
        ),
    };
    let path = program_path(&common.machine, &common.program);
    let text = match std::fs::read(&path) {
        Ok(b) => String::from_utf8_lossy(&b).into_owned(),
        Err(e) => {
            eprintln!("ncplc nc: cannot read {}: {e}", path.display());
            return ExitCode::from(2);
        }
    };
    let spec = match machine_spec(&common.machine, common.dialect.as_deref(), &text) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("ncplc nc: {e}");
            return ExitCode::from(2);
        }
    };
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| format!("nc/{}", n.to_string_lossy()),
    );
    let (prog, diags) = partprogram::compile(&spec, &name, &text);
    let mut sources = diag::Sources::new();
    sources.add(name.clone(), text.clone());
    if let Some(p) = &prog {
        for f in &p.files {
            sources.add(f.name.clone(), f.text.clone());
        }
    }
    let print_diags = |diags: &[diag::Diagnostic], json: bool| {
        if diags.is_empty() {
            return;
        }
        if json {
            for d in diags {
                eprintln!("{}", d.to_json_line());
            }
        } else {
            eprint!("{}", diag::render_human(diags, &sources));
        }
    };
    let json = format == "json";
    print_diags(&diags, json);
    let Some(prog) = prog else {
        return ExitCode::from(1);
    };
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
        print_diags(&[d], json);
        return ExitCode::from(1);
    }
    ExitCode::SUCCESS
}
