//! The wiring between a simulated machine and the terminals of the simulated CiA 401 nodes of the
//! `virtual` transport: which packet-A bytes are which node's physical input or output bytes.
//!
//! A part run on the virtual bus (`controller::drive_io`) lets `sim.toml`'s script and the plant
//! write the packet-A inputs onto the nodes' terminals ([`SimWiring::put_inputs`]) instead of into
//! the scan's image, so that they reach the scan through the TPDOs of the next SYNC as on real
//! wiring; the outputs they read come from the nodes' terminals ([`SimWiring::get_outputs`]), set
//! by the RPDOs the master sent.
//!
//! Invariant: only mappings of TPDO/RPDO 1 and 2 are wired (the simulated node has 16 input and 16
//! output bytes: PDO 1 carries bytes 0..7, PDO 2 bytes 8..15); each wired packet byte is one
//! terminal byte of one node.

use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use super::node_sim::{IO_BYTES, NodeState};
use crate::map::{ByteRange, CanopenConfig, PdoMapping};

/// One node's wired bytes: (packet-A byte, terminal byte).
struct Wired {
    state: Arc<Mutex<NodeState>>,
    inputs: Vec<(usize, usize)>,
    outputs: Vec<(usize, usize)>,
}

/// The simulated nodes' terminals, wired to packet A as io.toml maps them.
pub struct SimWiring {
    nodes: Vec<Wired>,
}

fn lock(s: &Mutex<NodeState>) -> MutexGuard<'_, NodeState> {
    s.lock().unwrap_or_else(PoisonError::into_inner)
}

/// (packet byte, terminal byte) of every byte of `maps` that a simulated node has.
fn wire(maps: &[PdoMapping]) -> Vec<(usize, usize)> {
    let mut v = Vec::new();
    for m in maps.iter().filter(|m| (1..=2).contains(&m.pdo)) {
        let base = usize::from(m.pdo - 1) * 8 + usize::from(m.offset);
        for i in 0..m.range.len {
            if base + i < IO_BYTES && usize::from(m.offset) + i < 8 {
                v.push((m.range.start + i, base + i));
            }
        }
    }
    v
}

impl SimWiring {
    /// Wires the nodes of `cfg` to their states (`states`: node id and state, the simulated
    /// nodes the virtual transport started).
    pub fn new(cfg: &CanopenConfig, states: &[(u8, Arc<Mutex<NodeState>>)]) -> SimWiring {
        let nodes = cfg
            .nodes
            .iter()
            .filter_map(|n| {
                let (_, state) = states.iter().find(|(id, _)| *id == n.node_id)?;
                Some(Wired {
                    state: Arc::clone(state),
                    inputs: wire(&n.inputs),
                    outputs: wire(&n.outputs),
                })
            })
            .collect();
        SimWiring { nodes }
    }

    /// The packet-A input bytes wired to a node's terminals, as ranges of one byte, in order.
    pub fn input_bytes(&self) -> Vec<ByteRange> {
        let mut v: Vec<usize> = self
            .nodes
            .iter()
            .flat_map(|n| n.inputs.iter().map(|(p, _)| *p))
            .collect();
        v.sort_unstable();
        v.dedup();
        v.into_iter()
            .map(|start| ByteRange { start, len: 1 })
            .collect()
    }

    /// True when packet byte `byte` is a wired input.
    pub fn is_input(&self, byte: usize) -> bool {
        self.nodes
            .iter()
            .any(|n| n.inputs.iter().any(|(p, _)| *p == byte))
    }

    /// Copies the nodes' physical inputs into the wired bytes of `packets` (what the terminals
    /// carry now, for a machine model that changes some of them).
    pub fn get_inputs(&self, packets: &mut [u8]) {
        for n in &self.nodes {
            let s = lock(&n.state);
            for &(p, t) in &n.inputs {
                if let Some(b) = packets.get_mut(p) {
                    *b = s.inputs[t];
                }
            }
        }
    }

    /// Puts the wired bytes of `packets` on the nodes' input terminals.
    pub fn put_inputs(&self, packets: &[u8]) {
        for n in &self.nodes {
            let mut s = lock(&n.state);
            for &(p, t) in &n.inputs {
                if let Some(b) = packets.get(p) {
                    s.inputs[t] = *b;
                }
            }
        }
    }

    /// Copies the nodes' output terminals into the wired output bytes of `packets`.
    pub fn get_outputs(&self, packets: &mut [u8]) {
        for n in &self.nodes {
            let s = lock(&n.state);
            for &(p, t) in &n.outputs {
                if let Some(b) = packets.get_mut(p) {
                    *b = s.outputs[t];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::{CanNode, TransportConfig};
    use std::time::Duration;

    fn mapping(start: usize, len: usize, pdo: u8, offset: u8) -> PdoMapping {
        PdoMapping {
            range: ByteRange { start, len },
            pdo,
            offset,
            fail: 0,
        }
    }

    #[test]
    fn pdo_bytes_are_terminal_bytes_and_pdo_3_is_not_wired() {
        let cfg = CanopenConfig {
            transport: TransportConfig::Virtual,
            sdo_timeout: Duration::from_millis(100),
            nodes: vec![CanNode {
                name: "dio1".into(),
                node_id: 2,
                heartbeat: Duration::from_millis(100),
                healthy: None,
                sdo: Vec::new(),
                inputs: vec![
                    mapping(0, 4, 1, 0),
                    mapping(4, 2, 2, 6),
                    mapping(8, 1, 3, 0),
                ],
                outputs: vec![mapping(16, 2, 1, 4)],
                simulate: Default::default(),
            }],
            drives: Vec::new(),
        };
        let state = super::super::node_sim::Cia401Node::new_state(0);
        let w = SimWiring::new(&cfg, &[(2, Arc::clone(&state))]);
        let mut packets = [0u8; 32];
        packets[..8].copy_from_slice(&[1, 2, 3, 4, 5, 6, 7, 8]);
        w.put_inputs(&packets);
        // TPDO1 bytes 0..3 ← packet bytes 0..3; TPDO2 bytes 6, 7 (terminal 14, 15) ← 4, 5.
        let want = [1, 2, 3, 4, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 5, 6];
        assert_eq!(lock(&state).inputs, want);
        assert_eq!(
            w.input_bytes().iter().map(|r| r.start).collect::<Vec<_>>(),
            [0, 1, 2, 3, 4, 5]
        );
        assert!(!w.is_input(8));
        lock(&state).outputs[4] = 0xA5;
        lock(&state).outputs[5] = 0x5A;
        let mut out = [0u8; 32];
        w.get_outputs(&mut out);
        assert_eq!(&out[15..19], &[0, 0xA5, 0x5A, 0]);
        let mut back = [9u8; 32];
        w.get_inputs(&mut back);
        assert_eq!(&back[..9], &[1, 2, 3, 4, 5, 6, 9, 9, 9]);
    }
}
