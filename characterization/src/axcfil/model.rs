//! The typed model of AXCFIL: section 1 (CPU tick, processes, interpolators, drives), section 2
//! (one [`Axis`] per `NAS` subsection) and section 3 (geometric compensation tables).
//!
//! Every instruction keeps the span of its record so later rules can point at it. Empty
//! parameters are `None`; the manual's defaults are applied by the accessor methods, not here.

use std::ops::Range;

use packets::Signal;
use serde::{Deserialize, Serialize};

pub use super::axis_type::AxisType;

/// The whole AXCFIL.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Axcfil {
    /// NBP `proc_num`: number of processes (1…5).
    pub nbp: u32,
    /// NBP `SW_extension`, decoded.
    pub extension: Extension,
    /// TIM `CPU_tick` in ms.
    pub tim: u32,
    /// ACC (ECDF): acceleration-law coefficients, global for all processes.
    pub acc: Option<Acc>,
    /// The processes in the order of their section-1 `PRO`.
    pub processes: Vec<Process>,
}

impl Axcfil {
    /// Process `n` (1-based number as written in `PRO=n`).
    pub fn process(&self, n: u32) -> Option<&Process> {
        self.processes.iter().find(|p| p.number == n)
    }
}

/// NBP's second parameter: the arithmetic sum of 0, 1, 2 and ECDF.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Extension {
    /// The value as written.
    pub raw: u32,
    /// ECDF: extension functions (the instructions marked ECDF).
    pub ecdf: bool,
    /// 1: second layout of display page #7.
    pub page7_layout2: bool,
    /// 2: ADC module NC110-8АД 2000,12,28 enabled.
    pub adc_module: bool,
}

/// ACC (ECDF): S-curve and exponential acceleration coefficients.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Acc {
    /// acc_linear_part_S (> 0).
    pub linear_part_s: f64,
    /// acc_nonlinear_part_S (0…0.5).
    pub nonlinear_part_s: f64,
    /// acc_min_exp (> 0).
    pub min_exp: f64,
    /// acc_max_exp (> 0).
    pub max_exp: f64,
}

/// One process: its section-1 declarations, its section-2 axes and section-3 tables.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Process {
    /// Process number 1…5.
    pub number: u32,
    /// Span of the section-1 `PRO` record.
    pub span: Range<usize>,
    /// COM: axes shared with an earlier process.
    pub common: Vec<Common>,
    /// INx interpolators in file order.
    pub interpolators: Vec<Interpolator>,
    /// CAS: the drive-controlled axes in order.
    pub cas: Option<Cas>,
    /// Section-2 axes in file order.
    pub axes: Vec<Axis>,
    /// Section-3 compensation tables.
    pub compensation: Vec<Compensation>,
}

impl Process {
    /// The section-2 axis named `name`.
    pub fn axis(&self, name: char) -> Option<&Axis> {
        self.axes.iter().find(|a| a.name == name)
    }

    /// The interpolator that lists `name` as an axis or as its spindle.
    pub fn interpolator_of(&self, name: char) -> Option<&Interpolator> {
        self.interpolators
            .iter()
            .find(|i| i.axes.contains(&name) || i.spindle == Some(name))
    }

    /// Axes shared from other processes by COM.
    pub fn common_axes(&self) -> impl Iterator<Item = char> + '_ {
        self.common.iter().flat_map(|c| c.axes.iter().copied())
    }
}

/// COM: axes common with an earlier process.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Common {
    /// The process that defines the axes.
    pub process: u32,
    /// The shared axes.
    pub axes: Vec<char>,
    /// Span of the record.
    pub span: Range<usize>,
}

/// INx: one interpolator.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Interpolator {
    /// x of `INx`: the interpolator name.
    pub name: String,
    /// cpu_num (must be 1).
    pub cpu: u32,
    /// Interpolated axes in order (axis 1, 2, …).
    pub axes: Vec<char>,
    /// The spindle with encoder, if any.
    pub spindle: Option<char>,
    /// int_tick in ms.
    pub int_tick: u32,
    /// block_num: pre-computed profile blocks.
    pub block_num: u32,
    /// Span of the record.
    pub span: Range<usize>,
}

/// CAS: drive (servo) control.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Cas {
    /// cpu_num (must be 1).
    pub cpu: u32,
    /// The axes in order.
    pub axes: Vec<char>,
    /// servo_tick in ms.
    pub servo_tick: u32,
    /// Span of the record.
    pub span: Range<usize>,
}

/// TPA: axis type, switched-axis name, and the Р-ПД signals.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Tpa {
    /// The decoded type.
    pub axis_type: AxisType,
    /// switch_axis_name: the axis this one is switched onto.
    pub switch_axis: Option<String>,
    /// memory_signal (Р-ПД form).
    pub memory_signal: Option<Signal>,
    /// signal_recovery (Р-ПД form).
    pub signal_recovery: Option<Signal>,
    /// Span of the record.
    pub span: Range<usize>,
}

/// NTC: transducer (encoder) and converter (DAC/DPC) numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Ntc {
    /// trans: encoder number; `None` or 0 = no encoder.
    pub trans: Option<i32>,
    /// conv: converter number as written (`n`, `-(n+200)` 16-bit, `-(n+100)` 12-bit).
    pub conv: Option<i32>,
}

impl Ntc {
    /// True when an encoder is declared (trans ≠ 0).
    pub fn has_transducer(&self) -> bool {
        self.trans.is_some_and(|t| t != 0)
    }

    /// True when a converter channel is declared (conv ≠ 0).
    pub fn has_converter(&self) -> bool {
        self.conv.is_some_and(|c| c != 0)
    }

    /// The converter channel number and its resolution in bits, decoded from conv.
    pub fn channel(&self) -> Option<(u32, u8)> {
        let c = self.conv?;
        match c {
            1.. => Some((c as u32, 14)),
            ..=-201 => Some(((-c - 200) as u32, 16)),
            -199..=-101 => Some(((-c - 100) as u32, 12)),
            _ => None,
        }
    }
}

/// A pair of reals (RAP, MAN, POS, LOP, TSM, …): both optional because either may be empty.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Pair {
    /// First parameter.
    pub a: Option<f64>,
    /// Second parameter.
    pub b: Option<f64>,
}

/// GAS: backlash and dead zone (ECDF: zero-drift signals).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Gas {
    /// axis_bck1: backlash.
    pub backlash: Option<f64>,
    /// dead_zone.
    pub dead_zone: Option<f64>,
    /// zero_drift_read (ECDF).
    pub zero_drift_read: Option<Signal>,
    /// zero_drift_cor (ECDF).
    pub zero_drift_cor: Option<Signal>,
}

/// PAS (section 2): electrical and mechanical pitch (ECDF: tool magazine).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Pas {
    /// el_pitch: counts per mechanical pitch.
    pub el_pitch: f64,
    /// mec_pitch: distance (or positions, or spindle revolutions) per el_pitch counts.
    pub mec_pitch: f64,
    /// rev_num_motor (ECDF): motor revolutions per tool-magazine revolution.
    pub rev_num_motor: Option<f64>,
    /// start_point_# (ECDF): first position number.
    pub start_point: Option<f64>,
}

/// SKW: master of a slave parallel axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Skw {
    /// master_axis.
    pub master: String,
    /// SKEW: maximum asymmetry.
    pub skew: Option<f64>,
    /// KDS: reference-mark offset in counts.
    pub kds: Option<f64>,
    /// SGAN: skew-compensation gain (0 = off).
    pub sgan: Option<f64>,
}

/// MCZ: homing (KKRM form with HDBRP and Δs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Mcz {
    /// zero_input: home switch signal.
    pub zero_input: Option<Signal>,
    /// direction: false = positive, true = negative.
    pub negative: bool,
    /// speed: search speed.
    pub speed: Option<f64>,
    /// HDBRP (KKRM), default 20 mm.
    pub hdbrp: Option<f64>,
    /// Δs (KKRM).
    pub delta_s: Option<f64>,
}

/// GMxx: speed, reference voltage, gain of range xx (ECDF: speed threshold signal).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Gm {
    /// xx: 0 for non-spindle axes, 1…99 = spindle range.
    pub range: u32,
    /// Vmax.
    pub vmax: Option<f64>,
    /// KC: reference voltage at Vmax.
    pub kc: Option<f64>,
    /// KV: gain.
    pub kv: Option<f64>,
    /// limit_speed (ECDF).
    pub limit_speed: Option<f64>,
    /// input_speed_limit (ECDF).
    pub input_speed_limit: Option<Signal>,
}

/// FRC (ECDF): friction compensation and loop coefficients.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Frc {
    /// t_ffa in ms.
    pub t_ffa: Option<u32>,
    /// ΔVmax, ΔVmin, A1, A2, A3.
    pub values: [Option<f64>; 5],
    /// Kvff (default 1).
    pub kvff: f64,
    /// Kvffi (default 0).
    pub kvffi: f64,
    /// input_ffa.
    pub input_ffa: Option<Signal>,
}

/// A zone with limits and an allowance (LOx, CUB).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Zone {
    /// Number (x of LOx; 0 for CUB).
    pub number: u32,
    /// Positive limit.
    pub pos: Option<f64>,
    /// Negative limit.
    pub neg: Option<f64>,
    /// space.
    pub space: Option<f64>,
}

/// SWx (ECDF): software cam.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Cam {
    /// x: 1…8.
    pub number: u32,
    /// pos_limit_SW.
    pub pos: Option<f64>,
    /// neg_limit_SW.
    pub neg: Option<f64>,
    /// input_SW.
    pub signal: Option<Signal>,
}

/// POM: spindle orientation (ECDF: speed monitoring).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Pom {
    /// spiaz: orientation angle in revolutions.
    pub spiaz: Option<f64>,
    /// limit_speed.
    pub limit_speed: Option<f64>,
    /// max_deviation_speed (ECDF), 0…1.
    pub max_deviation: Option<f64>,
    /// input_speed (ECDF).
    pub input_speed: Option<Signal>,
}

/// ZNO: home offset, travel counter, reference-mark distance.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Zno {
    /// null_offset.
    pub null_offset: Option<f64>,
    /// distance.
    pub distance: Option<f64>,
    /// input_distance.
    pub input_distance: Option<Signal>,
    /// DBRP.
    pub dbrp: Option<f64>,
}

/// FBF: encoder fault detection.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Fbf {
    /// space (default mec_pitch).
    pub space: Option<f64>,
    /// time in s (default 400 servo ticks).
    pub time: Option<f64>,
    /// input_break_wire.
    pub input_break_wire: Option<Signal>,
    /// status_break_wire.
    pub status_break_wire: Option<bool>,
}

/// HWC: correction handwheel / correction axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Hwc {
    /// HW_axis_name.
    pub axis: String,
    /// input_enable_HW.
    pub enable: Option<Signal>,
    /// input_correction_reset (x.86 form).
    pub reset: Option<Signal>,
    /// input_select_HW_axis_mode (x.86 form).
    pub mode: Option<Signal>,
}

/// GRA: Gray-code encoder inputs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Gra {
    /// LSB input (default I0A0).
    pub input: Option<Signal>,
    /// Number of bits (default 12).
    pub bits: Option<u32>,
}

/// ADG: air-gap mode.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Adg {
    /// CHN_N_ADC.
    pub channel: Option<i32>,
    /// U_near.
    pub u_near: Option<f64>,
    /// U_far.
    pub u_far: Option<f64>,
    /// remember_air_gap, set_mode_air_gap, air_gap_status, indication_air_gap.
    pub signals: [Option<Signal>; 4],
}

/// ADP: spindle load levels.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Adp {
    /// number_ADC.
    pub channel: Option<i32>,
    /// P_100.
    pub p100: Option<f64>,
    /// P_level_1.
    pub level1: Option<f64>,
    /// P_level_2.
    pub level2: Option<f64>,
}

/// LAS: laser power control (13 parameters, kept as written).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Las {
    /// CHN_N_PV, P_min, V_lim_min, P_max, V_lim_max.
    pub power: (Option<i32>, [Option<f64>; 4]),
    /// set_P_control.
    pub set_p_control: Option<Signal>,
    /// The pulse generator: CHN_N_G, N_TIK_hig, U_hig, N_TIK_low, U_low.
    pub generator: PulseGenerator,
    /// set_G_control.
    pub set_g_control: Option<Signal>,
    /// P_O.
    pub override_percent: Option<f64>,
}

/// LAS pulse generator on a DAC/DPC channel.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct PulseGenerator {
    /// CHN_N_G: the channel.
    pub channel: Option<i32>,
    /// N_TIK_hig: CPU ticks at the high level.
    pub ticks_high: Option<i32>,
    /// U_hig: high-level voltage.
    pub u_high: Option<f64>,
    /// N_TIK_low: CPU ticks at the low level.
    pub ticks_low: Option<i32>,
    /// U_low: low-level voltage.
    pub u_low: Option<f64>,
}

/// A `file/MPx` reference (FTP, FEG).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct FileRef {
    /// File name.
    pub file: String,
    /// x of MPx.
    pub mp: u8,
}

/// One section-2 axis subsection (`NAS=name` and what follows).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    /// The axis name.
    pub name: char,
    /// Span of the NAS record.
    pub span: Range<usize>,
    /// TPA.
    pub tpa: Option<Tpa>,
    /// NTC.
    pub ntc: Option<Ntc>,
    /// RAP: fast_speed, fast_accel.
    pub rap: Option<Pair>,
    /// GAS.
    pub gas: Option<Gas>,
    /// VGAS: speed and the two signals.
    pub vgas: Option<(Option<f64>, Option<Signal>, Option<Signal>)>,
    /// PAS.
    pub pas: Option<Pas>,
    /// SKW.
    pub skw: Option<Skw>,
    /// MCZ.
    pub mcz: Option<Mcz>,
    /// POS: pos_allow, wait_pos.
    pub pos: Option<Pair>,
    /// SRV: stand-by, with VFF, without VFF.
    pub srv: Option<[Option<f64>; 3]>,
    /// MAN: max_man_speed, max_accel.
    pub man: Option<Pair>,
    /// MSS: Vmin.
    pub mss: Option<f64>,
    /// GMxx by range.
    pub gm: Vec<Gm>,
    /// FRC.
    pub frc: Option<Frc>,
    /// LOP: pos, neg.
    pub lop: Option<Pair>,
    /// LO1/LO2.
    pub lo: Vec<Zone>,
    /// MFC: + and − limit inputs.
    pub mfc: Option<(Option<Signal>, Option<Signal>)>,
    /// AFC: acc_MFC.
    pub afc: Option<f64>,
    /// CUB.
    pub cub: Option<Zone>,
    /// SW1…SW8.
    pub cams: Vec<Cam>,
    /// TSM: max_inver_time, max_inver_ref.
    pub tsm: Option<Pair>,
    /// ASM: master axis.
    pub asm: Option<String>,
    /// POM.
    pub pom: Option<Pom>,
    /// ADP.
    pub adp: Option<Adp>,
    /// ZNO.
    pub zno: Option<Zno>,
    /// FBF.
    pub fbf: Option<Fbf>,
    /// HWC.
    pub hwc: Option<Hwc>,
    /// ATR: resolution ST, MT.
    pub atr: Option<(Option<u32>, Option<u32>)>,
    /// GRA.
    pub gra: Option<Gra>,
    /// FOPP: input.
    pub fopp: Option<Signal>,
    /// FTP: position-correction file.
    pub ftp: Option<FileRef>,
    /// ADG.
    pub adg: Option<Adg>,
    /// LAS.
    pub las: Option<Las>,
    /// FQF: position-loop filter in Hz (0 = off).
    pub fqf: Option<f64>,
    /// The instructions of the subsection in file order with their spans (for order rules).
    #[serde(skip)]
    pub order: Vec<(String, Range<usize>)>,
}

impl Axis {
    /// The decoded axis type (all flags off when TPA is missing).
    pub fn axis_type(&self) -> AxisType {
        self.tpa.as_ref().map(|t| t.axis_type).unwrap_or_default()
    }

    /// True when NTC declares an encoder.
    pub fn has_transducer(&self) -> bool {
        self.ntc.is_some_and(|n| n.has_transducer())
    }

    /// Span of the first record with key `key` in this subsection.
    pub fn span_of(&self, key: &str) -> Option<Range<usize>> {
        self.order
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, s)| s.clone())
    }

    /// Position of the first record with key `key` in the subsection.
    pub fn index_of(&self, key: &str) -> Option<usize> {
        self.order.iter().position(|(k, _)| k == key)
    }
}

/// A section-3 compensation table (`NAS` or `NAC`, `PAS`, `Ennn`/`FEG`, `NM0`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Compensation {
    /// The corrected axis.
    pub axis: char,
    /// NAC: the master axis whose position drives the correction.
    pub master: Option<char>,
    /// PAS: correction pitch.
    pub pitch: Option<f64>,
    /// Ennn points: (nnn, error).
    pub points: Vec<(u32, f64)>,
    /// FEG: the points are in this file.
    pub file: Option<FileRef>,
    /// NM0: the reference point number nnn.
    pub reference: Option<u32>,
    /// Span of the NAS/NAC record.
    pub span: Range<usize>,
}
