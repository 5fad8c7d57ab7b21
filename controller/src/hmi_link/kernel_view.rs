//! The render thread's half of the kernel-backed Machine page: turns the kernel processes a
//! [`Frame`] carries into the page's status (mode and state names, the current block's source
//! line and codes, the modal codes in effect, DRO, alarms) and draws the tool path: the
//! programmed path from the loaded program's blocks, the actual one sampled from the set point of
//! every frame (≥ 20 per second of a real-time run).

use detmath::Det as _;
use std::collections::BTreeMap;
use std::sync::Arc;

use cnc::Interp;
use hmi::{AxisStatus, MachineStatus, PathPiece, Toolpath};
use partprogram::canon::Canon;

use super::CncView;
use super::frame::Frame;
use super::image_cnc::ImageCnc;
use super::kernel_cnc::{block_codes, mode_name, view_of};
use super::modal::ModalTracker;
use plot::toolpath::{View, pieces};

/// Most sampled set points kept per process; when full, every second one is dropped and the
/// sampling distance doubles (the path stays drawn end to end at half the detail).
const MAX_SAMPLES: usize = 4000;
/// The first sampling distance in mm.
const FIRST_STEP_MM: f64 = 0.01;

/// A partprogram's text, for the current block's source line.
#[derive(Debug, Clone)]
pub(super) struct Source {
    lines: Vec<String>,
    by_n: BTreeMap<u32, usize>,
}

impl Source {
    pub(super) fn new(text: &str) -> Source {
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
pub(super) struct PathState {
    pub(super) process: u8,
    pub(super) view: (char, char),
    pub(super) index: (usize, usize),
    /// The drawn program: load number, name and length.
    pub(super) loaded: (u64, String, usize),
    pub(super) path: Toolpath,
    pub(super) step: f64,
}

impl PathState {
    /// An empty path of `process` drawn in `view` from set points `index`.
    pub(super) fn new(process: u8, view: (char, char), index: (usize, usize)) -> PathState {
        PathState {
            process,
            view,
            index,
            loaded: (0, String::new(), 0),
            path: Toolpath {
                process,
                axes: [view.0.to_string(), view.1.to_string()],
                ..Toolpath::default()
            },
            step: FIRST_STEP_MM,
        }
    }

    /// Follows the program load `id` (`name`, `prog`) and samples the set points `sp`.
    fn update(&mut self, id: u64, name: &str, prog: &[Canon], sp: [f64; 2], next_id: &mut u64) {
        if self.loaded.0 != id {
            let view = view_of(&[self.view.0, self.view.1]).unwrap_or(View::Xy);
            let drawn = pieces(prog, view)
                .into_iter()
                .map(|pc| PathPiece {
                    rapid: pc.rapid,
                    points: pc.points.into_iter().map(|(h, v)| [h, v]).collect(),
                })
                .collect();
            if self.loaded.1 != name || self.loaded.2 != prog.len() {
                self.path.actual.clear();
                self.step = FIRST_STEP_MM;
            }
            self.path.program = name.to_string();
            self.path.programmed = Arc::new(drawn);
            self.path.id = *next_id;
            *next_id += 1;
            self.loaded = (id, name.to_string(), prog.len());
        }
        sample(&mut self.path.actual, &mut self.step, sp);
    }
}

/// The render thread's half of [`super::kernel_cnc::KernelCnc`].
pub struct KernelView {
    pub(super) image: ImageCnc,
    pub(super) sources: BTreeMap<String, Source>,
    pub(super) paths: Vec<PathState>,
    pub(super) modal: Vec<ModalTracker>,
    pub(super) mdi_seen: u64,
    pub(super) next_id: u64,
}

impl KernelView {
    fn source_line(&self, program: &str, block: Option<&Canon>) -> Option<String> {
        let b = block?;
        if b.unit.is_some() {
            return None;
        }
        Some(self.sources.get(program)?.line(b.n)?.to_string())
    }
}

impl CncView for KernelView {
    fn status(&mut self, frame: &Frame) -> MachineStatus {
        if frame.mdi.0 != self.mdi_seen {
            self.mdi_seen = frame.mdi.0;
            self.sources.insert("MDI".into(), Source::new(&frame.mdi.1));
        }
        let from_image = self.image.status(&frame.image);
        if self.modal.len() < frame.kernel.len() {
            self.modal
                .resize(frame.kernel.len(), ModalTracker::default());
        }
        let mut processes = Vec::with_capacity(frame.kernel.len());
        for (k, raw) in frame.kernel.iter().enumerate() {
            let st = &raw.status;
            let (id, prog) = (raw.program.0, &raw.program.1[..]);
            let block = prog.get(st.block);
            let mut ps = from_image
                .processes
                .iter()
                .find(|q| q.process == st.process)
                .cloned()
                .unwrap_or_default();
            let state = match st.interp {
                Interp::Running if raw.held => "held",
                Interp::Running => "running",
                Interp::Paused => "paused",
                Interp::Idle => "idle",
            };
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
                    limit: a.limit.name().to_string(),
                    limit_mm: a.limit_mm,
                    largest: a.largest,
                })
                .collect();
            ps.spindle_speed = Some(st.spindle_rpm);
            ps.path_speed = Some(st.feed_mm_min);
            ps.active_codes = block.map(block_codes).unwrap_or_default();
            ps.modal_codes = self.modal[k].at(id, prog, st.block).codes();
            // The kernel's active alarms; the render thread keeps the list with acknowledge.
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
                m: raw.handshakes[0],
                s: raw.handshakes[1],
                t: raw.handshakes[2],
                timeouts: 0,
            });
            if let Some(path) = self.paths.iter_mut().find(|t| t.process == st.process) {
                let at = |i: usize| st.axes.get(i).map_or(0.0, |a| a.command);
                let sp = [at(path.index.0), at(path.index.1)];
                path.update(id, &st.program, prog, sp, &mut self.next_id);
                ps.toolpath = Some(path.path.id);
            }
            ps.commands = ["start", "hold", "reset", "mode", "mdi", "ack"]
                .map(String::from)
                .to_vec();
            processes.push(ps);
        }
        MachineStatus { processes }
    }

    fn toolpaths(&self) -> Vec<Toolpath> {
        self.paths.iter().map(|p| p.path.clone()).collect()
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
        (a[0] - b[0]).dhypot(a[1] - b[1]) >= *step
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
