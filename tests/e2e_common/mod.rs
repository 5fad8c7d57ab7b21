//! Shared by the part-run end-to-end tests: the workspace root, running the `ncplc` binary, and
//! copying a bundled machine into a temporary directory.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The workspace root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Runs the `ncplc` binary with `args` and collects its output.
pub fn ncplc<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .args(args)
        .output()
        .expect("ncplc runs")
}

/// Copies the directory tree `from` into `to` (which exists).
pub fn copy_dir(from: &Path, to: &Path) {
    for e in std::fs::read_dir(from).expect("dir") {
        let e = e.expect("entry");
        let dst = to.join(e.file_name());
        if e.file_type().expect("type").is_dir() {
            std::fs::create_dir_all(&dst).expect("mkdir");
            copy_dir(&e.path(), &dst);
        } else {
            std::fs::copy(e.path(), &dst).expect("copy");
        }
    }
}

/// A copy of the bundled lathe whose `sim.toml` ends just before the line `marker` (the script's
/// later events dropped).
pub fn lathe_cut_at(marker: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("tempdir");
    copy_dir(&root().join("plc-programs/lathe"), dir.path());
    let sim = dir.path().join("sim.toml");
    let text = std::fs::read_to_string(&sim).expect("sim.toml");
    let cut = text
        .find(marker)
        .unwrap_or_else(|| panic!("the lathe's sim.toml has `{marker}`"));
    std::fs::write(&sim, &text[..cut]).expect("write sim.toml");
    dir
}
