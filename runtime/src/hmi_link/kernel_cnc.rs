//! The Machine page driven by the CNC kernel (`ncplc run --hmi` with `--program`/`--mdi`):
//! operator commands go to [`cnc::Cnc`]'s operator channel (the one the part run uses), refused
//! ones answer with the kernel's reason; the status is the kernel's (mode, state, block and its
//! source line, DRO, path speed, spindle, the current block's codes, alarms) plus the overrides
//! and the handshake counts the image shows; the tool path is the plan's, with the set points
//! sampled after every tick.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use cnc::{Interp, Mode};
use hmi::{AxisStatus, Cnc, Command, MachineStatus, PathPiece, Toolpath};
use partprogram::canon::{Canon, Kind, num};

use super::image_cnc::ImageCnc;
use crate::plot::toolpath::{View, pieces};

/// Most sampled set points kept per process; when full, every second one is dropped and the
/// sampling distance doubles (the path stays drawn end to end at half the detail).
const MAX_SAMPLES: usize = 4000;
/// The first sampling distance in mm.
const FIRST_STEP_MM: f64 = 0.01;

/// A partprogram's text, for the current block's source line.
#[derive(Debug, Clone)]
struct Source {
    lines: Vec<String>,
    by_n: BTreeMap<u32, usize>,
}

impl Source {
    fn new(text: &str) -> Source {
        let lines: Vec<String> = text.lines().map(|l| l.trim_end().to_string()).collect();
        let mut by_n = BTreeMap::new();
        for (i, l) in lines.iter().enumerate() {
            let t = l.trim_start();
            let t = t.strip_prefix('/').unwrap_or(t).trim_start();
            let Some(rest) = t.strip_prefix(['N', 'n']) else {
                continue;
            };
            let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
            if let Ok(n) = digits.parse::<u32>() {
                by_n.entry(n).or_insert(i);
            }
        }
        Source { lines, by_n }
    }

    /// The source line of a block numbered `n` (the first line with that N), or the only line
    /// of a one-line text (an MDI line without N).
    fn line(&self, n: Option<u32>) -> Option<&str> {
        match n {
            Some(n) => self.by_n.get(&n).map(|&i| self.lines[i].as_str()),
            None => {
                let mut it = self.lines.iter().filter(|l| !l.trim().is_empty());
                match (it.next(), it.next()) {
                    (Some(only), None) => Some(only.as_str()),
                    _ => None,
                }
            }
        }
    }
}

/// The tool path of one process as it is being drawn.
#[derive(Debug, Clone)]
struct PathState {
    process: u8,
    view: (char, char),
    index: (usize, usize),
    loaded: (String, usize, usize),
    path: Toolpath,
    step: f64,
}

/// The kernel-backed [`Cnc`].
pub struct KernelCnc {
    cnc: Arc<Mutex<cnc::Cnc>>,
    image: ImageCnc,
    sources: BTreeMap<String, Source>,
    paths: Vec<PathState>,
    next_id: u64,
}

/// The view of a process with axes `names`: XY on a mill, ZX on a lathe, else YZ.
fn view_of(names: &[char]) -> Option<View> {
    let has = |c| names.contains(&c);
    if has('X') && has('Y') {
        Some(View::Xy)
    } else if has('X') && has('Z') {
        Some(View::Zx)
    } else if has('Y') && has('Z') {
        Some(View::Yz)
    } else {
        None
    }
}

/// The codes of a block: its motion G code, F, S, T and M functions.
pub fn block_codes(b: &Canon) -> Vec<String> {
    let mut v = Vec::new();
    let g = match b.kind {
        Kind::Rapid => Some("G00"),
        Kind::Linear if b.thread => Some("G33"),
        Kind::Linear => Some("G01"),
        Kind::ArcCw => Some("G02"),
        Kind::ArcCcw => Some("G03"),
        Kind::Dwell => Some("G04"),
        Kind::Aux => None,
    };
    v.extend(g.map(String::from));
    if let Some(f) = b.feed {
        v.push(format!("F{}", num(f)));
    }
    if let Some(s) = b.s {
        v.push(format!("S{}", num(s)));
    }
    if let Some(t) = b.t {
        v.push(format!("T{t}"));
    }
    v.extend(b.m.iter().map(|m| format!("M{:02}", m.m)));
    v
}

/// The operator's name of a mode (`AUTO`, …, as the status shows it).
fn mode_name(m: Mode) -> String {
    format!("{m:?}").to_uppercase()
}

/// The mode named `name` (case-insensitive; `JOG` is MANU).
pub fn parse_mode(name: &str) -> Result<Mode, String> {
    let up = name.trim().to_uppercase();
    if up == "JOG" {
        return Ok(Mode::Manu);
    }
    Mode::ALL
        .iter()
        .copied()
        .find(|m| mode_name(*m) == up)
        .ok_or_else(|| {
            format!("unknown mode \"{name}\" (expected AUTO, STEP, MDI, MANU, MANJ, HOME or IDLE)")
        })
}

/// The partprogram texts of a part run by the names the kernel loads them under: `--program`,
/// `sim.toml [cnc] programs`, and the `--mdi` blocks (`MDI`). Unreadable files are left out (the
/// part run has read them already).
pub fn sources(
    args: &crate::cli::run::Args,
    machine: &crate::machine::Machine,
) -> Vec<(String, String)> {
    let mut names: Vec<std::path::PathBuf> = args.program.iter().cloned().collect();
    names.extend(
        machine
            .script
            .cnc
            .programs
            .values()
            .map(std::path::PathBuf::from),
    );
    let mut v: Vec<(String, String)> = names
        .iter()
        .filter_map(|p| {
            let path = crate::sim::part::program_path(&machine.dir, p);
            let bytes = std::fs::read(path).ok()?;
            Some((
                p.display().to_string(),
                String::from_utf8_lossy(&bytes).into_owned(),
            ))
        })
        .collect();
    if !args.mdi.is_empty() {
        v.push(("MDI".into(), args.mdi.join("\n")));
    }
    v
}

impl KernelCnc {
    /// Over the kernel `cnc`; `image` gives the overrides and handshake counts; `sources` are
    /// the partprograms' texts by the names the kernel loads them under.
    pub fn new(cnc: Arc<Mutex<cnc::Cnc>>, image: ImageCnc, sources: &[(String, String)]) -> Self {
        let mut k = KernelCnc {
            cnc,
            image,
            sources: BTreeMap::new(),
            paths: Vec::new(),
            next_id: 1,
        };
        for (name, text) in sources {
            k.sources.insert(name.clone(), Source::new(text));
        }
        let paths: Vec<PathState> = k
            .lock()
            .processes()
            .iter()
            .filter_map(|p| {
                let names = p.axis_names();
                let view = view_of(&names)?.axes();
                let index = (
                    p.axis_index(view.0).unwrap_or(0),
                    p.axis_index(view.1).unwrap_or(0),
                );
                Some(PathState {
                    process: p.number(),
                    view,
                    index,
                    loaded: (String::new(), 0, 0),
                    path: Toolpath {
                        process: p.number(),
                        axes: [view.0.to_string(), view.1.to_string()],
                        ..Toolpath::default()
                    },
                    step: FIRST_STEP_MM,
                })
            })
            .collect();
        k.paths = paths;
        k
    }

    fn lock(&self) -> MutexGuard<'_, cnc::Cnc> {
        self.cnc.lock().unwrap_or_else(PoisonError::into_inner)
    }

    fn source_line(&self, program: &str, block: Option<&Canon>) -> Option<String> {
        let b = block?;
        if b.unit.is_some() {
            return None;
        }
        Some(self.sources.get(program)?.line(b.n)?.to_string())
    }
}

impl Cnc for KernelCnc {
    fn status(&self, image: &[u8]) -> MachineStatus {
        let from_image = self.image.status(image);
        let c = self.lock();
        let processes = c
            .processes()
            .iter()
            .map(|p| {
                let st = p.status();
                let block = p.program().get(st.block);
                let mut ps = from_image
                    .processes
                    .iter()
                    .find(|q| q.process == st.process)
                    .cloned()
                    .unwrap_or_default();
                let state = match st.interp {
                    Interp::Running if p.held() => "held",
                    Interp::Running => "running",
                    Interp::Paused => "paused",
                    Interp::Idle => "idle",
                };
                let k = p.counters();
                ps.process = st.process;
                ps.mode = Some(mode_name(st.mode));
                ps.state = Some(state.into());
                ps.on = Some(st.on);
                ps.homed = Some(st.homed);
                ps.program = (!st.program.is_empty()).then(|| st.program.clone());
                ps.block = block.and_then(|b| b.n).map(u64::from);
                ps.block_index = block.map(|_| st.block as u64 + 1);
                ps.block_source = self.source_line(&st.program, block);
                ps.axes = st
                    .axes
                    .iter()
                    .map(|a| AxisStatus {
                        name: a.name.to_string(),
                        command: a.command,
                        actual: a.actual,
                        following_error: a.following_error,
                    })
                    .collect();
                ps.spindle_speed = Some(st.spindle_rpm);
                ps.path_speed = Some(st.feed_mm_min);
                ps.active_codes = block.map(block_codes).unwrap_or_default();
                // The kernel's active alarms; the link keeps the list with acknowledge.
                ps.alarms = st
                    .alarms
                    .iter()
                    .map(|a| hmi::AlarmEntry {
                        text: a.clone(),
                        active: true,
                        acknowledged: false,
                        tick: 0,
                    })
                    .collect();
                ps.handshakes = Some(hmi::HandshakeCounts {
                    m: k.handshakes[0],
                    s: k.handshakes[1],
                    t: k.handshakes[2],
                    timeouts: 0,
                });
                ps.toolpath = self
                    .paths
                    .iter()
                    .find(|t| t.process == st.process)
                    .map(|t| t.path.id);
                ps.commands = ["start", "hold", "reset", "mode", "mdi", "ack"]
                    .map(String::from)
                    .to_vec();
                ps
            })
            .collect();
        MachineStatus { processes }
    }

    fn command(&mut self, process: u8, command: &Command) -> Result<(), String> {
        let mut c = self.lock();
        let r = match command {
            Command::Start => c.start(process),
            Command::Hold => c.hold(process),
            Command::Reset => {
                c.process_mut(process).map_err(|e| e.to_string())?;
                c.reset();
                Ok(())
            }
            Command::Mode { mode } => c.mode(process, parse_mode(mode)?),
            Command::Mdi { line } => {
                let r = c.mdi(process, line);
                if r.is_ok() {
                    drop(c);
                    self.sources.insert("MDI".into(), Source::new(line));
                }
                r
            }
            Command::Ack => Ok(()),
        };
        r.map_err(|e| e.to_string())
    }

    fn after_tick(&mut self, _image: &[u8]) {
        let cnc = Arc::clone(&self.cnc);
        let c = cnc.lock().unwrap_or_else(PoisonError::into_inner);
        for ps in &mut self.paths {
            let Some(p) = c.processes().iter().find(|p| p.number() == ps.process) else {
                continue;
            };
            let prog = p.program();
            let same = ps.loaded.0 == p.program_name()
                && ps.loaded.1 == prog.len()
                && ps.loaded.2 == prog.as_ptr() as usize;
            if !same {
                let loaded = (
                    p.program_name().to_string(),
                    prog.len(),
                    prog.as_ptr() as usize,
                );
                let view = view_of(&[ps.view.0, ps.view.1]).unwrap_or(View::Xy);
                let drawn = pieces(prog, view)
                    .into_iter()
                    .map(|pc| PathPiece {
                        rapid: pc.rapid,
                        points: pc.points.into_iter().map(|(h, v)| [h, v]).collect(),
                    })
                    .collect();
                if loaded.0 != ps.loaded.0 || loaded.1 != ps.loaded.1 {
                    ps.path.actual.clear();
                    ps.step = FIRST_STEP_MM;
                }
                ps.path.program = loaded.0.clone();
                ps.path.programmed = Arc::new(drawn);
                ps.path.id = self.next_id;
                self.next_id += 1;
                ps.loaded = loaded;
            }
            let sp = p.set_points();
            let at = [
                sp.get(ps.index.0).copied().unwrap_or(0.0),
                sp.get(ps.index.1).copied().unwrap_or(0.0),
            ];
            sample(&mut ps.path.actual, &mut ps.step, at);
        }
    }

    fn toolpaths(&self) -> Vec<Toolpath> {
        self.paths.iter().map(|p| p.path.clone()).collect()
    }

    fn owns_alarm(&self, text: &str) -> bool {
        text.starts_with("cnc: ")
    }
}

/// Records the set point `at`: the last point is always the current one, the ones before it are
/// at least `step` apart. At most [`MAX_SAMPLES`] points: when full, every second one goes and
/// `step` doubles.
fn sample(points: &mut Vec<[f64; 2]>, step: &mut f64, at: [f64; 2]) {
    let n = points.len();
    if points.last() == Some(&at) {
        return;
    }
    let keep_last = n < 2 || {
        let (a, b) = (points[n - 2], points[n - 1]);
        (a[0] - b[0]).hypot(a[1] - b[1]) >= *step
    };
    if !keep_last {
        points[n - 1] = at;
        return;
    }
    if n >= MAX_SAMPLES {
        let mut i = 0;
        points.retain(|_| {
            i += 1;
            i % 2 == 1
        });
        *step *= 2.0;
    }
    points.push(at);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn block_source_lines_are_found_by_their_n_word() {
        let s = Source::new("%1 \"part\"\nN10 G54 S1200 M03\n/N20 M08\n  N30 G00 X-44\nN300 X1\n");
        assert_eq!(s.line(Some(20)), Some("/N20 M08"));
        assert_eq!(s.line(Some(30)), Some("  N30 G00 X-44"));
        assert_eq!(s.line(Some(3)), None);
        assert_eq!(s.line(None), None);
        assert_eq!(Source::new("G0 X10\n").line(None), Some("G0 X10"));
    }

    #[test]
    fn modes_are_named_as_the_status_shows_them() {
        assert_eq!(parse_mode("auto"), Ok(Mode::Auto));
        assert_eq!(parse_mode("MANJ"), Ok(Mode::Manj));
        assert_eq!(parse_mode("jog"), Ok(Mode::Manu));
        assert_eq!(
            parse_mode("fast"),
            Err(
                "unknown mode \"fast\" (expected AUTO, STEP, MDI, MANU, MANJ, HOME or IDLE)".into()
            )
        );
    }

    #[test]
    fn sampling_keeps_points_a_step_apart_and_halves_when_full() {
        let mut pts = Vec::new();
        let mut step = 1.0;
        for i in 0..10 {
            sample(&mut pts, &mut step, [f64::from(i) * 0.5, 0.0]);
        }
        // Every 0.5 mm: the points kept are 1 mm apart, and the last is the current one.
        assert_eq!(
            pts,
            vec![
                [0.0, 0.0],
                [1.0, 0.0],
                [2.0, 0.0],
                [3.0, 0.0],
                [4.0, 0.0],
                [4.5, 0.0]
            ]
        );
        let mut pts: Vec<[f64; 2]> = (0..MAX_SAMPLES).map(|i| [i as f64, 0.0]).collect();
        let mut step = 1.0;
        sample(&mut pts, &mut step, [MAX_SAMPLES as f64, 0.0]);
        assert_eq!(pts.len(), MAX_SAMPLES / 2 + 1);
        assert_eq!(pts[1], [2.0, 0.0]);
        assert_eq!(step, 2.0);
    }
}
