//! The drives' per-tick logic without I/O: commands → RPDOs, TPDOs/EMCY/heartbeats → feedback.
//!
//! [`DriveSet`] is what a master task embeds: before each SYNC it takes [`DriveSet::rpdos`] (one
//! RPDO1 per started drive: controlword and the scaled target of this tick's set point), after it
//! it feeds every received frame to [`DriveSet::on_frame`] and calls [`DriveSet::after_sync`]
//! (heartbeat consumer, missing TPDOs, enable timeout). A statusword with the fault bit or an EMCY
//! frame makes the drive faulted and asks (once) for `603Fh` by SDO; the answer fills the fault's
//! code. A lost heartbeat, a refused enable or a drive that leaves NMT *operational* (once it had
//! one heartbeat consumer time since the NMT start to report it) is a latched fault too, cleared
//! only by a fault reset once the cause is gone. Feedback is *healthy* only
//! while the drive is operational, unfaulted and answered the last SYNC: the position of any
//! other drive is the last healthy one, never a value from the faulted or silent drive.
//!
//! A `csp` drive also has the homing PDOs (see [`super::startup::homing_pdos`]): before each
//! SYNC its RPDO2 carries the touch probe function (probe 1 armed on the encoder's zero impulse,
//! positive edge, first event, while [`DriveCommand::probe`]), and it has answered a SYNC only
//! when TPDO1, TPDO2 (probe status and latched position) and TPDO3 (digital inputs) all came.
//!
//! **Late answers.** A TPDO carries no SYNC number, but a drive answers its SYNCs in order. A
//! SYNC whose TPDO of a kind did not come before the next SYNC is sent is *owed*: the drive's next
//! frame of that kind is that late answer and is dropped (it is not the answer to the SYNC now on
//! the bus, and its position is older than that SYNC's target), until nothing is owed. So a late
//! answer makes a SYNC unhealthy, never a stale position healthy. A drive whose answers are
//! lost rather than late would have every later answer taken as owed: when it has not once
//! answered a SYNC in time for a heartbeat consumer time, what it owes is written off.

use tokio::time::{Duration, Instant};

use super::super::{CanMsg, cob, nmt, sdo};
use super::cia402::{self, Request, State};
use crate::map::{CanDrive, DriveMode};

/// Ticks a drive may take from the enable request to *Operation enabled* before it is a fault.
pub const ENABLE_TICKS: u32 = 20;
/// The heartbeat consumer time is this many producer times.
pub const HEARTBEAT_FACTOR: u32 = 2;
/// `60B8h` touch probe function: probe 1 enabled (bit 0), first event (bit 1 = 0), triggered
/// by the encoder's zero impulse (bits 2–3 = 01), sampling on the positive edge (bit 4).
pub const PROBE_ZERO_IMPULSE: u16 = 0x0015;
/// `60B9h` bit 1: touch probe 1 has stored a position at the positive edge.
pub const PROBE_STORED: u16 = 0x0002;
/// `60FDh` bit 2: the home switch.
pub const INPUT_HOME_SWITCH: u32 = 0x0004;
/// CiA 301 EMCY code "life guard error or heartbeat error", used for a lost heartbeat.
pub const CODE_HEARTBEAT: u16 = 0x8130;
/// CiA 301 EMCY code "communication error" (the drive left NMT operational).
pub const CODE_NMT: u16 = 0x8100;
/// Manufacturer-neutral code used for a drive that did not enable within [`ENABLE_TICKS`].
pub const CODE_ENABLE: u16 = 0xFF01;

/// An axis, by process and name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct AxisId {
    /// Process number (1..5).
    pub process: u32,
    /// Axis name.
    pub name: char,
}

impl AxisId {
    /// Axis `name` of process 1.
    pub fn new(name: char) -> AxisId {
        AxisId { process: 1, name }
    }
}

/// What the controller commands one drive for one tick.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DriveCommand {
    /// The set point in axis units: position (mm, degree) for `csp`, speed (units per second,
    /// revolutions per second for a spindle) for `csv`.
    pub set_point: f64,
    /// Power the axis.
    pub enable: bool,
    /// Quick stop (ESTOP).
    pub quick_stop: bool,
    /// Fault reset (RESET).
    pub fault_reset: bool,
    /// Arm touch probe 1 on the encoder's zero impulse (`60B8h` = [`PROBE_ZERO_IMPULSE`]; 0
    /// when false, which disarms it: the next arming latches afresh).
    pub probe: bool,
}

/// Why a drive is faulted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FaultCause {
    /// The drive reports a fault (statusword bit 3 or an EMCY frame); `code` is its `603Fh`.
    Drive,
    /// No heartbeat within the consumer time.
    HeartbeatLost,
    /// The drive left NMT operational.
    NotOperational,
    /// The drive did not reach *Operation enabled* within [`ENABLE_TICKS`] of the request.
    EnableRefused,
}

/// A drive fault: node, code and cause.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DriveFault {
    /// Node id.
    pub node: u8,
    /// Error code: `603Fh` (or the EMCY code until it is read) for a drive fault, else the
    /// CiA 301 code of the cause (`8130h` heartbeat, `8100h` NMT, `FF01h` enable refused).
    pub code: u16,
    /// The cause.
    pub cause: FaultCause,
}

/// What the master knows of one drive after a SYNC.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DriveFeedback {
    /// Actual position in axis units (`6064h` / counts_per_unit; `csp` only), the last healthy one.
    pub position: f64,
    /// Actual velocity in axis units per second (`606Ch` for `csv`; the position difference per
    /// tick for `csp`).
    pub velocity: f64,
    /// The CiA 402 state of the last statusword.
    pub state: State,
    /// The fault, when there is one.
    pub fault: Option<DriveFault>,
    /// True when this feedback is a fresh value from an operational, unfaulted drive.
    pub healthy: bool,
    /// The digital inputs `60FDh` of the last healthy answer (`csp`; bit 2: home switch).
    pub inputs: u32,
    /// The touch probe status `60B9h` of the last healthy answer (`csp`).
    pub probe_status: u16,
    /// The touch probe's latched position `60BAh` in axis units (meaningful while
    /// `probe_status` has [`PROBE_STORED`]).
    pub probe_position: f64,
}

#[derive(Debug, Clone)]
struct Slot {
    cfg: CanDrive,
    id: AxisId,
    cmd: DriveCommand,
    last_cw: u16,
    statusword: u16,
    state: State,
    actual: i32,
    have_actual: bool,
    position: f64,
    velocity: f64,
    fresh: bool,
    /// The homing PDOs (TPDO2, TPDO3) of this SYNC arrived (always true without them).
    fresh_homing: [bool; 2],
    inputs: u32,
    probe_status: u16,
    probe_value: i32,
    nmt: u8,
    last_hb: Option<Instant>,
    fault: Option<DriveFault>,
    code_asked: bool,
    /// The `603Fh` read is on the wire and unanswered (waited for within the tick only).
    code_wait: bool,
    enable_ticks: u32,
    /// A SYNC was sent since the start (the answers before it owe nothing).
    synced: bool,
    /// Per TPDO (1, 2, 3): answers of earlier SYNCs that did not come before the next SYNC.
    owed: [u32; 3],
    /// Since when the drive owes answers without having answered a SYNC in time.
    behind_since: Option<Instant>,
}

/// The drives of one bus and their per-tick logic.
#[derive(Debug, Clone)]
pub struct DriveSet {
    slots: Vec<Slot>,
    tick: Duration,
    started: Option<Instant>,
}

impl DriveSet {
    /// The drives of `drives`, with SYNC every `tick`; none is started yet.
    pub fn new(drives: &[CanDrive], tick: Duration) -> DriveSet {
        let slots = drives
            .iter()
            .map(|d| Slot {
                cfg: d.clone(),
                id: AxisId {
                    process: d.process,
                    name: d.axis,
                },
                cmd: DriveCommand::default(),
                last_cw: 0,
                statusword: 0,
                state: State::NotReadyToSwitchOn,
                actual: 0,
                have_actual: false,
                position: 0.0,
                velocity: 0.0,
                fresh: false,
                fresh_homing: [false; 2],
                inputs: 0,
                probe_status: 0,
                probe_value: 0,
                nmt: nmt::PRE_OPERATIONAL,
                last_hb: None,
                fault: None,
                code_asked: false,
                code_wait: false,
                enable_ticks: 0,
                synced: false,
                owed: [0; 3],
                behind_since: None,
            })
            .collect();
        DriveSet {
            slots,
            tick,
            started: None,
        }
    }

    /// Marks the drives started at `now` with their start-up statuswords (in drive order).
    pub fn started(&mut self, now: Instant, statuswords: &[u16]) {
        self.started = Some(now);
        for (s, sw) in self.slots.iter_mut().zip(statuswords) {
            s.statusword = *sw;
            s.state = State::from_statusword(*sw);
            s.nmt = nmt::OPERATIONAL;
            s.last_hb.get_or_insert(now);
        }
    }

    /// The axes, in drive order.
    pub fn axes(&self) -> impl Iterator<Item = AxisId> + '_ {
        self.slots.iter().map(|s| s.id)
    }

    /// Sets the command of `axis` for the next SYNC; false when no drive has that axis.
    pub fn command(&mut self, axis: AxisId, cmd: DriveCommand) -> bool {
        match self.slots.iter_mut().find(|s| s.id == axis) {
            Some(s) => {
                s.cmd = cmd;
                true
            }
            None => false,
        }
    }

    /// The feedback of `axis` as of the last SYNC.
    pub fn feedback(&self, axis: AxisId) -> Option<DriveFeedback> {
        self.slots
            .iter()
            .find(|s| s.id == axis)
            .map(|s| DriveFeedback {
                position: s.position,
                velocity: s.velocity,
                state: s.state,
                fault: s.fault,
                healthy: s.answered() && s.fault.is_none() && !s.state.is_fault(),
                inputs: s.inputs,
                probe_status: s.probe_status,
                probe_position: f64::from(s.probe_value) / s.cfg.counts_per_unit,
            })
    }

    /// The RPDO1 of every drive for this tick (controlword + scaled target); call once per
    /// tick, right before the SYNC, at `now`. Marks every drive's feedback stale until its TPDO
    /// arrives.
    pub fn rpdos(&mut self, now: Instant) -> Vec<CanMsg> {
        let mut out = Vec::with_capacity(self.slots.len());
        for s in &mut self.slots {
            let req = Request {
                enable: s.cmd.enable,
                quick_stop: s.cmd.quick_stop,
                fault_reset: s.cmd.fault_reset,
            };
            // A latched fault of the master's own (heartbeat, enable) keeps the drive off until
            // the controller resets it.
            let state = match s.fault {
                Some(f) if f.cause != FaultCause::Drive => {
                    if s.cmd.fault_reset && cause_gone(s, f.cause, now) {
                        s.fault = None;
                        s.enable_ticks = 0;
                        s.state
                    } else {
                        State::Fault
                    }
                }
                _ => s.state,
            };
            let word = if s
                .fault
                .is_some_and(|f| f.cause == FaultCause::HeartbeatLost)
            {
                cia402::cw::QUICK_STOP
            } else {
                cia402::controlword(state, req, s.last_cw)
            };
            s.last_cw = word;
            let target = scale(s.cmd.set_point, s.cfg.counts_per_unit);
            let mut d = [0u8; 6];
            d[..2].copy_from_slice(&word.to_le_bytes());
            d[2..].copy_from_slice(&target.to_le_bytes());
            out.push(CanMsg::new(cob::rpdo(1, s.cfg.node_id), &d));
            s.owe_missing(now);
            s.fresh = false;
            if s.homing() {
                let probe = if s.cmd.probe { PROBE_ZERO_IMPULSE } else { 0 };
                out.push(CanMsg::new(
                    cob::rpdo(2, s.cfg.node_id),
                    &probe.to_le_bytes(),
                ));
                s.fresh_homing = [false; 2];
            }
        }
        out
    }

    /// Handles one received frame; returns frames to send (the `603Fh` read of a faulted drive).
    pub fn on_frame(&mut self, m: &CanMsg, now: Instant) -> Vec<CanMsg> {
        let mut out = Vec::new();
        if m.extended || m.rtr {
            return out;
        }
        let id = m.id as u16;
        let d = m.payload();
        for s in &mut self.slots {
            let node = s.cfg.node_id;
            let kind = [1, 2, 3].into_iter().position(|p| id == cob::tpdo(p, node));
            if let Some(k) = kind
                && s.owed[k] > 0
            {
                // The late answer to an earlier SYNC: not this SYNC's.
                s.owed[k] -= 1;
            } else if id == cob::tpdo(1, node) && d.len() >= 6 {
                let sw = u16::from_le_bytes([d[0], d[1]]);
                let value = i32::from_le_bytes([d[2], d[3], d[4], d[5]]);
                s.statusword = sw;
                s.state = State::from_statusword(sw);
                if s.state.is_fault() {
                    if s.fault.is_none_or(|f| f.cause != FaultCause::Drive) {
                        s.fault = Some(DriveFault {
                            node,
                            code: 0,
                            cause: FaultCause::Drive,
                        });
                    }
                } else if s.fault.is_some_and(|f| f.cause == FaultCause::Drive) {
                    // The drive left Fault (after a reset): the fault is over.
                    s.fault = None;
                    s.code_asked = false;
                    s.enable_ticks = 0;
                }
                let healthy = s.fault.is_none();
                match s.cfg.mode {
                    DriveMode::Csp if healthy => {
                        let pos = f64::from(value) / s.cfg.counts_per_unit;
                        s.velocity = if s.have_actual {
                            f64::from(value.wrapping_sub(s.actual))
                                / s.cfg.counts_per_unit
                                / self.tick.as_secs_f64()
                        } else {
                            0.0
                        };
                        s.position = pos;
                        s.actual = value;
                        s.have_actual = true;
                    }
                    DriveMode::Csv if healthy => {
                        s.velocity = f64::from(value) / s.cfg.counts_per_unit;
                    }
                    _ => {}
                }
                s.fresh = true;
            } else if id == cob::tpdo(2, node) && d.len() >= 6 && s.homing() {
                if s.fault.is_none() {
                    s.probe_status = u16::from_le_bytes([d[0], d[1]]);
                    s.probe_value = i32::from_le_bytes([d[2], d[3], d[4], d[5]]);
                }
                s.fresh_homing[0] = true;
            } else if id == cob::tpdo(3, node) && d.len() >= 4 && s.homing() {
                if s.fault.is_none() {
                    s.inputs = u32::from_le_bytes([d[0], d[1], d[2], d[3]]);
                }
                s.fresh_homing[1] = true;
            } else if id == 0x080 + u16::from(node) && d.len() >= 2 {
                let code = u16::from_le_bytes([d[0], d[1]]);
                if code != 0
                    && s.fault
                        .is_none_or(|f| f.cause == FaultCause::Drive && f.code == 0)
                {
                    s.fault = Some(DriveFault {
                        node,
                        code,
                        cause: FaultCause::Drive,
                    });
                }
            } else if id == cob::HEARTBEAT + u16::from(node) {
                if let Some(&st) = d.first() {
                    s.last_hb = Some(now);
                    s.nmt = st;
                }
            } else if id == cob::SDO_TX + u16::from(node) {
                s.code_wait = false;
                if let Some(sdo::SdoResponse::Uploaded {
                    index: 0x603F,
                    value,
                    ..
                }) = sdo::parse_response(d)
                    && let Some(f) = s.fault.as_mut().filter(|f| f.cause == FaultCause::Drive)
                {
                    f.code = value as u16;
                }
            }
            if s.fault.is_some_and(|f| f.cause == FaultCause::Drive) && !s.code_asked {
                s.code_asked = true;
                s.code_wait = true;
                out.push(CanMsg::new(
                    cob::SDO_RX + u16::from(node),
                    &sdo::upload_request(0x603F, 0),
                ));
            }
        }
        out
    }

    /// The checks after a SYNC's answers: heartbeat consumer, NMT state, enable timeout.
    pub fn after_sync(&mut self, now: Instant) {
        let Some(started) = self.started else { return };
        for s in &mut self.slots {
            // An unanswered `603Fh` read is not waited for past its tick.
            s.code_wait = false;
            let consumer = s.cfg.heartbeat * HEARTBEAT_FACTOR;
            let last = s.last_hb.unwrap_or(started);
            let node = s.cfg.node_id;
            let latch = |s: &mut Slot, code, cause| {
                if s.fault.is_none_or(|f| {
                    f.cause == FaultCause::Drive && cause == FaultCause::HeartbeatLost
                }) {
                    s.fault = Some(DriveFault { node, code, cause });
                }
            };
            if now.duration_since(last) > consumer {
                latch(s, CODE_HEARTBEAT, FaultCause::HeartbeatLost);
            } else if s.nmt != nmt::OPERATIONAL && now.duration_since(started) > consumer {
                // A heartbeat sent before the NMT start may arrive after it: a drive has one
                // consumer time to report operational.
                latch(s, CODE_NMT, FaultCause::NotOperational);
            }
            if s.cmd.enable && !s.cmd.quick_stop && s.fault.is_none() {
                if s.state == State::OperationEnabled {
                    s.enable_ticks = 0;
                } else {
                    s.enable_ticks += 1;
                    if s.enable_ticks > ENABLE_TICKS {
                        latch(s, CODE_ENABLE, FaultCause::EnableRefused);
                    }
                }
            } else {
                s.enable_ticks = 0;
            }
        }
    }

    /// True when every drive that should answer this SYNC has answered.
    pub fn all_answered(&self) -> bool {
        self.slots.iter().all(|s| {
            s.answered()
                || s.fault
                    .is_some_and(|f| f.cause == FaultCause::HeartbeatLost)
        })
    }

    /// True when a `603Fh` read sent this tick is still unanswered.
    pub fn code_pending(&self) -> bool {
        self.slots.iter().any(|s| s.code_wait)
    }
}

impl Slot {
    /// The drive has the homing PDOs (a `csp` drive).
    fn homing(&self) -> bool {
        self.cfg.mode == DriveMode::Csp && self.cfg.homing
    }

    /// Every TPDO of this SYNC arrived.
    fn answered(&self) -> bool {
        self.fresh && (!self.homing() || self.fresh_homing == [true; 2])
    }

    /// Right before a SYNC: the TPDOs of the previous SYNC that did not come are owed (by a drive
    /// that answers SYNCs: operational, not lost); written off once the drive has been behind
    /// for a heartbeat consumer time.
    fn owe_missing(&mut self, now: Instant) {
        let answers = self.nmt == nmt::OPERATIONAL
            && self
                .fault
                .is_none_or(|f| f.cause != FaultCause::HeartbeatLost);
        if !answers {
            self.owed = [0; 3];
            self.behind_since = None;
        } else if self.synced {
            let got = [self.fresh, self.fresh_homing[0], self.fresh_homing[1]];
            let kinds = if self.homing() { 3 } else { 1 };
            for (owed, got) in self.owed.iter_mut().zip(got).take(kinds) {
                if !got {
                    *owed = owed.saturating_add(1);
                }
            }
            if self.answered() && self.owed == [0; 3] {
                self.behind_since = None;
            } else if self.owed != [0; 3] {
                let since = *self.behind_since.get_or_insert(now);
                if now.duration_since(since) > self.cfg.heartbeat * HEARTBEAT_FACTOR {
                    self.owed = [0; 3];
                    self.behind_since = None;
                }
            }
        }
        self.synced = true;
    }
}

/// True when the cause of a latched master fault is gone at `now` (heartbeat back within the
/// consumer time, operational again).
fn cause_gone(s: &Slot, cause: FaultCause, now: Instant) -> bool {
    let consumer = s.cfg.heartbeat * HEARTBEAT_FACTOR;
    let beating = s.last_hb.is_some_and(|t| now.duration_since(t) <= consumer);
    match cause {
        FaultCause::HeartbeatLost | FaultCause::NotOperational => {
            beating && s.nmt == nmt::OPERATIONAL
        }
        FaultCause::EnableRefused | FaultCause::Drive => true,
    }
}

/// `units × counts_per_unit`, rounded, saturated to `i32` (NaN gives 0).
pub fn scale(units: f64, counts_per_unit: f64) -> i32 {
    let v = (units * counts_per_unit).round();
    if v.is_nan() {
        0
    } else {
        v.clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    impl DriveSet {
        /// A heartbeat of every drive at `now` (operational).
        fn heartbeat_at(&mut self, now: Instant) {
            let ids: Vec<u8> = self.slots.iter().map(|s| s.cfg.node_id).collect();
            for id in ids {
                self.on_frame(
                    &CanMsg::new(cob::HEARTBEAT + u16::from(id), &[nmt::OPERATIONAL]),
                    now,
                );
            }
        }
    }

    fn set() -> (DriveSet, Instant) {
        let d = CanDrive {
            process: 1,
            axis: 'X',
            node_id: 3,
            counts_per_unit: 100.0,
            mode: DriveMode::Csp,
            heartbeat: Duration::from_millis(50),
            sdo: Vec::new(),
            simulate: Default::default(),
            span: 0..0,
            homing: true,
        };
        let mut s = DriveSet::new(&[d], Duration::from_millis(10));
        let now = Instant::now();
        s.started(now, &[0x0240]);
        (s, now)
    }

    #[test]
    fn the_rpdo_carries_the_controlword_and_the_scaled_set_point() {
        let (mut s, now) = set();
        let cmd = DriveCommand {
            set_point: 1.234,
            enable: true,
            ..DriveCommand::default()
        };
        assert!(s.command(AxisId::new('X'), cmd));
        assert!(!s.command(AxisId::new('Y'), cmd));
        let f = s.rpdos(now);
        assert_eq!(f.len(), 2);
        assert_eq!(
            (f[0].id, f[0].payload()),
            (0x203, &[0x06, 0, 123, 0, 0, 0][..])
        );
        // RPDO2: the touch probe function, disarmed.
        assert_eq!((f[1].id, f[1].payload()), (0x303, &[0, 0][..]));
        let armed = DriveCommand { probe: true, ..cmd };
        assert!(s.command(AxisId::new('X'), armed));
        assert_eq!(s.rpdos(now)[1].payload(), &[0x15, 0]);
    }

    #[test]
    fn a_csp_drive_answered_when_its_three_tpdos_came() {
        let (mut s, now) = set();
        let x = AxisId::new('X');
        s.rpdos(now);
        s.on_frame(&CanMsg::new(0x183, &[0x27, 0x02, 0x10, 0, 0, 0]), now);
        assert!(!s.all_answered());
        // TPDO2: probe status "stored" with 60BAh = 250 counts = 2.5 mm; TPDO3: home switch.
        s.on_frame(&CanMsg::new(0x283, &[0x03, 0, 250, 0, 0, 0]), now);
        assert!(!s.all_answered());
        s.on_frame(&CanMsg::new(0x383, &[0x04, 0, 0, 0]), now);
        assert!(s.all_answered());
        let f = s.feedback(x).expect("X");
        assert_eq!(
            (
                f.healthy,
                f.position,
                f.inputs,
                f.probe_status,
                f.probe_position
            ),
            (true, 0.16, INPUT_HOME_SWITCH, 0x03, 2.5)
        );
    }

    #[test]
    fn a_fault_statusword_asks_for_603f_once_and_the_answer_fills_the_code() {
        let (mut s, now) = set();
        let x = AxisId::new('X');
        let tpdo = CanMsg::new(0x183, &[0x08, 0x02, 0x10, 0, 0, 0]);
        let asked = s.on_frame(&tpdo, now);
        assert_eq!(asked.len(), 1);
        assert_eq!(
            (asked[0].id, asked[0].payload()),
            (0x603, &sdo::upload_request(0x603F, 0)[..])
        );
        assert!(s.code_pending());
        let fault = |code| {
            Some(DriveFault {
                node: 3,
                code,
                cause: FaultCause::Drive,
            })
        };
        assert_eq!(
            s.feedback(x).map(|f| (f.state, f.fault, f.healthy)),
            Some((State::Fault, fault(0), false))
        );
        // The faulted drive's 6064h (16 counts) is not taken as a position.
        assert_eq!(s.feedback(x).map(|f| f.position), Some(0.0));
        assert!(s.on_frame(&tpdo, now).is_empty(), "asked once");
        let answer = [0x4B, 0x3F, 0x60, 0, 0x30, 0x55, 0, 0];
        assert!(s.on_frame(&CanMsg::new(0x583, &answer), now).is_empty());
        assert!(!s.code_pending());
        assert_eq!(s.feedback(x).and_then(|f| f.fault), fault(0x5530));
    }

    /// The three TPDOs of drive 3: Operation enabled at `counts`.
    fn answer(s: &mut DriveSet, counts: u8, now: Instant) {
        s.on_frame(&CanMsg::new(0x183, &[0x27, 0x02, counts, 0, 0, 0]), now);
        s.on_frame(&CanMsg::new(0x283, &[0, 0, 0, 0, 0, 0]), now);
        s.on_frame(&CanMsg::new(0x383, &[0, 0, 0, 0]), now);
    }

    /// (healthy, position) of X after the frames so far.
    fn seen(s: &DriveSet) -> (bool, f64) {
        let f = s.feedback(AxisId::new('X')).expect("X");
        (f.healthy, f.position)
    }

    #[test]
    fn a_late_answer_is_dropped_not_taken_for_the_next_sync() {
        let (mut s, now) = set();
        // SYNC 1, answered in time: 10 counts = 0.1 mm.
        s.rpdos(now);
        answer(&mut s, 10, now);
        s.after_sync(now);
        assert_eq!(seen(&s), (true, 0.1));
        // SYNC 2: its answer does not come before SYNC 3 is sent.
        s.rpdos(now);
        s.after_sync(now);
        assert_eq!(seen(&s), (false, 0.1));
        s.rpdos(now);
        // Now SYNC 2's answer (20 counts) arrives: it is not SYNC 3's.
        answer(&mut s, 20, now);
        assert!(!s.all_answered());
        assert_eq!(seen(&s), (false, 0.1), "the late answer is not a position");
        // SYNC 3's own answer.
        answer(&mut s, 30, now);
        assert!(s.all_answered());
        s.after_sync(now);
        assert_eq!(seen(&s), (true, 0.3));
        // A drive two SYNCs behind: both late answers are dropped, oldest first.
        s.rpdos(now);
        s.after_sync(now);
        s.rpdos(now);
        s.after_sync(now);
        s.rpdos(now);
        answer(&mut s, 40, now);
        answer(&mut s, 50, now);
        assert_eq!(seen(&s), (false, 0.3));
        answer(&mut s, 60, now);
        assert_eq!(seen(&s), (true, 0.6));
    }

    #[test]
    fn an_answer_lost_for_good_is_written_off_after_the_consumer_time() {
        let (mut s, now) = set();
        let sync = Duration::from_millis(10);
        s.rpdos(now);
        answer(&mut s, 10, now);
        s.after_sync(now);
        // SYNC 2's answer is lost; from then on each answer is taken as the one owed.
        s.rpdos(now + sync);
        let mut t = now + sync * 2;
        let mut healthy_again = None;
        for k in 3..30u8 {
            s.rpdos(t);
            answer(&mut s, k, t);
            s.heartbeat_at(t);
            if seen(&s).0 && healthy_again.is_none() {
                healthy_again = Some(k);
            }
            t += sync;
        }
        // Behind since SYNC 3 (20 ms); written off at the first SYNC past 2 × 50 ms: SYNC 14
        // (130 ms), whose own answer is taken.
        assert_eq!(healthy_again, Some(14));
        assert_eq!(seen(&s), (true, 0.29));
    }

    #[test]
    fn scaling_rounds_and_saturates() {
        assert_eq!(scale(0.375, 1000.0), 375);
        assert_eq!(scale(0.0625, 100.0), 6);
        assert_eq!(scale(-0.5, 1.0), -1);
        assert_eq!(scale(f64::NAN, 1.0), 0);
        assert_eq!(scale(1e12, 1.0), i32::MAX);
        assert_eq!(scale(f64::NEG_INFINITY, 1.0), i32::MIN);
    }
}
