//! Writes issue 10's benchmark programs as RS274 G-code for LinuxCNC (`<dir>/<name>.ngc`: G64
//! P0.01, a rapid to the start and a 1 s dwell, then the moves) and prints, per program,
//! ncplc's motion time and the lower bound on the mill (each axis 100 mm/s,
//! 1000 mm/s², 1 ms tick, tolerance 0.01 mm). Then the same for issue 22's CAM set
//! ([`motion::cam::set`]), which ncplc runs with tolerance-band smoothing on (as a program
//! starting with `G05.1 Q1` or MEFI `G23` does). Used by `motion/compare/linuxcnc/run.sh`
//! (an argument after the directory keeps only the programs whose name contains it).

use std::fmt::Write;

use motion::{Move, Path, bound::lower_bound, cam, samples};

/// The program as G-code.
fn gcode(moves: &[Move], start: [f64; 3]) -> Result<String, std::fmt::Error> {
    let mut g = String::new();
    writeln!(g, "G21 G90 G17 G64 P0.01")?;
    writeln!(g, "G0 X{:.6} Y{:.6} Z{:.6}", start[0], start[1], start[2])?;
    writeln!(g, "G4 P1")?;
    let mut p = start;
    for m in moves {
        let f = m.feed_mm_min.unwrap_or(0.0);
        let (x, y, z) = (m.end[0], m.end[1], m.end[2]);
        match &m.path {
            Path::Arc { center, cw, .. } => {
                let (i, j) = (center[0] - p[0], center[1] - p[1]);
                let g23 = if *cw { "G2" } else { "G3" };
                writeln!(g, "{g23} X{x:.6} Y{y:.6} Z{z:.6} I{i:.6} J{j:.6} F{f}")?;
            }
            _ => writeln!(g, "G1 X{x:.6} Y{y:.6} Z{z:.6} F{f}")?,
        }
        p = [x, y, z];
    }
    writeln!(g, "M2")?;
    Ok(g)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::args()
        .nth(1)
        .ok_or("usage: linuxcnc_programs <dir> [filter]")?;
    let filter = std::env::args().nth(2).unwrap_or_default();
    for (name, moves) in [
        ("squares", samples::squares()),
        ("circles", samples::circles()),
        ("zigzag", samples::zigzag()),
        ("chord_circle", samples::chord_circle()),
        ("spiral", samples::spiral()),
        ("cam", samples::cam(20)),
    ] {
        if !name.contains(&filter) {
            continue;
        }
        let start = samples::start(name);
        std::fs::write(format!("{dir}/{name}.ngc"), gcode(&moves, start)?)?;
        let t = samples::ticks_to_idle(samples::mill(), &moves, start)? as f64 * 0.001;
        let lb = lower_bound(&samples::mill(), &start, &moves);
        println!("{name} {t:.3} {lb:.4}");
    }
    for p in cam::set() {
        if !p.name.contains(&filter) {
            continue;
        }
        std::fs::write(format!("{dir}/{}.ngc", p.name), gcode(&p.moves, p.start)?)?;
        let t =
            samples::ticks_to_idle_with(samples::mill(), &p.moves, p.start, true)? as f64 * 0.001;
        let lb = lower_bound(&samples::mill(), &p.start, &p.moves);
        println!("{} {t:.3} {lb:.4}", p.name);
    }
    Ok(())
}
