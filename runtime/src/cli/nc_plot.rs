//! `ncplc nc plot <machine> <program> -o path.svg|png [--view xy|zx|yz] [--trajectory FILE]`:
//! plans the partprogram like `ncplc nc plan` and draws its tool path.

use std::path::PathBuf;
use std::process::ExitCode;

use partprogram::PlanOptions;

use super::nc::{Common, load_corrections, machine_spec, program_path};
use crate::plot::{self, toolpath};

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
    let path = program_path(&common.machine, &common.program);
    let bytes = std::fs::read(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let text = String::from_utf8_lossy(&bytes).into_owned();
    let mut spec = machine_spec(&common.machine, common.dialect.as_deref(), &text)
        .map_err(|e| e.to_string())?;
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| format!("nc/{}", n.to_string_lossy()),
    );
    let kor = load_corrections(&common.machine, common.kor.as_deref(), &mut spec);
    let (prog, mut diags) = partprogram::compile(&spec, &name, &text);
    let mut sources = diag::Sources::new();
    sources.add(name.clone(), text.clone());
    if let Some((kname, ktext, kdiags)) = kor {
        sources.add(kname, ktext);
        diags.splice(0..0, kdiags);
    }
    if let Some(p) = &prog {
        for f in &p.files {
            sources.add(f.name.clone(), f.text.clone());
        }
    }
    if !diags.is_empty() {
        eprint!("{}", diag::render_human(&diags, &sources));
    }
    let Some(prog) = prog.filter(|_| !diag::has_errors(&diags)) else {
        return Ok(ExitCode::from(1));
    };
    let blocks = match partprogram::plan(&prog, PlanOptions::default()) {
        Ok(p) => p.blocks,
        Err((_, d)) => {
            eprint!("{}", diag::render_human(&[d], &sources));
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
