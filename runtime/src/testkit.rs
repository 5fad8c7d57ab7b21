//! Hand-written programs for tests and benchmarks: a closure as the logic, fixed facts as the meta.

use std::any::Any;
use std::ops::Range;
use std::sync::Arc;

use packets::{PACKETS_LEN, Signal};

use crate::program::{Loaded, Logic, ProgramMeta};

/// Fixed program facts; migration copies the common prefix of the compiler areas.
#[derive(Debug, Clone)]
pub struct FixedMeta {
    /// Image length.
    pub image_len: usize,
    /// Written signals.
    pub written: Vec<Signal>,
    /// Retain area.
    pub retain: Range<usize>,
    /// Retain layout fingerprint.
    pub layout: u64,
}

impl ProgramMeta for FixedMeta {
    fn image_len(&self) -> usize {
        self.image_len
    }
    fn written_signals(&self) -> Vec<Signal> {
        self.written.clone()
    }
    fn retain_range(&self) -> Range<usize> {
        self.retain.clone()
    }
    fn retain_layout(&self) -> u64 {
        self.layout
    }
    fn migrate_from(&self, _old: &dyn ProgramMeta, old_image: &[u8], new_image: &mut [u8]) {
        let n = old_image.len().min(new_image.len());
        if n > PACKETS_LEN {
            new_image[PACKETS_LEN..n].copy_from_slice(&old_image[PACKETS_LEN..n]);
        }
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// A closure as the logic.
pub struct FnLogic<F>(pub F);

impl<F: FnMut(&mut [u8]) + Send> Logic for FnLogic<F> {
    fn tick(&mut self, image: &mut [u8]) {
        (self.0)(image)
    }
    fn name(&self) -> &str {
        "fn"
    }
}

/// A loaded program from a closure and its facts.
pub fn loaded(f: impl FnMut(&mut [u8]) + Send + 'static, meta: FixedMeta) -> Loaded {
    Loaded {
        logic: Box::new(FnLogic(f)),
        meta: Arc::new(meta),
    }
}

/// Parses a signal name (panics on a bad one: for tests and benches with literal names).
pub fn sig(name: &str) -> Signal {
    match name.parse() {
        Ok(s) => s,
        Err(e) => panic!("bad signal {name}: {e}"),
    }
}
