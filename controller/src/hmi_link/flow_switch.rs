//! Power flow switched at run time (`POST /api/flow`): the HMI says which variant it wants; the
//! other variant of the running program is compiled on a thread of its own
//! ([`runtime::compiled::variant`], one JIT thread, the run's code cache) and the scan switches to it
//! at a tick boundary keeping its image ([`Scheduler::switch_variant`]). Online changes compile the
//! wanted variant too (the run's compile functions read the same flag). A variant compiled for a
//! program that an online change has replaced meanwhile is dropped, and the new program's is
//! compiled; each (program, variant) is tried once, so a program that cannot be instrumented is
//! not compiled over and over.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, mpsc};

use runtime::compiled::{VariantFn, base_program};
use runtime::program::Loaded;
use runtime::scheduler::Scheduler;

/// What a variant compile hands back: (the base program's address, flow, the variant).
type Compiled = (usize, bool, Result<Loaded, String>);

/// The run-time power-flow switch of an HMI.
pub struct FlowSwitch {
    wanted: Arc<AtomicBool>,
    compile: VariantFn,
    pending: Option<mpsc::Receiver<Compiled>>,
    tried: Option<(usize, bool)>,
    /// The last variant compile's error, if it failed.
    pub error: Option<String>,
}

impl FlowSwitch {
    /// A switch over `wanted` (shared with the run's compile functions) compiling with `compile`.
    pub fn new(wanted: Arc<AtomicBool>, compile: VariantFn) -> FlowSwitch {
        FlowSwitch {
            wanted,
            compile,
            pending: None,
            tried: None,
            error: None,
        }
    }

    /// Power flow is wanted.
    pub fn wanted(&self) -> bool {
        self.wanted.load(Ordering::Relaxed)
    }

    /// Wants power flow on or off.
    pub fn set(&mut self, on: bool) {
        self.wanted.store(on, Ordering::Relaxed);
    }

    /// At a tick boundary: switches the scan to a finished variant, or starts compiling the
    /// wanted one when the scan runs the other.
    pub fn update(&mut self, sched: &mut Scheduler) {
        let wanted = self.wanted();
        if self.pending.is_none() && wanted == sched.flow().is_some() {
            return;
        }
        let Some(base) = base_program(sched.meta().as_ref()).cloned() else {
            return;
        };
        let id = Arc::as_ptr(&base) as usize;
        if let Some(rx) = &self.pending {
            match rx.try_recv() {
                Err(mpsc::TryRecvError::Empty) => return,
                Err(mpsc::TryRecvError::Disconnected) => self.pending = None,
                Ok((of, flow, result)) => {
                    self.pending = None;
                    match result {
                        Ok(loaded) if of == id && flow == wanted => {
                            self.error = None;
                            sched.switch_variant(loaded);
                        }
                        // Compiled for a program or a variant no longer wanted: may be asked again.
                        Ok(_) => self.tried = None,
                        Err(e) => self.error = Some(e),
                    }
                }
            }
        }
        if wanted == sched.flow().is_some() || self.tried == Some((id, wanted)) {
            return;
        }
        self.tried = Some((id, wanted));
        let (tx, rx) = mpsc::channel();
        let compile = Arc::clone(&self.compile);
        let spawned = std::thread::Builder::new()
            .name("hmi-flow-compile".into())
            .spawn(move || {
                let r = compile(base, wanted).map_err(|e| e.to_string());
                let _ = tx.send((id, wanted, r));
            });
        match spawned {
            Ok(_) => self.pending = Some(rx),
            Err(e) => self.error = Some(format!("power flow: {e}")),
        }
    }
}
