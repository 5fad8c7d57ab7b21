//! The typed IOCFIL model: packet-A connectors, PLC timing, per-process M functions and PLC-handled
//! equipment, and the packet-T initial bytes.

use serde::{Deserialize, Serialize};

/// One `INx` or `OUx` instruction: up to eight packet-A connectors.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ConnectorGroup {
    /// The instruction number x (0…3).
    pub index: u8,
    /// The connectors written, in order (empty fields left out).
    pub connectors: Vec<u16>,
}

/// Decoded bits of an M declaration (Tables 6.1 and 6.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct MFlags {
    /// m_type 01: executed before the motion of the block.
    pub before_motion: bool,
    /// m_type 02: executed after the motion.
    pub after_motion: bool,
    /// m_type 04: processed in the STOP state.
    pub in_stop: bool,
    /// m_type 08: not displayed.
    pub hidden: bool,
    /// m_type 10: immediate action (BCD code to W3K1 during continuous mode, no handshake).
    pub immediate: bool,
    /// m_type 40: modal.
    pub modal: bool,
    /// m_type 80: displayed after reset.
    pub shown_after_reset: bool,
    /// m_request 02: stop at end of block when USO=1 (M01).
    pub optional_stop: bool,
    /// m_request 04: blocks the calculation (look-ahead) until finished.
    pub blocks_calculation: bool,
    /// m_request 08: stop at end of block (M00).
    pub stop_at_end: bool,
    /// m_request 10: tool-offset change request.
    pub tool_offset_request: bool,
    /// m_request 20: reset request at end of execution (M02, M30).
    pub reset_request: bool,
    /// m_request 80: end of part machining (ARMD PartFinish).
    pub part_finish: bool,
}

impl MFlags {
    /// Decodes `m_type` and `m_request`.
    pub fn decode(m_type: u8, m_request: u8) -> Self {
        MFlags {
            before_motion: m_type & 0x01 != 0,
            after_motion: m_type & 0x02 != 0,
            in_stop: m_type & 0x04 != 0,
            hidden: m_type & 0x08 != 0,
            immediate: m_type & 0x10 != 0,
            modal: m_type & 0x40 != 0,
            shown_after_reset: m_type & 0x80 != 0,
            optional_stop: m_request & 0x02 != 0,
            blocks_calculation: m_request & 0x04 != 0,
            stop_at_end: m_request & 0x08 != 0,
            tool_offset_request: m_request & 0x10 != 0,
            reset_request: m_request & 0x20 != 0,
            part_finish: m_request & 0x80 != 0,
        }
    }
}

/// `Mxx=m_type,m_request,class`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct MFunction {
    /// M number 0…99.
    pub number: u8,
    /// Type bits (Table 6.1).
    pub m_type: u8,
    /// Execution-mode bits (Table 6.2).
    pub m_request: u8,
    /// Class byte: high nibble memorized-search class, low nibble display class.
    pub class: u8,
    /// The decoded bits.
    pub flags: MFlags,
}

impl MFunction {
    /// Display class (low nibble; 0 = not displayed).
    pub fn display_class(&self) -> u8 {
        self.class & 0x0F
    }
    /// Memorized-search class (high nibble; 0 = not memorized).
    pub fn search_class(&self) -> u8 {
        self.class >> 4
    }
}

/// S/T/M sequencing of GPS.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Sequencing {
    /// GPS=0 (default): S, T, then the before-motion M functions one after another.
    #[default]
    Sequential,
    /// GPS=1: S, T and the first M of the block in parallel.
    Parallel,
}

/// `TAx`: a point-to-point axis handled by the PLC.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PtpAxis {
    /// x, 1…8: the number the PLC uses to activate the axis.
    pub number: u8,
    /// Axis name (declared in AXCFIL).
    pub axis: char,
    /// Table 6.4 bits.
    pub axis_type: u8,
    /// Phase offset in positions.
    pub phase_disp: Option<f64>,
    /// Number of positions.
    pub positions: Option<f64>,
    /// First slow-down threshold / limit_1.
    pub limit_1: Option<f64>,
    /// Second slow-down threshold / limit_2.
    pub limit_2: Option<f64>,
}

impl PtpAxis {
    /// Bit 0: with DAC/DPC.
    pub fn has_dac(&self) -> bool {
        self.axis_type & 1 != 0
    }
    /// Bit 1: rotary.
    pub fn rotary(&self) -> bool {
        self.axis_type & 2 != 0
    }
    /// Bits 3,2 = 10 or 11: absolute axis (resolver or encoder).
    pub fn absolute(&self) -> bool {
        self.axis_type & 0x08 != 0
    }
}

/// `ASx`: an index axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct IndexAxis {
    /// x, 1…3.
    pub number: u8,
    /// Axis name used in programming.
    pub axis: char,
    /// false = absolute (target position), true = incremental (number of positions).
    pub incremental: bool,
    /// false = rotary, true = linear.
    pub linear: bool,
    /// Number of positions.
    pub positions: u32,
}

/// One `ADV` channel: a handwheel axis (encoder channel) or `0` (electronic-handwheel connector).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Handwheel {
    /// `0`: the standard electronic-handwheel channel or panel handwheel.
    Electronic,
    /// A handwheel axis defined in AXCFIL, connected through an encoder channel.
    Axis(char),
}

/// Everything IOCFIL says about one process (sections 2 and 3).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct IoProcess {
    /// Process number 1…5.
    pub number: u32,
    /// Declared M functions in file order.
    pub m_functions: Vec<MFunction>,
    /// GPS, `None` = default sequential.
    pub gps: Option<Sequencing>,
    /// ASM: spindle axis.
    pub spindle: Option<char>,
    /// TAx.
    pub ptp_axes: Vec<PtpAxis>,
    /// ASx.
    pub index_axes: Vec<IndexAxis>,
    /// UCDA: axes whose DAC voltage the PLC sets.
    pub ucda: Vec<char>,
    /// ADV: handwheel of channel 1 and 2.
    pub adv: Option<[Option<Handwheel>; 2]>,
    /// CWD: PLC-side tasks disabled (bit sum).
    pub cwd: Option<u16>,
    /// ADC channels 1…8 readable with ADR.
    pub adc: Vec<i32>,
    /// DAC channels 1…16 (−201…−216 for 16-bit converters) writable with DAW.
    pub dac: Vec<i32>,
}

impl IoProcess {
    /// The declaration of M`number`.
    pub fn m_function(&self, number: u8) -> Option<&MFunction> {
        self.m_functions.iter().find(|m| m.number == number)
    }
    /// GPS or its default.
    pub fn sequencing(&self) -> Sequencing {
        self.gps.unwrap_or_default()
    }
}

/// One `Txx=value` of section 4.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct TRecord {
    /// xx, 1…64.
    pub record: u8,
    /// Byte value.
    pub value: u8,
}

/// A whole IOCFIL.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct Iocfil {
    /// ALM: present = PLC loaded and started at power-on ("operation" mode).
    pub alm: Option<u16>,
    /// INx instructions.
    pub inputs: Vec<ConnectorGroup>,
    /// OUx instructions.
    pub outputs: Vec<ConnectorGroup>,
    /// CLO tick_logic: period of the PLC (fast and slow parts, timers), ms; 0 when CLO is missing.
    pub tick_logic_ms: u32,
    /// CLO time_slow: slow-logic budget within each tick, ms; 0 when CLO is missing.
    pub time_slow_ms: u32,
    /// SPL: number of symbolic PLC names.
    pub spl: Option<u32>,
    /// Processes in ascending number.
    pub processes: Vec<IoProcess>,
    /// Section 4 in file order.
    pub t_records: Vec<TRecord>,
}

impl Iocfil {
    /// Packet-A input connectors of all INx, in declaration order.
    pub fn input_connectors(&self) -> Vec<u16> {
        self.inputs
            .iter()
            .flat_map(|g| g.connectors.iter().copied())
            .collect()
    }
    /// Packet-A output connectors of all OUx, in declaration order.
    pub fn output_connectors(&self) -> Vec<u16> {
        self.outputs
            .iter()
            .flat_map(|g| g.connectors.iter().copied())
            .collect()
    }
    /// SPL or its default 1.
    pub fn spl_or_default(&self) -> u32 {
        self.spl.unwrap_or(1)
    }
    /// True when ALM is written: the PLC is loaded automatically and operator compiles are refused.
    pub fn plc_autoload(&self) -> bool {
        self.alm.is_some()
    }
    /// Packet-T bytes: (byte index 0…63 = W(i div 4)T(i mod 4), value), sorted by index.
    pub fn t_bytes(&self) -> Vec<(usize, u8)> {
        let mut v: Vec<(usize, u8)> = self
            .t_records
            .iter()
            .map(|t| (usize::from(t.record) - 1, t.value))
            .collect();
        v.sort_unstable();
        v
    }
    /// The process with `number`.
    pub fn process(&self, number: u32) -> Option<&IoProcess> {
        self.processes.iter().find(|p| p.number == number)
    }
}
