//! End-to-end tests of `ncplc check` on the bundled machines and on broken copies of them.

use std::path::PathBuf;

use crate::e2e_common::{copy_machine, ncplc, ncplc_in, root};

fn machine(name: &str) -> String {
    root().join("plc-programs").join(name).display().to_string()
}

#[test]
fn ncplc_prints_help() {
    let out = ncplc(&["--help"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("check"), "{text}");
}

#[test]
fn example_machines_check_clean() {
    // The mill's interface.toml (process 2's handshake signals) is checked and named too.
    // Run from the workspace root: the files are named as the user can open them from there.
    let root = root();
    for (name, extra) in [("lathe", false), ("mill", true)] {
        let out = ncplc_in(&root, &["check", &format!("plc-programs/{name}")]);
        let text = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{name}: {text}");
        assert!(
            out.stdout.is_empty(),
            "{name}: a check has no results on stdout"
        );
        let m = format!("plc-programs/{name}");
        // Both have an io.toml, which `check` validates too.
        // And sim.toml and the part-run tables (issue 23: check reads what run reads).
        // The lathe's PLC message file (FCRSYS FILMS5) follows IOCFIL; the PLC program and the
        // macro library come last, then the mill magazine's program (sim.toml [cnc] programs).
        let extra = if extra {
            format!(
                ", {m}/interface.toml, {m}/io.toml, {m}/sim.toml, {m}/MP0/TAB0.KOR, {m}/MP0/TAB0.POS, {m}/MP0/PLCPRG, {m}/macros/L9001, {m}/macros/PCYKLYDG.NCP, {m}/nc/MAGAZINE"
            )
        } else {
            format!(
                ", {m}/MP0/MESSAG, {m}/io.toml, {m}/sim.toml, {m}/nc/CONSTANTS, {m}/MP0/TAB0.KOR, {m}/MP0/TAB0.POS, {m}/MP0/PLCPRG, {m}/macros/PEVNECY5.NCP"
            )
        };
        assert_eq!(
            text,
            format!(
                "{m}/FCRSYS, {m}/MP0/AXCFIL, {m}/MP0/PGCFIL, {m}/MP0/IOCFIL{extra}: no problems found\n"
            ),
            "{name}"
        );
    }
}

/// A copy of the lathe with a broken AXCFIL: exit 1, rustc-style output and JSON lines.
#[test]
fn broken_machine_exits_1_with_located_diagnostics() {
    let dir = tempfile::tempdir().expect("temp dir");
    let lathe = PathBuf::from(machine("lathe"));
    for f in [
        "FCRSYS",
        "MP0/AXCFIL",
        "MP0/PGCFIL",
        "MP0/IOCFIL",
        "MP0/MESSAG",
    ] {
        let to = dir.path().join(f);
        std::fs::create_dir_all(to.parent().expect("parent")).expect("mkdir");
        std::fs::copy(lathe.join(f), &to).expect("copy");
    }
    let ax = dir.path().join("MP0/AXCFIL");
    let bytes = std::fs::read(&ax).expect("read");
    let text = String::from_utf8_lossy(&bytes).replacen("TIM=1,0,0,0,0", "TIM=64,0,0,0,0", 1);
    std::fs::write(&ax, text).expect("write");
    let out = ncplc_in(dir.path(), &["check", "."]);
    assert_eq!(out.status.code(), Some(1));
    let human = String::from_utf8_lossy(&out.stderr);
    assert!(
        human.contains("error[E0101]: CPU tick 64 ms is too large"),
        "{human}"
    );
    assert!(human.contains("MP0/AXCFIL:5:5"), "{human}");
    assert!(human.contains("TIM=64,0,0,0,0"), "{human}");
    assert!(human.contains("^^"), "{human}");

    let out = ncplc_in(dir.path(), &["check", ".", "--format", "json"]);
    assert_eq!(out.status.code(), Some(1));
    let lines: Vec<serde_json::Value> = String::from_utf8_lossy(&out.stderr)
        .lines()
        .map(|l| serde_json::from_str(l).expect("JSON line"))
        .collect();
    let e = lines.iter().find(|v| v["code"] == 101).expect("error 101");
    assert_eq!(
        (
            e["file"].as_str(),
            e["section"].as_u64(),
            e["line"].as_u64(),
            e["column"].as_u64()
        ),
        (Some("MP0/AXCFIL"), Some(1), Some(5), Some(5))
    );
    assert_eq!(e["severity"], "error");
    assert!(e["hint"].as_str().is_some_and(|h| h.contains("1 to 63")));
}

#[test]
fn dump_prints_the_typed_model() {
    let out = ncplc(&["check", &machine("mill"), "--dump"]);
    assert_eq!(out.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("model JSON");
    assert_eq!(v["axcfil"]["tim"], 1);
    assert_eq!(v["axcfil"]["nbp"], 2);
    assert_eq!(v["axcfil"]["processes"][1]["axes"][0]["name"], "T");
    assert_eq!(
        v["axcfil"]["processes"][1]["axes"][0]["tpa"]["axis_type"]["ptp"],
        true
    );
}

#[test]
fn missing_machine_directory_is_a_usage_error() {
    let out = ncplc(&["check", "/nonexistent/machine", "--format", "json"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "ncplc check: /nonexistent/machine: not a machine directory (no such directory)\n"
    );
}

/// Runs the machine in `dir` for one tick; asserts that `run` refuses it and returns its stderr.
pub(crate) fn run_refuses(dir: &str) -> String {
    refuses(&["run", dir, "--virtual-time", "--ticks", "1"])
}

/// Runs `ncplc <args>`; asserts that it fails and returns its stderr.
pub(crate) fn refuses(args: &[&str]) -> String {
    let out = ncplc(args);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_ne!(out.status.code(), Some(0), "{err}");
    err
}

/// The JSON lines of `ncplc check <args>` as (code, file, line, column, message).
pub(crate) fn json_check(args: &[&str]) -> (Option<i32>, Vec<serde_json::Value>) {
    let mut all = vec!["check"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--format", "json"]);
    let out = ncplc(&all);
    // Diagnostics go to stderr, files named as from the current directory: the machine's path
    // is taken off again so that the tests compare the names inside the machine.
    let prefix = format!("{}/", args[0]);
    let lines = String::from_utf8_lossy(&out.stderr)
        .lines()
        .map(|l| {
            let mut v: serde_json::Value = serde_json::from_str(l).expect("JSON line");
            if let Some(f) = v["file"].as_str().and_then(|f| f.strip_prefix(&prefix)) {
                v["file"] = serde_json::Value::from(f);
            }
            v
        })
        .collect();
    (out.status.code(), lines)
}

pub(crate) fn brief(v: &serde_json::Value) -> (u64, String, u64, u64, String) {
    (
        v["code"].as_u64().unwrap_or(0),
        v["file"].as_str().unwrap_or("").to_string(),
        v["line"].as_u64().unwrap_or(0),
        v["column"].as_u64().unwrap_or(0),
        v["message"].as_str().unwrap_or("").to_string(),
    )
}

/// `check` validates io.toml with the fieldbus crate's located codes (issue 12, item 5).
#[test]
fn check_validates_the_io_map() {
    let dir = copy_machine("mill");
    let io = dir.path().join("io.toml");
    let text = std::fs::read_to_string(&io).expect("io.toml");
    // The first device's timeout (line 14) and the second's healthy bit (line 25).
    let text = text
        .replacen("timeout_ms = 20", "timeout_ms = 0", 1)
        .replacen("healthy = \"I100K1\"", "healthy = \"I9A3\"", 1);
    std::fs::write(&io, text).expect("write");
    let (code, lines) = json_check(&[&dir.path().display().to_string()]);
    assert_eq!(code, Some(1));
    let got: Vec<_> = lines.iter().map(brief).collect();
    assert_eq!(
        got,
        [
            (
                3033,
                "io.toml".to_string(),
                14,
                14,
                "timeout_ms 0 ms is out of range".to_string()
            ),
            (
                3023,
                "io.toml".to_string(),
                25,
                11,
                "healthy bit `I9A3` is on connector 9, which IOCFIL does not declare as IN9"
                    .to_string()
            ),
        ]
    );
}

/// A file of lines that are not records: the reader stops after 50 of them (971) and the file is
/// not validated further; a NUL byte stops it at once (970).
#[test]
fn reader_gives_up_on_a_file_that_is_not_a_characterization_file() {
    let dir = copy_machine("mill");
    let ax = dir.path().join("MP0/AXCFIL");
    // 200 lines `1+1`: each is error 2 (a line cannot start with `1`).
    std::fs::write(&ax, "1+1\n".repeat(200)).expect("write");
    let d = dir.path().display().to_string();
    let (code, lines) = json_check(&[&d]);
    assert_eq!(code, Some(1));
    let got: Vec<_> = lines.iter().map(brief).collect();
    assert_eq!(got.len(), 51, "{got:?}");
    assert_eq!(
        got[0],
        (
            2,
            "MP0/AXCFIL".to_string(),
            1,
            1,
            "a line cannot start with `1`".to_string()
        )
    );
    assert_eq!(
        got[50],
        (
            971,
            "MP0/AXCFIL".to_string(),
            50,
            1,
            "50 lines in a row are not valid records; reading of MP0/AXCFIL stopped here"
                .to_string()
        )
    );

    std::fs::write(&ax, b"*1\nTIM=1\0\0garbage").expect("write");
    let (code, lines) = json_check(&[&d]);
    assert_eq!(code, Some(1));
    let got: Vec<_> = lines.iter().map(brief).collect();
    assert_eq!(
        got,
        [(
            970,
            "MP0/AXCFIL".to_string(),
            2,
            6,
            "NUL byte at byte 8: MP0/AXCFIL is not a text file".to_string()
        )]
    );
}

/// At most `--max-errors` diagnostics per file (default 100), then one note with the count.
#[test]
fn max_errors_caps_the_diagnostics_of_a_file() {
    let dir = copy_machine("mill");
    std::fs::write(dir.path().join("MP0/AXCFIL"), "1+1\n".repeat(200)).expect("write");
    let d = dir.path().display().to_string();
    let (_, lines) = json_check(&[&d, "--max-errors", "3"]);
    assert_eq!(lines.len(), 4);
    assert_eq!(
        lines[3].to_string(),
        r#"{"file":"MP0/AXCFIL","more_errors":48,"more_warnings":0}"#
    );
    let out = ncplc(&["check", &d, "--max-errors", "3", "--color", "never"]);
    let text = String::from_utf8_lossy(&out.stderr);
    assert!(
        text.ends_with(&format!(
            "note: 48 more errors in {d}/MP0/AXCFIL (--max-errors 0 shows all)\n51 errors, 0 warnings\n"
        )),
        "{text}"
    );
    let (_, lines) = json_check(&[&d, "--max-errors", "0"]);
    assert_eq!(lines.len(), 51);
}

/// An error-dense AXCFIL (`tests/gen/error_dense.py`'s pairs `NAS=X` / `QZQ<n>=1`, three errors
/// each) is rejected with every error counted but only `--max-errors` of them kept (issue 23).
#[test]
fn an_error_dense_axcfil_is_counted_exactly_and_capped() {
    let dir = copy_machine("lathe");
    let ax = dir.path().join("MP0/AXCFIL");
    let mut text = std::fs::read(&ax).expect("read");
    for i in 0..20_000 {
        text.extend_from_slice(format!("NAS=X\nQZQ{}=1\n", i % 10).as_bytes());
    }
    std::fs::write(&ax, text).expect("write");
    let d = dir.path().display().to_string();
    let out = ncplc(&["check", &d, "--max-errors", "3", "--color", "never"]);
    assert_eq!(out.status.code(), Some(1));
    let text = String::from_utf8_lossy(&out.stderr);
    assert!(
        text.ends_with(&format!(
            "note: 59997 more errors in {d}/MP0/AXCFIL (--max-errors 0 shows all)\n60000 errors, 0 warnings\n"
        )),
        "{text}"
    );
    let (_, lines) = json_check(&[&d, "--max-errors", "3"]);
    let codes: Vec<u64> = lines[..3]
        .iter()
        .filter_map(|l| l["code"].as_u64())
        .collect();
    assert_eq!(codes, [173, 175, 6]);
    assert_eq!(
        lines[3].to_string(),
        r#"{"file":"MP0/AXCFIL","more_errors":59997,"more_warnings":0}"#
    );
    assert_eq!(lines.len(), 4);
}

/// An empty AXCFIL is one error saying so (972), not missing sections and the cross-file rules of
/// PGCFIL and IOCFIL against NBP=0 and TIM=0 (12 errors before).
#[test]
fn empty_characterization_file_is_one_error() {
    let dir = copy_machine("mill");
    std::fs::write(dir.path().join("MP0/AXCFIL"), "").expect("write");
    let (code, lines) = json_check(&[&dir.path().display().to_string()]);
    assert_eq!(code, Some(1));
    let got: Vec<_> = lines.iter().map(brief).collect();
    assert_eq!(
        got,
        [(
            972,
            "MP0/AXCFIL".to_string(),
            1,
            1,
            "MP0/AXCFIL is empty".to_string()
        )]
    );
}

/// An io.toml that declares no I/O is a warning that says what `run` will do with it (3050 from
/// `run --io modbus|canopen`), not "no problems found"; the exit code stays 0 (`--io sim` runs).
#[test]
fn io_toml_without_io_is_a_warning() {
    let dir = copy_machine("lathe");
    let io = dir.path().join("io.toml");
    let path = dir.path().display().to_string();
    for (text, message) in [
        (
            "",
            "io.toml is empty: it declares no I/O; `run --io modbus` and `run --io canopen` refuse it (3050)",
        ),
        (
            "# no devices yet\n",
            "io.toml declares no I/O (no Modbus device, no CANopen node); `run --io modbus` and `run --io canopen` refuse it (3050)",
        ),
    ] {
        std::fs::write(&io, text).expect("write");
        let (code, lines) = json_check(&[&path]);
        assert_eq!(code, Some(0), "{text:?}");
        let got: Vec<_> = lines.iter().map(brief).collect();
        assert_eq!(
            got,
            [(3050, "io.toml".to_string(), 0, 0, message.to_string())],
            "{text:?}"
        );
        assert_eq!(lines[0]["severity"], "warning");
    }
}

/// `check` validates `[[canopen.drive]]` entries against the machine's AXCFIL axes (issue 21):
/// the mill's bundled drives for X, Y, Z and S are valid, an axis it lacks and a second spindle
/// drive in `csp` on an I/O node are located errors.
#[test]
fn check_validates_the_drive_entries_against_axcfil() {
    let dir = copy_machine("mill");
    let io = dir.path().join("io.toml");
    let mut text = std::fs::read_to_string(&io).expect("io.toml");
    assert_eq!(text.matches("[[canopen.drive]]").count(), 4);
    let (code, lines) = json_check(&[&dir.path().display().to_string()]);
    assert_eq!((code, lines.len()), (Some(0), 0), "{lines:?}");
    // n+1..n+5: an undeclared axis; n+6..n+10: the spindle again, in csp on node 3, an I/O node.
    let n = text.lines().count() as u64;
    text += "[[canopen.drive]]\naxis = \"Q\"\nnode_id = 20\ncounts_per_unit = 1\nmode = \"csp\"\n";
    text += "[[canopen.drive]]\naxis = \"S\"\nnode_id = 3\ncounts_per_unit = 1\nmode = \"csp\"\n";
    std::fs::write(&io, text).expect("write");
    let (code, lines) = json_check(&[&dir.path().display().to_string()]);
    assert_eq!(code, Some(1));
    let got: Vec<_> = lines.iter().map(brief).collect();
    let io_toml = || "io.toml".to_string();
    assert_eq!(
        got,
        [
            (
                3070,
                io_toml(),
                n + 2,
                8,
                "AXCFIL declares no axis Q in process 1".to_string()
            ),
            (
                3071,
                io_toml(),
                n + 7,
                8,
                "axis S of process 1 is on two drives".to_string()
            ),
            (
                3072,
                io_toml(),
                n + 8,
                11,
                "node id 3 is already an I/O node".to_string()
            ),
            (
                3074,
                io_toml(),
                n + 10,
                8,
                "mode \"csp\" does not fit axis S (TPA=820), a spindle".to_string()
            ),
        ]
    );
}

/// interface.toml: a table other than `[[signal]]` is a located error (1601), not ignored.
#[test]
fn interface_toml_unknown_table_is_a_located_error() {
    let dir = copy_machine("lathe");
    std::fs::write(
        dir.path().join("interface.toml"),
        "# overrides\n[[signl]]\nname = \"SPARE\"\n",
    )
    .expect("write");
    let (code, lines) = json_check(&[&dir.path().display().to_string()]);
    assert_eq!(code, Some(1));
    let got: Vec<_> = lines.iter().map(brief).collect();
    assert_eq!(got.len(), 1, "{got:?}");
    assert_eq!(
        (got[0].0, got[0].1.as_str(), got[0].2, got[0].3),
        (1601, "interface.toml", 2, 3)
    );
    assert!(got[0].4.contains("unknown field `signl`"), "{got:?}");
}

/// Every unknown key of io.toml, sim.toml and interface.toml is reported in one `check` (serde
/// stops at the first: the integrator fixed typos one run at a time), each at its place, and
/// `run` refuses the machine with every one of them.
#[test]
fn every_unknown_key_of_every_toml_file_is_reported_in_one_run() {
    let dir = copy_machine("lathe");
    let edit = |name: &str, from: &str, to: &str| {
        let path = dir.path().join(name);
        let text = std::fs::read_to_string(&path).expect("read");
        assert!(text.contains(from), "{name}: {from}");
        std::fs::write(&path, text.replacen(from, to, 1)).expect("write");
    };
    edit("io.toml", "timeout_ms = 20", "timout_ms = 20");
    edit("io.toml", "poll_us = 500", "pol_us = 500");
    edit("sim.toml", "period = 2000", "periode = 2000");
    edit("sim.toml", "tick = 10\n", "tick = 10\nspeed = 3\n");
    let d = dir.path().display().to_string();
    let unknown = |m: &str| m.split('`').nth(1).unwrap_or("").to_string();
    let check = || {
        let (code, lines) = json_check(&[&d]);
        assert_eq!(code, Some(1));
        lines.iter().map(brief).collect::<Vec<_>>()
    };
    let got = check();
    let found: Vec<(u64, &str, String)> = got
        .iter()
        .map(|(c, f, _, _, m)| (*c, f.as_str(), unknown(m)))
        .collect();
    assert_eq!(
        found,
        [
            (3000, "io.toml", "timout_ms".to_string()),
            (3000, "io.toml", "pol_us".to_string()),
            (3600, "sim.toml", "periode".to_string()),
            (3600, "sim.toml", "speed".to_string()),
        ],
        "{got:?}"
    );
    let io = std::fs::read_to_string(dir.path().join("io.toml")).expect("io");
    let sim = std::fs::read_to_string(dir.path().join("sim.toml")).expect("sim");
    let line_of = |text: &str, what: &str| {
        text.lines()
            .position(|l| l.starts_with(what))
            .map_or(0, |i| i as u64 + 1)
    };
    assert_eq!((got[0].2, got[0].3), (line_of(&io, "timout_ms"), 1));
    assert_eq!((got[1].2, got[1].3), (line_of(&io, "pol_us"), 1));
    assert_eq!((got[2].2, got[2].3), (line_of(&sim, "periode"), 1));
    assert_eq!((got[3].2, got[3].3), (line_of(&sim, "speed"), 1));
    // `run` refuses what `check` reports, io.toml's errors first (with the simulated I/O too,
    // which reads no I/O map), then, io.toml mended, sim.toml's.
    let err = run_refuses(&d);
    assert!(
        err.contains("`timout_ms`") && err.contains("`pol_us`"),
        "{err}"
    );
    let mended = io
        .replace("timout_ms", "timeout_ms")
        .replace("pol_us", "poll_us");
    std::fs::write(dir.path().join("io.toml"), mended).expect("write");
    let err = run_refuses(&d);
    assert!(
        err.contains("`periode`") && err.contains("`speed`"),
        "{err}"
    );
    // interface.toml: both misspelt keys, and the entry left without its address.
    std::fs::write(
        dir.path().join("interface.toml"),
        "[[signal]]\nname = \"SPARE\"\nadress = \"I200K0\"\ndirectoin = \"in\"\n",
    )
    .expect("write");
    let got = check();
    let found: Vec<(u64, &str, u64, String)> = got
        .iter()
        .filter(|(_, f, ..)| f == "interface.toml")
        .map(|(c, f, l, _, m)| (*c, f.as_str(), *l, m.clone()))
        .collect();
    let expected =
        "expected one of `name`, `address`, `width`, `dir`, `meaning`, `process`, `role`";
    assert_eq!(
        found,
        [
            (
                1601,
                "interface.toml",
                1,
                "missing field `address`".to_string()
            ),
            (
                1601,
                "interface.toml",
                3,
                format!("unknown field `adress`, {expected}")
            ),
            (
                1601,
                "interface.toml",
                4,
                format!("unknown field `directoin`, {expected}")
            ),
        ],
        "{got:?}"
    );
    // sim.toml meanwhile: its form only (the misspelt keys), not its names, which need the map
    // (I29A3 is on no connector: reported once the map is valid).
    let sim_errors = |got: &[(u64, String, u64, u64, String)]| {
        got.iter()
            .filter(|(_, f, ..)| f == "sim.toml")
            .map(|(c, _, l, _, m)| (*c, *l, unknown(m)))
            .collect::<Vec<_>>()
    };
    let want = vec![
        (3600, line_of(&sim, "periode"), "periode".to_string()),
        (3600, line_of(&sim, "speed"), "speed".to_string()),
    ];
    assert_eq!(sim_errors(&got), want, "{got:?}");
    let mended = sim.replace("periode", "period").replace("speed = 3\n", "")
        + "\n[[at]]\ntick = 30\nset = { I29A3 = 1 }\n";
    std::fs::write(dir.path().join("sim.toml"), &mended).expect("write");
    assert_eq!(sim_errors(&check()), []);
    // `run` refuses the machine with the same three errors of interface.toml.
    let err = run_refuses(&d);
    let e1601 = err
        .lines()
        .filter(|l| l.starts_with("error[E1601]"))
        .count();
    assert_eq!(e1601, 3, "{err}");
    assert!(
        err.contains("`adress`") && err.contains("`directoin`"),
        "{err}"
    );
}

/// A machine configuration file over 1 MiB (well-formed TOML, every table an error) is refused
/// at once by `check` and by `run`, naming its size: parsed whole it would take gigabytes
/// (issue 23: 50 MB of `[[at]]` tables took 12 s and 4.3 GB).
#[test]
fn oversized_sim_and_io_toml_are_refused_naming_their_size() {
    let dir = copy_machine("lathe");
    let mut table = String::new();
    let mut n = 0;
    while table.len() <= 1 << 20 {
        table.push_str(&format!(
            "[[at]]\ntick = {}\nset = {{ BOGUS{n} = 2 }}\n",
            n % 1000
        ));
        n += 1;
    }
    let sim = dir.path().join("sim.toml");
    let mut text = std::fs::read_to_string(&sim).expect("sim.toml");
    text.push_str(&table);
    let sim_len = text.len();
    std::fs::write(&sim, &text).expect("write");
    let io = dir.path().join("io.toml");
    let mut text = std::fs::read_to_string(&io).expect("io.toml");
    text.push_str(&table.replace("[[at]]", "[[bogus]]"));
    let io_len = text.len();
    std::fs::write(&io, &text).expect("write");
    let d = dir.path().display().to_string();
    let (code, lines) = json_check(&[&d]);
    assert_eq!(code, Some(1));
    let limit = "a machine configuration file is read whole and may have at most 1048576 bytes";
    let got: Vec<_> = lines.iter().map(brief).collect();
    assert_eq!(
        got,
        [
            (
                3001,
                "io.toml".to_string(),
                0,
                0,
                format!("cannot read {d}/io.toml: the file has {io_len} bytes; {limit}")
            ),
            (
                3608,
                "sim.toml".to_string(),
                0,
                0,
                format!("cannot read sim.toml: the file has {sim_len} bytes; {limit}")
            ),
        ]
    );
    // `run` refuses both: io.toml first (with every `--io`), then sim.toml.
    let err = run_refuses(&d);
    assert!(
        err.contains(&format!("the file has {io_len} bytes; {limit}")),
        "{err}"
    );
    std::fs::remove_file(dir.path().join("io.toml")).expect("remove");
    let err = run_refuses(&d);
    assert!(
        err.contains(&format!("the file has {sim_len} bytes; {limit}")),
        "{err}"
    );
}

/// The PLC program `run` loads is read by `check` too: an undefined name is a located error of
/// `check` (the front end `build` runs), and `run` refuses the same program.
#[test]
fn check_compiles_the_plc_program_run_would_load() {
    let dir = copy_machine("lathe");
    let plc = dir.path().join("MP0/PLCPRG");
    let text = std::fs::read(&plc).expect("PLCPRG");
    // Before the program's end `$` (the last line).
    let end = text.iter().rposition(|b| *b == b'$').expect("$");
    let line = text[..end].split(|b| *b == b'\n').count();
    let mut edited = text[..end].to_vec();
    edited.extend_from_slice(b"MSG_LUBE = NOSUCHNAME\n");
    edited.extend_from_slice(&text[end..]);
    std::fs::write(&plc, &edited).expect("write");
    let d = dir.path().display().to_string();
    let (code, lines) = json_check(&[&d]);
    assert_eq!(code, Some(1));
    let got: Vec<_> = lines.iter().map(brief).collect();
    assert_eq!(got.len(), 1, "{got:?}");
    let (code, file, l, column, message) = &got[0];
    assert_eq!(
        (*code, file.as_str(), *l, *column),
        (1207, "MP0/PLCPRG", line as u64, 12)
    );
    assert!(message.contains("NOSUCHNAME"), "{message}");
    let err = run_refuses(&d);
    assert!(err.contains("NOSUCHNAME"), "{err}");
}

/// FCRSYS bindings of files ncplc does not read are never silently ignored when the file exists:
/// a system message file (FILMS1) is a warning, a file of PLC-requested programs (FILCMD) an
/// error; a binding whose file does not exist (the lathe's FORMAT) is the manual's fallback.
#[test]
fn bound_files_ncplc_does_not_read_are_reported_when_they_exist() {
    let dir = copy_machine("lathe");
    std::fs::write(dir.path().join("MP0/RUMES1"), "1 Сообщение\n").expect("RUMES1");
    std::fs::write(dir.path().join("MP0/FILCMD"), "PROG1\n").expect("FILCMD");
    let fcrsys = dir.path().join("FCRSYS");
    // The file has CRLF line ends, as the CNC writes them.
    let text = std::fs::read_to_string(&fcrsys).expect("FCRSYS");
    let text = text.replace(
        "FILMS5, MESSAG/MP0\r\n",
        "FILMS5, MESSAG/MP0\r\nFILCMD, FILCMD/MP0\r\n",
    );
    assert!(text.contains("FILCMD"));
    std::fs::write(&fcrsys, &text).expect("write");
    let line_of =
        |what: &str| 1 + text.lines().position(|l| l.starts_with(what)).expect(what) as u64;
    let d = dir.path().display().to_string();
    let (code, lines) = json_check(&[&d]);
    assert_eq!(code, Some(1));
    let got: Vec<_> = lines.iter().map(brief).collect();
    assert_eq!(
        got,
        [
            (
                975,
                "FCRSYS".to_string(),
                line_of("FILMS1"),
                1,
                "FILMS1 binds MP0/RUMES1, which ncplc does not read: the system's messages are ncplc's own (its diagnostics and alarms)".to_string()
            ),
            (
                976,
                "FCRSYS".to_string(),
                line_of("FILCMD"),
                1,
                "FILCMD binds MP0/FILCMD, which ncplc does not read: part programs started on PLC request are not implemented".to_string()
            ),
        ]
    );
}
