//! A trace replay assembled from the machine: [`crate::Builder::replayer`] opens the machine and
//! reads its PLC source once; [`Replayer::compile`] builds the program for a trace's tick and
//! [`Replayer::replay`] re-applies the trace (re-running the CNC kernel when the trace's header
//! names partprograms, [`crate::part_replay`]). `ncplc replay` and `ncplc test` go through it.
//!
//! **Invariant:** a replay is a pure function of the trace, the program and the machine files: no
//! clock, no I/O, no server.

use runtime::compiled::EngineKind;
use runtime::program::Loaded;
use runtime::replay::{Replay, ReplayOptions};
use std::borrow::Borrow;

use trace::TickRecord;
use trace::reader::Header;

use crate::machine::Machine;

/// The machine and program a replay runs against.
pub struct Replayer {
    machine: Machine,
    source: Vec<u8>,
    engine: EngineKind,
}

impl Replayer {
    pub(crate) fn new(machine: Machine, source: Vec<u8>, engine: EngineKind) -> Replayer {
        Replayer {
            machine,
            source,
            engine,
        }
    }

    /// The opened machine.
    pub fn machine(&self) -> &Machine {
        &self.machine
    }

    /// Compiles the PLC program for `tick_ms` on `threads` JIT threads (0: every core); the error
    /// is the rendered diagnostics.
    pub fn compile(&self, tick_ms: u32, threads: usize) -> Result<Loaded, String> {
        let compile = self
            .machine
            .compile_fn_with_threads(self.engine, tick_ms, threads);
        compile(&self.source).map_err(|e| e.to_string())
    }

    /// Replays the trace with `header` whose `records` arrive one at a time through `loaded`
    /// (memory does not grow with the trace); each record the replay produces goes to `actual`
    /// and `progress` hears the ticks done.
    pub fn replay<R: Borrow<TickRecord>>(
        &self,
        header: &Header,
        records: impl IntoIterator<Item = Result<R, String>>,
        loaded: Loaded,
        options: ReplayOptions,
        actual: &mut dyn FnMut(&TickRecord) -> Result<(), String>,
        progress: impl FnMut(u64),
    ) -> Result<Replay, String> {
        crate::part_replay::replay_trace(
            &self.machine,
            header,
            records,
            loaded,
            options,
            actual,
            progress,
        )
    }
}
