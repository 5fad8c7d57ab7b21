//! The [`Engine`] trait both back ends implement: one tick over the flat image.

/// Something that runs a compiled program over the flat image (the interpreter or the JIT).
pub trait Engine: Send {
    /// Runs one logic tick: the FAST part, then the next SLOW slice. An image shorter than the
    /// program's `image_len()` is left untouched.
    fn tick(&mut self, image: &mut [u8]);
    /// Short name for status lines and benchmarks (`interp`, `jit`).
    fn name(&self) -> &'static str;
}
