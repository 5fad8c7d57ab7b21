//! A simulated CiA 402 servo drive on any [`CanBus`], for tests, peers and the `virtual` transport.
//!
//! It boots (boot-up message), follows NMT, produces its heartbeat every `1017h` ms and serves an
//! object dictionary over SDO: `1000h` (`00020192h`, CiA 402), `1017h`, the RPDO1/TPDO1
//! communication (`1400h`, `1800h`) and mapping (`1600h`, `1A00h`) records, `603Fh` error code,
//! `6040h` controlword, `6041h` statusword, `6060h`/`6061h` mode, `6064h` position actual,
//! `606Ch` velocity actual, `607Ah` target position, `60FFh` target velocity, `60C2h`
//! interpolation period, and the homing objects `60B8h` touch probe function, `60B9h` touch
//! probe status, `60BAh` touch probe 1 positive edge position, `60FDh` digital inputs, with
//! RPDO2 and TPDO2/TPDO3 (`1401h`, `1601h`, `1801h`–`1802h`, `1A01h`–`1A02h`; disabled until a
//! master maps and enables them). RPDOs are synchronous: their mapped objects are applied at the
//! next SYNC, then the power state machine ([`cia402::transition`]) takes the controlword, the
//! axis model moves, and the enabled TPDOs carry the mapped objects (transmission type n: every
//! n-th SYNC).
//!
//! The machine behind the drive ([`SimMachine`], optional): the home switch (`60FDh` bit 2 while
//! the machine position is on its pressed side of the edge) and the encoder's zero impulse every
//! mark pitch on the machine's scale. Touch probe 1 latches like a real drive's: armed by a
//! rising bit 0 of `60B8h` (which clears what it stored), on the zero impulse with bits 2–3 =
//! 01, it stores the exact drive position of the first mark the axis crosses (`60BAh`, status
//! bit 1), not the position of the SYNC after it; bit 0 = 0 disarms it and clears the status.
//!
//! The axis model is an ideal follower with a lag of `lag` SYNCs: in *Operation enabled* the
//! actual value is the target received `lag` SYNCs before (0: the target of this SYNC). In `csv`
//! the velocity follows the same way and the position integrates it over the interpolation
//! period. Test hooks: [`DriveSimState::inject_fault`] (statusword fault + EMCY at the next SYNC),
//! `heartbeat_stopped` (a lost heartbeat, the node otherwise working), `silent` (no frame at
//! all), `refuse_enable`, `sdo_abort` (one object aborts every write), `max_speed` (a `csv`
//! drive that cannot reach its target velocity).

use std::collections::VecDeque;
use std::sync::{Arc, Mutex, MutexGuard};

use super::drive::cia402::{self, State};
pub use super::drive_machine::SimMachine;
use super::transport::CanBus;
use super::{CanMsg, cob, nmt, sdo};

/// Device type `1000h`: CiA 402 (profile 402 = 0192h), servo drive (type 0002h).
pub const DEVICE_TYPE: u32 = 0x0002_0192;
/// Abort code: value range of parameter exceeded.
pub const ABORT_RANGE: u32 = 0x0609_0030;
/// Abort code: object cannot be mapped to the PDO.
pub const ABORT_NOT_MAPPABLE: u32 = 0x0604_0041;
/// Abort code: mapped objects exceed the PDO length.
pub const ABORT_PDO_LENGTH: u32 = 0x0604_0042;

/// The drive's state, shared with whoever runs it.
#[derive(Debug, Clone)]
pub struct DriveSimState {
    /// NMT state.
    pub nmt: u8,
    /// CiA 402 state.
    pub state: State,
    /// Controlword last applied (`6040h`).
    pub controlword: u16,
    /// Mode of operation (`6060h`).
    pub mode: i8,
    /// Target position (`607Ah`).
    pub target_position: i32,
    /// Target velocity (`60FFh`).
    pub target_velocity: i32,
    /// Position actual value (`6064h`).
    pub position: i32,
    /// Velocity actual value (`606Ch`).
    pub velocity: i32,
    /// Error code (`603Fh`).
    pub error_code: u16,
    /// Interpolation period (`60C2h` sub 1, sub 2).
    pub interpolation: (u8, i8),
    /// Producer heartbeat time in ms (`1017h`); 0 = none.
    pub heartbeat_ms: u16,
    /// RPDO1 COB-ID (`1400h`/1), transmission type (`1400h`/2), mapping (`1600h`).
    pub rpdo: PdoConfig,
    /// TPDO1 COB-ID (`1800h`/1), transmission type (`1800h`/2), mapping (`1A00h`).
    pub tpdo: PdoConfig,
    /// RPDO2 (`1401h`, `1601h`).
    pub rpdo2: PdoConfig,
    /// TPDO2 (`1801h`, `1A01h`).
    pub tpdo2: PdoConfig,
    /// TPDO3 (`1802h`, `1A02h`).
    pub tpdo3: PdoConfig,
    /// Touch probe function (`60B8h`).
    pub probe_function: u16,
    /// Touch probe status (`60B9h`).
    pub probe_status: u16,
    /// Touch probe 1 positive edge position (`60BAh`).
    pub probe_position: i32,
    /// The machine behind the drive (home switch, zero impulses).
    pub machine: Option<SimMachine>,
    /// SYNCs the follower lags behind the target.
    pub lag: usize,
    /// Hook: no heartbeat is produced (the node otherwise works).
    pub heartbeat_stopped: bool,
    /// Hook: the node sends nothing and ignores everything.
    pub silent: bool,
    /// Hook: the drive stays *Switched on* when asked to enable operation.
    pub refuse_enable: bool,
    /// Hook: at this SYNC number the drive faults with this code (as [`Self::inject_fault`]).
    pub fault_at_sync: Option<(u64, u16)>,
    /// Hook: from this SYNC number on no heartbeat is produced.
    pub heartbeat_stop_at_sync: Option<u64>,
    /// The heartbeat is produced on SYNCs (every `1017h` ms of interpolation periods) instead of
    /// by the clock: the drive of a lock-step run in virtual time, where SYNCs come faster than
    /// the wall clock.
    pub sync_heartbeat: bool,
    /// Hook: the velocity of a `csv` drive is limited to this (drive units per second).
    pub max_speed: Option<u32>,
    /// Hook: writes to this object (index, sub-index) abort with this code.
    pub sdo_abort: Option<(u16, u8, u32)>,
    /// SYNCs received.
    pub syncs: u64,
    /// Every (SYNC number, controlword, target) applied at a SYNC while operational (the first
    /// [`APPLIED_CAP`]).
    pub applied: Vec<(u64, u16, i32)>,
    pending_fault: Option<u16>,
    pending_rpdo: Option<CanMsg>,
    pending_rpdo2: Option<CanMsg>,
    history: VecDeque<i32>,
    exact_position: f64,
}

/// The most SYNCs [`DriveSimState::applied`] keeps (a long run's memory stays bounded).
pub const APPLIED_CAP: usize = 100_000;

/// One PDO's communication and mapping parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PdoConfig {
    /// COB-ID; bit 31 set = PDO disabled.
    pub cob_id: u32,
    /// Transmission type (1..240: every n-th SYNC).
    pub transmission: u8,
    /// Number of mapped objects.
    pub count: u8,
    /// Mapping entries: index << 16 | sub-index << 8 | bit length.
    pub map: [u32; 8],
}

impl DriveSimState {
    fn new(id: u8) -> DriveSimState {
        let pdo = |cob: u16, map: [u32; 2]| PdoConfig {
            cob_id: u32::from(cob) + u32::from(id),
            transmission: 1,
            count: 2,
            map: [map[0], map[1], 0, 0, 0, 0, 0, 0],
        };
        let off = |n: u8, tx: bool, map: [u32; 2]| PdoConfig {
            cob_id: 0x8000_0000
                | u32::from(if tx {
                    cob::tpdo(n, id)
                } else {
                    cob::rpdo(n, id)
                }),
            count: if map[1] == 0 { 1 } else { 2 },
            ..pdo(0, map)
        };
        DriveSimState {
            nmt: nmt::PRE_OPERATIONAL,
            state: State::SwitchOnDisabled,
            controlword: 0,
            mode: 0,
            target_position: 0,
            target_velocity: 0,
            position: 0,
            velocity: 0,
            error_code: 0,
            interpolation: (1, -3),
            heartbeat_ms: 0,
            rpdo: pdo(cob::RPDO1, [0x6040_0010, 0x607A_0020]),
            tpdo: pdo(cob::TPDO1, [0x6041_0010, 0x6064_0020]),
            rpdo2: off(2, false, [0x60B8_0010, 0]),
            tpdo2: off(2, true, [0x60B9_0010, 0x60BA_0020]),
            tpdo3: off(3, true, [0x60FD_0020, 0]),
            probe_function: 0,
            probe_status: 0,
            probe_position: 0,
            machine: None,
            lag: 0,
            heartbeat_stopped: false,
            silent: false,
            refuse_enable: false,
            fault_at_sync: None,
            heartbeat_stop_at_sync: None,
            sync_heartbeat: false,
            sdo_abort: None,
            max_speed: None,
            syncs: 0,
            applied: Vec::new(),
            pending_fault: None,
            pending_rpdo: None,
            pending_rpdo2: None,
            history: VecDeque::new(),
            exact_position: 0.0,
        }
    }

    /// Makes the drive fault at the next SYNC with error code `code` (`603Fh`), sending an EMCY.
    pub fn inject_fault(&mut self, code: u16) {
        self.pending_fault = Some(code);
    }

    /// The statusword (`6041h`).
    pub fn statusword(&self) -> u16 {
        self.state.statusword()
    }

    fn period_s(&self) -> f64 {
        let scale = match self.interpolation.1 {
            -6 => 1e-6,
            -5 => 1e-5,
            -4 => 1e-4,
            -3 => 1e-3,
            -2 => 1e-2,
            -1 => 1e-1,
            _ => 1.0,
        };
        f64::from(self.interpolation.0) * scale
    }

    fn get(&self, index: u16, sub: u8) -> Result<(u32, u8), u32> {
        let pdo = |p: &PdoConfig, comm: bool| -> Result<(u32, u8), u32> {
            match (comm, sub) {
                (true, 0) => Ok((2, 1)),
                (true, 1) => Ok((p.cob_id, 4)),
                (true, 2) => Ok((u32::from(p.transmission), 1)),
                (false, 0) => Ok((u32::from(p.count), 1)),
                (false, 1..=8) => Ok((p.map[usize::from(sub) - 1], 4)),
                _ => Err(sdo::ABORT_NO_SUBINDEX),
            }
        };
        let only0 = |v: u32, size: u8| {
            if sub == 0 {
                Ok((v, size))
            } else {
                Err(sdo::ABORT_NO_SUBINDEX)
            }
        };
        match index {
            0x1000 => only0(DEVICE_TYPE, 4),
            0x1017 => only0(u32::from(self.heartbeat_ms), 2),
            0x1400 => pdo(&self.rpdo, true),
            0x1600 => pdo(&self.rpdo, false),
            0x1800 => pdo(&self.tpdo, true),
            0x1A00 => pdo(&self.tpdo, false),
            0x1401 => pdo(&self.rpdo2, true),
            0x1601 => pdo(&self.rpdo2, false),
            0x1801 => pdo(&self.tpdo2, true),
            0x1A01 => pdo(&self.tpdo2, false),
            0x1802 => pdo(&self.tpdo3, true),
            0x1A02 => pdo(&self.tpdo3, false),
            0x60B8 => only0(u32::from(self.probe_function), 2),
            0x60B9 => only0(u32::from(self.probe_status), 2),
            0x60BA => only0(self.probe_position as u32, 4),
            0x60FD => only0(self.inputs(), 4),
            0x603F => only0(u32::from(self.error_code), 2),
            0x6040 => only0(u32::from(self.controlword), 2),
            0x6041 => only0(u32::from(self.statusword()), 2),
            0x6060 | 0x6061 => only0(u32::from(self.mode as u8), 1),
            0x6064 => only0(self.position as u32, 4),
            0x606C => only0(self.velocity as u32, 4),
            0x607A => only0(self.target_position as u32, 4),
            0x60FF => only0(self.target_velocity as u32, 4),
            0x60C2 => match sub {
                0 => Ok((2, 1)),
                1 => Ok((u32::from(self.interpolation.0), 1)),
                2 => Ok((u32::from(self.interpolation.1 as u8), 1)),
                _ => Err(sdo::ABORT_NO_SUBINDEX),
            },
            _ => Err(sdo::ABORT_NO_OBJECT),
        }
    }

    /// Writes an object from SDO (`size` checked) or from a PDO (`size` = the mapped size).
    fn set(&mut self, index: u16, sub: u8, v: u32, size: u8) -> Result<(), u32> {
        if let Some((i, s, code)) = self.sdo_abort
            && (i, s) == (index, sub)
        {
            return Err(code);
        }
        let (_, want) = self.get(index, sub)?;
        if size != want {
            return Err(sdo::ABORT_LENGTH);
        }
        let map_entry = |p: &mut PdoConfig, v: u32, rx: bool| -> Result<(), u32> {
            let obj = (v >> 16) as u16;
            let ok = if rx {
                matches!(obj, 0x6040 | 0x607A | 0x60FF | 0x6060 | 0x60B8)
            } else {
                matches!(
                    obj,
                    0x6041 | 0x6064 | 0x606C | 0x6061 | 0x603F | 0x60B9 | 0x60BA | 0x60FD
                )
            };
            if !ok || v & 0xFF == 0 || v & 0x07 != 0 {
                return Err(ABORT_NOT_MAPPABLE);
            }
            p.map[usize::from(sub) - 1] = v;
            Ok(())
        };
        let count = |p: &mut PdoConfig, v: u32| -> Result<(), u32> {
            let bits: u32 = p.map.iter().take(v as usize).map(|m| m & 0xFF).sum();
            if v > 8 || bits > 64 {
                return Err(ABORT_PDO_LENGTH);
            }
            p.count = v as u8;
            Ok(())
        };
        match (index, sub) {
            (0x1017, 0) => self.heartbeat_ms = v as u16,
            (0x1400, 1) => self.rpdo.cob_id = v,
            (0x1400, 2) => self.rpdo.transmission = v as u8,
            (0x1800, 1) => self.tpdo.cob_id = v,
            (0x1800, 2) => self.tpdo.transmission = v as u8,
            (0x1600, 0) => count(&mut self.rpdo, v)?,
            (0x1A00, 0) => count(&mut self.tpdo, v)?,
            (0x1600, _) => map_entry(&mut self.rpdo, v, true)?,
            (0x1A00, _) => map_entry(&mut self.tpdo, v, false)?,
            (0x1401, 1) => self.rpdo2.cob_id = v,
            (0x1401, 2) => self.rpdo2.transmission = v as u8,
            (0x1801, 1) => self.tpdo2.cob_id = v,
            (0x1801, 2) => self.tpdo2.transmission = v as u8,
            (0x1802, 1) => self.tpdo3.cob_id = v,
            (0x1802, 2) => self.tpdo3.transmission = v as u8,
            (0x1601, 0) => count(&mut self.rpdo2, v)?,
            (0x1A01, 0) => count(&mut self.tpdo2, v)?,
            (0x1A02, 0) => count(&mut self.tpdo3, v)?,
            (0x1601, _) => map_entry(&mut self.rpdo2, v, true)?,
            (0x1A01, _) => map_entry(&mut self.tpdo2, v, false)?,
            (0x1A02, _) => map_entry(&mut self.tpdo3, v, false)?,
            (0x60B8, 0) => self.set_probe_function(v as u16),
            (0x6040, 0) => self.controlword = v as u16,
            (0x6060, 0) => {
                if !matches!(v, 8 | 9) {
                    return Err(ABORT_RANGE);
                }
                self.mode = v as i8;
            }
            (0x607A, 0) => self.target_position = v as i32,
            (0x60FF, 0) => self.target_velocity = v as i32,
            (0x60C2, 1) => self.interpolation.0 = v as u8,
            (0x60C2, 2) => self.interpolation.1 = v as u8 as i8,
            _ => return Err(sdo::ABORT_READ_ONLY),
        }
        Ok(())
    }

    /// The digital inputs `60FDh`: bit 2 is the home switch.
    pub fn inputs(&self) -> u32 {
        let p = f64::from(self.position);
        match self.machine {
            Some(m) if m.pressed(m.start + p) => 0x0004,
            _ => 0,
        }
    }

    /// Writes `60B8h`: a rising bit 0 arms probe 1 afresh, bit 0 = 0 disarms it.
    fn set_probe_function(&mut self, v: u16) {
        if v & 1 == 0 {
            self.probe_status = 0;
        } else if self.probe_function & 1 == 0 {
            self.probe_status = 1;
        }
        self.probe_function = v;
    }

    /// Touch probe 1 on the axis's move from drive position `from` to `to`: armed on the zero
    /// impulse's positive edge and not yet stored, it stores the first mark crossed.
    fn probe(&mut self, from: f64, to: f64) {
        let f = self.probe_function;
        let armed = f & 1 == 1 && (f >> 2) & 3 == 1 && f & 0x10 != 0;
        if !armed || self.probe_status & 2 != 0 {
            return;
        }
        let Some(m) = self.machine else { return };
        if let Some(mark) = m.mark_between(m.start + from, m.start + to) {
            self.probe_position = (mark - m.start).round() as i32;
            self.probe_status |= 2;
        }
    }

    /// Applies a received RPDO's bytes to the mapped objects of `pdo`.
    fn apply_rpdo(&mut self, m: &CanMsg, pdo: PdoConfig) {
        let d = m.payload();
        let mut at = 0usize;
        for e in pdo.map.iter().take(usize::from(pdo.count)).copied() {
            let n = ((e & 0xFF) / 8) as usize;
            let Some(bytes) = d.get(at..at + n) else {
                return;
            };
            let mut v = [0u8; 4];
            v[..n.min(4)].copy_from_slice(&bytes[..n.min(4)]);
            let _ = self.set(
                (e >> 16) as u16,
                (e >> 8) as u8,
                u32::from_le_bytes(v),
                n as u8,
            );
            at += n;
        }
    }

    fn tpdo_bytes(&self, pdo: &PdoConfig) -> Vec<u8> {
        let mut out = Vec::with_capacity(8);
        for e in pdo.map.iter().take(usize::from(pdo.count)).copied() {
            let n = ((e & 0xFF) / 8) as usize;
            let v = self
                .get((e >> 16) as u16, (e >> 8) as u8)
                .map_or(0, |(v, _)| v);
            out.extend_from_slice(&v.to_le_bytes()[..n.min(4)]);
        }
        out
    }

    /// One SYNC: the pending RPDO, the state machine, the axis model; the frames to send.
    fn on_sync(&mut self, id: u8) -> Vec<CanMsg> {
        self.syncs += 1;
        if let Some((at, code)) = self.fault_at_sync
            && at == self.syncs
        {
            self.pending_fault = Some(code);
        }
        if self.heartbeat_stop_at_sync == Some(self.syncs) {
            self.heartbeat_stopped = true;
        }
        let mut out = Vec::new();
        if self.sync_heartbeat && self.heartbeat_ms > 0 && !self.silent && !self.heartbeat_stopped {
            let period = self.period_s();
            let every = if period > 0.0 {
                ((f64::from(self.heartbeat_ms) / 1000.0 / period).round() as u64).max(1)
            } else {
                1
            };
            if self.syncs.is_multiple_of(every) {
                out.push(CanMsg::new(cob::HEARTBEAT + u16::from(id), &[self.nmt]));
            }
        }
        if self.nmt != nmt::OPERATIONAL {
            return out;
        }
        let last = self.controlword;
        if let Some(m) = self.pending_rpdo.take() {
            self.apply_rpdo(&m, self.rpdo);
        }
        if let Some(m) = self.pending_rpdo2.take() {
            self.apply_rpdo(&m, self.rpdo2);
        }
        if self.applied.len() < APPLIED_CAP {
            self.applied
                .push((self.syncs, self.controlword, self.target_position));
        }
        self.state = cia402::transition(self.state, self.controlword, last, self.refuse_enable);
        if let Some(code) = self.pending_fault.take() {
            self.state = State::Fault;
            self.error_code = code;
            let c = code.to_le_bytes();
            out.push(CanMsg::new(
                0x080 + u16::from(id),
                &[c[0], c[1], 0x01, 0, 0, 0, 0, 0],
            ));
        } else if self.state == State::SwitchOnDisabled && self.error_code != 0 {
            // Left Fault by a reset: the error is cleared (an EMCY with code 0 says so).
            self.error_code = 0;
            out.push(CanMsg::new(0x080 + u16::from(id), &[0; 8]));
        }
        let before = self.exact_position;
        self.follow();
        self.probe(before, self.exact_position);
        for pdo in [self.tpdo, self.tpdo2, self.tpdo3] {
            let every = u64::from(pdo.transmission.max(1));
            if pdo.cob_id & 0x8000_0000 == 0
                && pdo.transmission <= 240
                && self.syncs.is_multiple_of(every)
            {
                out.push(CanMsg::new(
                    (pdo.cob_id & 0x7FF) as u16,
                    &self.tpdo_bytes(&pdo),
                ));
            }
        }
        out
    }

    fn follow(&mut self) {
        let enabled = self.state == State::OperationEnabled;
        let target = if self.mode == 9 {
            self.target_velocity
        } else {
            self.target_position
        };
        if !enabled {
            self.history.clear();
            self.velocity = 0;
            return;
        }
        self.history.push_back(target);
        while self.history.len() > self.lag + 1 {
            self.history.pop_front();
        }
        if self.history.len() <= self.lag {
            return;
        }
        let Some(&now) = self.history.front() else {
            return;
        };
        let period = self.period_s();
        if self.mode == 9 {
            let limit = self
                .max_speed
                .map_or(i32::MAX, |m| m.min(i32::MAX as u32) as i32);
            let now = now.clamp(-limit, limit);
            self.velocity = now;
            self.exact_position += f64::from(now) * period;
            self.position = self.exact_position.round() as i32;
        } else {
            let moved = f64::from(now.wrapping_sub(self.position));
            self.velocity = if period > 0.0 {
                (moved / period).round() as i32
            } else {
                0
            };
            self.position = now;
            self.exact_position = f64::from(now);
        }
    }
}

/// A running simulated drive.
pub struct Cia402Node {
    /// The node id.
    pub node_id: u8,
    state: Arc<Mutex<DriveSimState>>,
    task: Option<tokio::task::JoinHandle<()>>,
}

fn lock(s: &Mutex<DriveSimState>) -> MutexGuard<'_, DriveSimState> {
    s.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

impl Cia402Node {
    /// Spawns the drive on the current tokio runtime.
    pub fn spawn<B: CanBus>(bus: B, node_id: u8) -> Cia402Node {
        let state = Arc::new(Mutex::new(DriveSimState::new(node_id)));
        let task = tokio::spawn(super::sim_node::run(bus, node_id, state.clone()));
        Cia402Node {
            node_id,
            state,
            task: Some(task),
        }
    }

    /// Locks the drive's state (to read it or to set a hook).
    pub fn state(&self) -> MutexGuard<'_, DriveSimState> {
        lock(&self.state)
    }

    /// Stops the drive: no more frames at all.
    pub fn kill(&mut self) {
        if let Some(t) = self.task.take() {
            t.abort();
        }
    }
}

impl Drop for Cia402Node {
    fn drop(&mut self) {
        self.kill();
    }
}

impl super::sim_node::SimNode for DriveSimState {
    fn heartbeat_ms(&self) -> u16 {
        self.heartbeat_ms
    }
    fn heartbeat_state(&self) -> Option<u8> {
        (!self.silent && !self.heartbeat_stopped && !self.sync_heartbeat).then_some(self.nmt)
    }
    fn handle(&mut self, id: u8, m: &CanMsg) -> Vec<CanMsg> {
        handle(self, id, m)
    }
}

/// What the drive does with one frame; the frames it answers with.
pub fn handle(s: &mut DriveSimState, id: u8, m: &CanMsg) -> Vec<CanMsg> {
    if s.silent || m.extended || m.rtr {
        return Vec::new();
    }
    let d = m.payload();
    let cob_id = m.id as u16;
    let mut out = Vec::new();
    if cob_id == cob::NMT && d.len() >= 2 && (d[1] == id || d[1] == 0) {
        match d[0] {
            nmt::CMD_START => s.nmt = nmt::OPERATIONAL,
            nmt::CMD_STOP => s.nmt = nmt::STOPPED,
            nmt::CMD_PRE_OPERATIONAL => s.nmt = nmt::PRE_OPERATIONAL,
            nmt::CMD_RESET_NODE | nmt::CMD_RESET_COMM => {
                let hooks = (s.refuse_enable, s.sdo_abort, s.lag, s.machine, s.max_speed);
                *s = DriveSimState::new(id);
                (s.refuse_enable, s.sdo_abort, s.lag, s.machine, s.max_speed) = hooks;
                out.push(CanMsg::new(cob::HEARTBEAT + u16::from(id), &[nmt::BOOTUP]));
            }
            _ => {}
        }
    } else if cob_id == cob::SYNC {
        out = s.on_sync(id);
    } else if u32::from(cob_id) == s.rpdo.cob_id && s.nmt == nmt::OPERATIONAL {
        s.pending_rpdo = Some(*m);
    } else if u32::from(cob_id) == s.rpdo2.cob_id && s.nmt == nmt::OPERATIONAL {
        s.pending_rpdo2 = Some(*m);
    } else if cob_id == cob::SDO_RX + u16::from(id) && s.nmt != nmt::STOPPED {
        let snapshot = s.clone();
        let mut write = None;
        let answer = sdo::serve_request(
            d,
            |index, sub| snapshot.get(index, sub),
            |index, sub, v, size| {
                let mut probe = snapshot.clone();
                let r = probe.set(index, sub, v, size);
                if r.is_ok() {
                    write = Some(probe);
                }
                r
            },
        );
        if let Some(new) = write {
            *s = new;
        }
        if let Some(a) = answer {
            out.push(CanMsg::new(cob::SDO_TX + u16::from(id), &a));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sdo_write(s: &mut DriveSimState, index: u16, sub: u8, v: u32, size: u8) -> Vec<u8> {
        let req = sdo::download_request(index, sub, v, size).expect("size");
        let out = handle(s, 3, &CanMsg::new(0x603, &req));
        out[0].payload().to_vec()
    }

    #[test]
    fn the_dictionary_refuses_bad_writes_with_the_cia_301_codes() {
        let mut s = DriveSimState::new(3);
        assert_eq!(sdo_write(&mut s, 0x6060, 0, 8, 1)[0], 0x60);
        assert_eq!(s.mode, 8);
        let abort = |b: Vec<u8>| (b[0], u32::from_le_bytes([b[4], b[5], b[6], b[7]]));
        assert_eq!(
            abort(sdo_write(&mut s, 0x6060, 0, 3, 1)),
            (0x80, ABORT_RANGE)
        );
        assert_eq!(
            abort(sdo_write(&mut s, 0x6060, 0, 8, 2)),
            (0x80, sdo::ABORT_LENGTH)
        );
        assert_eq!(
            abort(sdo_write(&mut s, 0x6041, 0, 1, 2)),
            (0x80, sdo::ABORT_READ_ONLY)
        );
        assert_eq!(
            abort(sdo_write(&mut s, 0x1600, 1, 0x6041_0010, 4)),
            (0x80, ABORT_NOT_MAPPABLE)
        );
        assert_eq!(
            abort(sdo_write(&mut s, 0x2000, 0, 1, 1)),
            (0x80, sdo::ABORT_NO_OBJECT)
        );
        s.sdo_abort = Some((0x60C2, 1, ABORT_RANGE));
        assert_eq!(
            abort(sdo_write(&mut s, 0x60C2, 1, 10, 1)),
            (0x80, ABORT_RANGE)
        );
    }

    #[test]
    fn a_sync_applies_the_rpdo_then_answers_with_the_tpdo() {
        let mut s = DriveSimState::new(3);
        handle(&mut s, 3, &CanMsg::new(0, &[nmt::CMD_START, 3]));
        s.mode = 8;
        s.state = State::SwitchedOn;
        s.controlword = 0x07;
        let mut rpdo = [0u8; 6];
        rpdo[..2].copy_from_slice(&0x0Fu16.to_le_bytes());
        rpdo[2..].copy_from_slice(&12_345i32.to_le_bytes());
        handle(&mut s, 3, &CanMsg::new(0x203, &rpdo));
        let out = handle(&mut s, 3, &CanMsg::new(0x80, &[]));
        assert_eq!(s.state, State::OperationEnabled);
        assert_eq!(out.len(), 1);
        assert_eq!(out[0].id, 0x183);
        assert_eq!(out[0].payload(), &[0x27, 0x02, 0x39, 0x30, 0, 0]);
        assert_eq!(s.applied, vec![(1, 0x0F, 12_345)]);
    }

    /// Touch probe 1 on the zero impulse: armed by a rising `60B8h` bit 0, it stores the exact
    /// drive position of the first mark crossed (not the position of the SYNC), keeps it
    /// (first event), and is cleared by disarming; `60FDh` bit 2 is the home switch.
    #[test]
    fn the_touch_probe_latches_the_first_zero_impulse_exactly() {
        let mut s = DriveSimState::new(3);
        handle(&mut s, 3, &CanMsg::new(0, &[nmt::CMD_START, 3]));
        (s.mode, s.state, s.controlword) = (8, State::OperationEnabled, 0x0F);
        // Drive 0 stands at machine −50 mm (10 000 counts/mm); switch from 3 mm up; marks every 5.
        s.machine = Some(SimMachine {
            start: -500_000.0,
            home_switch: Some((30_000.0, false)),
            mark_pitch: 50_000.0,
        });
        for p in [&mut s.rpdo2, &mut s.tpdo2, &mut s.tpdo3] {
            p.cob_id &= 0x7FF;
        }
        let step = |s: &mut DriveSimState, target: i32, probe: Option<u16>| {
            let mut rpdo = [0u8; 6];
            rpdo[..2].copy_from_slice(&0x0Fu16.to_le_bytes());
            rpdo[2..].copy_from_slice(&target.to_le_bytes());
            handle(s, 3, &CanMsg::new(0x203, &rpdo));
            if let Some(f) = probe {
                handle(s, 3, &CanMsg::new(0x303, &f.to_le_bytes()));
            }
            let out = handle(s, 3, &CanMsg::new(0x80, &[]));
            let ids: Vec<u32> = out.iter().map(|m| m.id).collect();
            assert_eq!(ids, [0x183, 0x283, 0x383]);
            (out[1].payload().to_vec(), out[2].payload().to_vec())
        };
        // Onto the switch, crossing marks unarmed: nothing stored.
        assert_eq!(
            step(&mut s, 530_000, None),
            (vec![0, 0, 0, 0, 0, 0], vec![4, 0, 0, 0])
        );
        // Armed on the zero impulse, positive edge; off the switch (machine 2.9 mm).
        assert_eq!(
            step(&mut s, 529_000, Some(0x15)),
            (vec![1, 0, 0, 0, 0, 0], vec![0, 0, 0, 0])
        );
        assert_eq!(step(&mut s, 520_000, Some(0x15)).1, vec![0, 0, 0, 0]);
        // Past the mark at machine 0 (drive 500 000) in one SYNC: its exact position is stored.
        let stored = [3, 0, 0x20, 0xA1, 0x07, 0];
        assert_eq!(step(&mut s, 499_990, Some(0x15)).0, stored);
        assert_eq!(s.position, 499_990);
        // First event: the next mark (drive 450 000) does not overwrite it.
        assert_eq!(step(&mut s, 449_000, Some(0x15)).0, stored);
        // Disarmed: the status clears; armed again, the next crossing is stored.
        assert_eq!(step(&mut s, 449_000, Some(0)).0[..2], [0, 0]);
        assert_eq!(step(&mut s, 449_000, Some(0x15)).0[..2], [1, 0]);
        let again = step(&mut s, 399_000, Some(0x15)).0;
        assert_eq!(again, [3, 0, 0x80, 0x1A, 0x06, 0]);
        assert_eq!(
            i32::from_le_bytes([again[2], again[3], again[4], again[5]]),
            400_000
        );
    }
}
