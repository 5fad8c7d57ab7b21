//! The handshake signals the simulated CNC drives and watches: the general reset, and per process
//! one strobe / FIN / code triple for each of M, S and T.
//!
//! Process 1's signals fall back on docs/plc-interface-map.md §1 where the map has none (as before
//! processes 2..5 existed); a process 2..5 has a channel only when the map gives all three of its
//! roles (`MSTB`, `MFIN`, `MCODE` for M, …; `ncplc run` refuses a machine whose processes 2..NBP
//! lack the roles they need).

use compiler::InterfaceMap;
use packets::Signal;

use cnc::handshake::Kind;

/// The strobe, FIN and code of one channel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChannelSignals {
    /// The strobe (CNC → logic).
    pub strobe: Signal,
    /// The FIN (logic → CNC).
    pub fin: Signal,
    /// The code's first byte (M: 1 byte BCD; S: 4 bytes binary; T: 4 bytes BCD; little-endian).
    pub code: Signal,
}

/// The channels of one process, indexed M, S, T.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ProcessSignals {
    /// The process (1..5).
    pub process: u8,
    /// M, S and T (`None`: the process has no such handshake).
    pub channels: [Option<ChannelSignals>; 3],
}

/// The handshake signals the simulated CNC uses.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CncSignals {
    /// General reset (input to the logic); it clears every process's strobes.
    pub reset: Signal,
    /// The processes in order, process 1 first.
    pub processes: Vec<ProcessSignals>,
}

/// The roles of one channel: strobe, FIN, code, and process 1's default addresses.
const ROLES: [[(&str, &str); 3]; 3] = [
    [("MSTB", "I1K0"), ("MFIN", "U11K0"), ("MCODE", "W3K0")],
    [("SSTB", "I1K1"), ("SFIN", "U11K1"), ("SCODE", "W4K0")],
    [("TSTB", "I1K2"), ("TFIN", "U11K2"), ("TCODE", "W5K0")],
];

/// The index of `kind` in [`ProcessSignals::channels`].
pub fn index(kind: Kind) -> usize {
    match kind {
        Kind::M => 0,
        Kind::S => 1,
        Kind::T => 2,
    }
}

/// The role names of `kind`'s channel (`["MSTB", "MFIN", "MCODE"]`, …).
pub fn roles(kind: Kind) -> [&'static str; 3] {
    ROLES[index(kind)].map(|(r, _)| r)
}

fn parse_default(s: &str) -> Signal {
    s.parse().unwrap_or(Signal::Byte {
        packet: packets::Packet::K,
        connector: 0,
        index: 0,
    })
}

impl CncSignals {
    /// Process 1's addresses from a lookup by interface-map name (`RESET`, `MSTB`, `MFIN`,
    /// `MCODE`, …), falling back on docs/plc-interface-map.md where the lookup has none.
    pub fn from_lookup(lookup: impl Fn(&str) -> Option<Signal>) -> CncSignals {
        let get =
            |name: &str, default: &str| lookup(name).unwrap_or_else(|| parse_default(default));
        CncSignals {
            reset: get("RESET", "I0K1"),
            processes: vec![ProcessSignals {
                process: 1,
                channels: ROLES.map(|[(s, sd), (f, fd), (c, cd)]| {
                    Some(ChannelSignals {
                        strobe: get(s, sd),
                        fin: get(f, fd),
                        code: get(c, cd),
                    })
                }),
            }],
        }
    }

    /// Processes 1..`nbp` from the map's roles: process 1 as [`CncSignals::from_lookup`], processes
    /// 2..`nbp` with the channels whose three roles the map gives.
    pub fn from_map(map: &InterfaceMap, nbp: u8) -> CncSignals {
        let mut signals = CncSignals::from_lookup(|role| map.role(1, role).map(|s| s.signal));
        for process in 2..=nbp.min(5) {
            let channels = ROLES.map(|[(s, _), (f, _), (c, _)]| {
                let get = |role| map.role(process, role).map(|e| e.signal);
                Some(ChannelSignals {
                    strobe: get(s)?,
                    fin: get(f)?,
                    code: get(c)?,
                })
            });
            signals.processes.push(ProcessSignals { process, channels });
        }
        signals
    }

    /// The signals of `process`.
    pub fn process(&self, process: u8) -> Option<&ProcessSignals> {
        self.processes.iter().find(|p| p.process == process)
    }

    /// Moves process 1's signal `name` (`RESET`, `MSTB`, `MFIN`, `MCODE`, … as in sim.toml
    /// `[signals]`) to `to`; false when `name` is not a handshake signal.
    pub fn set_process1(&mut self, name: &str, to: Signal) -> bool {
        if name == "RESET" {
            self.reset = to;
            return true;
        }
        let Some(p1) = self.processes.iter_mut().find(|p| p.process == 1) else {
            return false;
        };
        for (k, roles) in ROLES.iter().enumerate() {
            for (part, (role, _)) in roles.iter().enumerate() {
                if *role == name
                    && let Some(ch) = p1.channels[k].as_mut()
                {
                    match part {
                        0 => ch.strobe = to,
                        1 => ch.fin = to,
                        _ => ch.code = to,
                    }
                    return true;
                }
            }
        }
        false
    }
}

impl Default for CncSignals {
    fn default() -> Self {
        CncSignals::from_lookup(|_| None)
    }
}
