//! The simulated CNC's handshake of one process: an M, S and T [`Channel`] on that process's
//! signals, and the completed / timed-out counts every process shares with the caller
//! ([`HandshakeCounts`], printed by `ncplc run --stats`).

use std::collections::BTreeMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use packets::{IoAlarm, Signal};

use super::signals::{ChannelSignals, ProcessSignals};
use cnc::handshake::{Channel, Kind, Note, bcd};

const KINDS: [Kind; 3] = [Kind::M, Kind::S, Kind::T];

/// One process's counters.
#[derive(Debug, Default)]
struct Counter {
    process: u8,
    has: [bool; 3],
    done: [AtomicU64; 3],
    timeouts: AtomicU64,
}

/// Completed functions and strobe timeouts per process, shared with the running sim.
#[derive(Debug, Clone, Default)]
pub struct HandshakeCounts(Arc<Vec<Counter>>);

impl HandshakeCounts {
    fn new(processes: &[ProcessSignals]) -> HandshakeCounts {
        HandshakeCounts(Arc::new(
            processes
                .iter()
                .map(|p| Counter {
                    process: p.process,
                    has: p.channels.map(|c| c.is_some()),
                    ..Counter::default()
                })
                .collect(),
        ))
    }

    /// Functions completed by process `process` (M, S, T); `None` for a process without channels.
    pub fn completed(&self, process: u8) -> Option<[u64; 3]> {
        let c = self.0.iter().find(|c| c.process == process)?;
        Some(c.done.each_ref().map(|d| d.load(Ordering::Relaxed)))
    }

    /// Strobes of `process` that timed out.
    pub fn timeouts(&self, process: u8) -> u64 {
        self.0
            .iter()
            .find(|c| c.process == process)
            .map_or(0, |c| c.timeouts.load(Ordering::Relaxed))
    }

    /// One line per process: `handshake p2   M 4  S -  T -  completed, 0 timeouts` (`-`: the
    /// process has no such channel).
    pub fn summary(&self) -> String {
        let mut s = String::new();
        for c in self.0.iter() {
            let n = |i: usize| {
                if c.has[i] {
                    c.done[i].load(Ordering::Relaxed).to_string()
                } else {
                    "-".into()
                }
            };
            s.push_str(&format!(
                "{:<14} M {}  S {}  T {}  completed, {} timeouts\n",
                format!("handshake p{}", c.process),
                n(0),
                n(1),
                n(2),
                c.timeouts.load(Ordering::Relaxed)
            ));
        }
        s
    }
}

/// The handshake of one process.
pub(super) struct ProcessSim {
    process: u8,
    slot: usize,
    lanes: [Option<(ChannelSignals, Channel)>; 3],
}

impl ProcessSim {
    /// The sims of every process in `signals`, with their shared counts.
    pub(super) fn all(
        signals: &[ProcessSignals],
        timeout_ticks: u64,
    ) -> (Vec<ProcessSim>, HandshakeCounts) {
        let sims = signals
            .iter()
            .enumerate()
            .map(|(slot, p)| ProcessSim {
                process: p.process,
                slot,
                lanes: [0, 1, 2]
                    .map(|i| p.channels[i].map(|sig| (sig, Channel::new(KINDS[i], timeout_ticks)))),
            })
            .collect();
        (sims, HandshakeCounts::new(signals))
    }

    /// The process number.
    pub(super) fn process(&self) -> u8 {
        self.process
    }

    /// Queues function `code` on channel `kind`; false when the process has no such channel.
    pub(super) fn issue(&mut self, kind: usize, code: u32) -> bool {
        match self.lanes.get_mut(kind).and_then(Option::as_mut) {
            Some((_, ch)) => {
                ch.issue(code);
                true
            }
            None => false,
        }
    }

    /// Advances every channel one tick: FINs from `last_out`, strobes and codes into `driven`.
    pub(super) fn step(
        &mut self,
        tick: u64,
        reset: bool,
        last_out: &[u8],
        driven: &mut BTreeMap<Signal, u8>,
        counts: &HandshakeCounts,
        alarms: &mut Vec<IoAlarm>,
    ) {
        let counter = counts.0.get(self.slot);
        for (i, lane) in self.lanes.iter_mut().enumerate() {
            let Some((sig, ch)) = lane else { continue };
            let fin = sig.fin.read(last_out) == 1;
            let (drive, note) = ch.step(tick, fin, reset);
            if let Some(code) = drive.code {
                let bytes = match KINDS[i] {
                    Kind::M => vec![bcd(code, 2) as u8],
                    Kind::S => code.to_le_bytes().to_vec(),
                    Kind::T => bcd(code, 8).to_le_bytes().to_vec(),
                };
                drive_bytes(driven, sig.code, &bytes);
            }
            driven.insert(sig.strobe, u8::from(drive.strobe));
            if let Some(c) = counter {
                c.done[i].store(ch.done, Ordering::Relaxed);
            }
            // Process 1 keeps the messages it always had; the others say which process.
            let prefix = if self.process == 1 {
                String::new()
            } else {
                format!("process {}: ", self.process)
            };
            match note {
                Some(Note::Timeout(f)) => {
                    if let Some(c) = counter {
                        c.timeouts.fetch_add(1, Ordering::Relaxed);
                    }
                    alarms.push(IoAlarm {
                        device: "cnc".into(),
                        message: format!(
                            "{prefix}{f} not acknowledged (FIN) within the strobe timeout"
                        ),
                        cleared: false,
                    });
                }
                Some(Note::Recovered(f)) => alarms.push(IoAlarm {
                    device: "cnc".into(),
                    message: format!("{prefix}{f} acknowledged late"),
                    cleared: true,
                }),
                None => {}
            }
        }
    }
}

/// Drives `bytes` from the image byte of `first` on.
fn drive_bytes(driven: &mut BTreeMap<Signal, u8>, first: Signal, bytes: &[u8]) {
    let base = first.image_byte();
    for (i, b) in bytes.iter().enumerate() {
        if let Some(s) = byte_signal_at(base + i) {
            driven.insert(s, *b);
        }
    }
}

/// The `W` signal of an image byte in packets A, K, N or T.
fn byte_signal_at(at: usize) -> Option<Signal> {
    let packet = packets::Packet::ALL
        .into_iter()
        .find(|p| at >= p.offset() && at < p.offset() + p.len())?;
    let rel = at - packet.offset();
    Some(Signal::Byte {
        packet,
        connector: (rel / 4) as u16,
        index: (rel % 4) as u8,
    })
}
