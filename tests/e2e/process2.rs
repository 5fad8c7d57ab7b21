//! End-to-end tests of processes 2..5 in the interface map: `ncplc check` and `ncplc run` refuse a
//! NBP=2 machine whose map does not give process 2 its handshake signals, map errors are located in
//! `interface.toml`, and the mill runs process 2's M functions through the simulated CNC.

use std::path::Path;

use crate::e2e_common;
use e2e_common::{Ncplc, ncplc, root};

/// A copy of the mill with `interface` as its interface.toml (`None`: no interface.toml).
fn mill_copy(dir: &Path, interface: Option<&str>) -> String {
    let m = dir.join("mill");
    for f in [
        "FCRSYS",
        "MP0/AXCFIL",
        "MP0/PGCFIL",
        "MP0/IOCFIL",
        "MP0/PLCPRG",
        "sim.toml",
    ] {
        let to = m.join(f);
        std::fs::create_dir_all(to.parent().expect("parent")).expect("mkdir");
        std::fs::copy(root().join("plc-programs/mill").join(f), &to).expect("copy");
    }
    if let Some(text) = interface {
        std::fs::write(m.join("interface.toml"), text).expect("interface.toml");
    }
    m.display().to_string()
}

fn json(out: &[u8]) -> Vec<serde_json::Value> {
    String::from_utf8_lossy(out)
        .lines()
        .map(|l| serde_json::from_str(l).expect("one JSON object per line"))
        .collect()
}

fn fields(d: &serde_json::Value) -> (u64, String, u64, u64, u64) {
    (
        d["code"].as_u64().unwrap_or(0),
        d["file"].as_str().unwrap_or("").to_string(),
        d["process"].as_u64().unwrap_or(0),
        d["line"].as_u64().unwrap_or(0),
        d["column"].as_u64().unwrap_or(0),
    )
}

#[test]
fn check_names_every_missing_process_2_role_at_its_pro_record() {
    let dir = tempfile::tempdir().expect("tempdir");
    let m = mill_copy(dir.path(), None);
    let out = ncplc(&["check", &m, "--format", "json"]);
    assert_eq!(out.status.code(), Some(1));
    let diags = json(&out.stderr);
    let got: Vec<_> = diags.iter().map(fields).collect();
    // Files are named as the user can open them from the current directory (here: absolute).
    let at = |_| (1609, format!("{m}/MP0/AXCFIL"), 2, 9, 1);
    assert_eq!(got, (0..3).map(at).collect::<Vec<_>>());
    let messages: Vec<&str> = diags
        .iter()
        .map(|d| d["message"].as_str().unwrap_or(""))
        .collect();
    assert_eq!(
        messages,
        vec![
            "process 2 has no MSTB in the interface map (AXCFIL NBP=2)",
            "process 2 has no MFIN in the interface map (AXCFIL NBP=2)",
            "process 2 has no MCODE in the interface map (AXCFIL NBP=2)",
        ]
    );
    let human = ncplc(&["check", &m]);
    assert_eq!(human.status.code(), Some(1));
    let text = String::from_utf8_lossy(&human.stderr);
    assert!(
        text.contains("error[E1609]: process 2 has no MCODE in the interface map (AXCFIL NBP=2)"),
        "{text}"
    );
    assert!(text.contains("width = \"byte\", dir = \"in\""), "{text}");
    assert!(text.ends_with("3 errors, 0 warnings\n"), "{text}");
}

#[test]
fn run_refuses_a_machine_whose_process_2_lacks_its_handshake() {
    let dir = tempfile::tempdir().expect("tempdir");
    // Only the strobe is given: MFIN and MCODE are missing.
    let m = mill_copy(
        dir.path(),
        Some(
            "[[signal]]\nname = \"MSTB_T\"\nrole = \"MSTB\"\nprocess = 2\naddress = \"I6K0\"\nwidth = \"bit\"\ndir = \"in\"\n",
        ),
    );
    let out = ncplc(&["run", &m, "--virtual-time", "--ticks", "10", "--no-watch"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.starts_with(&format!(
            "error[E1609]: {m}: AXCFIL NBP=2, but the interface map does not give these \
             processes their handshake signals:\n  process 2: MFIN, MCODE\n"
        )),
        "{err}"
    );
}

#[test]
fn map_errors_are_located_in_interface_toml() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text = "[[signal]]\nname = \"MSTB_T\"\nrole = \"MSTB\"\nprocess = 2\naddress = \"I1K0\"\nwidth = \"bit\"\ndir = \"in\"\n\
                [[signal]]\nname = \"MFIN_T\"\nrole = \"MFIN\"\nprocess = 6\naddress = \"U30K0\"\nwidth = \"bit\"\ndir = \"out\"\n\
                [[signal]]\nname = \"MCODE_T\"\nrole = \"MCODE\"\nprocess = 2\naddress = \"W30K1\"\nwidth = \"byte\"\ndir = \"in\"\n";
    let m = mill_copy(dir.path(), Some(text));
    let out = ncplc(&["check", &m, "--format", "json"]);
    assert_eq!(out.status.code(), Some(1));
    let got: Vec<(u64, String, u64, u64)> = json(&out.stderr)
        .iter()
        .map(|d| {
            let (code, file, _, line, column) = fields(d);
            (code, file, line, column)
        })
        .collect();
    assert_eq!(
        got,
        vec![
            (1605, format!("{m}/interface.toml"), 11, 11),
            (1608, format!("{m}/interface.toml"), 21, 7),
        ]
    );
    // Fixed, the clash with process 1's MSTB (I1K0) remains.
    let fixed = text.replace("process = 6", "process = 2").replace(
        "address = \"W30K1\"\nwidth = \"byte\"\ndir = \"in\"",
        "address = \"W7K0\"\nwidth = \"byte\"\ndir = \"in\"",
    );
    std::fs::write(Path::new(&m).join("interface.toml"), fixed).expect("write");
    let out = ncplc(&["check", &m]);
    assert_eq!(out.status.code(), Some(1));
    let human = String::from_utf8_lossy(&out.stderr);
    assert!(
        human.contains(&format!(
            "error[E1607]: entry `MSTB_T`: address I1K0 overlaps entry `MSTB` (I1K0)\n  ┌─ {m}/interface.toml:5:11"
        )),
        "{human}"
    );
}

#[test]
fn the_mill_completes_process_2_m_functions() {
    let mill = root().join("plc-programs/mill").display().to_string();
    let out = Ncplc::run(&mill)
        .virtual_time()
        .ticks(4000)
        .stats()
        .output();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    // Per 2000-tick period: process 1 T12, M06, S2000, M03, M08, M09, M05; process 2 M30, M00, M02.
    assert!(
        stdout.ends_with(
            "handshake p1   M 10  S 2  T 2  completed, 0 timeouts\n\
             handshake p2   M 6  S -  T -  completed, 0 timeouts\n"
        ),
        "{stdout}"
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("alarm"), "{stderr}");
}

/// `--dialect` names the dialect of the operator's program: a Fanuc MDI block on the mill runs
/// while process 2 runs its MEFI MAGAZINE program (it was parsed as Fanuc too and refused).
#[test]
fn dialect_applies_to_the_operators_program_not_to_process_2s() {
    let mill = root().join("plc-programs/mill");
    let out = ncplc(&[
        "run".as_ref(),
        mill.as_os_str(),
        "--virtual-time".as_ref(),
        "--no-watch".as_ref(),
        "--dialect".as_ref(),
        "fanuc".as_ref(),
        "--mdi".as_ref(),
        "G91 G00 X-10.".as_ref(),
        "--until-end".as_ref(),
        "--ticks".as_ref(),
        "3000".as_ref(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("process 1: 1 blocks;"), "{stdout}");
    assert!(
        stdout.contains("process 2: 1 blocks; handshakes M 1"),
        "{stdout}"
    );
}
