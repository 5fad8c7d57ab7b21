//! What the compiler needs to know about the machine: the declared packet-A connectors, IOCFIL
//! `SPL`, the logic tick and SLOW budget (`CLO`), and the interface map.
//!
//! The compiler does not read characterization files itself; the runtime fills this from the
//! machine it loaded, and tests use [`MachineContext::lathe_like`].

use crate::interface_map::InterfaceMap;

/// The machine facts the PLC compiler checks a program against.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MachineContext {
    /// Packet-A input connectors declared by IOCFIL `INx=` lines.
    pub a_inputs: Vec<u16>,
    /// Packet-A output connectors declared by IOCFIL `OUx=` lines.
    pub a_outputs: Vec<u16>,
    /// IOCFIL `SPL`: how many symbolic names the program may define (manual default 1).
    pub spl: u32,
    /// IOCFIL `CLO` tick_logic in ms: the timer period.
    pub tick_ms: u32,
    /// IOCFIL `CLO` time_slow in ms: the SLOW part's budget per tick.
    pub time_slow_ms: u32,
    /// The named interface signals (predeclared names).
    pub interface: InterfaceMap,
}

impl MachineContext {
    /// The example lathe's facts, for tests: inputs IN0, IN1, outputs OU4, OU5, `SPL=64`,
    /// `CLO=10,2`, the builtin interface map.
    pub fn lathe_like() -> Self {
        MachineContext {
            a_inputs: vec![0, 1],
            a_outputs: vec![4, 5],
            spl: 64,
            tick_ms: 10,
            time_slow_ms: 2,
            interface: InterfaceMap::builtin(),
        }
    }

    /// True when packet-A connector `c` is declared (as input or output).
    pub fn a_declared(&self, c: u16) -> bool {
        self.a_inputs.contains(&c) || self.a_outputs.contains(&c)
    }
}
