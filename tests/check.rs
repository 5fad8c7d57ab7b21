//! End-to-end tests of `ncplc check` on the bundled machines.

use std::process::Command;

#[test]
fn ncplc_prints_help() {
    let out = Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .arg("--help")
        .output()
        .expect("ncplc runs");
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("check"), "{text}");
}
