//! Adapting the PLC compiler (front end, interpreter, JIT) to the runtime's program traits.
//!
//! [`compile`] runs `compiler::compile` against a [`MachineContext`] built from the
//! [`RunConfig`], then wraps the program in the chosen engine. Online-change migration copies
//! every state slot (variable, timer, counter, pulse) whose name, kind and type are unchanged.

use std::any::Any;
use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::ops::Range;
use std::sync::{Arc, Mutex};

use compiler::context::MachineContext;
use compiler::interface_map::InterfaceMap;
use compiler::ir::Program;
use compiler::jit::CodeCache;
use compiler::{Engine, Interpreter};
use packets::Signal;

use crate::config::RunConfig;
use crate::program::{Loaded, Logic, ProgramMeta};

/// Why a PLC source could not become a loaded program.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The source has errors (the compiler's diagnostics).
    #[error("{rendered}")]
    Diagnostics {
        /// The diagnostics, errors and warnings.
        diagnostics: Vec<diag::Diagnostic>,
        /// Their rustc-style rendering with the source lines.
        rendered: String,
    },
    /// Cranelift could not compile the checked program.
    #[error("error: JIT: {0}")]
    Jit(#[from] compiler::JitError),
}

/// Which engine runs the program.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum EngineKind {
    /// Native code (cranelift).
    Jit,
    /// The reference interpreter.
    Interp,
}

/// A compiled program's facts.
#[derive(Debug)]
pub struct CompiledMeta {
    /// The IR program.
    pub program: Arc<Program>,
    written: Vec<Signal>,
    layout: u64,
    flow: Option<Arc<compiler::ir::flow::FlowMap>>,
    /// The program without power flow (`program` itself when it was not instrumented).
    base: Arc<Program>,
}

impl CompiledMeta {
    /// Facts of `program`.
    pub fn new(program: Arc<Program>) -> CompiledMeta {
        let written = program.written_signals();
        let mut h = std::collections::hash_map::DefaultHasher::new();
        for v in program.vars.iter().filter(|v| v.retain) {
            (&v.name, format!("{:?}", v.ty), v.offset).hash(&mut h);
        }
        program.retain_range().hash(&mut h);
        CompiledMeta {
            flow: None,
            base: Arc::clone(&program),
            program,
            written,
            layout: h.finish(),
        }
    }
}

impl ProgramMeta for CompiledMeta {
    fn image_len(&self) -> usize {
        self.program.image_len()
    }
    fn written_signals(&self) -> Vec<Signal> {
        self.written.clone()
    }
    fn retain_range(&self) -> Range<usize> {
        self.program.retain_range()
    }
    fn retain_layout(&self) -> u64 {
        self.layout
    }
    fn init_image(&self, image: &mut [u8]) {
        self.program.init_image(image);
    }
    fn migrate_from(&self, old: &dyn ProgramMeta, old_image: &[u8], new_image: &mut [u8]) {
        // Fresh initial values first; then every unchanged slot keeps its state.
        self.program.init_image(new_image);
        let Some(old) = old.as_any().downcast_ref::<CompiledMeta>() else {
            return;
        };
        let old_slots: HashMap<String, _> = old
            .program
            .state_slots()
            .into_iter()
            .map(|s| (s.name.to_ascii_uppercase(), s))
            .collect();
        for s in self.program.state_slots() {
            let Some(o) = old_slots.get(&s.name.to_ascii_uppercase()) else {
                continue;
            };
            if o.kind != s.kind || o.ty != s.ty || o.len != s.len {
                continue;
            }
            if let (Some(src), Some(dst)) = (
                old_image.get(o.offset..o.offset + o.len),
                new_image.get_mut(s.offset..s.offset + s.len),
            ) {
                dst.copy_from_slice(src);
            }
        }
    }
    fn idle_facts(&self) -> Option<compiler::ir::IdleFacts> {
        Some(self.program.idle_facts())
    }
    fn flow(&self) -> Option<&Arc<compiler::ir::flow::FlowMap>> {
        self.flow.as_ref()
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// A compiler engine as the runtime's [`Logic`].
pub struct EngineLogic(pub Box<dyn Engine>);

impl Logic for EngineLogic {
    fn tick(&mut self, image: &mut [u8]) {
        self.0.tick(image);
    }
    fn name(&self) -> &str {
        self.0.name()
    }
}

/// The compiler's view of the machine.
pub fn machine_context(cfg: &RunConfig, tick_ms: u32, interface: InterfaceMap) -> MachineContext {
    MachineContext {
        a_inputs: cfg.a_inputs.clone(),
        a_outputs: cfg.a_outputs.clone(),
        spl: cfg.spl,
        tick_ms,
        time_slow_ms: cfg.time_slow_ms,
        interface,
    }
}

/// Wraps an IR program in an engine (the JIT compiles on one thread).
pub fn load(program: Program, engine: EngineKind) -> Result<Loaded, LoadError> {
    load_with_threads(program, engine, 1)
}

/// [`load`] with the JIT compiling on `threads` threads (0: all available cores). A first load,
/// before the scan runs, uses every core; an online change keeps 1 so that compiling never
/// competes with the scan thread.
pub fn load_with_threads(
    program: Program,
    engine: EngineKind,
    threads: usize,
) -> Result<Loaded, LoadError> {
    load_cached(program, engine, threads, None)
}

/// [`load_with_threads`]; with `cache`, the JIT reuses the machine code of every function left
/// unchanged since the last program loaded through the same cache (see
/// [`compiler::jit::compile_cached`]) and leaves this program's code there.
pub fn load_cached(
    program: Program,
    engine: EngineKind,
    threads: usize,
    cache: Option<&Mutex<CodeCache>>,
) -> Result<Loaded, LoadError> {
    load_flow(Arc::new(program), None, engine, threads, cache)
}

/// Compiles a program's two power-flow variants at run time: (the program without power flow,
/// instrument it) → the loaded variant (see [`variant`]).
pub type VariantFn = Arc<dyn Fn(Arc<Program>, bool) -> Result<Loaded, LoadError> + Send + Sync>;

/// `base` (a program without power flow) instrumented for power flow when `flow` (and it can
/// be: a program built without source lines cannot), else as it is. Both variants lay out the
/// image alike up to the flow area the instrumented one appends, so the scan can switch between
/// them at a tick boundary keeping its image ([`crate::scheduler::Scheduler::switch_variant`]).
pub fn variant(
    base: Arc<Program>,
    flow: bool,
    engine: EngineKind,
    threads: usize,
    cache: Option<&Mutex<CodeCache>>,
) -> Result<Loaded, LoadError> {
    match flow
        .then(|| compiler::ir::flow::instrument(&base))
        .flatten()
    {
        Some((f, map)) => load_flow(Arc::new(f), Some((map, base)), engine, threads, cache),
        None => load_flow(base, None, engine, threads, cache),
    }
}

/// The running program without power flow (None: not a compiled program).
pub fn base_program(meta: &dyn ProgramMeta) -> Option<&Arc<Program>> {
    meta.as_any()
        .downcast_ref::<CompiledMeta>()
        .map(|m| &m.base)
}

/// [`load_cached`] of a program instrumented for power flow (`flow`: its slots and the program
/// without them).
fn load_flow(
    program: Arc<Program>,
    flow: Option<(compiler::ir::flow::FlowMap, Arc<Program>)>,
    engine: EngineKind,
    threads: usize,
    cache: Option<&Mutex<CodeCache>>,
) -> Result<Loaded, LoadError> {
    let logic: Box<dyn Engine> = match engine {
        EngineKind::Interp => Box::new(Interpreter::new(program.clone())),
        EngineKind::Jit => {
            let opts = compiler::jit::JitOptions {
                threads,
                ..compiler::jit::JitOptions::default()
            };
            match cache {
                // `ncplc run`'s first load: code an `ncplc build` left on disk is mapped, and
                // its functions fill the in-memory cache, so the first online change compiles
                // only what it changed.
                Some(cache)
                    if threads == 0
                        && let Some(found) = compiler::jit::disk_cache::DiskCache::from_env()
                            .and_then(|d| {
                                let mut cache = cache.lock().unwrap_or_else(|e| e.into_inner());
                                compiler::jit::disk_cache::lookup_cached(
                                    &program, &opts, &d, &mut cache,
                                )
                            }) =>
                {
                    Box::new(found)
                }
                Some(cache) => {
                    // A poisoned lock only means an earlier compile panicked; the cache is
                    // replaced as a whole by every compile, so its content is still consistent.
                    let mut cache = cache.lock().unwrap_or_else(|e| e.into_inner());
                    Box::new(compiler::jit::compile_cached(&program, &opts, &mut cache)?)
                }
                // A first load on every core (CLI `replay`, `run`'s start): through the on-disk
                // code cache, so a program `ncplc build` compiled is not compiled again.
                None if threads == 0 => {
                    let disk = compiler::jit::disk_cache::DiskCache::from_env();
                    Box::new(compiler::jit::disk_cache::compile(&program, &opts, disk.as_ref())?.0)
                }
                None => Box::new(compiler::jit::compile_with(&program, &opts)?),
            }
        }
    };
    let mut meta = CompiledMeta::new(program);
    if let Some((map, base)) = flow {
        meta.flow = Some(Arc::new(map));
        meta.base = base;
    }
    Ok(Loaded {
        logic: Box::new(EngineLogic(logic)),
        meta: Arc::new(meta),
    })
}

/// Compiles `source` (named `file_name` in diagnostics) for the machine `cfg` with tick `tick_ms`.
/// `Err` holds the diagnostics and their rendering. Warnings of a successful compile are printed to stderr.
/// The JIT uses one thread (what an online change needs).
pub fn compile(
    file_name: &str,
    source: &[u8],
    cfg: &RunConfig,
    interface: &InterfaceMap,
    tick_ms: u32,
    engine: EngineKind,
) -> Result<Loaded, LoadError> {
    compile_with_threads(file_name, source, cfg, interface, tick_ms, engine, 1)
}

/// [`compile`] parsing and JIT-compiling on `threads` threads (0: all available cores; see
/// [`load_with_threads`]).
pub fn compile_with_threads(
    file_name: &str,
    source: &[u8],
    cfg: &RunConfig,
    interface: &InterfaceMap,
    tick_ms: u32,
    engine: EngineKind,
    threads: usize,
) -> Result<Loaded, LoadError> {
    compile_cached(
        file_name,
        Source {
            bytes: source,
            cfg,
            interface,
            tick_ms,
            flow: false,
        },
        engine,
        threads,
        None,
    )
}

/// What [`compile_cached`] compiles: the source bytes and the machine they are for.
pub struct Source<'a> {
    /// The PLC source.
    pub bytes: &'a [u8],
    /// The machine's runtime settings.
    pub cfg: &'a RunConfig,
    /// The interface map.
    pub interface: &'a InterfaceMap,
    /// The logic tick in ms.
    pub tick_ms: u32,
    /// Instrument the program for power flow ([`compiler::ir::flow`]; `ncplc run --hmi`).
    pub flow: bool,
}

/// [`compile_with_threads`] with the JIT reusing unchanged functions' code through `cache`
/// (see [`load_cached`]): an online change then recompiles only the functions it changed.
pub fn compile_cached(
    file_name: &str,
    src: Source<'_>,
    engine: EngineKind,
    threads: usize,
    cache: Option<&Mutex<CodeCache>>,
) -> Result<Loaded, LoadError> {
    let Source {
        bytes: source,
        cfg,
        interface,
        tick_ms,
        flow,
    } = src;
    let ctx = machine_context(cfg, tick_ms, interface.clone());
    // A first load on every core goes through the on-disk front-end cache (beside the code
    // cache): after `ncplc build` of the same source, nothing is parsed or checked again.
    let c = if threads == 0 {
        let disk = compiler::jit::disk_cache::DiskCache::from_env();
        compiler::front_cache::compile_cached(file_name, source, &ctx, threads, disk.as_ref()).0
    } else {
        compiler::compile_with_threads(file_name, source, &ctx, threads)
    };
    let mut sources = diag::Sources::new();
    sources.add(file_name, c.text.clone());
    match c.program {
        Some(p) if !diag::has_errors(&c.diagnostics) => {
            if !c.diagnostics.is_empty() {
                eprint!(
                    "{}",
                    crate::render::render_diagnostics(&c.diagnostics, &sources)
                );
            }
            variant(Arc::new(p), flow, engine, threads, cache)
        }
        _ => Err(LoadError::Diagnostics {
            rendered: crate::render::render_diagnostics(&c.diagnostics, &sources),
            diagnostics: c.diagnostics,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testkit::sig;

    fn build(src: &str, engine: EngineKind) -> Loaded {
        let cfg = RunConfig {
            a_inputs: vec![0, 1],
            a_outputs: vec![4, 5],
            spl: 64,
            ..RunConfig::default()
        };
        compile(
            "PLCPRG",
            src.as_bytes(),
            &cfg,
            &InterfaceMap::builtin(),
            10,
            engine,
        )
        .unwrap_or_else(|e| panic!("{e}"))
    }

    const OLD: &str = "DEF T1 : TON(100ms)\nDEF N : DINT := 5\nT1 = I0A0\nU4A0 = T1\nP3 = I0A1\nIF P3 THEN\nN = N + 1\nEND_IF\n";
    /// Same names and types, one statement more, one variable removed and one added.
    const NEW: &str = "DEF T1 : TON(100ms)\nDEF M : DINT := 9\nDEF N : DINT := 5\nT1 = I0A0\nU4A0 = T1\nU4A1 = [M > 3]\nP3 = I0A1\nIF P3 THEN\nN = N + 1\nEND_IF\n";

    #[test]
    fn migration_keeps_unchanged_state_and_initialises_the_rest() {
        for engine in [EngineKind::Interp, EngineKind::Jit] {
            let mut old = build(OLD, engine);
            let mut image = vec![0u8; old.meta.image_len()];
            old.meta.init_image(&mut image);
            sig("I0A0").write(&mut image, 1);
            sig("I0A1").write(&mut image, 1);
            for _ in 0..10 {
                old.logic.tick(&mut image);
            }
            assert_eq!(
                sig("U4A0").read(&image),
                0,
                "{engine:?}: ET is 90 ms after 9 executions past the rise"
            );
            let mut new = build(NEW, engine);
            let mut new_image = vec![0u8; new.meta.image_len()];
            new_image[..packets::PACKETS_LEN].copy_from_slice(&image[..packets::PACKETS_LEN]);
            new.meta
                .migrate_from(old.meta.as_ref(), &image, &mut new_image);
            new.logic.tick(&mut new_image);
            // The timer kept its elapsed time: the next execution reaches 100 ms.
            assert_eq!(sig("U4A0").read(&new_image), 1, "{engine:?}");
            // P3 kept its previous input (no new edge), so N stayed 6; M took its initial value.
            let meta = new
                .meta
                .as_any()
                .downcast_ref::<CompiledMeta>()
                .expect("compiled");
            let var = |name: &str| {
                let v = meta
                    .program
                    .vars
                    .iter()
                    .find(|v| v.name.eq_ignore_ascii_case(name))
                    .expect("var");
                i32::from_le_bytes(
                    new_image[v.offset..v.offset + 4]
                        .try_into()
                        .expect("4 bytes"),
                )
            };
            assert_eq!((var("N"), var("M")), (6, 9), "{engine:?}");
        }
    }
}
