//! `ncplc nc run`: plans a partprogram and runs its blocks through the motion kernel in virtual
//! time (M/S/T functions acknowledged at once), printing a summary of the motion and optionally
//! writing the trajectory as JSON Lines.
//!
//! The dynamics come from AXCFIL process 1 (see `motion::config_from_axcfil`); every block,
//! aux records included, is one kernel move whose tag is its 0-based index in the
//! `ncplc nc plan --format json` output. The kernel starts at rest with every axis at 0.

use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use motion::monitor::Monitor;
use motion::{Config, Kernel, Law, Move};
use partprogram::PlanOptions;

use runtime::machine_facts::Facts;

/// Arguments of `ncplc nc run`.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// Machine and program.
    #[command(flatten)]
    pub common: super::nc::Common,
    /// Path tolerance of corner blending, mm (default 0.01).
    #[arg(long, value_name = "MM")]
    pub tolerance: Option<f64>,
    /// Acceleration law: linear, s or exp.
    #[arg(long, default_value = "linear")]
    pub law: String,
    /// Feed override, percent (0–255).
    #[arg(long = "override", default_value_t = 100, value_name = "PCT")]
    pub feed_override: u16,
    /// Write the trajectory (JSON Lines: a header, then one line per tick) to FILE.
    #[arg(long, value_name = "FILE")]
    pub trajectory: Option<PathBuf>,
    /// Check the software limits (LO1/LOP): `on` refuses a block that leaves them; `off` for
    /// programs written in part coordinates without a work offset.
    #[arg(long, default_value = "on", value_name = "on|off")]
    pub soft_limits: String,
}

/// Runs `ncplc nc run`.
pub fn run(a: &RunArgs) -> ExitCode {
    match run_inner(a) {
        Ok(code) => code,
        Err(msg) => {
            eprintln!("ncplc nc run: {msg}");
            ExitCode::from(2)
        }
    }
}

fn run_inner(a: &RunArgs) -> Result<ExitCode, String> {
    let law: Law = a.law.parse()?;
    if a.feed_override > 255 {
        return Err(format!("--override {} (0…255)", a.feed_override));
    }
    let soft = match a.soft_limits.as_str() {
        "on" => true,
        "off" => false,
        o => return Err(format!("--soft-limits {o} (on or off)")),
    };
    let facts = Facts::load(&a.common.machine).map_err(|e| e.to_string())?;
    let mut cfg =
        motion::config_from_axcfil(&facts.machine.axcfil, 1).map_err(|e| format!("AXCFIL: {e}"))?;
    if let Some(t) = a.tolerance {
        if !(t.is_finite() && t >= 0.0) {
            return Err(format!("--tolerance {t} (a distance ≥ 0 in mm)"));
        }
        cfg.tolerance_mm = t;
    }
    cfg.law = law;
    // Complex speed: R39, R384, R385, R386, R236 from nc/CONSTANTS (the manual's defaults).
    cfg.complex = sim::machine_view::complex_speed(&a.common.machine)?;
    if !soft {
        for ax in &mut cfg.axes {
            ax.soft_min = None;
            ax.soft_max = None;
        }
    }
    let compiled = match super::nc::compile_common(&a.common, false) {
        Ok(c) => c,
        Err(code) => return Ok(code),
    };
    let blocks = match partprogram::plan(&compiled.prog, PlanOptions::default()) {
        Ok(p) => p.blocks,
        Err((_, d)) => {
            super::nc::print_diags(&[d], &compiled.sources, false, a.common.max_errors);
            return Ok(ExitCode::from(1));
        }
    };
    let names = cfg.axis_names();
    // Blocks under contour control (Fanuc G05.1 Q1 / G08 P1, MEFI G23): smoothed within the band.
    let contour = blocks.iter().filter(|c| c.modal.contour).count();
    let start = vec![0.0; names.len()];
    let mut kernel = Kernel::new(cfg.clone(), &start).map_err(|e| e.to_string())?;
    kernel.set_feed_override(a.feed_override);
    let mut monitor = Monitor::new(&cfg, &start, law);
    let mut out = match &a.trajectory {
        Some(p) => {
            let f = std::fs::File::create(p)
                .map_err(|e| format!("cannot create {}: {e}", p.display()))?;
            let mut w = std::io::BufWriter::new(f);
            writeln!(w, "{}", header(&cfg, law, contour)).map_err(|e| e.to_string())?;
            Some((w, p.clone()))
        }
        None => None,
    };
    let write_err = |e: std::io::Error| format!("writing the trajectory: {e}");
    let mut line = String::with_capacity(128);
    let mut next = 0usize;
    let mut ticks: u64 = 0;
    let mut last_block = 0usize;
    // The virtual spindle turns at the S of the block being run (its direction and M05 are not
    // simulated): G33 threads wait for its index and follow its position.
    let (mut spindle_rev, mut spindle_rpm) = (0.0f64, 0.0f64);
    if let Some((w, _)) = out.as_mut() {
        tick_line(&mut line, 0, &start, 0, 0.0);
        w.write_all(line.as_bytes()).map_err(write_err)?;
    }
    loop {
        while next < blocks.len() && kernel.space() > 0 {
            let c = &blocks[next];
            let m = Move::from_canon(next as u64, c, &names).and_then(|m| {
                kernel.set_smoothing(c.modal.contour)?;
                kernel.push(m.clone()).map(|()| m)
            });
            match m {
                Ok(m) => monitor.push(&m),
                Err(e) => {
                    eprintln!("error: {} (N{}): {e}", compiled.name, c.n.unwrap_or(0));
                    return Ok(ExitCode::from(1));
                }
            }
            next += 1;
            // The last block is in: what the smoother holds goes to the queue now (as a part
            // run does when its look-ahead meets the program's end or a block with functions).
            if next == blocks.len()
                && let Err(e) = kernel.end_of_input()
            {
                eprintln!("error: {}: {e}", compiled.name);
                return Ok(ExitCode::from(1));
            }
        }
        if next >= blocks.len() && kernel.is_idle() {
            break;
        }
        spindle_rev += spindle_rpm / 60.0 * cfg.tick_s;
        kernel.set_spindle_position(spindle_rev);
        if let Some(e) = kernel.take_fault() {
            eprintln!("error: {}: {e}", compiled.name);
            return Ok(ExitCode::from(1));
        }
        let t = kernel.tick();
        ticks += 1;
        if let Some(s) = t.tag.and_then(|b| blocks.get(b as usize)).and_then(|c| c.s) {
            spindle_rpm = s.abs();
        }
        monitor.sample(t);
        // At rest after the last block: the last block finished (an aux record's path is its point).
        if let Some(b) = t.tag.or(t.finished.last().copied()) {
            last_block = b as usize;
        }
        if let Some((w, _)) = out.as_mut() {
            tick_line(&mut line, ticks, &t.position, last_block, t.feed_mm_min);
            w.write_all(line.as_bytes()).map_err(write_err)?;
        }
    }
    if let Some((mut w, p)) = out {
        w.flush().map_err(write_err)?;
        eprintln!("trajectory: {} ({} lines)", p.display(), ticks + 2);
    }
    print!(
        "{}",
        summary(
            &compiled.name,
            &cfg,
            law,
            a.feed_override,
            Counts {
                blocks: blocks.len(),
                contour,
                ticks,
            },
            monitor.report()
        )
    );
    Ok(ExitCode::SUCCESS)
}

/// A number rounded to `d` decimals in its shortest form with a decimal point (`200.0`).
fn num(v: f64, scale: f64) -> String {
    let r = (v * scale).round() / scale;
    let r = if r == 0.0 { 0.0 } else { r };
    format!("{r:?}")
}

/// The trajectory header line.
fn header(cfg: &Config, law: Law, contour: usize) -> String {
    let axes: Vec<String> = cfg.axes.iter().map(|a| format!("\"{}\"", a.name)).collect();
    let limits: Vec<String> = cfg
        .axes
        .iter()
        .map(|ax| {
            let (v, a, j) = motion::plan::axis_vaj(ax, false, law, &cfg.acc);
            let j = if j.is_finite() {
                num(j, 1e3)
            } else {
                "null".into()
            };
            format!(
                "\"{}\":{{\"v\":{},\"a\":{},\"j\":{j}}}",
                ax.name,
                num(v, 1e3),
                num(a, 1e3)
            )
        })
        .collect();
    format!(
        "{{\"tick_s\":{},\"axes\":[{}],\"limits\":{{{}}},\"tolerance_mm\":{},\"law\":\"{}\",\"contour\":{}}}",
        num(cfg.tick_s, 1e9),
        axes.join(","),
        limits.join(","),
        num(cfg.tolerance_mm, 1e9),
        law.name(),
        motion::smooth::header_json(cfg.tolerance_mm, contour, &cfg.complex)
    )
}

fn tick_line(line: &mut String, t: u64, p: &[f64], block: usize, feed: f64) {
    use std::fmt::Write as _;
    line.clear();
    let _ = write!(line, "{{\"t\":{t},\"p\":[");
    for (i, x) in p.iter().enumerate() {
        let _ = write!(line, "{}{}", if i > 0 { "," } else { "" }, num(*x, 1e6));
    }
    let _ = writeln!(line, "],\"block\":{block},\"feed\":{}}}", num(feed, 1e3));
}

/// What a run counted, for its summary.
struct Counts {
    /// Canonical blocks planned.
    blocks: usize,
    /// Blocks under contour control.
    contour: usize,
    /// Interpolation ticks of the motion.
    ticks: u64,
}

fn summary(
    name: &str,
    cfg: &Config,
    law: Law,
    ovr: u16,
    counts: Counts,
    r: &motion::monitor::Report,
) -> String {
    let Counts {
        blocks,
        contour,
        ticks,
    } = counts;
    let mut s = format!(
        "{name}: {blocks} blocks, law {}, tolerance {} mm, override {ovr} %\n{}\n",
        law.name(),
        cfg.tolerance_mm,
        motion::smooth::summary_line(cfg.tolerance_mm, contour, &cfg.complex)
    );
    s.push_str(&format!(
        "motion time: {:.3} s ({ticks} ticks of {} ms)\n",
        ticks as f64 * cfg.tick_s,
        num(cfg.tick_s * 1000.0, 1e6)
    ));
    s.push_str(
        "axis  peak v/limit  peak a/limit  peak j/limit  (finite differences of the set points)\n",
    );
    for (i, ax) in cfg.axes.iter().enumerate() {
        let j = match r.j[i] {
            Some(f) => format!("{f:.3}"),
            None => format!("- ({:.0} mm/s³)", r.j_abs[i]),
        };
        s.push_str(&format!(
            "{:<4}  {:>12.3}  {:>12.3}  {:>12}\n",
            ax.name, r.v[i], r.a[i], j
        ));
    }
    s.push_str(&format!(
        "path deviation: max {:.4} mm{}\n",
        r.deviation,
        r.deviation_tag
            .map_or(String::new(), |t| format!(" (block {t})"))
    ));
    s
}
