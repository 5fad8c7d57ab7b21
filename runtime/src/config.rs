//! The few machine facts the runtime needs, gathered in one [`RunConfig`].
//!
//! [`RunConfig::from_facts`] fills it from a validated machine (`machine_facts::Facts`); tests
//! and benchmarks may build one by hand.

use std::path::PathBuf;

use packets::Packet;

use crate::machine_facts::Facts;

/// Runtime settings derived from the machine's characterization.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RunConfig {
    /// The logic tick (IOCFIL `CLO tick_logic`), in milliseconds.
    pub tick_ms: u32,
    /// IOCFIL `CLO time_slow`, in milliseconds (the SLOW budget per tick).
    pub time_slow_ms: u32,
    /// Packet-A input connectors (IOCFIL `INx`).
    pub a_inputs: Vec<u16>,
    /// Packet-A output connectors (IOCFIL `OUx`).
    pub a_outputs: Vec<u16>,
    /// IOCFIL `SPL` (symbolic names allowed; manual default 1).
    pub spl: u32,
    /// Initial packet-T bytes (IOCFIL section 4), 64 bytes.
    pub t_init: Vec<u8>,
    /// PGCFIL `OLD`: restore logic-written T bytes and RETAIN variables at start.
    pub restore_old: bool,
    /// Consecutive overruns that trip the safe state.
    pub overrun_limit: u32,
    /// The PLC source file.
    pub plc_source: PathBuf,
    /// Where retained data is kept (None: nothing is retained).
    pub retain_file: Option<PathBuf>,
}

impl Default for RunConfig {
    fn default() -> Self {
        RunConfig {
            tick_ms: 10,
            time_slow_ms: 2,
            a_inputs: Vec::new(),
            a_outputs: Vec::new(),
            spl: 1,
            t_init: vec![0; Packet::T.len()],
            restore_old: false,
            overrun_limit: 3,
            plc_source: PathBuf::new(),
            retain_file: None,
        }
    }
}

impl RunConfig {
    /// The settings of a validated machine (`machine_facts`): CLO, INx/OUx, SPL, section-4 T
    /// bytes, PGCFIL OLD/NEW, the PLC source; retained data in `<machine>/retain.bin`.
    pub fn from_facts(facts: &Facts) -> RunConfig {
        let io = facts.iocfil();
        RunConfig {
            tick_ms: io.tick_logic_ms.max(1),
            time_slow_ms: io.time_slow_ms,
            a_inputs: io.input_connectors(),
            a_outputs: io.output_connectors(),
            spl: io.spl_or_default(),
            t_init: facts.t_init(),
            restore_old: facts.retains(),
            overrun_limit: 3,
            plc_source: facts.plc_source().to_path_buf(),
            retain_file: Some(facts.machine.dir.join("retain.bin")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_example_machines_give_their_settings() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../plc-programs");
        let lathe = RunConfig::from_facts(&Facts::load(&dir.join("lathe")).expect("lathe"));
        assert_eq!(
            (lathe.tick_ms, lathe.time_slow_ms, lathe.restore_old),
            (10, 2, false)
        );
        assert_eq!(
            (lathe.a_inputs.as_slice(), lathe.a_outputs.as_slice()),
            (&[0, 1][..], &[4, 5][..])
        );
        assert_eq!(&lathe.t_init[..4], &[0x10, 0x00, 0x32, 0x05]);
        assert!(lathe.plc_source.ends_with("MP0/PLCPRG"));
        let mill = RunConfig::from_facts(&Facts::load(&dir.join("mill")).expect("mill"));
        assert!(mill.restore_old);
    }
}
