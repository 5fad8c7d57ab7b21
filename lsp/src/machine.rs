//! The machine a PLC source belongs to: the nearest directory above the file that holds FCRSYS,
//! and the compiler's view of it ([`compiler::MachineContext`]) built from the characterization
//! exactly as `ncplc build` builds it (runtime `machine_facts`).
//!
//! A file outside any machine, or in a machine whose characterization has errors, is checked
//! against [`language_only`]: every packet-A connector declared (inputs where `c mod 8 < 4`, as
//! the language's connector rule says), no SPL limit, the builtin interface map. The reason is
//! kept in [`Machine::note`] so that the server can say it once.

use std::path::{Path, PathBuf};

use compiler::{InterfaceMap, MachineContext};

/// The machine facts a document is checked against.
#[derive(Debug, Clone)]
pub struct Machine {
    /// The machine directory, when the file is inside one that loaded.
    pub dir: Option<PathBuf>,
    /// What the compiler checks against.
    pub ctx: MachineContext,
    /// The PLC source FCRSYS names (PLCSRC, default MP0/PLCPRG), when there is a machine.
    pub plc_source: Option<PathBuf>,
    /// IOCFIL's path and text, for the connector lines hover shows.
    pub iocfil: Option<(PathBuf, String)>,
    /// Why there is no machine context (shown once), when there is none.
    pub note: Option<String>,
}

/// The nearest directory at or above `file`'s directory that holds a file named FCRSYS.
pub fn find_dir(file: &Path) -> Option<PathBuf> {
    file.ancestors()
        .skip(1)
        .find(|d| d.join("FCRSYS").is_file())
        .map(Path::to_path_buf)
}

/// The context of the language rules without a machine (see the module header).
pub fn language_only() -> MachineContext {
    let all: Vec<u16> = (0..32).collect();
    MachineContext {
        a_inputs: all.iter().copied().filter(|c| c % 8 < 4).collect(),
        a_outputs: all.iter().copied().filter(|c| c % 8 >= 4).collect(),
        spl: u32::MAX,
        tick_ms: 10,
        time_slow_ms: 2,
        interface: InterfaceMap::builtin(),
    }
}

impl Machine {
    /// The machine of the source file `file` (see the module header).
    pub fn for_file(file: &Path) -> Machine {
        match find_dir(file) {
            Some(dir) => Machine::load(&dir),
            None => Machine::without(format!(
                "{} is not inside a machine directory (no FCRSYS above it): checking the language rules only, without IOCFIL connectors, SPL or the machine's interface.toml",
                file.display()
            )),
        }
    }

    fn without(note: String) -> Machine {
        Machine {
            dir: None,
            ctx: language_only(),
            plc_source: None,
            iocfil: None,
            note: Some(note),
        }
    }

    /// Loads the machine in `dir` as `ncplc build` does, in bounded memory: only whether the
    /// characterization has errors is used, so one diagnostic per file is stored and the rest
    /// counted (an error-dense file of any size costs no memory per error, issue 23).
    pub fn load(dir: &Path) -> Machine {
        let load = characterization::load_machine_capped(dir, 1);
        let shown = dir.display();
        let bad = load.has_errors();
        let machine = match load.machine {
            Some(m) if !bad => m,
            _ => {
                return Machine::without(format!(
                    "{shown}: the characterization files have errors (see `ncplc check {shown}`): checking the language rules only"
                ));
            }
        };
        let Some(io) = machine.iocfil.as_ref() else {
            return Machine::without(format!(
                "{shown}: FCRSYS section 2 binds no IOCFIL (logical name IOCONF): checking the language rules only"
            ));
        };
        let interface = match InterfaceMap::load_for_machine(&machine.dir) {
            Ok(m) => m,
            Err(e) => {
                return Machine::without(format!("{shown}: {e}: checking the language rules only"));
            }
        };
        let ctx = MachineContext {
            a_inputs: io.input_connectors(),
            a_outputs: io.output_connectors(),
            spl: io.spl_or_default(),
            tick_ms: io.tick_logic_ms,
            time_slow_ms: io.time_slow_ms,
            interface,
        };
        let iocfil = machine
            .paths
            .iocfil
            .as_ref()
            .and_then(|p| Some((p.clone(), std::fs::read(p).ok()?)))
            .map(|(p, b)| (p, compiler::lexer::decode_source(&b)));
        Machine {
            dir: Some(dir.to_path_buf()),
            ctx,
            plc_source: Some(machine.paths.plc_source.clone()),
            iocfil,
            note: None,
        }
    }

    /// The IOCFIL line declaring packet-A connector `c` (`IN0=0,1,…` or `OU0=4,5,…`), with its
    /// 1-based line number, when the machine has one.
    pub fn iocfil_line(&self, c: u16) -> Option<(u32, String)> {
        let (_, text) = self.iocfil.as_ref()?;
        text.lines().enumerate().find_map(|(i, l)| {
            let code = l.split(';').next().unwrap_or("").trim();
            let (key, value) = code.split_once('=')?;
            let key = key.trim().to_ascii_uppercase();
            if !(key.starts_with("IN") || key.starts_with("OU")) {
                return None;
            }
            let listed = value
                .split(',')
                .any(|v| v.trim().parse::<u16>().ok() == Some(c));
            listed.then(|| (i as u32 + 1, code.to_string()))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn example(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../plc-programs")
            .join(name)
    }

    #[test]
    fn the_lathe_program_finds_its_machine_and_iocfil_lines() {
        let m = Machine::for_file(&example("lathe").join("MP0/PLCPRG"));
        assert_eq!(m.note, None);
        assert_eq!(m.ctx.a_inputs, vec![0, 1]);
        assert_eq!(m.ctx.a_outputs, vec![4, 5]);
        assert_eq!(m.ctx.spl, 400);
        assert_eq!(m.iocfil_line(5), Some((7, "OU0=4,5,,,,,,".to_string())));
        assert_eq!(m.iocfil_line(1), Some((6, "IN0=0,1,,,,,,".to_string())));
        assert_eq!(m.iocfil_line(9), None);
    }

    #[test]
    fn an_error_dense_machine_is_refused_through_the_capped_load() {
        // The lathe with 10,000 bad IOCFIL lines (a duplicate T01 and an instruction section 4
        // does not allow): one diagnostic is stored, the other 19,999 only counted.
        let dir = std::env::temp_dir().join(format!("lsp-dense-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("MP0")).expect("mkdir");
        std::fs::copy(example("lathe").join("FCRSYS"), dir.join("FCRSYS")).expect("FCRSYS");
        for f in ["AXCFIL", "PGCFIL", "IOCFIL", "PLCPRG"] {
            std::fs::copy(
                example("lathe").join("MP0").join(f),
                dir.join("MP0").join(f),
            )
            .expect("copy");
        }
        let mut io = std::fs::read(dir.join("MP0/IOCFIL")).expect("IOCFIL");
        for _ in 0..10_000 {
            io.extend_from_slice(b"\nT01=10\nQZQ=1");
        }
        std::fs::write(dir.join("MP0/IOCFIL"), io).expect("write");
        let m = Machine::load(&dir);
        let _ = std::fs::remove_dir_all(&dir);
        assert!(m.dir.is_none());
        assert!(
            m.note
                .as_deref()
                .is_some_and(|n| n.contains("the characterization files have errors")),
            "{:?}",
            m.note
        );
    }

    #[test]
    fn a_file_outside_any_machine_gets_the_language_rules() {
        let m = Machine::for_file(Path::new("/nonexistent/dir/x.plc"));
        assert!(m.dir.is_none());
        assert!(
            m.note
                .as_deref()
                .is_some_and(|n| n.contains("not inside a machine"))
        );
        assert_eq!(m.ctx.a_inputs.len(), 16);
        assert!(m.ctx.a_outputs.contains(&4) && m.ctx.a_outputs.contains(&31));
    }
}
