//! The CNC kernel: one [`Process`] per AXCFIL process with its interpolator, M/S/T handshake
//! channels, mode and state, the block executor that runs canonical blocks through the PLC, and
//! the simulated machine around it ([`plant`]).
//!
//! [`Cnc::step`] is called once per logic tick, after the scan has published: it reads the
//! PLC→CNC signals of the published outputs, advances every process (process 1 first) by the
//! interpolation ticks that fit the logic tick, and writes the CNC→PLC signals the next scan
//! reads. Machine-wide first: ESTOP (active low; read from the second tick on, when the logic has
//! published once) switches every process off with an alarm; a reset pulses RESET for one tick.
//!
//! Read in this order: [`state`] (the rule table), [`signals`], [`config`], [`process`],
//! [`exec`], [`spindle`] (G96 and gear ranges), [`alt_feed`] (QCKFD), [`correction`] (the
//! tool-correction request), [`zones`] (the active soft limits), [`limit_switch`] (MFC), [`manual`], [`handwheel`],
//! [`plant`], [`status`], [`interp`] (the interpolator as the kernel sees it).

pub mod alt_feed;
pub mod bus;
pub mod config;
pub mod correction;
pub mod exec;
pub mod following;
pub mod handshake;
pub mod handwheel;
pub mod homing;
pub mod interp;
pub mod limit_switch;
pub mod manual;
pub mod motion_link;
pub mod plant;
pub mod process;
pub mod servo;
pub mod signals;
pub mod spindle;
pub mod state;
pub mod status;
pub mod thread_wait;
pub mod written;
pub mod zones;

use std::sync::Arc;

use packets::Signal;
use partprogram::Canon;

pub use config::ProcessConfig;
pub use process::{Alarm, Blocks, Counters, Process, Timing};
pub use signals::{MachineSignals, ProcessSignals};
pub use state::{Command, Interp, Mode, Reject};
pub use status::ProcessStatus;

/// The kernel's version, named in the header of a part-run trace.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// Turns MDI text into canonical blocks for a process (the machine's partprogram compiler).
pub type MdiCompiler = Box<dyn Fn(u8, &str) -> Result<Vec<Canon>, String> + Send>;

/// Turns MDI text into canonical blocks planned from the process's current set points (axis
/// letter and position), so that MDI moves start where the axes stand. Shared, so that an HMI's
/// request thread can compile beside the scan ([`Cnc::mdi_compiler_at`], [`Cnc::mdi_planned`]).
pub type MdiCompilerAt =
    Arc<dyn Fn(u8, &str, &[(char, f64)]) -> Result<Vec<Canon>, String> + Send + Sync>;

/// The kernel: every process of the machine.
pub struct Cnc {
    processes: Vec<Process>,
    machine: MachineSignals,
    mdi: Option<MdiCompiler>,
    mdi_at: Option<MdiCompilerAt>,
    mdi_compiles: u64,
    plc_halted: bool,
}

/// Why an operator command could not be given.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CommandError {
    /// No such process.
    #[error("no process {0}")]
    NoProcess(u8),
    /// The state refuses it.
    #[error("process {0}: {1}")]
    Rejected(u8, Reject),
    /// MDI text that does not compile, or no compiler.
    #[error("MDI: {0}")]
    Mdi(String),
}

impl Cnc {
    /// A kernel over `processes` (process 1 first) with the machine-wide signals.
    pub fn new(processes: Vec<Process>, machine: MachineSignals) -> Cnc {
        Cnc {
            processes,
            machine,
            mdi: None,
            mdi_at: None,
            mdi_compiles: 0,
            plc_halted: false,
        }
    }

    /// The PLC logic stopped (the runtime tripped on scan overruns): nothing answers the
    /// handshakes and ESTOP can no longer be trusted, so every process takes the emergency stop,
    /// with an alarm that names the cause, and stays off for the rest of the run.
    pub fn plc_halted(&mut self) {
        if std::mem::replace(&mut self.plc_halted, true) {
            return;
        }
        for p in &mut self.processes {
            p.raise("the PLC logic halted (scan overruns)".into(), true);
        }
    }

    /// Sets the compiler of MDI text.
    pub fn set_mdi_compiler(&mut self, f: MdiCompiler) {
        self.mdi = Some(f);
    }

    /// One logic tick: `out` are the PLC's last published outputs, `image` the packets the next
    /// scan reads.
    pub fn step(&mut self, tick: u64, out: &[u8], image: &mut [u8]) {
        let estop_ok =
            !self.plc_halted && tick > 0 && self.machine.estop.is_none_or(|s| s.read(out) == 1);
        let mut reset = false;
        for p in &mut self.processes {
            p.set_power(estop_ok);
            p.step(tick, out, image);
            reset |= std::mem::take(&mut p.reset_pulse);
        }
        if let Some(r) = self.machine.reset {
            r.write(image, u8::from(reset));
        }
    }

    /// The processes, process 1 first.
    pub fn processes(&self) -> &[Process] {
        &self.processes
    }

    /// Process `n` for changes.
    pub fn process_mut(&mut self, n: u8) -> Result<&mut Process, CommandError> {
        self.processes
            .iter_mut()
            .find(|p| p.number() == n)
            .ok_or(CommandError::NoProcess(n))
    }

    fn check(&mut self, n: u8, c: Command) -> Result<&mut Process, CommandError> {
        let p = self.process_mut(n)?;
        state::decide(&p.state(), c).map_err(|r| CommandError::Rejected(n, r))?;
        Ok(p)
    }

    /// Sets the compiler of MDI text that plans from the current position (preferred over
    /// [`Cnc::set_mdi_compiler`]'s).
    pub fn set_mdi_compiler_at(&mut self, f: MdiCompilerAt) {
        self.mdi_at = Some(f);
    }

    /// Operator: cycle start of process `n`.
    pub fn start(&mut self, n: u8) -> Result<(), CommandError> {
        self.check(n, Command::Start)?.command(Command::Start);
        Ok(())
    }

    /// Operator: feed hold of process `n` (START resumes).
    pub fn hold(&mut self, n: u8) -> Result<(), CommandError> {
        self.check(n, Command::Hold)?.command(Command::Hold);
        Ok(())
    }

    /// Operator: reset of every process.
    pub fn reset(&mut self) {
        for p in &mut self.processes {
            p.command(Command::Reset);
        }
    }

    /// Operator: selects mode `m` of process `n`.
    pub fn mode(&mut self, n: u8, m: Mode) -> Result<(), CommandError> {
        self.check(n, Command::SetMode(m))?
            .command(Command::SetMode(m));
        Ok(())
    }

    /// The compiler of MDI text planned from a position, shared (None: not set).
    pub fn mdi_compiler_at(&self) -> Option<MdiCompilerAt> {
        self.mdi_at.clone()
    }

    /// Where an MDI program of process `n` starts: each axis letter with its current set point.
    pub fn mdi_start(&self, n: u8) -> Result<Vec<(char, f64)>, CommandError> {
        let p = self
            .processes
            .iter()
            .find(|p| p.number() == n)
            .ok_or(CommandError::NoProcess(n))?;
        Ok(p.cfg
            .axes
            .iter()
            .map(|a| a.name)
            .zip(p.set_points().iter().copied())
            .collect())
    }

    /// How many times this kernel compiled MDI text itself ([`Cnc::mdi`], and
    /// [`Cnc::mdi_planned`] when the axes had moved): the compiles that ran on the caller's
    /// thread, the scan's in a live run.
    pub fn mdi_compiles(&self) -> u64 {
        self.mdi_compiles
    }

    /// Operator: runs MDI text in process `n` (MDI mode, interpreter idle).
    pub fn mdi(&mut self, n: u8, text: &str) -> Result<(), CommandError> {
        let blocks = match (&self.mdi_at, &self.mdi) {
            (Some(f), _) => {
                let at = self.mdi_start(n)?;
                self.mdi_compiles += 1;
                f(n, text, &at).map_err(CommandError::Mdi)?
            }
            (None, Some(f)) => {
                self.mdi_compiles += 1;
                f(n, text).map_err(CommandError::Mdi)?
            }
            (None, None) => return Err(CommandError::Mdi("no MDI compiler".into())),
        };
        self.run_mdi(n, blocks)
    }

    /// Operator: runs MDI text `text` of process `n` whose `blocks` were compiled elsewhere
    /// (with [`Cnc::mdi_compiler_at`]) from the start position `at`. When the set points are still
    /// bit for bit `at`, the blocks are loaded as they are; else the text is compiled here, as
    /// [`Cnc::mdi`] does (the axes moved between the compile and this call: rare, MDI needs an
    /// idle interpreter). Either way the result is the one [`Cnc::mdi`] gives now, so a replay
    /// that calls [`Cnc::mdi`] at the same tick loads the same blocks.
    pub fn mdi_planned(
        &mut self,
        n: u8,
        text: &str,
        at: &[(char, f64)],
        blocks: Vec<Canon>,
    ) -> Result<(), CommandError> {
        let now = self.mdi_start(n)?;
        let same = self.mdi_at.is_some()
            && now.len() == at.len()
            && now
                .iter()
                .zip(at)
                .all(|(a, b)| a.0 == b.0 && a.1.to_bits() == b.1.to_bits());
        if same {
            self.run_mdi(n, blocks)
        } else {
            self.mdi(n, text)
        }
    }

    fn run_mdi(&mut self, n: u8, blocks: Vec<Canon>) -> Result<(), CommandError> {
        let p = self.check(n, Command::Mdi)?;
        p.load("MDI", blocks)
            .map_err(|r| CommandError::Rejected(n, r))?;
        p.command(Command::Start);
        Ok(())
    }

    /// The status of every process.
    pub fn status(&self) -> Vec<ProcessStatus> {
        self.processes.iter().map(Process::status).collect()
    }

    /// Marks in `mask` (one byte per image byte) every bit the kernel and its plant write
    /// ([`written`]); a replay recomputes those bits instead of applying the trace's.
    pub fn written_mask(&self, mask: &mut [u8]) {
        if let Some(r) = self.machine.reset {
            written::mark(mask, r, 1);
        }
        for p in &self.processes {
            p.written_mask(mask);
        }
    }

    /// Every CNC→PLC signal the kernel writes (a sim.toml may not set these).
    pub fn written_signals(&self) -> Vec<Signal> {
        let mut v: Vec<Signal> = self.machine.reset.into_iter().collect();
        for p in &self.processes {
            v.extend(p.sig.written());
        }
        v
    }
}

#[cfg(test)]
mod tests;
