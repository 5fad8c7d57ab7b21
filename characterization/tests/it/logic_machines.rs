//! The example machines' PGCFIL and IOCFIL (plc-programs/lathe, plc-programs/mill) load without
//! a diagnostic and say what the shared conventions say.

use std::path::PathBuf;

use characterization::reader::{Grammar, read, read_with};
use characterization::{iocfil, pgcfil};

fn text(machine: &str, file: &str) -> Vec<u8> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../plc-programs")
        .join(machine)
        .join("MP0")
        .join(file);
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn load(machine: &str) -> (pgcfil::Pgcfil, iocfil::Iocfil, Vec<diag::Diagnostic>) {
    let (pf, mut d) = read_with("MP0/PGCFIL", &text(machine, "PGCFIL"), Grammar::PGCFIL);
    let (pg, more) = pgcfil::parse(&pf);
    d.extend(more);
    let (iof, more) = read("MP0/IOCFIL", &text(machine, "IOCFIL"));
    d.extend(more);
    let (io, more) = iocfil::parse(&iof);
    d.extend(more);
    (pg, io, d)
}

#[test]
fn lathe_loads() {
    let (pg, io, d) = load("lathe");
    assert_eq!(d, []);
    assert!(!pg.retains());
    assert_eq!(pg.processes.len(), 1);
    assert_eq!(pg.processes[0].mas, ['X', 'Z']);
    assert_eq!(io.input_connectors(), [0, 1]);
    assert_eq!(io.output_connectors(), [4, 5]);
    assert_eq!((io.tick_logic_ms, io.time_slow_ms), (10, 2));
    let ms: Vec<u8> = io.processes[0]
        .m_functions
        .iter()
        .map(|m| m.number)
        .collect();
    assert_eq!(ms, [0, 1, 2, 3, 4, 5, 8, 9, 30]);
    assert_eq!(io.t_bytes(), [(0, 0x10), (1, 0), (2, 0x32), (3, 5)]);
}

#[test]
fn mill_loads() {
    let (pg, io, d) = load("mill");
    assert_eq!(d, []);
    assert!(pg.retains());
    assert_eq!(
        pg.processes.iter().map(|p| p.number).collect::<Vec<_>>(),
        [1, 2]
    );
    assert_eq!(io.input_connectors(), [0, 1, 2]);
    assert_eq!(io.output_connectors(), [4, 5, 6]);
    let p1 = &io.processes[0];
    assert_eq!(
        p1.m_function(6).map(|m| m.flags.tool_offset_request),
        Some(true)
    );
    assert_eq!(io.processes[1].ptp_axes[0].axis, 'T');
}

#[test]
fn both_machines_load_with_all_four_files_clean() {
    for machine in ["lathe", "mill"] {
        let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../plc-programs")
            .join(machine);
        let load = characterization::machine::load_machine(&dir);
        let errors: Vec<String> = load
            .diagnostics
            .iter()
            .filter(|d| d.file.contains("PGCFIL") || d.file.contains("IOCFIL") || d.is_error())
            .map(|d| d.to_string())
            .collect();
        assert_eq!(errors, Vec::<String>::new(), "{machine}");
        let m = load
            .machine
            .unwrap_or_else(|| panic!("{machine} did not load"));
        assert!(m.pgcfil.is_some() && m.iocfil.is_some(), "{machine}");
    }
}

#[test]
fn mill_axes_agree_between_files() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../plc-programs/mill");
    let load = characterization::machine::load_machine(&dir);
    let m = load.machine.unwrap_or_else(|| panic!("mill did not load"));
    let (ax, io, pg) = (
        m.axcfil,
        m.iocfil.unwrap_or_default(),
        m.pgcfil.unwrap_or_default(),
    );
    assert_eq!(ax.nbp, 2);
    assert_eq!(pg.processes.len(), 2);
    let ta = io.processes[1].ptp_axes[0];
    let pas = ax
        .process(2)
        .and_then(|p| p.axis('T'))
        .and_then(|a| a.pas.as_ref())
        .map(|p| p.mec_pitch);
    assert_eq!((ta.axis, ta.positions, ta.has_dac()), ('T', pas, true));
    assert_eq!(io.tick_logic_ms % ax.tim, 0);
}

#[test]
fn errors_of_all_four_files_come_out_of_one_run() {
    let src = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../plc-programs/lathe");
    let tmp = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let dir = tmp.path();
    std::fs::create_dir_all(dir.join("MP0")).unwrap_or_else(|e| panic!("{e}"));
    let copy = |name: &str, edit: &dyn Fn(String) -> String| {
        let text = std::fs::read(src.join(name))
            .map(|b| characterization::reader::decode(&b))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        std::fs::write(dir.join(name), edit(text)).unwrap_or_else(|e| panic!("{name}: {e}"));
    };
    copy("FCRSYS", &|t| t.replace("MP1=", "MP9="));
    copy("MP0/AXCFIL", &|t| {
        t.replace("TIM=1,0,0,0,0", "TIM=99,0,0,0,0")
    });
    copy("MP0/PGCFIL", &|t| t.replace("TOF=12", "TOF=13"));
    copy("MP0/IOCFIL", &|t| t.replace("GPS=0", "GPS=2"));
    let load = characterization::machine::load_machine(dir);
    let mut files: Vec<&str> = load
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .map(|d| d.file.as_str())
        .collect();
    files.dedup();
    assert_eq!(files, ["FCRSYS", "MP0/AXCFIL", "MP0/PGCFIL", "MP0/IOCFIL"]);
    let logic: Vec<(&str, u32)> = load
        .diagnostics
        .iter()
        .filter(|d| d.file.ends_with("GCFIL") || d.file.ends_with("OCFIL"))
        .map(|d| (d.file.as_str(), d.code))
        .collect();
    assert!(
        logic.contains(&("MP0/PGCFIL", 133)) && logic.contains(&("MP0/IOCFIL", 130)),
        "{logic:?}"
    );
}
