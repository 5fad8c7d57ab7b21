//! The PLC's messages (docs/plc-messages.md): raised and cleared from the request bits the logic
//! writes (MSGA/MSGB, connectors 21K and 22K), listed with the alarm lists' acknowledge rules, and
//! acknowledged back to the logic through MSGACKA/MSGACKB (N connectors 0 and 1).
//!
//! After every tick the scan's outputs are compared with the last tick's: a rising request bit
//! raises message n of its process at that tick (text from the message file, severity from
//! MSGPRIO), a falling one clears it. The operator's acknowledge (the web HMI's `ack`) goes to the
//! logic as one-shot writes ([`runtime::force::Forces::write_once`]): the acknowledge bits of the
//! messages it acknowledged are 1 in the next scan and 0 in the one after, so the scheduler
//! records them as the trace's inputs and a replay feeds them to the logic exactly.
//!
//! **Invariants:** messages are a function of the image sequence (nothing here reads a clock);
//! a process whose IOCFIL `CWD` has bit 0004H set, or whose interface map has no MSGA/MSGB, has
//! no messages and its acknowledge bits are never written.

use characterization::messages::{MAX_MESSAGE, PlcMessages};
use compiler::InterfaceMap;
use hmi::MessageEntry;
use packets::Signal;
use runtime::force::Forces;
use runtime::machine_facts::Facts;

/// IOCFIL CWD bit that switches the PLC messages off (003:6261).
pub const CWD_MESSAGES_OFF: u16 = 0x0004;

/// The message signals of one process.
#[derive(Debug, Clone, PartialEq)]
struct ProcessSignals {
    process: u8,
    /// MSGA and MSGB: the dwords of request bits 1..32 and 33..64.
    request: [Option<Signal>; 2],
    /// MSGPRIO.
    priority: Option<Signal>,
    /// MSGACKA and MSGACKB: the dwords of acknowledge bits.
    ack: [Option<Signal>; 2],
}

/// What a machine's PLC messages need: each serviced process's signals and the message texts.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MessageSetup {
    processes: Vec<ProcessSignals>,
    texts: PlcMessages,
}

impl MessageSetup {
    /// The setup of the machine `facts` describe, with its interface map: processes 1..NBP with
    /// MSGA or MSGB and without CWD bit 0004H.
    pub fn new(facts: &Facts, map: &InterfaceMap) -> MessageSetup {
        let nbp = runtime::process_map::nbp(&facts.machine);
        let processes = (1..=nbp)
            .filter(|&p| {
                let cwd = facts
                    .iocfil()
                    .process(u32::from(p))
                    .and_then(|io| io.cwd)
                    .unwrap_or(0);
                cwd & CWD_MESSAGES_OFF == 0
            })
            .map(|p| {
                let role = |r: &str| map.role(p, r).map(|s| s.signal);
                ProcessSignals {
                    process: p,
                    request: [role("MSGA"), role("MSGB")],
                    priority: role("MSGPRIO"),
                    ack: [role("MSGACKA"), role("MSGACKB")],
                }
            })
            .filter(|s| s.request.iter().any(Option::is_some))
            .collect();
        MessageSetup {
            processes,
            texts: facts.machine.messages.clone(),
        }
    }

    /// True when no process has messages.
    pub fn is_empty(&self) -> bool {
        self.processes.is_empty()
    }
}

/// A message raised or cleared at a tick (what the CLI prints and OPC UA sends as an event).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MessageEvent {
    /// The message as listed (for a clear: as it was raised).
    pub entry: MessageEntry,
    /// Raised (true) or cleared.
    pub raised: bool,
    /// The tick whose scan raised or cleared it.
    pub tick: u64,
}

/// The running messages: last request bits per process and the list with acknowledge.
#[derive(Debug, Clone)]
pub struct Messages {
    setup: MessageSetup,
    last: Vec<u64>,
    list: Vec<MessageEntry>,
    /// Acknowledge bytes written at the last boundary, to be written 0 at the next.
    pulse: Vec<Signal>,
    changed: bool,
}

/// The 32 bits of the dword at `s` in `image` (0 without one).
fn dword(image: &[u8], s: Option<Signal>) -> u64 {
    let Some(s) = s else { return 0 };
    let at = s.image_byte();
    image.get(at..at + 4).map_or(0, |b| {
        u64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    })
}

/// Byte `i` (0..3) of the dword at `s`.
fn byte_of(s: Signal, i: u8) -> Option<Signal> {
    match s {
        Signal::Byte {
            packet, connector, ..
        } => Some(Signal::Byte {
            packet,
            connector,
            index: i,
        }),
        Signal::Bit { .. } => None,
    }
}

/// OPC UA severity from MSGPRIO: 0 → 500, else 4 × value, at most 1000.
pub fn severity(priority: u8) -> u16 {
    match priority {
        0 => 500,
        p => (u16::from(p) * 4).min(1000),
    }
}

impl Messages {
    /// Messages of `setup`, none raised yet.
    pub fn new(setup: MessageSetup) -> Messages {
        let n = setup.processes.len();
        Messages {
            setup,
            last: vec![0; n],
            list: Vec::new(),
            pulse: Vec::new(),
            changed: false,
        }
    }

    /// The listed messages, oldest first.
    pub fn entries(&self) -> &[MessageEntry] {
        &self.list
    }

    /// True once since the list last changed (raised, cleared or acknowledged).
    pub fn take_changed(&mut self) -> bool {
        std::mem::take(&mut self.changed)
    }

    /// After the scan of `tick`: raises the messages whose bits rose in `image`, clears those whose
    /// bits fell, appending what happened to `out` in process and number order.
    pub fn scan(&mut self, image: &[u8], tick: u64, out: &mut Vec<MessageEvent>) {
        for (i, ps) in self.setup.processes.iter().enumerate() {
            let now = dword(image, ps.request[0]) | (dword(image, ps.request[1]) << 32);
            let was = self.last[i];
            if now == was {
                continue;
            }
            self.last[i] = now;
            let prio = ps.priority.map_or(0, |s| s.read(image));
            for n in 0..MAX_MESSAGE {
                let bit = 1u64 << n;
                if (now ^ was) & bit == 0 {
                    continue;
                }
                let number = n + 1;
                self.changed = true;
                if now & bit != 0 {
                    let entry = MessageEntry {
                        process: ps.process,
                        number,
                        text: self.setup.texts.shown(ps.process, number),
                        severity: severity(prio),
                        active: true,
                        acknowledged: false,
                        tick,
                    };
                    raise(&mut self.list, entry.clone());
                    out.push(MessageEvent {
                        entry,
                        raised: true,
                        tick,
                    });
                } else if let Some(entry) = clear(&mut self.list, ps.process, number) {
                    out.push(MessageEvent {
                        entry,
                        raised: false,
                        tick,
                    });
                }
            }
        }
    }

    /// At a tick boundary, before new acknowledges: the acknowledge bits set at the last boundary
    /// go back to 0 (written once before the next scan).
    pub fn end_pulse(&mut self, forces: &mut Forces) {
        for s in self.pulse.drain(..) {
            forces.write_once(s, 0);
        }
    }

    /// The operator acknowledged `process`'s messages (0: every process's): the unacknowledged
    /// listed ones get their acknowledge bit for the next scan; the list keeps the active ones,
    /// marked acknowledged.
    pub fn acknowledge(&mut self, process: u8, forces: &mut Forces) {
        for ps in &self.setup.processes {
            if process != 0 && ps.process != process {
                continue;
            }
            let mut mask = 0u64;
            for e in &self.list {
                if e.process == ps.process && !e.acknowledged {
                    mask |= 1u64 << (e.number - 1);
                }
            }
            for (half, sig) in ps.ack.iter().enumerate() {
                let Some(sig) = *sig else { continue };
                let bits = (mask >> (32 * half)) as u32;
                for (i, b) in bits.to_le_bytes().into_iter().enumerate() {
                    if b == 0 {
                        continue;
                    }
                    let Some(byte) = byte_of(sig, i as u8) else {
                        continue;
                    };
                    forces.write_once(byte, b);
                    self.pulse.push(byte);
                }
            }
        }
        self.list.retain_mut(|e| {
            if process != 0 && e.process != process {
                return true;
            }
            e.acknowledged = true;
            e.active
        });
        self.changed = true;
    }
}

/// Lists `entry` (again, when it is listed inactive: new and unacknowledged at its new tick).
fn raise(list: &mut Vec<MessageEntry>, entry: MessageEntry) {
    match list
        .iter_mut()
        .find(|e| e.process == entry.process && e.number == entry.number)
    {
        Some(e) => *e = entry,
        None => list.push(entry),
    }
}

/// Marks message `number` of `process` inactive (gone when it was acknowledged); returns it.
fn clear(list: &mut Vec<MessageEntry>, process: u8, number: u8) -> Option<MessageEntry> {
    let i = list
        .iter()
        .position(|e| e.process == process && e.number == number)?;
    list[i].active = false;
    let e = list[i].clone();
    if e.acknowledged {
        list.remove(i);
    }
    Some(e)
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use characterization::messages::MessageFile;

    use super::*;

    fn sig(s: &str) -> Signal {
        s.parse().expect("signal")
    }

    fn messages() -> Messages {
        let texts = PlcMessages {
            common: Some(MessageFile {
                name: "MP0/MESSAG".into(),
                texts: BTreeMap::from([(1, "lube low".to_string())]),
            }),
            processes: BTreeMap::new(),
        };
        Messages::new(MessageSetup {
            processes: vec![ProcessSignals {
                process: 1,
                request: [Some(sig("W21K0")), Some(sig("W22K0"))],
                priority: Some(sig("W17K3")),
                ack: [Some(sig("W0N0")), Some(sig("W1N0"))],
            }],
            texts,
        })
    }

    fn image() -> Vec<u8> {
        vec![0; packets::PACKETS_LEN]
    }

    fn shown(m: &Messages) -> Vec<(u8, &str, u16, bool, bool, u64)> {
        m.entries()
            .iter()
            .map(|e| {
                let t = e.text.as_str();
                (e.number, t, e.severity, e.active, e.acknowledged, e.tick)
            })
            .collect()
    }

    #[test]
    fn edges_raise_and_clear_with_text_priority_and_tick() {
        let mut m = messages();
        let mut img = image();
        let mut out = Vec::new();
        sig("U21K0").write(&mut img, 1);
        sig("U22K31").write(&mut img, 1);
        sig("W17K3").write(&mut img, 100);
        m.scan(&img, 7, &mut out);
        let raised: Vec<(u8, bool, u64)> = out
            .iter()
            .map(|e| (e.entry.number, e.raised, e.tick))
            .collect();
        assert_eq!(raised, vec![(1, true, 7), (64, true, 7)]);
        assert_eq!(
            shown(&m),
            vec![
                (1, "lube low", 400, true, false, 7),
                (64, "PLC message 64", 400, true, false, 7)
            ]
        );
        assert!(m.take_changed() && !m.take_changed());
        // Unchanged bits: nothing happens.
        out.clear();
        m.scan(&img, 8, &mut out);
        assert!(out.is_empty() && !m.take_changed());
        // Bit 1 falls: cleared, listed inactive until acknowledged.
        sig("U21K0").write(&mut img, 0);
        m.scan(&img, 9, &mut out);
        assert_eq!(
            (out[0].entry.number, out[0].raised, out[0].tick),
            (1, false, 9)
        );
        assert_eq!(shown(&m)[0], (1, "lube low", 400, false, false, 7));
        assert_eq!(severity(0), 500);
        assert_eq!(severity(255), 1000);
    }

    #[test]
    fn acknowledge_pulses_the_bits_of_the_unacknowledged_messages_for_one_scan() {
        let mut m = messages();
        let mut img = image();
        let mut out = Vec::new();
        sig("U21K2").write(&mut img, 1);
        sig("U22K0").write(&mut img, 1);
        m.scan(&img, 3, &mut out);
        sig("U21K2").write(&mut img, 0);
        m.scan(&img, 4, &mut out);
        let mut forces = Forces::default();
        m.acknowledge(1, &mut forces);
        // Message 3 (gone) leaves the list; message 33 (active) stays acknowledged.
        assert_eq!(shown(&m), vec![(33, "PLC message 33", 500, true, true, 3)]);
        let mut scan = image();
        forces.apply_before(&mut scan);
        assert_eq!(sig("W0N0").read(&scan), 0b100);
        assert_eq!(sig("W1N0").read(&scan), 1);
        // The next boundary writes them back to 0; a second acknowledge has nothing new.
        m.end_pulse(&mut forces);
        m.acknowledge(1, &mut forces);
        forces.apply_before(&mut scan);
        assert_eq!((sig("W0N0").read(&scan), sig("W1N0").read(&scan)), (0, 0));
        // Another process's acknowledge writes nothing.
        m.end_pulse(&mut forces);
        m.acknowledge(2, &mut forces);
        let mut untouched = vec![0xAA; packets::PACKETS_LEN];
        forces.apply_before(&mut untouched);
        assert!(untouched.iter().all(|&b| b == 0xAA));
    }
}
