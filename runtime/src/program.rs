//! What the runtime needs from a compiled PLC program, independent of how it was compiled.
//!
//! The scheduler drives a [`Logic`] (one scan per tick over the flat image) and consults the
//! program's [`ProgramMeta`] for the image size, the signals the program writes (trace outputs), the
//! retain area and the state migration used by online change. The `compiled` module adapts the
//! compiler's interpreter and JIT to these traits; tests use small hand-written implementations.

use std::any::Any;
use std::ops::Range;
use std::sync::Arc;

use packets::Signal;

/// One scan of the PLC logic over the flat image (packets first, compiler areas after).
pub trait Logic: Send {
    /// Runs one logic tick: the FAST part and the next SLOW slice.
    fn tick(&mut self, image: &mut [u8]);
    /// Short engine name for status lines (`jit`, `interp`, …).
    fn name(&self) -> &str;
}

/// Static facts about a program that the runtime needs beside its code.
pub trait ProgramMeta: Send + Sync + Any {
    /// Total image length the program needs (at least [`packets::PACKETS_LEN`]).
    fn image_len(&self) -> usize;
    /// Every packet bit and byte the program writes (the trace outputs), in a stable order.
    fn written_signals(&self) -> Vec<Signal>;
    /// Byte range of the RETAIN variables in the image (empty when there are none).
    fn retain_range(&self) -> Range<usize>;
    /// A fingerprint of the retain area's layout; a stored retain area is restored only when it matches.
    fn retain_layout(&self) -> u64;
    /// Writes the program's initial values into a fresh image (non-RETAIN variables with `:=`).
    fn init_image(&self, _image: &mut [u8]) {}
    /// Carries state over from `old` (whose image is `old_image`) into `new_image` for online change:
    /// timers, counters, pulses and variables whose name and type are unchanged keep their state.
    /// The packets are copied by the caller.
    fn migrate_from(&self, old: &dyn ProgramMeta, old_image: &[u8], new_image: &mut [u8]);
    /// What a replay needs to skip idle ticks exactly; `None` (the default) never skips.
    fn idle_facts(&self) -> Option<compiler::ir::IdleFacts> {
        None
    }
    /// Where the scan writes its power flow (a program compiled for the HMI), if it does.
    fn flow(&self) -> Option<&Arc<compiler::ir::flow::FlowMap>> {
        None
    }
    /// `self` as `Any`, so implementations can downcast the `old` program in `migrate_from`.
    fn as_any(&self) -> &dyn Any;
}

/// A program ready to run: its code and its facts.
pub struct Loaded {
    /// The executable scan.
    pub logic: Box<dyn Logic>,
    /// The program's facts.
    pub meta: Arc<dyn ProgramMeta>,
}

impl std::fmt::Debug for Loaded {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Loaded")
            .field("engine", &self.logic.name())
            .field("image_len", &self.meta.image_len())
            .finish()
    }
}
