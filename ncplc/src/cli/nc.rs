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

use std::path::PathBuf;
use std::process::ExitCode;

use partprogram::{Backend, PlanOptions};
pub use sim::machine_view::{
    load_corrections, load_machine_macro_vars, machine_spec, program_path,
};

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
        // circle is a mistake of the text, so `check` refuses it as `plan` does (issue 12). The
        // run keeps none of the canonical blocks (issue 23).
        if let Err(d) = partprogram::check_plan(&prog, PlanOptions::default())
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
    print_diags_with(diags, &[], sources, json, max_errors);
}

/// [`print_diags`] with `hidden`, what a capped compile counted but did not keep.
fn print_diags_with(
    diags: &[diag::Diagnostic],
    hidden: &[diag::Hidden],
    sources: &diag::Sources,
    json: bool,
    max_errors: usize,
) {
    if diags.is_empty() && hidden.is_empty() {
        return;
    }
    if json {
        eprint!(
            "{}",
            diag::json_lines_capped_with(diags, hidden, max_errors)
        );
    } else {
        eprint!(
            "{}",
            super::output::render_diagnostics_capped_with(diags, hidden, sources, max_errors)
        );
    }
}

/// Reads and compiles the program of `common` for its machine (with the correction table),
/// printing every diagnostic; the exit code when it cannot be planned (2: unreadable input,
/// 1: errors).
pub fn compile_common(common: &Common, json: bool) -> Result<Compiled, ExitCode> {
    let path = program_path(&common.machine, &common.program);
    let text = match std::fs::read(&path) {
        // Valid UTF-8 becomes the text without a copy (a 50 MB program is 50 MB once).
        Ok(b) => partprogram::text_of(b),
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
    // At most `--max-errors` diagnostics per file are kept, the rest counted (issue 23).
    let (prog, diags, hidden) = partprogram::compile_capped(&spec, &name, &text, common.max_errors);
    let mut sources = diag::Sources::new();
    sources.add(name.clone(), text);
    let mut kor_failed = false;
    let mut diags = diags;
    for (kname, ktext, kdiags) in kor.into_iter().rev() {
        kor_failed |= diag::has_errors(&kdiags);
        sources.add(kname, ktext);
        diags.splice(0..0, kdiags);
    }
    if let Some(p) = &prog {
        // The main file is in the sources already.
        for f in p.files.iter().filter(|f| f.name != name) {
            sources.add(f.name.clone(), f.text.clone());
        }
    }
    print_diags_with(&diags, &hidden, &sources, json, common.max_errors);
    match prog.filter(|_| !kor_failed) {
        Some(prog) => Ok(Compiled {
            name,
            prog,
            sources,
        }),
        None => Err(ExitCode::from(1)),
    }
}
