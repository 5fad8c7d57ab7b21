//! End-to-end tests of `ncplc check` on the files a run reads besides the characterization and
//! the maps (issue 23: `check` reads what `run` reads): sim.toml against the machine, `nc/DIALECT`
//! and `nc/CONSTANTS`, the macro library, the programs of sim.toml's `[cnc] programs` and its
//! `[[axis]]` placements; each broken input is a located diagnostic and `run` refuses it too.

use crate::check::{brief, json_check, refuses, run_refuses};
use crate::e2e_common::copy_machine;

/// `check` reads sim.toml (issue 23, item 3): an input on a connector IOCFIL does not declare is
/// a located error (exit 1), and `run` refuses the machine with the same diagnostic.
#[test]
fn sim_toml_signal_on_an_undeclared_connector_is_a_located_error() {
    let dir = copy_machine("lathe");
    let sim = dir.path().join("sim.toml");
    let mut text = std::fs::read_to_string(&sim).expect("sim.toml");
    let line = text.lines().count() + 3;
    text.push_str("[[at]]\ntick = 5\nset = { I29A3 = 1 }\n");
    std::fs::write(&sim, text).expect("write");
    let d = dir.path().display().to_string();
    let (code, lines) = json_check(&[&d]);
    assert_eq!(code, Some(1));
    let got: Vec<_> = lines.iter().map(brief).collect();
    assert_eq!(
        got,
        [(
            3602,
            "sim.toml".to_string(),
            line as u64,
            9,
            "I29A3 is not an input signal of this machine".to_string()
        )]
    );
    let err = run_refuses(&d);
    assert!(
        err.contains("error[E3602]: I29A3 is not an input signal of this machine")
            && err.contains(&format!("sim.toml:{line}:9")),
        "{err}"
    );
}

/// Unknown keys, ticks a periodic script never reaches, out-of-range values, undeclared outputs
/// and K signals outside the interface map: every one located, none ignored.
#[test]
fn sim_toml_unknown_keys_ticks_and_values_are_located() {
    let dir = copy_machine("lathe");
    let sim = dir.path().join("sim.toml");
    let base = std::fs::read_to_string(&sim).expect("sim.toml");
    let n = base.lines().count() as u64;
    // (appended text, (code, line, column, message)).
    type Case<'a> = (&'a str, (u64, u64, u64, &'a str));
    let cases: [Case; 5] = [
        (
            "[[at]]\ntick = 5\nsett = { I0A3 = 1 }\n",
            (
                3600,
                n + 3,
                1,
                "unknown field `sett`, expected one of `tick`, `process`, `set`, `m`, `s`, `t`, `turn`",
            ),
        ),
        (
            "[[at]]\ntick = 2000\nset = { I0A3 = 1 }\n",
            (
                3604,
                n + 2,
                8,
                "[[at]] tick 2000 never comes: the script repeats every 2000 ticks",
            ),
        ),
        (
            "[[at]]\ntick = 5\nset = { I0A3 = 2 }\n",
            (3603, n + 3, 16, "I0A3 = 2 is out of range (0..1)"),
        ),
        (
            "[[follow]]\ninput = \"I0A5\"\noutput = \"U12A0\"\n",
            (
                3602,
                n + 3,
                10,
                "U12A0 is not an output signal of this machine",
            ),
        ),
        (
            "[[at]]\ntick = 5\nset = { I30K3 = 1 }\n",
            (
                3602,
                n + 3,
                9,
                "I30K3 is not an input signal of this machine",
            ),
        ),
    ];
    let d = dir.path().display().to_string();
    for (extra, (c, line, col, message)) in cases {
        std::fs::write(&sim, format!("{base}{extra}")).expect("write");
        let (code, lines) = json_check(&[&d]);
        assert_eq!(code, Some(1), "{extra}");
        let got: Vec<_> = lines.iter().map(brief).collect();
        assert_eq!(
            got,
            [(c, "sim.toml".to_string(), line, col, message.to_string())],
            "{extra}"
        );
    }
}

/// The part-run files `check` reads besides the characterization: nc/DIALECT and nc/CONSTANTS
/// (every bad line), located.
#[test]
fn nc_dialect_and_constants_are_checked() {
    let dir = copy_machine("lathe");
    std::fs::write(dir.path().join("nc/DIALECT"), "\n  fanuk\n").expect("write");
    std::fs::write(
        dir.path().join("nc/CONSTANTS"),
        "R8: 1\nR329 1000000\n\"comment\nR341: x\n",
    )
    .expect("write");
    let (code, lines) = json_check(&[&dir.path().display().to_string()]);
    assert_eq!(code, Some(1));
    let got: Vec<_> = lines.iter().map(brief).collect();
    assert_eq!(
        got,
        [
            (
                3620,
                "nc/DIALECT".to_string(),
                2,
                3,
                "unknown dialect `fanuk` (use mefi or fanuc)".to_string()
            ),
            (
                3621,
                "nc/CONSTANTS".to_string(),
                2,
                1,
                "expected `R<n>: <value>`, found `R329 1000000`".to_string()
            ),
            (
                3621,
                "nc/CONSTANTS".to_string(),
                4,
                1,
                "expected `R<n>: <value>`, found `R341: x`".to_string()
            ),
        ]
    );
}

/// `check` compiles the macro library every part and MDI compile loads (a broken cycle file
/// passed `check` and refused every part), and names a file of the folder that no compile reads;
/// `run --program` refuses the same library error.
#[test]
fn the_macro_library_is_checked_and_unread_files_are_named() {
    let dir = copy_machine("lathe");
    let cycles = dir.path().join("macros/PEVNECY5.NCP");
    let text = std::fs::read_to_string(&cycles).expect("cycles");
    // Line 10 of the cycle file is `    R00 = +0`.
    assert_eq!(text.lines().nth(9), Some("    R00 = +0"));
    std::fs::write(
        &cycles,
        text.replacen("    R00 = +0\n", "    R00 = +0 j\n", 1),
    )
    .expect("write");
    std::fs::write(dir.path().join("macros/notes.txt"), "cycle notes\n").expect("write");
    std::fs::create_dir(dir.path().join("macros/L0077")).expect("mkdir");
    std::fs::write(dir.path().join("macros/O0100"), "O0100\nG0 X1\nM99\n").expect("write");
    let path = dir.path().display().to_string();
    let (code, lines) = json_check(&[&path]);
    assert_eq!(code, Some(1));
    let got: Vec<_> = lines.iter().map(brief).collect();
    assert_eq!(
        got,
        [
            (
                2001,
                "macros/PEVNECY5.NCP".to_string(),
                10,
                14,
                "`j` is not allowed here".to_string()
            ),
            (
                3624,
                "macros/L0077".to_string(),
                0,
                0,
                "macros/L0077 is a folder: no compile reads it".to_string()
            ),
            (
                3624,
                "macros/notes.txt".to_string(),
                0,
                0,
                "macros/notes.txt is not read: no program can call it".to_string()
            ),
        ]
    );
    let err = refuses(&[
        "run",
        &path,
        "--virtual-time",
        "--program",
        "PART1",
        "--ticks",
        "1",
    ]);
    assert!(err.contains("macros/PEVNECY5.NCP:10:14"), "{err}");
    // Under nc/DIALECT the other dialect's files are not read either: the Fanuc program O0100
    // and the notes on a MEFI machine, the MEFI cycle file and the notes on a Fanuc one.
    std::fs::write(&cycles, &text).expect("write");
    std::fs::remove_dir(dir.path().join("macros/L0077")).expect("rmdir");
    for (dialect, unread) in [
        ("mefi", ["macros/O0100", "macros/notes.txt"]),
        ("fanuc", ["macros/PEVNECY5.NCP", "macros/notes.txt"]),
    ] {
        std::fs::write(dir.path().join("nc/DIALECT"), dialect).expect("write");
        let (code, lines) = json_check(&[&path]);
        assert_eq!(code, Some(0), "{dialect}: {lines:?}");
        let got: Vec<_> = lines.iter().map(brief).collect();
        let want: Vec<_> = unread
            .iter()
            .map(|f| {
                let message =
                    format!("{f} is not read: no program can call it (nc/DIALECT: {dialect})");
                (3624, f.to_string(), 0, 0, message)
            })
            .collect();
        assert_eq!(got, want, "{dialect}");
    }
}

/// `check` reads the other processes' programs sim.toml's `[cnc] programs` names as a part run
/// does: a key that is no process of the machine and a missing program are located in sim.toml
/// (3611), a program with errors is compiled with its own diagnostics; `run --program` refuses
/// both.
#[test]
fn the_programs_of_the_other_processes_are_checked() {
    let dir = copy_machine("mill");
    let sim_toml = dir.path().join("sim.toml");
    let text = std::fs::read_to_string(&sim_toml).expect("sim.toml");
    let line = "programs = { \"2\" = \"MAGAZINE\" }";
    let at = text
        .lines()
        .position(|l| l == line)
        .expect("the mill's [cnc] programs")
        + 1;
    let bad = text.replace(
        line,
        "programs = { \"2\" = \"MAGAZINX\", \"9\" = \"MAGAZINE\" }",
    );
    std::fs::write(&sim_toml, bad).expect("write");
    let path = dir.path().display().to_string();
    let (code, lines) = json_check(&[&path]);
    assert_eq!(code, Some(1));
    let got: Vec<_> = lines.iter().map(brief).collect();
    let sim = "sim.toml".to_string();
    assert_eq!(
        got,
        [
            (
                3611,
                sim.clone(),
                at as u64,
                20,
                "[cnc] programs: the program `MAGAZINX` of process 2 does not exist".to_string()
            ),
            (
                3611,
                sim,
                at as u64,
                32,
                "[cnc] programs: `9` is not a process of the machine (1..2)".to_string()
            ),
        ]
    );
    let run = [
        "run",
        &path,
        "--virtual-time",
        "--program",
        "O00023.nc",
        "--ticks",
        "1",
    ];
    let err = refuses(&run);
    assert!(err.contains("E3611"), "{err}");
    // The names are right again, the magazine program has an error on its second line.
    std::fs::write(&sim_toml, &text).expect("write");
    std::fs::write(dir.path().join("nc/MAGAZINE"), "%3\nN10 G4 j\nN20 M30\n").expect("write");
    let (code, lines) = json_check(&[&path]);
    assert_eq!(code, Some(1));
    let got: Vec<_> = lines.iter().map(brief).collect();
    assert_eq!(
        got,
        [(
            2001,
            "nc/MAGAZINE".to_string(),
            2,
            8,
            "`j` is not allowed here".to_string()
        )]
    );
    let err = refuses(&run);
    assert!(err.contains("nc/MAGAZINE:2:8"), "{err}");
    // A program that compiles but fails when executed (an arc whose end point is off its circle):
    // a part run plans it before its first tick and refuses it, `check` executes it too.
    let arc = "%3\nN10 G17 G1 X0 Y0 F100\nN20 G2 X10 Y5 I5 J0\nN30 M30\n";
    std::fs::write(dir.path().join("nc/MAGAZINE"), arc).expect("write");
    let (code, lines) = json_check(&[&path]);
    assert_eq!(code, Some(1));
    let got: Vec<_> = lines.iter().map(|l| brief(l).0).collect();
    assert_eq!(got, [2503], "{lines:?}");
    assert_eq!(lines[0]["file"], "nc/MAGAZINE", "{lines:?}");
    assert_eq!(lines[0]["line"], 3, "{lines:?}");
    let err = refuses(&run);
    assert!(err.contains("E2503"), "{err}");
}

/// `check` places sim.toml's `[[axis]]` entries as the part run's kernel does: an axis process 1
/// does not have, one placed twice and a limit switch without its AXCFIL MFC input are located
/// errors (3612), which `run` refuses too (it said `sim script: [[axis]] Q: …` without a place).
#[test]
fn sim_toml_axes_are_checked_against_process_1() {
    let dir = copy_machine("lathe");
    let axcfil = dir.path().join("MP0/AXCFIL");
    // The lathe's X (its first axis) loses its limit switch inputs (the file is not UTF-8).
    let mut bytes = std::fs::read(&axcfil).expect("AXCFIL");
    let mfc: &[u8] = b"MFC=I0A9,I0A10\r\n";
    let at = bytes
        .windows(mfc.len())
        .position(|w| w == mfc)
        .expect("X's MFC");
    bytes.drain(at..at + mfc.len());
    std::fs::write(&axcfil, bytes).expect("write");
    let sim_toml = dir.path().join("sim.toml");
    let mut sim = std::fs::read_to_string(&sim_toml).expect("sim.toml");
    let first = sim.lines().count() as u64 + 1;
    sim.push_str("[[axis]]\nname = \"Q\"\n[[axis]]\nname = \"X\"\nlimit_pos = 8.0\n");
    sim.push_str("[[axis]]\nname = \"Z\"\n[[axis]]\nname = \"Z\"\nstart = 1.0\n");
    std::fs::write(&sim_toml, sim).expect("write");
    let path = dir.path().display().to_string();
    let (code, lines) = json_check(&[&path]);
    assert_eq!(code, Some(1));
    let got: Vec<_> = lines.iter().map(brief).collect();
    let at = |line: u64, column: u64, message: &str| {
        (
            3612,
            "sim.toml".to_string(),
            first + line,
            column,
            message.to_string(),
        )
    };
    assert_eq!(
        got,
        [
            at(
                1,
                8,
                "[[axis]] Q: not a coordinated axis of process 1 (X, Z)"
            ),
            at(
                4,
                1,
                "[[axis]] X: a + limit switch without its AXCFIL MFC input"
            ),
            at(8, 8, "[[axis]] Z: placed twice"),
        ]
    );
    let err = run_refuses(&path);
    assert!(err.contains("E3612"), "{err}");
}
