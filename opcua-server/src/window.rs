//! The write window: the K/N bytes io.toml's `[hmi] holding` lets a client write (the same window
//! the Modbus HMI serves). Without io.toml or without `[hmi]`, nothing is writable.
//!
//! **Invariant:** a window holds flat-image byte ranges inside packets K and N only (io.toml's
//! validation refuses any other).

use std::path::Path;

use packets::Signal;

/// The writable byte ranges of the image.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Window {
    ranges: Vec<(usize, usize)>,
}

impl Window {
    /// A window of `(start, len)` flat-image byte ranges.
    pub fn from_ranges(ranges: Vec<(usize, usize)>) -> Window {
        Window { ranges }
    }

    /// Reads the window of the machine directory's io.toml (empty without the file or `[hmi]`);
    /// the located diagnostics of an invalid io.toml otherwise.
    pub fn load(
        machine_dir: &Path,
        declared: &fieldbus::DeclaredConnectors,
    ) -> Result<Window, Vec<diag::Diagnostic>> {
        if !machine_dir.join("io.toml").is_file() {
            return Ok(Window::default());
        }
        let (map, diags) = fieldbus::validate::load_map(machine_dir, declared);
        let map = map.ok_or(diags)?;
        Ok(Window::from_ranges(
            map.hmi
                .map(|h| h.holding.iter().map(|w| (w.start, w.len)).collect())
                .unwrap_or_default(),
        ))
    }

    /// True when the byte holding `signal` is inside the window.
    pub fn contains(&self, signal: &Signal) -> bool {
        let at = signal.image_byte();
        self.ranges.iter().any(|&(s, n)| at >= s && at < s + n)
    }

    /// The ranges, `(start, len)` in the flat image.
    pub fn ranges(&self) -> &[(usize, usize)] {
        &self.ranges
    }
}
