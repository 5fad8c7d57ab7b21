//! The Machine page's data before the CNC kernel is wired in: what the packet image and the
//! simulated handshakes say about each process (MODE byte, overrides, completed M/S/T functions).
//! Operator commands are refused with the reason: without `--program`/`--mdi` no CNC kernel runs
//! (the scripted sim plays the CNC); with one, [`super::kernel_cnc::KernelCnc`] takes its place.

use compiler::InterfaceMap;
use hmi::{Command, HandshakeCounts, MachineStatus, ProcessStatus};
use packets::Signal;

use super::frame::Frame;
use super::{Cnc, CncScan, CncView};
use sim::HandshakeCounts as SimCounts;

/// One process's interface signals.
#[derive(Debug, Clone)]
struct ProcessRoles {
    process: u8,
    mode: Option<Signal>,
    fov: Option<Signal>,
    sov: Option<Signal>,
    rov: Option<Signal>,
}

/// The image-backed [`Cnc`].
#[derive(Debug, Clone)]
pub struct ImageCnc {
    processes: Vec<ProcessRoles>,
    counts: Option<SimCounts>,
}

impl ImageCnc {
    /// For processes `processes` (1-based numbers) of a machine with `interface`; `counts` are the
    /// simulated handshakes' counters (with `--io sim`).
    pub fn new(interface: &InterfaceMap, processes: &[u8], counts: Option<SimCounts>) -> ImageCnc {
        let role = |p: u8, r: &str| interface.role(p, r).map(|s| s.signal);
        ImageCnc {
            processes: processes
                .iter()
                .map(|&p| ProcessRoles {
                    process: p,
                    mode: role(p, "MODE"),
                    fov: role(p, "FOV"),
                    sov: role(p, "SOV"),
                    rov: role(p, "ROV"),
                })
                .collect(),
            counts,
        }
    }
}

impl ImageCnc {
    /// The per-process state the packet image `image` shows.
    pub fn status(&self, image: &[u8]) -> MachineStatus {
        let read = |s: &Option<Signal>| s.map(|s| u32::from(s.read(image)));
        MachineStatus {
            processes: self
                .processes
                .iter()
                .map(|p| ProcessStatus {
                    process: p.process,
                    mode: read(&p.mode).map(|m| format!("code {m}")),
                    feed_override: read(&p.fov),
                    spindle_override: read(&p.sov),
                    rapid_override: read(&p.rov),
                    handshakes: self.counts.as_ref().and_then(|c| {
                        let [m, s, t] = c.completed(p.process)?;
                        Some(HandshakeCounts {
                            m,
                            s,
                            t,
                            timeouts: c.timeouts(p.process),
                        })
                    }),
                    ..ProcessStatus::default()
                })
                .collect(),
        }
    }
}

impl Cnc for ImageCnc {
    fn split(self: Box<Self>) -> (Box<dyn CncScan>, Box<dyn CncView>) {
        (Box::new((*self).clone()), self)
    }
}

impl CncView for ImageCnc {
    fn status(&mut self, frame: &Frame) -> MachineStatus {
        ImageCnc::status(self, &frame.image)
    }
}

impl CncScan for ImageCnc {
    fn command(&mut self, process: u8, command: &Command) -> Result<(), String> {
        if !self.processes.iter().any(|p| p.process == process) {
            return Err(format!("this machine has no process {process}"));
        }
        Err(format!(
            "{} for process {process}: no CNC kernel runs (the scripted sim plays the CNC); start with --program or --mdi for operator commands",
            match command {
                Command::Start => "start",
                Command::Hold => "hold",
                Command::Reset => "reset",
                Command::Mode { .. } => "mode",
                Command::Mdi { .. } => "mdi",
                Command::Ack => "ack",
            }
        ))
    }
}
