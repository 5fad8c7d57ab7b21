//! The built-in simulated machine: a deterministic model of the CNC side and of the machine, driven
//! by a script (`<machine>/sim.toml`), as a [`PacketIo`].
//!
//! ```toml
//! strobe_timeout_ms = 5000          # M/S/T strobe not answered → alarm naming the function
//! period = 20000                    # optional: the `at` schedule repeats every 20000 ticks
//! [signals]                         # optional: move handshake signals (defaults: interface map)
//! MFIN = "U11K0"
//! [[at]]                            # at tick 10: set inputs, issue functions through the handshake
//! tick = 10
//! set = { I0A0 = 1, I0K2 = 1 }
//! m = [3]
//! s = 1200
//! [[follow]]                        # machine feedback: input follows an output after a delay
//! input = "I0A3"
//! output = "U4A0"
//! or_outputs = ["U4A1"]             # optional: further outputs OR'ed
//! delay_ms = 500
//! invert = false
//! ```
//! Everything happens at tick numbers, so `run --virtual-time --record` gives reproducible traces.

use std::collections::{BTreeMap, VecDeque};

use packets::{IoAlarm, PacketIo, Signal};
use serde::Deserialize;

use crate::handshake::{Channel, Kind, Note, bcd};

/// The script as written in `sim.toml`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Script {
    /// Strobe timeout in ms (0: none; default 10 000).
    #[serde(default = "default_timeout")]
    pub strobe_timeout_ms: u64,
    /// When set, the `at` schedule repeats every `period` ticks (for long captures and benchmarks).
    #[serde(default)]
    pub period: Option<u64>,
    /// Handshake signal addresses that differ from the interface map (name → address).
    #[serde(default)]
    pub signals: BTreeMap<String, String>,
    /// Scheduled actions.
    #[serde(default)]
    pub at: Vec<At>,
    /// Feedback rules.
    #[serde(default)]
    pub follow: Vec<Follow>,
}

fn default_timeout() -> u64 {
    10_000
}

/// Actions at one tick.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct At {
    /// The tick.
    pub tick: u64,
    /// Input signals to set (held until changed).
    #[serde(default)]
    pub set: BTreeMap<String, u64>,
    /// M functions to issue, in order.
    #[serde(default)]
    pub m: Vec<u32>,
    /// S function to issue.
    pub s: Option<u32>,
    /// T function to issue.
    pub t: Option<u32>,
}

/// An input that follows an output after a delay (spindle at speed, lubrication level, …).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Follow {
    /// The input driven.
    pub input: String,
    /// The output followed.
    pub output: String,
    /// Further outputs OR'ed with `output`.
    #[serde(default)]
    pub or_outputs: Vec<String>,
    /// The delay in ms (rounded up to ticks; 0 = the next tick).
    #[serde(default)]
    pub delay_ms: u64,
    /// The input is the inverse of the output.
    #[serde(default)]
    pub invert: bool,
}

/// Why a script cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// TOML syntax or an unknown key.
    #[error("sim script: {0}")]
    Toml(#[from] toml::de::Error),
    /// A bad signal name or value.
    #[error("sim script: {0}")]
    Invalid(String),
}

/// The handshake signals the simulated CNC uses.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CncSignals {
    /// General reset (input to the logic).
    pub reset: Signal,
    /// Strobes M, S, T.
    pub strobes: [Signal; 3],
    /// FINs M, S, T.
    pub fins: [Signal; 3],
    /// MCODE (1 byte BCD).
    pub mcode: Signal,
    /// First byte of SCODE (4 bytes binary, little-endian).
    pub scode: Signal,
    /// First byte of TCODE (4 bytes BCD).
    pub tcode: Signal,
}

impl CncSignals {
    /// The addresses from a lookup by interface-map name (`RESET`, `MSTB`, `MFIN`, `MCODE`, …),
    /// falling back on plc-interface-map.md where the lookup has none.
    pub fn from_lookup(lookup: impl Fn(&str) -> Option<Signal>) -> CncSignals {
        let get =
            |name: &str, default: &str| lookup(name).unwrap_or_else(|| parse_default(default));
        CncSignals {
            reset: get("RESET", "I0K1"),
            strobes: [
                get("MSTB", "I1K0"),
                get("SSTB", "I1K1"),
                get("TSTB", "I1K2"),
            ],
            fins: [
                get("MFIN", "U11K0"),
                get("SFIN", "U11K1"),
                get("TFIN", "U11K2"),
            ],
            mcode: get("MCODE", "W3K0"),
            scode: get("SCODE", "W4K0"),
            tcode: get("TCODE", "W5K0"),
        }
    }
}

fn parse_default(s: &str) -> Signal {
    s.parse().unwrap_or(Signal::Byte {
        packet: packets::Packet::K,
        connector: 0,
        index: 0,
    })
}

impl Default for CncSignals {
    fn default() -> Self {
        CncSignals::from_lookup(|_| None)
    }
}

struct FollowRule {
    input: Signal,
    outputs: Vec<Signal>,
    delay: usize,
    invert: bool,
    history: VecDeque<u8>,
}

/// The simulated CNC and machine.
pub struct Sim {
    signals: CncSignals,
    schedule: BTreeMap<u64, Vec<At>>,
    period: Option<u64>,
    follow: Vec<FollowRule>,
    channels: [Channel; 3],
    driven: BTreeMap<Signal, u8>,
    last_out: Vec<u8>,
    alarms: Vec<IoAlarm>,
}

fn parse_sig(name: &str) -> Result<Signal, SimError> {
    name.parse()
        .map_err(|e| SimError::Invalid(format!("`{name}`: {e}")))
}

impl Sim {
    /// A sim from a script, for a logic tick of `tick_ms` ms.
    pub fn new(script: Script, signals: CncSignals, tick_ms: u32) -> Result<Sim, SimError> {
        let tick_ms = u64::from(tick_ms.max(1));
        let mut signals = signals;
        for (name, addr) in &script.signals {
            let s = parse_sig(addr)?;
            match name.to_ascii_uppercase().as_str() {
                "RESET" => signals.reset = s,
                "MSTB" => signals.strobes[0] = s,
                "SSTB" => signals.strobes[1] = s,
                "TSTB" => signals.strobes[2] = s,
                "MFIN" => signals.fins[0] = s,
                "SFIN" => signals.fins[1] = s,
                "TFIN" => signals.fins[2] = s,
                "MCODE" => signals.mcode = s,
                "SCODE" => signals.scode = s,
                "TCODE" => signals.tcode = s,
                other => {
                    return Err(SimError::Invalid(format!(
                        "unknown handshake signal `{other}`"
                    )));
                }
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
        Ok(Sim {
            signals,
            schedule,
            period: script.period.filter(|&p| p > 0),
            follow,
            channels: [
                Channel::new(Kind::M, timeout),
                Channel::new(Kind::S, timeout),
                Channel::new(Kind::T, timeout),
            ],
            driven: BTreeMap::new(),
            last_out: vec![0; packets::PACKETS_LEN],
            alarms: Vec::new(),
        })
    }

    /// Parses `sim.toml` text.
    pub fn parse_script(text: &str) -> Result<Script, SimError> {
        Ok(toml::from_str(text)?)
    }

    /// Functions completed per channel (M, S, T).
    pub fn completed(&self) -> [u64; 3] {
        [
            self.channels[0].done,
            self.channels[1].done,
            self.channels[2].done,
        ]
    }

    fn drive_bytes(&mut self, first: Signal, bytes: &[u8]) {
        let base = first.image_byte();
        for (i, b) in bytes.iter().enumerate() {
            if let Some(s) = byte_signal_at(base + i) {
                self.driven.insert(s, *b);
            }
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
                for m in &at.m {
                    self.channels[0].issue(*m);
                }
                if let Some(s) = at.s {
                    self.channels[1].issue(s);
                }
                if let Some(t) = at.t {
                    self.channels[2].issue(t);
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
        let reset = self.driven.get(&self.signals.reset).copied().unwrap_or(0) == 1;
        for i in 0..3 {
            let fin = self.signals.fins[i].read(&self.last_out) == 1;
            let (drive, note) = self.channels[i].step(tick, fin, reset);
            if let Some(code) = drive.code {
                match i {
                    0 => self.drive_bytes(self.signals.mcode, &[bcd(code, 2) as u8]),
                    1 => self.drive_bytes(self.signals.scode, &code.to_le_bytes()),
                    _ => self.drive_bytes(self.signals.tcode, &bcd(code, 8).to_le_bytes()),
                }
            }
            self.driven
                .insert(self.signals.strobes[i], u8::from(drive.strobe));
            match note {
                Some(Note::Timeout(f)) => self.alarms.push(IoAlarm {
                    device: "cnc".into(),
                    message: format!("{f} not acknowledged (FIN) within the strobe timeout"),
                    cleared: false,
                }),
                Some(Note::Recovered(f)) => self.alarms.push(IoAlarm {
                    device: "cnc".into(),
                    message: format!("{f} acknowledged late"),
                    cleared: true,
                }),
                None => {}
            }
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
mod tests {
    use super::*;
    use crate::testkit::sig;

    fn sim(text: &str, tick_ms: u32) -> Sim {
        Sim::new(
            Sim::parse_script(text).expect("script"),
            CncSignals::default(),
            tick_ms,
        )
        .expect("sim")
    }

    #[test]
    fn scripted_inputs_and_feedback_with_delay() {
        let mut s = sim(
            "[[at]]\ntick = 1\nset = { I0A0 = 1 }\n[[follow]]\ninput = \"I0A3\"\noutput = \"U4A0\"\ndelay_ms = 20\n",
            10,
        );
        let mut img = vec![0u8; packets::PACKETS_LEN];
        let mut seen = Vec::new();
        for t in 0..6 {
            s.latch_inputs(t, &mut img);
            seen.push((sig("I0A0").read(&img), sig("I0A3").read(&img)));
            // The "logic": U4A0 copies I0A0.
            let v = sig("I0A0").read(&img);
            sig("U4A0").write(&mut img, v);
            s.publish_outputs(t, &img);
        }
        // U4A0 rises at the end of tick 1; 20 ms = 2 ticks later than the next tick: tick 4.
        assert_eq!(seen, vec![(0, 0), (1, 0), (1, 0), (1, 0), (1, 1), (1, 1)]);
    }

    #[test]
    fn m_function_runs_the_handshake_against_a_logic() {
        let mut s = sim("strobe_timeout_ms = 100\n[[at]]\ntick = 0\nm = [3]\n", 10);
        let mut img = vec![0u8; packets::PACKETS_LEN];
        let mut log = Vec::new();
        for t in 0..8 {
            s.latch_inputs(t, &mut img);
            // Logic: MFIN = MSTB and MCODE = 03.
            let fin = sig("I1K0").read(&img) == 1 && sig("W3K0").read(&img) == 0x03;
            sig("U11K0").write(&mut img, u8::from(fin));
            log.push((sig("I1K0").read(&img), sig("U11K0").read(&img)));
            s.publish_outputs(t, &img);
        }
        assert_eq!(
            log,
            vec![
                (0, 0),
                (1, 1),
                (0, 0),
                (0, 0),
                (0, 0),
                (0, 0),
                (0, 0),
                (0, 0)
            ]
        );
        assert_eq!(s.completed(), [1, 0, 0]);
        assert!(s.take_alarms().is_empty());
    }

    #[test]
    fn unanswered_strobe_raises_an_alarm_naming_the_function() {
        let mut s = sim("strobe_timeout_ms = 30\n[[at]]\ntick = 0\nm = [91]\n", 10);
        let mut img = vec![0u8; packets::PACKETS_LEN];
        let mut alarms = Vec::new();
        for t in 0..10 {
            s.latch_inputs(t, &mut img);
            s.publish_outputs(t, &img);
            alarms.extend(s.take_alarms());
        }
        assert_eq!(alarms.len(), 1);
        assert_eq!(
            alarms[0].message,
            "M91 not acknowledged (FIN) within the strobe timeout"
        );
    }

    #[test]
    fn a_periodic_schedule_repeats() {
        let mut s = sim(
            "period = 3\n[[at]]\ntick = 1\nset = { I0A0 = 1 }\n[[at]]\ntick = 2\nset = { I0A0 = 0 }\n",
            10,
        );
        let mut img = vec![0u8; packets::PACKETS_LEN];
        let mut seen = Vec::new();
        for t in 0..7 {
            s.latch_inputs(t, &mut img);
            seen.push(sig("I0A0").read(&img));
        }
        assert_eq!(seen, vec![0, 1, 0, 0, 1, 0, 0]);
    }

    #[test]
    fn bad_scripts_are_rejected() {
        assert!(Sim::parse_script("bogus = 1\n").is_err());
        let script = Sim::parse_script("[[at]]\ntick = 0\nset = { I0A0 = 2 }\n").expect("toml");
        assert!(Sim::new(script, CncSignals::default(), 10).is_err());
    }
}
