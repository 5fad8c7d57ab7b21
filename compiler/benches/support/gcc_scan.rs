//! The C back end's program compiled by gcc and loaded with `dlopen` (shared by the scan benchmark
//! and the C back-end test; measurement only).

use std::ffi::CString;
use std::path::Path;
use std::process::Command;

/// A `plc_tick` compiled by gcc, loaded into this process.
pub struct GccScan {
    handle: *mut libc::c_void,
    tick: unsafe extern "C" fn(*mut u8),
    _dir: tempfile::TempDir,
}

impl GccScan {
    /// Compiles `c_source` with `gcc <flags> -shared -fPIC` in a fresh temporary directory and
    /// loads it; `Err` with a message when gcc is missing or fails.
    pub fn build(c_source: &str, flags: &[&str]) -> Result<GccScan, String> {
        let dir = tempfile::tempdir().map_err(|e| format!("temporary directory: {e}"))?;
        let c = dir.path().join("plc.c");
        let so = dir.path().join("plc.so");
        std::fs::write(&c, c_source).map_err(|e| format!("{}: {e}", c.display()))?;
        let out = Command::new("gcc")
            .args(flags)
            .args(["-ffp-contract=off", "-shared", "-fPIC", "-o"])
            .arg(&so)
            .arg(&c)
            .output()
            .map_err(|e| format!("gcc not available: {e}"))?;
        if !out.status.success() {
            return Err(format!(
                "gcc failed: {}",
                String::from_utf8_lossy(&out.stderr)
            ));
        }
        load(&so, dir)
    }

    /// Runs one scan over `image` (at least the program's image length).
    pub fn tick(&self, image: &mut [u8]) {
        // SAFETY: `tick` is the generated `plc_tick`, which touches only offsets below the
        // program's image length; callers pass an image of that length.
        unsafe { (self.tick)(image.as_mut_ptr()) }
    }
}

impl Drop for GccScan {
    fn drop(&mut self) {
        // SAFETY: the handle came from a successful dlopen and is closed once.
        unsafe {
            libc::dlclose(self.handle);
        }
    }
}

fn load(so: &Path, dir: tempfile::TempDir) -> Result<GccScan, String> {
    let path = CString::new(so.as_os_str().as_encoded_bytes()).map_err(|e| e.to_string())?;
    // SAFETY: dlopen/dlsym with valid NUL-terminated strings; the symbol is `void plc_tick(uint8_t*)`.
    unsafe {
        let handle = libc::dlopen(path.as_ptr(), libc::RTLD_NOW | libc::RTLD_LOCAL);
        if handle.is_null() {
            return Err(format!("dlopen {} failed", so.display()));
        }
        let sym = libc::dlsym(handle, c"plc_tick".as_ptr());
        if sym.is_null() {
            libc::dlclose(handle);
            return Err("plc_tick not found".into());
        }
        let tick = std::mem::transmute::<*mut libc::c_void, unsafe extern "C" fn(*mut u8)>(sym);
        Ok(GccScan {
            handle,
            tick,
            _dir: dir,
        })
    }
}
