//! `ncplc nc plot <machine> <program> -o path.svg|png [--view xy|zx|yz] [--trajectory FILE]`:
//! plans the partprogram like `ncplc nc plan` and draws its tool path.

use std::path::PathBuf;
use std::process::ExitCode;

use partprogram::PlanOptions;

use super::nc::{Common, compile_common, print_diags, program_path};
use plot::{self, toolpath};

/// Options of `ncplc nc plot`.
#[derive(Debug, clap::Args)]
pub struct PlotArgs {
    /// Output file (.svg or .png).
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
    /// Which plane to look at.
    #[arg(long, value_enum, default_value = "xy")]
    pub view: toolpath::View,
    /// A motion trajectory (JSON Lines of `ncplc nc run --trajectory`) drawn on top.
    #[arg(long, value_name = "FILE")]
    pub trajectory: Option<PathBuf>,
}

/// Runs `ncplc nc plot`.
pub fn run(common: &Common, args: &PlotArgs) -> ExitCode {
    match run_inner(common, args) {
        Ok(code) => code,
        Err(msg) => {
            eprintln!("ncplc nc plot: {msg}");
            ExitCode::from(2)
        }
    }
}

fn run_inner(common: &Common, args: &PlotArgs) -> Result<ExitCode, String> {
    // Compiled and its diagnostics printed exactly as `ncplc nc plan` does (files named as the
    // user can open them, capped, coloured); only the chart title keeps the short program name.
    let compiled = match compile_common(common, false) {
        Ok(c) => c,
        Err(code) => return Ok(code),
    };
    let path = program_path(&common.machine, &common.program);
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| format!("nc/{}", n.to_string_lossy()),
    );
    let blocks = match partprogram::plan(&compiled.prog, PlanOptions::default()) {
        Ok(p) => p.blocks,
        Err((_, d)) => {
            print_diags(&[d], &compiled.sources, false, common.max_errors);
            return Ok(ExitCode::from(1));
        }
    };
    let trajectory = match &args.trajectory {
        Some(t) => {
            let text = std::fs::read_to_string(t).map_err(|e| format!("{}: {e}", t.display()))?;
            toolpath::trajectory(&text, args.view).map_err(|e| format!("{}: {e}", t.display()))?
        }
        None => Vec::new(),
    };
    let pieces = toolpath::pieces(&blocks, args.view);
    let (h, v) = args.view.axes();
    let chart = toolpath::Toolpath {
        title: format!("{name} ({h}{v})"),
        view: args.view,
        pieces,
        trajectory,
    };
    plot::write(&chart, &args.output).map_err(|e| e.to_string())?;
    eprintln!(
        "{}: {} motion blocks of {} planned",
        args.output.display(),
        chart.pieces.len(),
        blocks.len()
    );
    Ok(ExitCode::SUCCESS)
}
