//! Where the kernel reads and writes the PLC interface of one process: the fixed K/N signals of
//! plc-interface-map.md §1 and the project's request signals (mode request, USO, block skip, jog),
//! looked up by role in the interface map (`compiler/interface-map.toml` plus the machine's
//! `interface.toml`).
//!
//! A role the map does not give for a process is absent: the kernel neither writes it nor reads
//! it (reading an absent PLC→CNC level gives its inactive value: FOLD 0, RABI 1, overrides 100 %).

use packets::Signal;

use crate::handshake::Kind;

/// The strobe, FIN and code of one M, S or T channel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChannelSignals {
    /// The strobe (CNC → logic).
    pub strobe: Signal,
    /// The FIN (logic → CNC).
    pub fin: Signal,
    /// The code's first byte (M: 1 byte BCD; S: 4 bytes binary; T: 4 bytes BCD; little-endian).
    pub code: Signal,
}

/// The interface signals of one process.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ProcessSignals {
    /// M, S, T channels.
    pub channels: [Option<ChannelSignals>; 3],
    /// CNC→PLC: process ready (CONP).
    pub conp: Option<Signal>,
    /// CNC→PLC: distribution end (DEN).
    pub den: Option<Signal>,
    /// CNC→PLC: alarm active (ALARM).
    pub alarm: Option<Signal>,
    /// CNC→PLC: cycle running (CYCLE).
    pub cycle: Option<Signal>,
    /// CNC→PLC: feed hold reached (HOLD).
    pub hold: Option<Signal>,
    /// CNC→PLC: axes at rest (STANDBY).
    pub standby: Option<Signal>,
    /// CNC→PLC: the MODE byte.
    pub mode: Option<Signal>,
    /// CNC→PLC: immediate M code (MIMM).
    pub mimm: Option<Signal>,
    /// CNC→PLC: constant surface speed active (FG96).
    pub fg96: Option<Signal>,
    /// CNC→PLC: the spindle gear range needed (GEARREQ byte).
    pub gear_request: Option<Signal>,
    /// PLC→CNC: the spindle gear range engaged (GEARACK byte).
    pub gear_ack: Option<Signal>,
    /// PLC→CNC: alternative feed request (QCKFD).
    pub qckfd: Option<Signal>,
    /// PLC→CNC: feed hold (FOLD).
    pub fold: Option<Signal>,
    /// PLC→CNC: axis enables RABI1..8.
    pub rabi: [Option<Signal>; 8],
    /// PLC→CNC: cycle start (START, rising edge).
    pub start: Option<Signal>,
    /// PLC→CNC: external reset (ERS, rising edge).
    pub ers: Option<Signal>,
    /// PLC→CNC: feed, spindle and rapid override bytes (FOV, SOV, ROV).
    pub overrides: [Option<Signal>; 3],
    /// PLC→CNC: mode request byte (MODEREQ; a new value selects that mode).
    pub mode_request: Option<Signal>,
    /// PLC→CNC: optional stop enabled (USO).
    pub uso: Option<Signal>,
    /// PLC→CNC: block skip switch (BSKIP).
    pub block_skip: Option<Signal>,
    /// PLC→CNC: jog + and − per axis (JOGP1..8, JOGM1..8).
    pub jog: [[Option<Signal>; 8]; 2],
    /// PLC→CNC: incremental jog step byte (JINC).
    pub jog_increment: Option<Signal>,
    /// PLC→CNC: acceleration law bits ACC1 and ACC2 (`ACC1 ACC2` = 00 linear, 01 S, 10 exp).
    pub acc: [Option<Signal>; 2],
    /// PLC→CNC: handwheel permission (COMU).
    pub comu: Option<Signal>,
    /// PLC→CNC: the soft-limit zone (ZONE2, U10N1: 0 LO1, 1 LO2).
    pub zone2: Option<Signal>,
    /// PLC→CNC: the CUB protected-box check on (CUB, U10N0).
    pub cub: Option<Signal>,
    /// PLC→CNC: the axis of handwheel channels 1 and 2 (HW_AXIS1/2, W15N0/W15N1; 1-based).
    pub hw_axis: [Option<Signal>; 2],
    /// PLC→CNC: the handwheel scale byte (HW_SCALE, W15N2; a nibble per channel).
    pub hw_scale: Option<Signal>,
    /// PLC→CNC: handwheel channels 1 and 2 active (HW_ON1/2, U15N24/U15N25).
    pub hw_on: [Option<Signal>; 2],
}

/// Signals that belong to the machine, not to a process.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct MachineSignals {
    /// CNC→PLC: general reset active (RESET).
    pub reset: Option<Signal>,
    /// PLC→CNC: emergency stop, active low (ESTOP).
    pub estop: Option<Signal>,
}

/// The roles of the M, S and T channels: strobe, FIN, code.
pub const CHANNEL_ROLES: [[&str; 3]; 3] = [
    ["MSTB", "MFIN", "MCODE"],
    ["SSTB", "SFIN", "SCODE"],
    ["TSTB", "TFIN", "TCODE"],
];

/// The index of `kind` in [`ProcessSignals::channels`].
pub fn index(kind: Kind) -> usize {
    match kind {
        Kind::M => 0,
        Kind::S => 1,
        Kind::T => 2,
    }
}

impl ProcessSignals {
    /// The signals of a process from a role lookup (`lookup("FOLD")` → its address).
    pub fn from_roles(lookup: impl Fn(&str) -> Option<Signal>) -> ProcessSignals {
        let numbered = |prefix: &str| -> [Option<Signal>; 8] {
            std::array::from_fn(|i| lookup(&format!("{prefix}{}", i + 1)))
        };
        ProcessSignals {
            channels: CHANNEL_ROLES.map(|[s, f, c]| {
                Some(ChannelSignals {
                    strobe: lookup(s)?,
                    fin: lookup(f)?,
                    code: lookup(c)?,
                })
            }),
            conp: lookup("CONP"),
            den: lookup("DEN"),
            alarm: lookup("ALARM"),
            cycle: lookup("CYCLE"),
            hold: lookup("HOLD"),
            standby: lookup("STANDBY"),
            mode: lookup("MODE"),
            mimm: lookup("MIMM"),
            fg96: lookup("FG96"),
            gear_request: lookup("GEARREQ"),
            gear_ack: lookup("GEARACK"),
            fold: lookup("FOLD"),
            qckfd: lookup("QCKFD"),
            rabi: numbered("RABI"),
            start: lookup("START"),
            ers: lookup("ERS"),
            overrides: [lookup("FOV"), lookup("SOV"), lookup("ROV")],
            mode_request: lookup("MODEREQ"),
            uso: lookup("USO"),
            block_skip: lookup("BSKIP"),
            jog: [numbered("JOGP"), numbered("JOGM")],
            jog_increment: lookup("JINC"),
            acc: [lookup("ACC1"), lookup("ACC2")],
            comu: lookup("COMU"),
            zone2: lookup("ZONE2"),
            cub: lookup("CUB"),
            hw_axis: [lookup("HW_AXIS1"), lookup("HW_AXIS2")],
            hw_scale: lookup("HW_SCALE"),
            hw_on: [lookup("HW_ON1"), lookup("HW_ON2")],
        }
    }

    /// Every CNC→PLC signal the kernel writes for this process (for the sim.toml check).
    pub fn written(&self) -> Vec<Signal> {
        let mut v: Vec<Signal> = [
            self.conp,
            self.den,
            self.alarm,
            self.cycle,
            self.hold,
            self.standby,
            self.mode,
            self.mimm,
            self.fg96,
            self.gear_request,
        ]
        .into_iter()
        .flatten()
        .collect();
        for c in self.channels.iter().flatten() {
            v.push(c.strobe);
            v.push(c.code);
        }
        v
    }
}

/// Reads a bit or byte signal from `image`, `default` when absent.
pub fn read(image: &[u8], s: Option<Signal>, default: u8) -> u8 {
    s.map_or(default, |s| s.read(image))
}

/// Writes `value` to `s` when present.
pub fn write(image: &mut [u8], s: Option<Signal>, value: u8) {
    if let Some(s) = s {
        s.write(image, value);
    }
}

/// Writes `bytes` from the image byte of `first` on (codes wider than a byte).
pub fn write_bytes(image: &mut [u8], first: Signal, bytes: &[u8]) {
    let base = first.image_byte();
    for (i, b) in bytes.iter().enumerate() {
        if let Some(slot) = image.get_mut(base + i) {
            *slot = *b;
        }
    }
}
