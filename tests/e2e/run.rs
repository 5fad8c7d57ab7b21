//! End-to-end tests of `ncplc run`: deterministic recording in virtual time (the golden traces
//! are exactly what `run --virtual-time --record` produces), binary recording, compile errors,
//! retain across runs, online change.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::Duration;

use crate::e2e_common::Ncplc;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn ncplc(args: &[&std::ffi::OsStr]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .args(args)
        .output()
        .expect("ncplc runs")
}

#[test]
fn virtual_time_recording_reproduces_the_golden_traces() {
    let dir = tempfile::tempdir().expect("tempdir");
    for name in ["lathe", "mill"] {
        let machine = root().join("plc-programs").join(name);
        let out_path = dir.path().join(format!("{name}.jsonl"));
        let out = Ncplc::run(&machine)
            .virtual_time()
            .ticks(2000)
            .record(&out_path)
            .output();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let got = std::fs::read_to_string(&out_path).expect("recorded");
        let golden = std::fs::read_to_string(machine.join("traces/basic.jsonl")).expect("golden");
        assert_eq!(got, golden, "{name}");
    }
}

#[test]
fn binary_recording_dumps_to_the_same_text() {
    let dir = tempfile::tempdir().expect("tempdir");
    let machine = root().join("plc-programs/lathe");
    let bin = dir.path().join("lathe.ptrace");
    let out = Ncplc::run(&machine)
        .virtual_time()
        .ticks(2000)
        .record(&bin)
        .output();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let dump = ncplc(&["trace".as_ref(), "dump".as_ref(), bin.as_os_str()]);
    let golden = std::fs::read_to_string(machine.join("traces/basic.jsonl")).expect("golden");
    assert_eq!(String::from_utf8_lossy(&dump.stdout), golden);
    assert!(std::fs::metadata(&bin).expect("bin").len() < golden.len() as u64 / 3);
}

#[test]
fn a_program_that_does_not_compile_is_not_run() {
    let dir = tempfile::tempdir().expect("tempdir");
    let plc = dir.path().join("PLCPRG");
    std::fs::write(&plc, "U4A0 = I0A0 *\nU4A1 = Q7\n").expect("write");
    let machine = root().join("plc-programs/lathe");
    let out = ncplc(&[
        "run".as_ref(),
        machine.as_os_str(),
        "--plc".as_ref(),
        plc.as_os_str(),
        "--virtual-time".as_ref(),
        "--ticks".as_ref(),
        "10".as_ref(),
    ]);
    // Refused to start, like a machine with errors (`ncplc build` exits 1 on the same program).
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("error"), "{err}");
    assert!(err.contains("PLCPRG"), "{err}");
}

/// A copy of the mill (PGCFIL OLD) in a temporary directory with a small RETAIN program.
fn old_machine(dir: &Path) -> PathBuf {
    let m = dir.join("mill");
    std::fs::create_dir_all(m.join("MP0")).expect("mkdir");
    // interface.toml gives process 2 (NBP=2) its handshake signals; without it `run` refuses.
    for f in [
        "FCRSYS",
        "MP0/AXCFIL",
        "MP0/PGCFIL",
        "MP0/IOCFIL",
        "interface.toml",
    ] {
        std::fs::copy(root().join("plc-programs/mill").join(f), m.join(f)).expect("copy");
    }
    std::fs::write(
        m.join("MP0/PLCPRG"),
        "DEF COUNT : DINT RETAIN\nP1 = I0A0\nIF P1 THEN\nCOUNT = COUNT + 1\nEND_IF\nMUSPE = 1\nW0T1 = BYTE(COUNT)\n",
    )
    .expect("plc");
    std::fs::write(
        m.join("sim.toml"),
        "[[at]]\ntick = 2\nset = { I0A0 = 1 }\n[[at]]\ntick = 4\nset = { I0A0 = 0 }\n",
    )
    .expect("sim");
    m
}

#[test]
fn retained_data_survives_a_restart_with_pgcfil_old() {
    let dir = tempfile::tempdir().expect("tempdir");
    let m = old_machine(dir.path());
    let retain = dir.path().join("retain.bin");
    let run = || {
        Ncplc::run(&m)
            .ticks(20)
            .args(["--tick-ms", "1"])
            // Real time while other tests run: overruns must not trip the safe state here.
            .args(["--overrun-limit", "0"])
            .args(["--retain-file".as_ref(), retain.as_os_str()])
            .output()
    };
    let first = run();
    assert!(
        first.status.success(),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    let rec = runtime::retain::load(&retain)
        .expect("valid")
        .expect("written");
    assert!(rec.muspe);
    assert_eq!(rec.retain, vec![1, 0, 0, 0]);
    assert_eq!(rec.t_bytes[1], 1);
    let second = run();
    let err = String::from_utf8_lossy(&second.stderr);
    assert!(
        err.contains("retain: restored T bytes and RETAIN variables"),
        "{err}"
    );
    let rec = runtime::retain::load(&retain)
        .expect("valid")
        .expect("written");
    assert_eq!(rec.retain, vec![2, 0, 0, 0]);
    assert_eq!(rec.t_bytes[1], 2);
}

#[test]
fn online_change_swaps_a_good_edit_and_rejects_a_bad_one() {
    use std::io::BufRead;
    let dir = tempfile::tempdir().expect("tempdir");
    let m = old_machine(dir.path());
    let plc = m.join("MP0/PLCPRG");
    std::fs::write(&plc, "U4A0 = I0A0\n").expect("plc");
    let mut child = Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .args([
            "run".as_ref(),
            m.as_os_str(),
            "--ticks".as_ref(),
            "6000".as_ref(),
            "--tick-ms".as_ref(),
            "10".as_ref(),
            // Real time while other tests run: overruns must not trip the safe state here.
            "--overrun-limit".as_ref(),
            "0".as_ref(),
        ])
        .arg("--retain-file")
        .arg(dir.path().join("r.bin"))
        .stderr(Stdio::piped())
        .spawn()
        .expect("ncplc runs");
    let stderr = child.stderr.take().expect("stderr");
    let (tx, rx) = std::sync::mpsc::channel::<String>();
    std::thread::spawn(move || {
        for line in std::io::BufReader::new(stderr).lines() {
            let Ok(line) = line else { break };
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    let mut seen = String::new();
    let mut wait_for = |needle: &str| {
        while !seen.contains(needle) {
            match rx.recv_timeout(Duration::from_secs(30)) {
                Ok(line) => {
                    seen.push_str(&line);
                    seen.push('\n');
                }
                Err(_) => panic!("no `{needle}` in:\n{seen}"),
            }
        }
    };
    wait_for("online change: watching");
    std::fs::write(&plc, "U4A0 = I0A0 *\n U4A1 = Q\n").expect("bad edit");
    wait_for("online change rejected; the running program stays");
    std::fs::write(&plc, "U4A0 = /I0A0\n").expect("good edit");
    wait_for("online change: new program runs from tick");
    wait_for("edit-to-running");
    // SAFETY: plain signal to our own child process.
    unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGTERM) };
    let status = child.wait().expect("wait");
    assert!(status.success(), "{status:?}");
}

#[test]
fn an_unanswered_m_strobe_raises_an_alarm_naming_the_function() {
    let dir = tempfile::tempdir().expect("tempdir");
    let m = old_machine(dir.path());
    std::fs::write(
        m.join("sim.toml"),
        "strobe_timeout_ms = 50\n[[at]]\ntick = 1\nm = [91]\n",
    )
    .expect("sim");
    let out = Ncplc::run(&m).virtual_time().ticks(20).output();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        err.matches("alarm: cnc: M91 not acknowledged (FIN) within the strobe timeout")
            .count(),
        1,
        "{err}"
    );
}
