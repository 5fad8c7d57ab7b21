//! End-to-end tests of the conventions every subcommand shares (`ncplc/src/cli/output.rs`):
//! exit codes, stdout for results and stderr for diagnostics, clap-checked value enums, a quiet
//! SIGPIPE, paths as the user can open them, colour, file modes, the text form of `nc plan`,
//! `--modbus-hmi`, and `<MACHINE>` in every usage line.

use std::io::{BufRead, BufReader};
use std::os::unix::fs::PermissionsExt;
use std::os::unix::process::ExitStatusExt;
use std::process::{Command, Output, Stdio};

use crate::e2e_common::{ncplc_at_root as ncplc, ncplc_in, root};

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn help_documents_the_exit_codes_and_names_the_machine_argument() {
    let top = ncplc(&["--help"]);
    assert!(top.status.success());
    let text = String::from_utf8_lossy(&top.stdout);
    assert!(
        text.contains("Exit codes: 0 ok; 1 problems found in the input"),
        "{text}"
    );
    for cmd in [
        &["check", "--help"][..],
        &["build", "--help"],
        &["run", "--help"],
        &["replay", "--help"],
        &["nc", "check", "--help"],
        &["nc", "plan", "--help"],
    ] {
        let out = ncplc(cmd);
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{cmd:?}");
        assert!(text.contains("Usage: ncplc "), "{cmd:?}: {text}");
        let usage = text.lines().find(|l| l.starts_with("Usage:")).unwrap_or("");
        assert!(usage.contains("<MACHINE>"), "{cmd:?}: {usage}");
        assert!(text.contains("2 usage or environment error"), "{cmd:?}");
    }
}

#[test]
fn a_missing_machine_directory_is_exit_2_everywhere() {
    let trace = "plc-programs/lathe/traces/basic.jsonl";
    for cmd in [
        &["check", "no/such/machine"][..],
        &["build", "no/such/machine"],
        &[
            "run",
            "no/such/machine",
            "--virtual-time",
            "--ticks",
            "1",
            "--no-watch",
        ],
        &["replay", "no/such/machine", trace],
        &["nc", "check", "no/such/machine", "GRID"],
        &["nc", "plan", "no/such/machine", "GRID"],
    ] {
        let out = ncplc(cmd);
        assert_eq!(out.status.code(), Some(2), "{cmd:?}: {}", stderr(&out));
        assert!(out.stdout.is_empty(), "{cmd:?}");
        assert!(stderr(&out).contains("no/such/machine"), "{cmd:?}");
    }
}

#[test]
fn value_enums_are_refused_by_clap_alike() {
    for cmd in [
        &["check", "plc-programs/mill", "--format", "xml"][..],
        &[
            "nc",
            "check",
            "plc-programs/mill",
            "GRID",
            "--format",
            "bogus",
        ],
        &[
            "nc",
            "plan",
            "plc-programs/mill",
            "GRID",
            "--format",
            "bogus",
        ],
        &["--color", "sometimes", "check", "plc-programs/mill"],
    ] {
        let out = ncplc(cmd);
        assert_eq!(out.status.code(), Some(2), "{cmd:?}");
        let err = stderr(&out);
        assert!(err.starts_with("error: invalid value '"), "{cmd:?}: {err}");
        assert!(err.contains("[possible values: "), "{cmd:?}: {err}");
    }
}

#[test]
fn results_go_to_stdout_and_diagnostics_to_stderr() {
    // nc check: the verdict is a summary (stderr); nc plan: the blocks are the result (stdout).
    let out = ncplc(&["nc", "check", "plc-programs/mill", "GRID"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(out.stdout.is_empty());
    assert!(stderr(&out).starts_with("plc-programs/mill/nc/GRID: ok ("));
    let dir = tempfile::tempdir().expect("tempdir");
    let bad = dir.path().join("bad");
    std::fs::write(&bad, "%1\nN10 G0 X10\nN20 M07\nN30 M30\n").expect("program");
    for format in ["human", "json"] {
        let out = ncplc(&[
            "nc",
            "check",
            "plc-programs/mill",
            bad.to_str().unwrap_or_default(),
            "--format",
            format,
        ]);
        assert_eq!(out.status.code(), Some(1), "{format}");
        assert!(out.stdout.is_empty(), "{format}");
        assert!(!stderr(&out).is_empty(), "{format}");
    }
}

#[test]
fn diagnostics_name_files_as_the_user_can_open_them() {
    // A program in a subdirectory of the current directory: named by its relative path, not
    // `nc/<basename>`.
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::create_dir(dir.path().join("progs")).expect("mkdir");
    std::fs::write(
        dir.path().join("progs/p1"),
        "%1\nN10 G0 X10\nN20 M07\nN30 M30\n",
    )
    .expect("write");
    let mill = root().join("plc-programs/mill");
    let out = ncplc_in(
        dir.path(),
        &[
            "nc",
            "check",
            mill.to_str().unwrap_or_default(),
            "progs/p1",
            "--format",
            "json",
        ],
    );
    assert_eq!(out.status.code(), Some(1));
    let first: serde_json::Value =
        serde_json::from_str(stderr(&out).lines().next().unwrap_or("")).expect("JSON");
    assert_eq!(first["file"], "progs/p1");
    // A program found in <machine>/nc/: the path from the current directory.
    let out = ncplc(&["nc", "check", "plc-programs/mill", "GRID"]);
    assert!(stderr(&out).starts_with("plc-programs/mill/nc/GRID: ok"));
    // A PLC program given with --plc from a subdirectory.
    std::fs::write(dir.path().join("progs/bad.plc"), "U4A0 = I2A0\n").expect("write");
    let lathe = root().join("plc-programs/lathe");
    let out = ncplc_in(
        &dir.path().join("progs"),
        &[
            "build",
            lathe.to_str().unwrap_or_default(),
            "--plc",
            "../progs/bad.plc",
        ],
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("┌─ bad.plc:1:8"), "{}", stderr(&out));
}

#[test]
fn colour_follows_the_color_option() {
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(dir.path().join("bad.plc"), "U4A0 = I2A0\n").expect("write");
    let build = |color: Option<&str>| {
        let mut args = Vec::new();
        if let Some(c) = color {
            args.extend(["--color", c]);
        }
        let lathe = root().join("plc-programs/lathe");
        args.extend([
            "build",
            lathe.to_str().unwrap_or_default(),
            "--plc",
            "bad.plc",
        ]);
        stderr(&ncplc_in(dir.path(), &args))
    };
    let always = build(Some("always"));
    assert!(
        always.starts_with("\x1b[1;31merror[E1104]\x1b[0m\x1b[1m: "),
        "{always:?}"
    );
    assert!(
        always.contains("\x1b[1;34m1 │\x1b[0m U4A0 = I2A0"),
        "{always:?}"
    );
    // stderr is a pipe here: auto means no colour, like never.
    for plain in [build(Some("never")), build(Some("auto")), build(None)] {
        assert!(plain.starts_with("error[E1104]: "), "{plain:?}");
        assert!(!plain.contains('\x1b'), "{plain:?}");
    }
}

#[test]
fn a_closed_pipe_ends_the_output_quietly() {
    // A trace whose text form is far larger than a pipe buffer (64 KiB).
    let dir = tempfile::tempdir().expect("tempdir");
    let trace = dir.path().join("big.jsonl");
    let mut text = String::from("{\"format\":\"ncplc-trace\",\"version\":1,\"tick_ms\":10}\n");
    for t in 0..20_000 {
        text.push_str(&format!("{{\"t\":{t},\"in\":{{\"I0A0\":{}}}}}\n", t % 2));
    }
    std::fs::write(&trace, text).expect("trace");
    let mut child = Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .args(["trace", "dump"])
        .arg(&trace)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("ncplc runs");
    let mut first = String::new();
    {
        // `| head -1`: read one line, then close the pipe.
        let mut out = BufReader::new(child.stdout.take().expect("stdout"));
        out.read_line(&mut first).expect("a line");
    }
    let out = child.wait_with_output().expect("ncplc ends");
    assert_eq!(
        first,
        "{\"format\":\"ncplc-trace\",\"version\":1,\"tick_ms\":10}\n"
    );
    // Killed by SIGPIPE like `cat` (141 in a shell), or done before the pipe closed; no panic.
    assert!(
        out.status.signal() == Some(libc::SIGPIPE) || out.status.success(),
        "{:?}",
        out.status
    );
    assert_eq!(stderr(&out), "");
}

#[test]
fn written_files_get_0666_less_the_umask() {
    let dir = tempfile::tempdir().expect("tempdir");
    let golden = root().join("plc-programs/lathe/traces/basic.jsonl");
    let lathe = root().join("plc-programs/lathe");
    for (umask, mode) in [("022", 0o644), ("027", 0o640)] {
        let packed = dir.path().join(format!("packed{umask}.ptrace"));
        let recorded = dir.path().join(format!("rec{umask}.jsonl"));
        let script = format!(
            "umask {umask} && exec \"$0\" trace pack '{}' '{}' && :",
            golden.display(),
            packed.display()
        );
        let status = Command::new("sh")
            .args(["-c", &script, env!("CARGO_BIN_EXE_ncplc")])
            .status()
            .expect("sh");
        assert!(status.success());
        let script = format!(
            "umask {umask} && exec \"$0\" run '{}' --virtual-time --ticks 5 --no-watch --record '{}'",
            lathe.display(),
            recorded.display()
        );
        let out = Command::new("sh")
            .args(["-c", &script, env!("CARGO_BIN_EXE_ncplc")])
            .output()
            .expect("sh");
        assert!(out.status.success(), "{}", stderr(&out));
        for f in [&packed, &recorded] {
            let m = std::fs::metadata(f).expect("written").permissions().mode() & 0o777;
            assert_eq!(m, mode, "{} under umask {umask}", f.display());
        }
    }
}

#[test]
fn plan_text_shows_every_field_of_the_json_form() {
    let dir = tempfile::tempdir().expect("tempdir");
    let p = dir.path().join("arc");
    std::fs::write(
        &p,
        "%1\nN10 G0 X0 Y0 Z0 S1000 M03\nN20 G1 X10 F200\nN30 G2 X20 Y0 I5 J0\nN40 M30\n",
    )
    .expect("program");
    let out = ncplc(&[
        "nc",
        "plan",
        "plc-programs/mill",
        p.to_str().unwrap_or_default(),
        "--format",
        "text",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    // The arc from (10, 0) to (20, 0) with I5 J0 has its centre at (15, 0). The modal record:
    // MEFI starts in G90 G94 with zero offset G53 (row 0) and G40.
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "N10 rapid X0 Y0 Z0 plane XY F- M3:before S1000 T- modal G90,G94,G53,G40\n\
         N20 linear X10 Y0 Z0 plane XY F200 M- S1000 T- modal G90,G94,G53,G40\n\
         N30 arc_cw X20 Y0 Z0 center X15 Y0 plane XY F200 M- S1000 T- modal G90,G94,G53,G40\n\
         N40 aux X20 Y0 Z0 plane XY F- M30:after S1000 T- modal G90,G94,G53,G40\n"
    );
}

/// A copy of the lathe whose coupler address is unused and whose `[hmi] bind` is `hmi`.
fn lathe_with_hmi(hmi: &str) -> tempfile::TempDir {
    let lathe = root().join("plc-programs/lathe");
    let dir = tempfile::tempdir().expect("tempdir");
    for f in [
        "FCRSYS",
        "MP0/AXCFIL",
        "MP0/PGCFIL",
        "MP0/IOCFIL",
        "MP0/PLCPRG",
        "MP0/MESSAG",
    ] {
        let to = dir.path().join(f);
        std::fs::create_dir_all(to.parent().expect("parent")).expect("mkdir");
        std::fs::copy(lathe.join(f), &to).expect("copy");
    }
    let free = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free port");
    let map = std::fs::read_to_string(lathe.join("io.toml"))
        .expect("io.toml")
        .replace("127.0.0.1:5020", &free.to_string())
        .replace("127.0.0.1:1502", hmi);
    std::fs::write(dir.path().join("io.toml"), map).expect("io.toml");
    dir
}

#[test]
fn modbus_hmi_overrides_the_hmi_address_of_io_toml() {
    // Another program holds the address io.toml names.
    let taken = std::net::TcpListener::bind("127.0.0.1:0").expect("bind");
    let taken_addr = taken.local_addr().expect("addr").to_string();
    let m = lathe_with_hmi(&taken_addr);
    let machine = m.path().to_str().unwrap_or_default();
    let run = |extra: &[&str]| {
        let mut args = vec![
            "run",
            machine,
            "--io",
            "modbus",
            "--ticks",
            "20",
            "--no-watch",
            "--overrun-limit",
            "0",
        ];
        args.extend_from_slice(extra);
        ncplc(&args)
    };
    let out = run(&[]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("error[E3060]"), "{}", stderr(&out));
    assert!(stderr(&out).contains(&taken_addr), "{}", stderr(&out));
    let out = run(&["--modbus-hmi", "127.0.0.1:0"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("20 ticks of 10 ms on modbus"),
        "{}",
        stderr(&out)
    );
    // Not an address: refused by clap.
    let out = run(&["--modbus-hmi", "localhost"]);
    assert_eq!(out.status.code(), Some(2));
    // The simulated I/O serves the Modbus HMI only when asked (tests/e2e/modbus_peer.rs talks to it).
    let out = ncplc(&[
        "run",
        machine,
        "--virtual-time",
        "--ticks",
        "1",
        "--no-watch",
        "--modbus-hmi",
        "127.0.0.1:0",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("1 ticks of 10 ms on sim"),
        "{}",
        stderr(&out)
    );
}
