//! `ncplc check <machine-dir>`: reads and validates a machine's characterization files.
//!
//! The machine's interface map is checked too: the errors of `<machine>/interface.toml` (codes
//! 1601–1608) and, when AXCFIL says NBP>1, every handshake signal a process 2..NBP lacks (1609).
//!
//! Prints every diagnostic of every file rustc-style (default) or as one JSON object per line
//! (`--format json`) on stderr, and exits 1 when there is any error, 2 when the machine directory
//! does not exist, 0 otherwise. `--dump` prints the typed model as JSON on stdout.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

/// Output format of the diagnostics.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// rustc-style with the source line and the span marked.
    Human,
    /// One JSON object per line per diagnostic.
    Json,
}

/// Arguments of `ncplc check`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The machine directory (holding FCRSYS).
    #[arg(value_name = "MACHINE")]
    pub machine_dir: PathBuf,
    /// How to print diagnostics.
    #[arg(long, value_enum, default_value_t = Format::Human)]
    pub format: Format,
    /// Print the typed model as JSON (diagnostics go to stderr).
    #[arg(long)]
    pub dump: bool,
}

/// Renders the diagnostics of `load` in `format`.
pub fn render(load: &characterization::MachineLoad, format: Format) -> String {
    match format {
        Format::Human if load.diagnostics.is_empty() => {
            // Say what was checked, so a clean run is distinguishable from one that read nothing.
            let mut files: Vec<&str> = Vec::new();
            for name in ["FCRSYS", "AXCFIL", "PGCFIL", "IOCFIL", "interface.toml"] {
                files.extend(load.sources.names().filter(|f| f.ends_with(name)));
            }
            format!("{}: no problems found\n", files.join(", "))
        }
        Format::Human => super::output::render_diagnostics(&load.diagnostics, &load.sources),
        Format::Json => load
            .diagnostics
            .iter()
            .map(|d| d.to_json_line() + "\n")
            .collect(),
    }
}

/// Runs `ncplc check`.
pub fn run(args: Args) -> ExitCode {
    if !args.machine_dir.is_dir() {
        return super::output::usage_error(format!(
            "ncplc check: {}: not a machine directory (no such directory)",
            args.machine_dir.display()
        ));
    }
    let mut load = characterization::load_machine(&args.machine_dir);
    if let Some(machine) = load.machine.clone() {
        let map = crate::process_map::check(&args.machine_dir, &machine, &mut load.sources);
        load.diagnostics.extend(map);
    }
    super::output::relocate(&mut load, &args.machine_dir);
    let report = render(&load, args.format);
    // Diagnostics on stderr; stdout holds only the --dump model.
    eprint!("{report}");
    if args.dump {
        let model = serde_json::to_string_pretty(&load.machine)
            .unwrap_or_else(|e| format!("{{\"error\":\"{e}\"}}"));
        if writeln!(std::io::stdout().lock(), "{model}").is_err() {
            return ExitCode::from(2);
        }
    }
    if load.has_errors() {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
