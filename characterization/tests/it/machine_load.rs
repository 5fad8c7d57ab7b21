//! Loading machine directories: the example machines, FCRSYS resolution, and the errors only a
//! machine directory can have (902 unreadable, 915 missing file, 916 missing PLC program).

use std::fs;
use std::path::{Path, PathBuf};

use characterization::load_machine;

fn machine(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../plc-programs")
        .join(name)
}

fn codes(dir: &Path) -> Vec<(u32, String, u32, u32)> {
    load_machine(dir)
        .diagnostics
        .iter()
        .map(|d| (d.code, d.file.clone(), d.line, d.column))
        .collect()
}

#[test]
fn example_machines_load_without_errors() {
    for name in ["lathe", "mill"] {
        let load = load_machine(&machine(name));
        assert!(!load.has_errors(), "{name}: {:?}", load.diagnostics);
        let m = load.machine.expect("machine loads");
        assert_eq!(
            m.paths.axcfil,
            Some(machine(name).join("MP0").join("AXCFIL"))
        );
        assert_eq!(m.paths.plc_source, machine(name).join("MP0").join("PLCPRG"));
        assert!(m.pgcfil.is_some() && m.iocfil.is_some());
    }
}

#[test]
fn lathe_model_matches_the_shared_convention() {
    let m = load_machine(&machine("lathe"))
        .machine
        .expect("lathe loads");
    assert_eq!((m.axcfil.tim, m.axcfil.nbp), (1, 1));
    let p = &m.axcfil.processes[0];
    assert_eq!(p.axes.iter().map(|a| a.name).collect::<String>(), "XZS");
    let s = p.axis('S').map(|a| a.axis_type()).unwrap_or_default();
    assert!(s.spindle_with_encoder && !s.coordinate);
    assert!(p.axis('X').is_some_and(|a| a.axis_type().diameter));
    assert_eq!(p.interpolators[0].spindle, Some('S'));
}

#[test]
fn mill_model_matches_the_shared_convention() {
    let m = load_machine(&machine("mill")).machine.expect("mill loads");
    assert_eq!(m.axcfil.nbp, 2);
    let p1 = &m.axcfil.processes[0];
    assert_eq!(p1.axes.iter().map(|a| a.name).collect::<String>(), "XYZS");
    let p2 = &m.axcfil.processes[1];
    let t = p2.axis('T').expect("magazine axis");
    assert!(t.axis_type().ptp);
    assert_eq!(t.pas.map(|p| p.mec_pitch), Some(24.0));
    // The mill's FCRSYS binds AXCONF with a DOS path.
    assert!(matches!(
        m.fcrsys.binding("AXCONF").map(|b| &b.location),
        Some(characterization::fcrsys::FileLocation::Dos(_))
    ));
}

/// A machine directory in a temporary folder with the given files.
fn temp_machine(files: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("temp dir");
    for (name, text) in files {
        let path = dir.path().join(name);
        if let Some(parent) = path.parent() {
            fs::create_dir_all(parent).expect("mkdir");
        }
        fs::write(&path, text).expect("write");
    }
    dir
}

const FCRSYS: &str = "*1\nMP0=C:\\CNC32\\MP0\nMP1=C:\\CNC32\\MP1\n*2\nAXCONF, AXCFIL/MP0\nPGCONF, PGCFIL/MP0\nIOCONF, IOCFIL/MP0\nFORMAT, FORMAT/MP0\n*\n";

#[test]
fn p902_fcrsys_missing() {
    let dir = temp_machine(&[]);
    let load = load_machine(dir.path());
    assert!(load.machine.is_none());
    assert_eq!(codes(dir.path()), [(902, "FCRSYS".to_string(), 0, 0)]);
}

#[test]
fn p915_p916_files_named_but_missing() {
    let dir = temp_machine(&[("FCRSYS", FCRSYS)]);
    let d = codes(dir.path());
    assert_eq!(
        d,
        [
            (916, "FCRSYS".to_string(), 0, 0),
            (915, "FCRSYS".to_string(), 5, 1),
            (915, "FCRSYS".to_string(), 6, 1),
            (915, "FCRSYS".to_string(), 7, 1)
        ]
    );
}

#[test]
fn errors_of_all_files_come_out_of_one_run() {
    let lathe = machine("lathe");
    let read = |f: &str| {
        String::from_utf8_lossy(&fs::read(lathe.join(f)).expect("lathe file")).into_owned()
    };
    let ax = read("MP0/AXCFIL").replacen("TIM=1,", "TIM=64,", 1);
    let io = read("MP0/IOCFIL").replacen("CLO=10,2", "CLO=10", 1);
    let fc = read("FCRSYS").replacen("MP1=", "MP7=", 1);
    let dir = temp_machine(&[
        ("FCRSYS", &fc),
        ("MP0/AXCFIL", &ax),
        ("MP0/PGCFIL", &read("MP0/PGCFIL")),
        ("MP0/IOCFIL", &io),
        ("MP0/PLCPRG", ""),
        ("MP0/MESSAG", "1 text\n"),
    ]);
    let load = load_machine(dir.path());
    let got: Vec<(u32, &str)> = load
        .diagnostics
        .iter()
        .map(|d| (d.code, d.file.as_str()))
        .collect();
    assert_eq!(
        got,
        [
            (905, "FCRSYS"),
            (904, "FCRSYS"),
            (101, "MP0/AXCFIL"),
            (10, "MP0/IOCFIL")
        ]
    );
    assert!(
        load.sources
            .get("MP0/AXCFIL")
            .is_some_and(|t| t.contains("TIM=64"))
    );
}

#[test]
fn plcsrc_names_the_plc_program() {
    let fc = FCRSYS.replace("*\n", "").replace(
        "FORMAT, FORMAT/MP0\n",
        "FORMAT, FORMAT/MP0\nPLCSRC, LOGIC/MP1\n",
    ) + "*\n";
    let dir = temp_machine(&[("FCRSYS", &fc)]);
    let load = load_machine(dir.path());
    assert!(
        load.diagnostics
            .iter()
            .any(|d| d.code == 916 && d.line == 9 && d.message.contains("MP1/LOGIC")),
        "{:?}",
        load.diagnostics
    );
}

#[test]
fn lathe_message_file_gives_the_texts() {
    let m = load_machine(&machine("lathe"))
        .machine
        .expect("lathe loads");
    let common = m.messages.common.as_ref().expect("FILMS5 read");
    assert_eq!(common.name, "MP0/MESSAG");
    assert_eq!(
        m.messages.text(1, 1),
        Some("Lubrication level low: refill the tank, then RESET")
    );
    assert_eq!(m.messages.shown(1, 4), "PLC message 4");
}

/// FILMS5 naming a missing file is 915; the lines of a message file and a missing FLC file
/// (949, at the FLC record of its process) are located.
#[test]
fn p915_p946_p948_p949_plc_message_files() {
    let fc = FCRSYS.replace("*\n", "") + "FILMS5, MESSAG/MP0\n*\n";
    let dir = temp_machine(&[("FCRSYS", &fc)]);
    assert!(
        codes(dir.path()).contains(&(915, "FCRSYS".to_string(), 9, 1)),
        "{:?}",
        codes(dir.path())
    );
    let lathe = machine("lathe");
    let read = |f: &str| {
        String::from_utf8_lossy(&fs::read(lathe.join(f)).expect("lathe file")).into_owned()
    };
    let pg = read("MP0/PGCFIL").replacen("NDD=MP1\n", "NDD=MP1\nFLC=,,FI1MSG/MP0,\n", 1);
    let flc_line = pg.lines().position(|l| l.starts_with("FLC")).expect("FLC") + 1;
    let dir = temp_machine(&[
        ("FCRSYS", &read("FCRSYS")),
        ("MP0/AXCFIL", &read("MP0/AXCFIL")),
        ("MP0/PGCFIL", &pg),
        ("MP0/IOCFIL", &read("MP0/IOCFIL")),
        ("MP0/PLCPRG", ""),
        ("MP0/MESSAG", "1 one\n; note\n1 again\nlow\n"),
    ]);
    assert_eq!(
        codes(dir.path()),
        [
            (948, "MP0/MESSAG".to_string(), 3, 1),
            (946, "MP0/MESSAG".to_string(), 4, 1),
            (
                949,
                "MP0/PGCFIL".to_string(),
                u32::try_from(flc_line).unwrap_or(0),
                1
            ),
        ]
    );
    // With the process's file present, it replaces the common one for process 1.
    fs::write(dir.path().join("MP0/FI1MSG"), "2 own text\n").expect("write");
    let m = load_machine(dir.path()).machine.expect("loads");
    assert_eq!(m.messages.text(1, 2), Some("own text"));
    assert_eq!(m.messages.text(1, 1), None);
}
