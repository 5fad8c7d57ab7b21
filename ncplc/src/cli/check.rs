//! `ncplc check <machine-dir>`: reads and validates a machine's characterization files.
//!
//! The machine's interface map is checked too: the errors of `<machine>/interface.toml` (codes
//! 1601–1608) and, when AXCFIL says NBP>1, every handshake signal a process 2..NBP lacks (1609).
//!
//! The I/O map `<machine>/io.toml` is checked too when the machine has one (the fieldbus crate's
//! located validation, codes 3000–3499, against the connectors IOCFIL declares and, for the
//! `[[canopen.drive]]` entries, the axes AXCFIL declares; `run` refuses the same errors with
//! every `--io`, see `run::io_map_refusal`); a machine without
//! io.toml runs with `--io sim` only, which is not a problem of the machine; an io.toml that
//! declares no I/O (empty, or no device and no node) is a warning (3050), since `run --io modbus`
//! and `--io canopen` refuse it.
//!
//! `sim.toml` is checked against the machine once the interface map is valid, before that only
//! its form (codes 3600–3612, `sim::validate`, the same validation `run` refuses with), and the
//! other files a run reads (`nc/DIALECT`, `nc/CONSTANTS`, the correction and zero-offset tables,
//! `nc/MACROVARS`, the macro library in `macros/`, the programs sim.toml's `[cnc] programs`
//! names, `retain.bin`) through [`super::check_files`], and the PLC program `run` loads
//! through the compiler's front end ([`super::check_plc`], codes 1000–1999, as `ncplc build`
//! reports them).
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
    /// Diagnostics printed per file; the rest are counted in one `note: N more errors in FILE`
    /// line (0: print all).
    #[arg(long, value_name = "N", default_value_t = diag::DEFAULT_MAX_PER_FILE)]
    pub max_errors: usize,
}

/// Renders the diagnostics of `load` in `format`, at most `max_errors` per file (0: all).
pub fn render(load: &characterization::MachineLoad, format: Format, max_errors: usize) -> String {
    match format {
        Format::Human if load.diagnostics.is_empty() => {
            // Say what was checked, so a clean run is distinguishable from one that read nothing.
            let mut files: Vec<&str> = Vec::new();
            for name in [
                "FCRSYS",
                "AXCFIL",
                "PGCFIL",
                "IOCFIL",
                "interface.toml",
                "io.toml",
                "sim.toml",
                "DIALECT",
                "CONSTANTS",
                "KOR",
                "TAB0.POS",
                "MACROVARS",
            ] {
                files.extend(load.sources.names().filter(|f| f.ends_with(name)));
                if name == "IOCFIL" {
                    // The PLC message files (FILMS5, FLC), named as the user chose.
                    let messages = load.machine.as_ref().map(|m| &m.messages);
                    let common = messages.and_then(|m| m.common.as_ref());
                    let own = messages.into_iter().flat_map(|m| m.processes.values());
                    for f in common.into_iter().chain(own) {
                        files.extend(load.sources.names().filter(|n| n.ends_with(&f.name)));
                    }
                }
            }
            // The PLC program, named as FCRSYS binds it (any name).
            let rest: Vec<&str> = load
                .sources
                .names()
                .filter(|n| !files.contains(n))
                .collect();
            files.extend(rest);
            files.dedup();
            format!("{}: no problems found\n", files.join(", "))
        }
        Format::Human => super::output::render_diagnostics_capped_with(
            &load.diagnostics,
            &load.hidden,
            &load.sources,
            max_errors,
        ),
        Format::Json => diag::json_lines_capped_with(&load.diagnostics, &load.hidden, max_errors),
    }
}

/// The diagnostics of `<machine_dir>/io.toml` (none when the file does not exist), its text
/// added to `sources` for rendering.
pub fn check_io_map(
    machine_dir: &std::path::Path,
    machine: &characterization::Machine,
    sources: &mut diag::Sources,
) -> Vec<diag::Diagnostic> {
    let path = machine_dir.join("io.toml");
    if !path.exists() {
        return Vec::new();
    }
    let declared = match &machine.iocfil {
        Some(io) => fieldbus::DeclaredConnectors {
            inputs: io.input_connectors(),
            outputs: io.output_connectors(),
        },
        // No IOCFIL (its own error is reported): check the map without connector rules.
        None => fieldbus::DeclaredConnectors::default(),
    };
    let axes = runtime::machine_facts::declared_axes(machine);
    // Read once; a file that cannot be read (or is over the size limit) gets the fieldbus
    // reader's own error.
    let Ok(text) = diag::read_config(&path) else {
        return fieldbus::load_map_with_axes(machine_dir, &declared, Some(&axes)).1;
    };
    let (map, mut diags) = fieldbus::parse_map_with_axes(&text, "io.toml", &declared, Some(&axes));
    if let Some(w) = map.as_ref().and_then(|m| no_io_declared(m, &text)) {
        diags.push(w);
    }
    // The OPC UA server's tables, which the fieldbus reader accepts without looking inside.
    if map.is_some()
        && let Err(d) = opcua_server::config::parse("io.toml", &text)
    {
        diags.extend(d);
    }
    sources.add("io.toml", text);
    diags
}

/// The warning for an io.toml that declares no I/O at all (empty, or only `[hmi]`/`[affinity]`):
/// `run --io modbus|canopen` refuses such a map (3050), `run --io sim` ignores it, so check says
/// so up front instead of "no problems found".
fn no_io_declared(map: &fieldbus::IoMap, text: &str) -> Option<diag::Diagnostic> {
    let has_nodes = map.canopen.as_ref().is_some_and(|c| !c.nodes.is_empty());
    if !map.modbus.is_empty() || has_nodes {
        return None;
    }
    let what = if text.trim().is_empty() {
        "io.toml is empty: it declares no I/O"
    } else {
        "io.toml declares no I/O (no Modbus device, no CANopen node)"
    };
    Some(
        diag::Diagnostic::warning(
            fieldbus::codes::NO_DEVICES,
            "io.toml",
            0..0,
            format!("{what}; `run --io modbus` and `run --io canopen` refuse it (3050)"),
        )
        .with_hint("add a [[modbus.device]] table or a [canopen] table with [[canopen.node]] entries (docs/io-toml.md), or delete io.toml and run with --io sim"),
    )
}

/// Runs `ncplc check`.
pub fn run(args: Args) -> ExitCode {
    if !args.machine_dir.is_dir() {
        return super::output::usage_error(format!(
            "ncplc check: {}: not a machine directory (no such directory)",
            args.machine_dir.display()
        ));
    }
    // Each characterization file keeps at most `--max-errors` diagnostics in memory and counts
    // the rest: an error-dense file of any size is rejected in bounded memory (issue 23).
    let mut load = characterization::load_machine_capped(&args.machine_dir, args.max_errors);
    // What a part run would accept: the tables are read with this machine's axes (the machine
    // is loaded once).
    let runnable = !load.has_errors();
    if let Some(machine) = load.machine.take() {
        let (map, interface) =
            runtime::process_map::check(&args.machine_dir, &machine, &mut load.sources);
        load.diagnostics.extend(map);
        let io = check_io_map(&args.machine_dir, &machine, &mut load.sources);
        load.diagnostics.extend(io);
        // sim.toml against the map `run` would use; while that map has errors (reported above,
        // and `run` refuses them before it reads sim.toml) only the file's form, since its
        // signal names would give follow-on errors.
        let sim = match &interface {
            Some(interface) => sim::validate::load(&args.machine_dir, &machine, interface),
            None => sim::validate::load_form(&args.machine_dir),
        };
        // The other processes' programs a part run compiles (sim.toml `[cnc] programs`).
        let programs: Vec<String> = sim
            .script
            .as_ref()
            .map(|s| s.cnc.programs.values().cloned().collect())
            .unwrap_or_default();
        if let Some(text) = sim.text {
            load.sources.add(sim::validate::FILE, text);
        }
        load.diagnostics.extend(sim.diagnostics);
        let tables = (runnable && machine.iocfil.is_some()).then_some(&machine);
        load.diagnostics.extend(super::check_files::check(
            &args.machine_dir,
            tables,
            &programs,
            args.max_errors,
            &mut load.sources,
            &mut load.hidden,
        ));
        // The PLC program `run` would load, through the front end `build` runs, once the map it
        // is compiled against is valid (as for sim.toml: its names would only be follow-on errors,
        // and `run` refuses the map first).
        if runnable && let Some(interface) = interface {
            let plc =
                super::check_plc::check(&args.machine_dir, &machine, interface, &mut load.sources);
            load.diagnostics.extend(plc);
        }
        load.machine = Some(machine);
    }
    super::output::relocate(&mut load, &args.machine_dir);
    let report = render(&load, args.format, args.max_errors);
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
