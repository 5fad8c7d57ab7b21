//! End-to-end tests of `ncplc trace`: text → binary → text round trip, readable errors.

use std::process::Command;

const TEXT: &str = "{\"format\":\"ncplc-trace\",\"version\":1,\"tick_ms\":10}\n\
{\"t\":0,\"in\":{\"I0A5\":1,\"W3K0\":145},\"out\":{\"U4A0\":1}}\n\
{\"t\":12,\"out\":{\"U4A0\":0,\"W14K0\":100}}\n\
{\"t\":40}\n";

fn ncplc(args: &[&std::ffi::OsStr]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .args(args)
        .output()
        .expect("ncplc runs")
}

#[test]
fn pack_then_dump_gives_the_text_back() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text = dir.path().join("t.jsonl");
    let bin = dir.path().join("t.ptrace");
    std::fs::write(&text, TEXT).expect("write");
    let out = ncplc(&[
        "trace".as_ref(),
        "pack".as_ref(),
        text.as_os_str(),
        bin.as_os_str(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let size = std::fs::metadata(&bin).expect("binary written").len();
    assert!(size < TEXT.len() as u64 / 2, "binary {size} bytes");
    let out = ncplc(&["trace".as_ref(), "dump".as_ref(), bin.as_os_str()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(String::from_utf8_lossy(&out.stdout), TEXT);
}

#[test]
fn a_damaged_trace_is_reported_with_its_line() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text = dir.path().join("bad.jsonl");
    std::fs::write(&text, "{\"format\":\"ncplc-trace\",\"version\":1,\"tick_ms\":10}\n{\"t\":1,\"in\":{\"Q0A5\":1}}\n")
        .expect("write");
    let out = ncplc(&["trace".as_ref(), "dump".as_ref(), text.as_os_str()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bad.jsonl: line 2: `Q0A5` is not a signal name"),
        "{err}"
    );
}
