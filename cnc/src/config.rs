//! What the kernel takes from the characterization for one process: its coordinated axes with the
//! drive constants the plant and the following-error check need (GMxx KV, FRC Kvff/Kvffi, FQF,
//! SRV, MCZ), its spindle
//! (GMxx, TSM, POM), its M-function declarations (IOCFIL section 2) and GPS.

use std::collections::BTreeMap;

use characterization::axcfil::{Axcfil, Axis};
use characterization::iocfil::{Iocfil, Sequencing};
use packets::Signal;
use partprogram::MTiming;

use crate::following::SrvLimits;
use crate::servo::Gains;

/// One coordinated axis.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisConfig {
    /// Address letter.
    pub name: char,
    /// Position-loop gain KV (1/s) of GM0 (20 when not given).
    pub kv: f64,
    /// FRC Kvff: velocity feed-forward coefficient (1 when not given).
    pub kvff: f64,
    /// FRC Kvffi: integral coefficient (0 when not given).
    pub kvffi: f64,
    /// FQF: feed-forward filter bandwidth in Hz (0 = off, also when not given).
    pub fqf_hz: f64,
    /// SRV: the allowed following error at rest, moving with VFF and without (mm; 0 = unchecked).
    pub srv: SrvLimits,
    /// The axis has an MCZ homing cycle (else it counts as referenced at power-on).
    pub needs_homing: bool,
    /// MFC limit-switch inputs (+, −).
    pub limit_inputs: (Option<Signal>, Option<Signal>),
    /// Soft limits of LO1 (or LOP) (−, +) in mm: the zone while ZONE2 = 0.
    pub soft: (Option<f64>, Option<f64>),
    /// Soft limits of LO2 (−, +) in mm: the zone while ZONE2 = 1 (none without an LO2 record).
    pub soft2: (Option<f64>, Option<f64>),
    /// CUB: this axis's side of the protected box (−, +, space), mm (checked while CUB = 1).
    pub cub: Option<(f64, f64, f64)>,
    /// Acceleration of point-to-point moves (handwheel), mm/s²: MAN acc, else RAP fast_accel.
    pub accel: f64,
    /// Jog speed (MAN max_man_speed, mm/min; 1000 when not given).
    pub jog_speed: f64,
    /// The MCZ homing cycle, when the axis has one.
    pub home: Option<HomeConfig>,
}

impl AxisConfig {
    /// The position-loop constants: KV, Kvff, Kvffi, FQF.
    pub fn gains(&self) -> Gains {
        Gains {
            kv: self.kv,
            kvff: self.kvff,
            kvffi: self.kvffi,
            fqf_hz: self.fqf_hz,
        }
    }
}

/// MCZ: the homing cycle of an axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HomeConfig {
    /// The home switch input (high at rest, low while actuated).
    pub input: Option<Signal>,
    /// Search in the negative direction (MCZ direction 1).
    pub negative: bool,
    /// Search speed of stages 2 and 3 (mm/min).
    pub speed: f64,
    /// Distance between encoder reference marks: PAS mechanical pitch (mm).
    pub mark_pitch: f64,
}

/// The spindle of a process.
#[derive(Debug, Clone, PartialEq)]
pub struct SpindleConfig {
    /// Address letter.
    pub name: char,
    /// Top speed of range 1 (rev/min).
    pub vmax: f64,
    /// Top speed of every gear range GM1, GM2, … in range order (rev/min; 3000 when not given).
    pub ranges: Vec<f64>,
    /// The controlling axis of constant surface speed G96 (ASM; X when not given).
    pub master: char,
    /// Acceleration (rev/min per s) from TSM: 2·Vmax reversed in `max_inver_time`.
    pub accel: f64,
    /// POM max_deviation_speed (fraction; at speed within it).
    pub max_deviation: f64,
    /// POM input_speed: 1 when at the commanded speed.
    pub at_speed_signal: Option<Signal>,
    /// GMxx limit_speed (rev/min): below it the spindle counts as stopped.
    pub limit_speed: f64,
    /// GMxx input_speed_limit: 1 when stopped.
    pub stopped_signal: Option<Signal>,
}

/// One process.
#[derive(Debug, Clone, PartialEq)]
pub struct ProcessConfig {
    /// Process number 1..5.
    pub number: u8,
    /// Coordinated axes in process order.
    pub axes: Vec<AxisConfig>,
    /// The spindle, when the process has one.
    pub spindle: Option<SpindleConfig>,
    /// Declared M functions.
    pub m_timing: BTreeMap<u16, MTiming>,
    /// GPS = 1: S, T and the first M in parallel.
    pub parallel: bool,
    /// Interpolation tick in seconds.
    pub int_tick_s: f64,
    /// PGCFIL QFD: the alternative feed (mm/min) QCKFD selects (None: QCKFD is ignored).
    pub qfd: Option<f64>,
    /// IOCFIL ADV: handwheel channels 1 and 2 declared (external control from the PLC).
    pub handwheels: [bool; 2],
}

/// LOx number `n` as (−, +); both 0 (or absent) means no check (003:2480-2492).
fn zone(a: &Axis, n: u32) -> (Option<f64>, Option<f64>) {
    let z = a.lo.iter().find(|z| z.number == n).map(|z| (z.neg, z.pos));
    let z = if n == 1 {
        z.or(a.lop.map(|l| (l.b, l.a)))
    } else {
        z
    };
    match z {
        Some((Some(lo), Some(hi))) if lo == 0.0 && hi == 0.0 => (None, None),
        Some(z) => z,
        None => (None, None),
    }
}

fn axis_config(a: &Axis) -> AxisConfig {
    let gm0 = a.gm.iter().find(|g| g.range == 0);
    let srv = a.srv.unwrap_or([None; 3]);
    AxisConfig {
        name: a.name,
        kv: gm0.and_then(|g| g.kv).filter(|k| *k > 0.0).unwrap_or(20.0),
        kvff: a.frc.as_ref().map_or(1.0, |f| f.kvff),
        kvffi: a.frc.as_ref().map_or(0.0, |f| f.kvffi),
        fqf_hz: a.fqf.filter(|f| *f > 0.0).unwrap_or(0.0),
        srv: SrvLimits {
            standby: srv[0].unwrap_or(0.0),
            vff: srv[1].unwrap_or(0.0),
            no_vff: srv[2].unwrap_or(0.0),
        },
        needs_homing: a.mcz.is_some(),
        limit_inputs: a.mfc.unwrap_or((None, None)),
        soft: zone(a, 1),
        soft2: zone(a, 2),
        cub: a
            .cub
            .as_ref()
            .and_then(|z| Some((z.neg?, z.pos?, z.space.unwrap_or(0.0)))),
        accel: a
            .man
            .and_then(|m| m.b)
            .or(a.rap.and_then(|r| r.b))
            .filter(|v| *v > 0.0)
            .unwrap_or(1000.0),
        jog_speed: a
            .man
            .and_then(|m| m.a)
            .filter(|v| *v > 0.0)
            .unwrap_or(1000.0),
        home: a.mcz.as_ref().map(|m| HomeConfig {
            input: m.zero_input,
            negative: m.negative,
            speed: m.speed.filter(|v| *v > 0.0).unwrap_or(200.0),
            mark_pitch: a
                .pas
                .as_ref()
                .map(|p| p.mec_pitch)
                .filter(|v| *v > 0.0)
                .unwrap_or(5.0),
        }),
    }
}

fn spindle_config(a: &Axis) -> SpindleConfig {
    let gm1 = a.gm.iter().find(|g| g.range == 1).or(a.gm.first());
    let vmax = gm1.and_then(|g| g.vmax).unwrap_or(3000.0);
    let inver = a.tsm.and_then(|t| t.a).filter(|t| *t > 0.0).unwrap_or(2.0);
    let mut gms: Vec<_> = a.gm.iter().filter(|g| g.range >= 1).collect();
    gms.sort_by_key(|g| g.range);
    let mut ranges: Vec<f64> = gms.iter().map(|g| g.vmax.unwrap_or(3000.0)).collect();
    if ranges.is_empty() {
        ranges.push(vmax);
    }
    SpindleConfig {
        name: a.name,
        vmax,
        ranges,
        master: a
            .asm
            .as_deref()
            .and_then(|s| s.trim().chars().next())
            .map_or('X', |c| c.to_ascii_uppercase()),
        accel: 2.0 * vmax / inver,
        max_deviation: a.pom.as_ref().and_then(|p| p.max_deviation).unwrap_or(0.1),
        at_speed_signal: a.pom.as_ref().and_then(|p| p.input_speed),
        limit_speed: gm1
            .and_then(|g| g.limit_speed)
            .or(a.pom.as_ref().and_then(|p| p.limit_speed))
            .unwrap_or(20.0),
        stopped_signal: gm1.and_then(|g| g.input_speed_limit),
    }
}

impl ProcessConfig {
    /// Every process of the machine.
    pub fn all(axcfil: &Axcfil, iocfil: Option<&Iocfil>) -> Vec<ProcessConfig> {
        axcfil
            .processes
            .iter()
            .map(|p| {
                let io = iocfil.and_then(|f| f.process(p.number));
                let int_ticks = p.interpolators.first().map_or(1, |i| i.int_tick.max(1));
                ProcessConfig {
                    number: p.number.min(5) as u8,
                    axes: p
                        .axes
                        .iter()
                        .filter(|a| {
                            let t = a.axis_type();
                            !t.spindle() && t.coordinate
                        })
                        .map(axis_config)
                        .collect(),
                    spindle: p
                        .axes
                        .iter()
                        .find(|a| a.axis_type().spindle())
                        .map(spindle_config),
                    m_timing: io
                        .map(|io| {
                            io.m_functions
                                .iter()
                                .map(|f| {
                                    (
                                        u16::from(f.number),
                                        MTiming {
                                            m_type: f.m_type,
                                            m_request: f.m_request,
                                            class: f.class,
                                        },
                                    )
                                })
                                .collect()
                        })
                        .unwrap_or_default(),
                    parallel: io.is_some_and(|io| io.sequencing() == Sequencing::Parallel),
                    int_tick_s: f64::from(int_ticks) / 1000.0,
                    qfd: None,
                    handwheels: io
                        .and_then(|io| io.adv)
                        .map_or([false; 2], |adv| adv.map(|h| h.is_some())),
                }
            })
            .collect()
    }

    /// The axis letters in process order.
    pub fn axis_names(&self) -> Vec<char> {
        self.axes.iter().map(|a| a.name).collect()
    }
}
