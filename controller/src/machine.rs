//! Opening an example machine directory for `run` and `replay`: configuration, PLC source, sim script.
//!
//! The characterization is loaded and validated by `machine_facts::Facts` (a machine with errors is
//! refused); [`RunConfig::from_facts`] takes what the runtime needs from it.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use compiler::InterfaceMap;
use compiler::interface_map::InterfaceMapError;

use compiler::jit::CodeCache;
use runtime::compiled::{EngineKind, Source, VariantFn, compile_cached, compile_with_threads};
use runtime::config::RunConfig;
use runtime::machine_facts::{Facts, MachineError};
use runtime::online::CompileFn;
use runtime::process_map::{self, MissingHandshakes};
use sim::{CncSignals, Script};

use crate::plc_messages::MessageSetup;

/// Why a machine directory could not be opened for `run` or `replay`.
#[derive(Debug, thiserror::Error)]
pub enum OpenError {
    /// The characterization is missing or has errors.
    #[error(transparent)]
    Facts(#[from] MachineError),
    /// `sim.toml` has errors (the located diagnostics `ncplc check` reports, rendered).
    #[error("{0}")]
    SimChecks(String),
    /// `interface.toml` is invalid: every error of it, in file order.
    #[error("{}", interface_errors(.0))]
    Interface(Vec<InterfaceMapError>),
    /// Processes 2..NBP lack handshake signals in the interface map.
    #[error(transparent)]
    MissingHandshakes(#[from] MissingHandshakes),
    /// The PLC source cannot be read.
    #[error("{}: {source}", path.display())]
    Source {
        /// The source file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
}

/// The errors of `interface.toml`, one line each (`error[E1601]: …`).
fn interface_errors(errors: &[InterfaceMapError]) -> String {
    let lines: Vec<String> = errors
        .iter()
        .map(|e| format!("error[E{:04}]: {e}", e.code()))
        .collect();
    lines.join("\n")
}

/// A machine ready to run.
#[derive(Debug, Clone)]
pub struct Machine {
    /// The machine directory.
    pub dir: PathBuf,
    /// Runtime settings.
    pub config: RunConfig,
    /// The simulated machine's script (empty when there is no `sim.toml`).
    pub script: Script,
    /// The handshake signals of processes 1..NBP.
    pub signals: CncSignals,
    /// The interface map (builtin plus `<machine>/interface.toml`).
    pub interface: InterfaceMap,
    /// The PLC messages' signals and texts.
    pub messages: MessageSetup,
}

impl Machine {
    /// Opens `dir`; `plc` overrides the PLC source (as `ncplc build --plc`).
    pub fn open(dir: &Path, plc: Option<&Path>) -> Result<Machine, OpenError> {
        let facts = Facts::load(dir)?;
        let mut config = RunConfig::from_facts(&facts);
        if let Some(p) = plc {
            config.plc_source = p.to_path_buf();
        }
        let interface = InterfaceMap::load_for_machine_all(dir).map_err(OpenError::Interface)?;
        process_map::require(&facts.machine, &interface)?;
        let sim = sim::validate::load(dir, &facts.machine, &interface);
        let script = match sim.script {
            Some(s) if !diag::has_errors(&sim.diagnostics) => s,
            _ => {
                let mut sources = diag::Sources::new();
                let name = runtime::render::user_path(&dir.join(sim::validate::FILE))
                    .display()
                    .to_string();
                sources.add(name.clone(), sim.text.unwrap_or_default());
                let diags: Vec<diag::Diagnostic> = sim
                    .diagnostics
                    .into_iter()
                    .map(|mut d| {
                        d.file.clone_from(&name);
                        d
                    })
                    .collect();
                let rendered = diag::render_human(&diags, &sources);
                return Err(OpenError::SimChecks(rendered.trim_end().to_string()));
            }
        };
        let signals = CncSignals::from_map(&interface, process_map::nbp(&facts.machine));
        let messages = MessageSetup::new(&facts, &interface);
        Ok(Machine {
            dir: dir.to_path_buf(),
            config,
            script,
            signals,
            interface,
            messages,
        })
    }

    /// The machine's process numbers (1 alone when the interface map names no process).
    pub fn process_numbers(&self) -> Vec<u8> {
        if self.signals.processes.is_empty() {
            vec![1]
        } else {
            self.signals.processes.iter().map(|p| p.process).collect()
        }
    }

    /// The packet-A connectors IOCFIL declares (the fieldbus I/O map must respect them).
    pub fn declared_connectors(&self) -> fieldbus::DeclaredConnectors {
        fieldbus::DeclaredConnectors {
            inputs: self.config.a_inputs.clone(),
            outputs: self.config.a_outputs.clone(),
        }
    }

    /// Reads the PLC source.
    pub fn read_source(&self) -> Result<Vec<u8>, OpenError> {
        compiler::read_source(&self.config.plc_source).map_err(|source| OpenError::Source {
            path: self.config.plc_source.clone(),
            source,
        })
    }

    /// The source's name for diagnostics.
    pub fn source_name(&self) -> String {
        self.config.plc_source.display().to_string()
    }

    /// A compile function for this machine, `engine` and tick; the JIT uses one thread (for
    /// online change, beside the running scan).
    pub fn compile_fn(&self, engine: EngineKind, tick_ms: u32) -> CompileFn {
        self.compile_fn_with_threads(engine, tick_ms, 1)
    }

    /// [`Machine::compile_fn`] with the JIT on `threads` threads (0: all cores; for a first load,
    /// before the scan starts).
    pub fn compile_fn_with_threads(
        &self,
        engine: EngineKind,
        tick_ms: u32,
        threads: usize,
    ) -> CompileFn {
        let cfg = self.config.clone();
        let name = self.source_name();
        let map = self.interface.clone();
        std::sync::Arc::new(move |src: &[u8]| {
            compile_with_threads(&name, src, &cfg, &map, tick_ms, engine, threads)
        })
    }

    /// The compile functions of a run: the first load on every core, online changes on one
    /// thread, and the run-time switch of power flow ([`runtime::compiled::variant`], one thread);
    /// all share one JIT code cache, so an online change recompiles only the functions whose code
    /// changed (the rest is reused from the program running before it). Every program is
    /// instrumented for power flow ([`compiler::ir::flow`]) while `flow` is set when it compiles.
    pub fn compile_fns(
        &self,
        engine: EngineKind,
        tick_ms: u32,
        flow: Arc<AtomicBool>,
    ) -> (CompileFn, CompileFn, VariantFn) {
        let cache = Arc::new(std::sync::Mutex::new(CodeCache::new()));
        let make = |threads: usize| -> CompileFn {
            let (cfg, name, map) = (
                self.config.clone(),
                self.source_name(),
                self.interface.clone(),
            );
            let (cache, flow) = (cache.clone(), flow.clone());
            Arc::new(move |src: &[u8]| {
                let source = Source {
                    bytes: src,
                    cfg: &cfg,
                    interface: &map,
                    tick_ms,
                    flow: flow.load(Ordering::Relaxed),
                };
                compile_cached(&name, source, engine, threads, Some(&cache))
            })
        };
        let variant_cache = cache.clone();
        let variant: VariantFn = Arc::new(move |base, flow| {
            runtime::compiled::variant(base, flow, engine, 1, Some(&variant_cache))
        });
        (make(0), make(1), variant)
    }
}
