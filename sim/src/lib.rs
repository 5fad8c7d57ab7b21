//! The built-in simulated machine: a deterministic model of the CNC side and of the machine, driven
//! by a script (`<machine>/sim.toml`), as a [`PacketIo`].
//!
//! ```toml
//! strobe_timeout_ms = 5000          # M/S/T strobe not answered → alarm naming the function
//! period = 20000                    # optional: the `at` schedule repeats every 20000 ticks
//! [signals]                         # optional: move process 1's handshake signals (defaults: map)
//! MFIN = "U11K0"
//! [[at]]                            # at tick 10: set inputs, issue functions through the handshake
//! tick = 10
//! set = { I0A0 = 1, I0K2 = 1 }
//! m = [3]
//! s = 1200
//! [[at]]                            # process 2's handshake (its roles come from interface.toml)
//! tick = 12
//! process = 2
//! m = [30]
//! [[follow]]                        # machine feedback: input follows an output after a delay
//! input = "I0A3"
//! output = "U4A0"
//! or_outputs = ["U4A1"]             # optional: further outputs OR'ed
//! delay_ms = 500
//! invert = false
//! ```
//! Every process has its own M, S and T channel ([`process`]): strobes, codes, FIN watching and
//! strobe timeouts are per process (an alarm of process 2..5 starts with `process n:`); the general
//! reset clears every process's strobes. Processes are stepped in order, process 1 first, and
//! everything happens at tick numbers, so `run --virtual-time --record` gives reproducible traces.
//!
//! | module | concept |
//! |---|---|
//! | this file, `process`, `script`, `signals` | the scripted machine: `[[at]]` schedule, `[[follow]]` rules, one M/S/T handshake per process |
//! | [`kernel`] | the part-run plant: the `cnc` kernel behind the same [`PacketIo`] (`KernelIo`) |
//! | [`handwheel`] | the `[[handwheel]]` counters turned before the kernel steps |
//! | [`part`] | a partprogram compiled and planned with the machine's view, and the files it read |
//! | [`machine_view`] | the partprogram view of a machine (`MachineSpec`, KOR/POS tables, macro variables) |
//!
//! **Invariants:** a pure function of the tick sequence (no clock, no threads, no hash-map order):
//! the same script and outputs give the same inputs. This crate sits beside the scan runtime: it
//! uses `runtime` for the validated machine facts and the paths shown in messages only, and knows
//! nothing of the scheduler, the CLI or the controller's assembly.

pub mod handwheel;
pub mod kernel;
pub mod machine_view;
pub mod part;
mod process;
mod script;
mod signals;
pub mod validate;

use std::collections::{BTreeMap, VecDeque};

use packets::{IoAlarm, PacketIo, Signal};

pub use process::HandshakeCounts;
use process::ProcessSim;
pub use script::{At, AxisPlace, CncSettings, Follow, PartScript, Script, SimError, SpindleWiring};
pub use signals::{ChannelSignals, CncSignals, ProcessSignals};

struct FollowRule {
    input: Signal,
    outputs: Vec<Signal>,
    delay: usize,
    invert: bool,
    history: VecDeque<u8>,
}

/// The simulated CNC and machine.
pub struct Sim {
    reset: Signal,
    schedule: BTreeMap<u64, Vec<At>>,
    period: Option<u64>,
    follow: Vec<FollowRule>,
    processes: Vec<ProcessSim>,
    counts: HandshakeCounts,
    driven: BTreeMap<Signal, u8>,
    last_out: Vec<u8>,
    alarms: Vec<IoAlarm>,
}

fn parse_sig(name: &str) -> Result<Signal, SimError> {
    name.parse()
        .map_err(|e| SimError::Invalid(format!("`{name}`: {e}")))
}

/// Checks that `at`'s functions have a channel in `signals`.
pub(crate) fn check_functions(at: &At, signals: &CncSignals) -> Result<(), SimError> {
    if !(1..=5).contains(&at.process) {
        return Err(SimError::Invalid(format!(
            "tick {}: process {} is outside 1..5",
            at.tick, at.process
        )));
    }
    let wanted = [
        (!at.m.is_empty(), cnc::handshake::Kind::M),
        (at.s.is_some(), cnc::handshake::Kind::S),
        (at.t.is_some(), cnc::handshake::Kind::T),
    ];
    for (used, kind) in wanted {
        let has = signals
            .process(at.process)
            .is_some_and(|p| p.channels[signals::index(kind)].is_some());
        if used && !has {
            return Err(SimError::Invalid(format!(
                "tick {}: process {} has no {kind:?} handshake ({}) in the interface map",
                at.tick,
                at.process,
                signals::roles(kind).join(", ")
            )));
        }
    }
    Ok(())
}

impl Sim {
    /// A sim from a script, for a logic tick of `tick_ms` ms.
    pub fn new(script: Script, signals: CncSignals, tick_ms: u32) -> Result<Sim, SimError> {
        let tick_ms = u64::from(tick_ms.max(1));
        let mut signals = signals;
        for (name, addr) in &script.signals {
            let s = parse_sig(addr)?;
            let name = name.to_ascii_uppercase();
            if !signals.set_process1(&name, s) {
                return Err(SimError::Invalid(format!(
                    "unknown handshake signal `{name}`"
                )));
            }
        }
        let mut schedule: BTreeMap<u64, Vec<At>> = BTreeMap::new();
        for at in script.at {
            for (name, v) in &at.set {
                let s = parse_sig(name)?;
                let max = if s.bit().is_some() { 1 } else { 255 };
                if *v > max {
                    return Err(SimError::Invalid(format!(
                        "tick {}: {name} = {v} is out of range (0..{max})",
                        at.tick
                    )));
                }
            }
            check_functions(&at, &signals)?;
            if !at.turn.is_empty() {
                return Err(SimError::Invalid(format!(
                    "tick {}: `turn` turns a handwheel of the CNC kernel: it belongs to [[part.at]] of a part run",
                    at.tick
                )));
            }
            schedule.entry(at.tick).or_default().push(at);
        }
        let follow = script
            .follow
            .iter()
            .map(|f| {
                Ok(FollowRule {
                    input: parse_sig(&f.input)?,
                    outputs: std::iter::once(&f.output)
                        .chain(&f.or_outputs)
                        .map(|o| parse_sig(o))
                        .collect::<Result<Vec<_>, _>>()?,
                    delay: f.delay_ms.div_ceil(tick_ms) as usize,
                    invert: f.invert,
                    history: VecDeque::new(),
                })
            })
            .collect::<Result<Vec<_>, SimError>>()?;
        let timeout = script.strobe_timeout_ms.div_ceil(tick_ms);
        let (processes, counts) = ProcessSim::all(&signals.processes, timeout);
        Ok(Sim {
            reset: signals.reset,
            schedule,
            period: script.period.filter(|&p| p > 0),
            follow,
            processes,
            counts,
            driven: BTreeMap::new(),
            last_out: vec![0; packets::PACKETS_LEN],
            alarms: Vec::new(),
        })
    }

    /// Parses `sim.toml` text.
    pub fn parse_script(text: &str) -> Result<Script, SimError> {
        Ok(toml::from_str(text)?)
    }

    /// Functions completed by process 1 per channel (M, S, T).
    pub fn completed(&self) -> [u64; 3] {
        self.counts.completed(1).unwrap_or_default()
    }

    /// The completed and timed-out counts of every process (stays valid after the sim is boxed).
    pub fn counts(&self) -> HandshakeCounts {
        self.counts.clone()
    }
}

impl PacketIo for Sim {
    fn name(&self) -> &str {
        "sim"
    }

    fn latch_inputs(&mut self, tick: u64, packets: &mut [u8]) {
        let key = self.period.map_or(tick, |p| tick % p);
        let list = if self.period.is_some() {
            self.schedule.get(&key).cloned()
        } else {
            self.schedule.remove(&key)
        };
        if let Some(list) = list {
            for at in list {
                for (name, v) in &at.set {
                    if let Ok(s) = name.parse::<Signal>() {
                        self.driven.insert(s, *v as u8);
                    }
                }
                // Checked in `new`: the process exists and has the channels used.
                if let Some(p) = self
                    .processes
                    .iter_mut()
                    .find(|p| p.process() == at.process)
                {
                    for m in &at.m {
                        p.issue(0, *m);
                    }
                    if let Some(s) = at.s {
                        p.issue(1, s);
                    }
                    if let Some(t) = at.t {
                        p.issue(2, t);
                    }
                }
            }
        }
        for f in &mut self.follow {
            let v = if f.history.len() > f.delay {
                f.history[f.history.len() - 1 - f.delay]
            } else {
                0
            };
            self.driven.insert(f.input, v ^ u8::from(f.invert));
        }
        let reset = self.driven.get(&self.reset).copied().unwrap_or(0) == 1;
        for p in &mut self.processes {
            p.step(
                tick,
                reset,
                &self.last_out,
                &mut self.driven,
                &self.counts,
                &mut self.alarms,
            );
        }
        for (s, v) in &self.driven {
            s.write(packets, *v);
        }
    }

    fn publish_outputs(&mut self, _tick: u64, packets: &[u8]) {
        let n = packets.len().min(self.last_out.len());
        self.last_out[..n].copy_from_slice(&packets[..n]);
        for f in &mut self.follow {
            f.history
                .push_back(f.outputs.iter().fold(0, |acc, o| acc | o.read(packets)));
            if f.history.len() > f.delay + 1 {
                f.history.pop_front();
            }
        }
    }

    fn take_alarms(&mut self) -> Vec<IoAlarm> {
        std::mem::take(&mut self.alarms)
    }
}

#[cfg(test)]
mod tests;

#[cfg(test)]
#[path = "scheduler_tests.rs"]
mod scheduler_tests;
