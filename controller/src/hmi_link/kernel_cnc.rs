//! The Machine page driven by the CNC kernel (`ncplc run --hmi` with `--program`/`--mdi`):
//! operator commands go to [`cnc::Cnc`]'s operator channel (the one the part run uses), refused
//! ones answer with the kernel's reason. The scan thread's half ([`KernelScan`]) copies each
//! process's status into the frame in place ([`cnc::Process::status_into`]) and shares a
//! program's blocks once per load; the render thread's half
//! ([`super::kernel_view::KernelView`]) names, looks up source lines, folds the modal codes and
//! draws the tool path.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use cnc::Mode;
use hmi::Command;
use partprogram::canon::{Canon, Kind, num};

use super::forward::{MdiPlanner, PlannedMdi};
use super::frame::{Frame, RawProcess};
use super::image_cnc::ImageCnc;
use super::kernel_view::{KernelView, PathState, Source};
use super::{Cnc, CncScan, CncView};
use plot::toolpath::View;

/// The view of a process with axes `names`: XY on a mill, ZX on a lathe, else YZ.
pub(super) fn view_of(names: &[char]) -> Option<View> {
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
pub(super) fn mode_name(m: Mode) -> String {
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
    args: &crate::part_run::PartSpec,
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
            let path = sim::part::program_path(&machine.dir, p);
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

/// The kernel-backed Machine page, before it is split between the scan and the render thread.
pub struct KernelCnc {
    scan: KernelScan,
    view: KernelView,
}

/// The scan thread's half: commands and the copy into the frame.
pub struct KernelScan {
    cnc: Arc<Mutex<cnc::Cnc>>,
    /// Per process: the loaded program.
    loaded: Vec<Loaded>,
    next_load: u64,
    mdi: (u64, String),
    /// MDI compiles on the request thread ([`super::forward`]).
    planned: Arc<AtomicU64>,
}

/// A process's loaded program as the scan last saw it: (name, length, address), its load number
/// and its blocks.
type Loaded = ((String, usize, usize), u64, Arc<[Canon]>);

impl KernelCnc {
    /// Over the kernel `cnc`; `image` gives the overrides and handshake counts; `sources` are
    /// the partprograms' texts by the names the kernel loads them under.
    pub fn new(cnc: Arc<Mutex<cnc::Cnc>>, image: ImageCnc, sources: &[(String, String)]) -> Self {
        let paths: Vec<PathState> = lock(&cnc)
            .processes()
            .iter()
            .filter_map(|p| {
                let names = p.axis_names();
                let view = view_of(&names)?.axes();
                let index = (
                    p.axis_index(view.0).unwrap_or(0),
                    p.axis_index(view.1).unwrap_or(0),
                );
                Some(PathState::new(p.number(), view, index))
            })
            .collect();
        KernelCnc {
            scan: KernelScan {
                cnc,
                loaded: Vec::new(),
                next_load: 1,
                mdi: (0, String::new()),
                planned: Arc::new(AtomicU64::new(0)),
            },
            view: KernelView {
                image,
                sources: sources
                    .iter()
                    .map(|(name, text)| (name.clone(), Source::new(text)))
                    .collect::<BTreeMap<_, _>>(),
                paths,
                modal: Vec::new(),
                mdi_seen: 0,
                next_id: 1,
            },
        }
    }
}

/// Gives operator command `command` for `process` to the kernel (the HMI's and a replay's way in),
/// or says why the kernel refused it.
pub fn apply_command(c: &mut cnc::Cnc, process: u8, command: &Command) -> Result<(), String> {
    let r = match command {
        Command::Start => c.start(process),
        Command::Hold => c.hold(process),
        Command::Reset => {
            c.process_mut(process).map_err(|e| e.to_string())?;
            c.reset();
            Ok(())
        }
        Command::Mode { mode } => c.mode(process, parse_mode(mode)?),
        Command::Mdi { line } => c.mdi(process, line),
        Command::Ack => Ok(()),
    };
    r.map_err(|e| e.to_string())
}

fn lock(cnc: &Mutex<cnc::Cnc>) -> MutexGuard<'_, cnc::Cnc> {
    cnc.lock().unwrap_or_else(PoisonError::into_inner)
}

impl Cnc for KernelCnc {
    fn split(self: Box<Self>) -> (Box<dyn CncScan>, Box<dyn CncView>) {
        let KernelCnc { scan, view } = *self;
        (Box::new(scan), Box::new(view))
    }

    fn mdi_planner(&self) -> Option<MdiPlanner> {
        Some(MdiPlanner::new(
            Arc::clone(&self.scan.cnc),
            Arc::clone(&self.scan.planned),
        ))
    }
}

impl CncScan for KernelScan {
    fn command(&mut self, process: u8, command: &Command) -> Result<(), String> {
        self.command_planned(process, command, None)
    }

    fn command_planned(
        &mut self,
        process: u8,
        command: &Command,
        planned: Option<PlannedMdi>,
    ) -> Result<(), String> {
        {
            let mut c = lock(&self.cnc);
            match (command, planned) {
                (Command::Mdi { line }, Some(p)) => c
                    .mdi_planned(process, line, &p.at, p.blocks)
                    .map_err(|e| e.to_string())?,
                _ => apply_command(&mut c, process, command)?,
            }
        }
        if let Command::Mdi { line } = command {
            self.mdi.0 += 1;
            self.mdi.1.clone_from(line);
        }
        Ok(())
    }

    fn capture(&mut self, out: &mut Frame) {
        let c = lock(&self.cnc);
        out.mdi_compiles = Some((self.planned.load(Ordering::Relaxed), c.mdi_compiles()));
        let procs = c.processes();
        out.kernel.truncate(procs.len());
        for (k, p) in procs.iter().enumerate() {
            let prog = p.program();
            let key = (p.program_name(), prog.len(), prog.as_ptr() as usize);
            let same = self
                .loaded
                .get(k)
                .is_some_and(|(l, _, _)| l.0 == key.0 && l.1 == key.1 && l.2 == key.2);
            if !same {
                // A new program: its blocks are copied once, here, for the render thread.
                let entry = (
                    (key.0.to_string(), key.1, key.2),
                    self.next_load,
                    Arc::from(prog),
                );
                self.next_load += 1;
                match self.loaded.get_mut(k) {
                    Some(slot) => *slot = entry,
                    None => self.loaded.push(entry),
                }
            }
            let (_, id, blocks) = &self.loaded[k];
            let held = p.held();
            let handshakes = p.counters().handshakes;
            match out.kernel.get_mut(k) {
                Some(raw) => {
                    p.status_into(&mut raw.status);
                    raw.held = held;
                    raw.handshakes = handshakes;
                    if raw.program.0 != *id {
                        raw.program = (*id, Arc::clone(blocks));
                    }
                }
                None => out.kernel.push(RawProcess {
                    status: p.status(),
                    held,
                    handshakes,
                    program: (*id, Arc::clone(blocks)),
                }),
            }
        }
        if out.mdi.0 != self.mdi.0 {
            out.mdi.0 = self.mdi.0;
            out.mdi.1.clone_from(&self.mdi.1);
        }
    }

    fn owns_alarm(&self, text: &str) -> bool {
        text.starts_with("cnc: ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
