//! A simulated CiA 401 digital I/O node on any [`CanBus`], for tests and the `virtual` transport.
//!
//! It boots (boot-up message), follows NMT commands, produces its heartbeat every `0x1017` ms, takes
//! RPDO1/RPDO2 (output bytes 0..7 / 8..15, applied at the next SYNC: synchronous transmission) and
//! answers each SYNC with TPDO1/TPDO2 (input bytes 0..7 / 8..15) while operational. Its object
//! dictionary answers SDO expedited transfers: `1000h` device type (`000F0191h`: CiA 401 with
//! digital inputs and outputs), `1017h` producer heartbeat time, `6000h` sub 1..16 the input bytes
//! (read-only), `6200h` sub 1..16 the output bytes.
//!
//! Its heartbeat runs on the wall clock (the shared loop of `sim_node`), or, with
//! [`NodeState::sync_period_us`] set (a lock-step run in virtual time), on the SYNCs it receives:
//! the first SYNC and then every `1017h` ms worth of SYNC periods, so a loaded machine cannot make it
//! late. Its physical inputs ([`NodeState::inputs`]) are what a test, or the part run's simulated
//! machine (`controller::drive_io`), wires to its terminals; they reach the master with the TPDOs
//! of the next SYNC.

use std::sync::{Arc, Mutex, MutexGuard};

use super::transport::CanBus;
use super::{CanMsg, cob, nmt, sdo};

/// Input and output bytes of the simulated module.
pub const IO_BYTES: usize = 16;

/// The node's state, shared with the test that drives it.
#[derive(Debug, Clone, Default)]
pub struct NodeState {
    /// NMT state (see [`nmt`]).
    pub nmt: u8,
    /// Physical inputs (what TPDOs carry).
    pub inputs: [u8; IO_BYTES],
    /// Physical outputs (what RPDOs set).
    pub outputs: [u8; IO_BYTES],
    pending: [u8; IO_BYTES],
    /// Producer heartbeat time in ms (`1017h`); 0 = no heartbeat.
    pub heartbeat_ms: u16,
    /// When true the node neither answers nor produces its heartbeat (a lost node).
    pub silent: bool,
    /// Hook: the node falls silent at this SYNC number (counted from 1) and stays so.
    pub silent_at_sync: Option<u64>,
    /// RPDOs received while operational.
    pub rpdos: u64,
    /// SYNCs received.
    pub syncs: u64,
    /// The SYNC period in µs when the heartbeat is produced on SYNCs (lock-step runs in virtual
    /// time); 0: the heartbeat runs on the wall clock.
    pub sync_period_us: u32,
    /// SYNCs counted by the SYNC heartbeat.
    hb_syncs: u64,
}

impl NodeState {
    /// SYNCs between two heartbeats produced on SYNCs (`1017h` rounded to whole SYNC periods).
    pub fn heartbeat_every(&self) -> u64 {
        let period = u64::from(self.sync_period_us.max(1));
        ((u64::from(self.heartbeat_ms) * 1000 + period / 2) / period).max(1)
    }
}

/// A running simulated node.
pub struct Cia401Node {
    /// The node id.
    pub node_id: u8,
    state: Arc<Mutex<NodeState>>,
    task: Option<tokio::task::JoinHandle<()>>,
}

fn lock(s: &Mutex<NodeState>) -> MutexGuard<'_, NodeState> {
    s.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

impl Cia401Node {
    /// Spawns the node on the current tokio runtime.
    pub fn spawn<B: CanBus>(bus: B, node_id: u8) -> Cia401Node {
        Cia401Node::spawn_with(bus, node_id, Cia401Node::new_state(0))
    }

    /// A fresh node's state (pre-operational); `sync_period_us` as [`NodeState::sync_period_us`].
    pub fn new_state(sync_period_us: u32) -> Arc<Mutex<NodeState>> {
        Arc::new(Mutex::new(NodeState {
            nmt: nmt::PRE_OPERATIONAL,
            sync_period_us,
            ..NodeState::default()
        }))
    }

    /// Spawns the node on the current tokio runtime with a state the caller keeps (to wire its
    /// terminals).
    pub fn spawn_with<B: CanBus>(bus: B, node_id: u8, state: Arc<Mutex<NodeState>>) -> Cia401Node {
        let task = tokio::spawn(super::sim_node::run(bus, node_id, state.clone()));
        Cia401Node {
            node_id,
            state,
            task: Some(task),
        }
    }

    /// Locks the node's state.
    pub fn state(&self) -> MutexGuard<'_, NodeState> {
        lock(&self.state)
    }

    /// Kills the node: no more frames at all.
    pub fn kill(&mut self) {
        if let Some(t) = self.task.take() {
            t.abort();
        }
    }
}

impl Drop for Cia401Node {
    fn drop(&mut self) {
        self.kill();
    }
}

impl super::sim_node::SimNode for NodeState {
    fn heartbeat_ms(&self) -> u16 {
        self.heartbeat_ms
    }
    fn heartbeat_state(&self) -> Option<u8> {
        (!self.silent && self.sync_period_us == 0).then_some(self.nmt)
    }
    fn handle(&mut self, id: u8, m: &CanMsg) -> Vec<CanMsg> {
        handle(self, id, m)
    }
}

fn handle(s: &mut NodeState, id: u8, m: &CanMsg) -> Vec<CanMsg> {
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
                s.nmt = nmt::PRE_OPERATIONAL;
                s.outputs = [0; IO_BYTES];
                s.pending = [0; IO_BYTES];
                out.push(CanMsg::new(cob::HEARTBEAT + u16::from(id), &[nmt::BOOTUP]));
            }
            _ => {}
        }
    } else if cob_id == cob::SYNC {
        s.syncs += 1;
        if s.silent_at_sync.is_some_and(|n| s.syncs >= n) {
            s.silent = true;
            return out;
        }
        if s.nmt == nmt::OPERATIONAL {
            s.outputs = s.pending;
            out.push(CanMsg::new(cob::tpdo(1, id), &s.inputs[..8]));
            out.push(CanMsg::new(cob::tpdo(2, id), &s.inputs[8..]));
        }
        if s.sync_period_us > 0 && s.heartbeat_ms > 0 {
            if s.hb_syncs.is_multiple_of(s.heartbeat_every()) {
                out.push(CanMsg::new(cob::HEARTBEAT + u16::from(id), &[s.nmt]));
            }
            s.hb_syncs += 1;
        }
    } else if (cob_id == cob::rpdo(1, id) || cob_id == cob::rpdo(2, id))
        && s.nmt == nmt::OPERATIONAL
    {
        let base = if cob_id == cob::rpdo(1, id) { 0 } else { 8 };
        s.pending[base..base + d.len().min(8)].copy_from_slice(&d[..d.len().min(8)]);
        s.rpdos += 1;
    } else if cob_id == cob::SDO_RX + u16::from(id) && s.nmt != nmt::STOPPED {
        let snapshot = s.clone();
        let mut write = None;
        let answer = sdo::serve_request(
            d,
            |index, sub| od_read(&snapshot, index, sub),
            |index, sub, v, size| {
                let r = od_check_write(index, sub, size);
                if r.is_ok() {
                    write = Some((index, sub, v));
                }
                r
            },
        );
        match write {
            Some((0x1017, _, v)) => s.heartbeat_ms = v as u16,
            Some((0x6200, sub, v)) => s.outputs[usize::from(sub) - 1] = v as u8,
            _ => {}
        }
        if let Some(a) = answer {
            out.push(CanMsg::new(cob::SDO_TX + u16::from(id), &a));
        }
    }
    out
}

fn od_read(s: &NodeState, index: u16, sub: u8) -> Result<(u32, u8), u32> {
    let io = |bytes: &[u8; IO_BYTES]| match sub {
        0 => Ok((IO_BYTES as u32, 1)),
        1..=16 => Ok((u32::from(bytes[usize::from(sub) - 1]), 1)),
        _ => Err(sdo::ABORT_NO_SUBINDEX),
    };
    match (index, sub) {
        (0x1000, 0) => Ok((0x000F_0191, 4)),
        (0x1017, 0) => Ok((u32::from(s.heartbeat_ms), 2)),
        (0x6000, _) => io(&s.inputs),
        (0x6200, _) => io(&s.outputs),
        (0x1000 | 0x1017, _) => Err(sdo::ABORT_NO_SUBINDEX),
        _ => Err(sdo::ABORT_NO_OBJECT),
    }
}

fn od_check_write(index: u16, sub: u8, size: u8) -> Result<(), u32> {
    match (index, sub) {
        (0x1017, 0) if size == 2 => Ok(()),
        (0x6200, 1..=16) if size == 1 => Ok(()),
        (0x1017, 0) | (0x6200, 1..=16) => Err(sdo::ABORT_LENGTH),
        (0x1000 | 0x6000, _) => Err(sdo::ABORT_READ_ONLY),
        (0x1017 | 0x6200, _) => Err(sdo::ABORT_NO_SUBINDEX),
        _ => Err(sdo::ABORT_NO_OBJECT),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// In lock-step the heartbeat comes with the first SYNC and then every `1017h` ms of SYNC
    /// periods (40 ms of 2 ms SYNCs: every 20th), after the TPDOs; a silent node sends nothing
    /// from its `silent_at_sync` on, not even the heartbeat.
    #[test]
    fn the_sync_heartbeat_counts_syncs_and_a_silent_node_stops_it() {
        let mut s = NodeState {
            nmt: nmt::OPERATIONAL,
            heartbeat_ms: 40,
            sync_period_us: 2000,
            silent_at_sync: Some(42),
            ..NodeState::default()
        };
        assert_eq!(s.heartbeat_every(), 20);
        let sync = CanMsg::new(cob::SYNC, &[]);
        let mut beats = Vec::new();
        for n in 1..=60u64 {
            let out = handle(&mut s, 2, &sync);
            if n < 42 {
                assert_eq!(out[0].id, u32::from(cob::tpdo(1, 2)), "SYNC {n}");
                assert_eq!(out[1].id, u32::from(cob::tpdo(2, 2)), "SYNC {n}");
            } else {
                assert!(out.is_empty(), "SYNC {n}: {out:?}");
            }
            if out.iter().any(|m| m.id == u32::from(cob::HEARTBEAT + 2)) {
                beats.push(n);
            }
        }
        assert_eq!(beats, [1, 21, 41]);
        assert!(s.silent);
        // On the wall clock (no SYNC period) the shared loop beats, never a SYNC.
        let mut w = NodeState {
            nmt: nmt::OPERATIONAL,
            heartbeat_ms: 40,
            ..NodeState::default()
        };
        let out = handle(&mut w, 2, &sync);
        assert_eq!(out.len(), 2);
        use super::super::sim_node::SimNode as _;
        assert_eq!(w.heartbeat_state(), Some(nmt::OPERATIONAL));
        assert_eq!(s.heartbeat_state(), None);
    }
}
