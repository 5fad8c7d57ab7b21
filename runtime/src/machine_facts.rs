//! The one place where a characterized machine is turned into what each part of ncplc needs.
//!
//! `characterization::load_machine` reads and validates FCRSYS, AXCFIL, PGCFIL and IOCFIL. The
//! compiler, the runtime, the fieldbus drivers and the partprogram compiler do not depend on the
//! characterization crate; they take small views of it (`compiler::MachineContext`,
//! `fieldbus::DeclaredConnectors`, …), and this module builds them. A machine whose
//! characterization has errors is refused here, with the rendered diagnostics, so that no program is
//! compiled or run against settings the controller would reject.

use std::path::{Path, PathBuf};

use characterization::Machine;
use characterization::iocfil::Iocfil;

/// Why a machine directory cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum MachineError {
    /// The directory does not exist.
    #[error("{0}: not a machine directory")]
    NotADirectory(PathBuf),
    /// The characterization files have errors; `report` is the rustc-style rendering.
    #[error("{dir}: the characterization files have errors (see `ncplc check {dir}`):\n{report}")]
    Invalid {
        /// The machine directory.
        dir: String,
        /// The rendered error diagnostics.
        report: String,
    },
    /// FCRSYS binds no IOCFIL (logical name IOCONF), so the logic has no connectors or tick.
    #[error("{0}: FCRSYS section 2 binds no IOCFIL (logical name IOCONF)")]
    NoIocfil(String),
    /// The machine's interface map override (`interface.toml`) is invalid.
    #[error(transparent)]
    Interface(#[from] compiler::interface_map::InterfaceMapError),
}

/// A machine that loaded without errors, with its IOCFIL.
#[derive(Debug, Clone)]
pub struct Facts {
    /// The typed characterization.
    pub machine: Machine,
    /// Its IOCFIL (a machine without one is refused).
    iocfil: Iocfil,
}

impl Facts {
    /// Loads and validates `dir`; any characterization error refuses the machine.
    pub fn load(dir: &Path) -> Result<Facts, MachineError> {
        if !dir.is_dir() {
            return Err(MachineError::NotADirectory(dir.to_path_buf()));
        }
        // The report prints at most the default cap per file: keeping more would only cost memory
        // (an error-dense file of any size is refused in bounded memory, issue 23).
        let max = diag::DEFAULT_MAX_PER_FILE;
        let mut load = characterization::load_machine_capped(dir, max);
        let shown = dir.display().to_string();
        if load.has_errors() || load.machine.is_none() {
            crate::render::relocate(&mut load, dir);
            let errors: Vec<_> = load
                .diagnostics
                .iter()
                .filter(|d| d.is_error())
                .cloned()
                .collect();
            let hidden: Vec<diag::Hidden> = load
                .hidden
                .iter()
                .filter(|h| h.errors > 0)
                .map(|h| diag::Hidden {
                    warnings: 0,
                    ..h.clone()
                })
                .collect();
            return Err(MachineError::Invalid {
                dir: shown,
                report: crate::render::render_diagnostics_capped_with(
                    &errors,
                    &hidden,
                    &load.sources,
                    max,
                ),
            });
        }
        match load.machine {
            Some(machine) => match machine.iocfil.clone() {
                Some(iocfil) => Ok(Facts { machine, iocfil }),
                None => Err(MachineError::NoIocfil(shown)),
            },
            None => Err(MachineError::NoIocfil(shown)),
        }
    }

    /// The machine's IOCFIL.
    pub fn iocfil(&self) -> &Iocfil {
        &self.iocfil
    }

    /// The PLC source FCRSYS names (`PLCSRC`, default `MP0/PLCPRG`).
    pub fn plc_source(&self) -> &Path {
        &self.machine.paths.plc_source
    }

    /// PGCFIL `OLD`: restore retained data at start.
    pub fn retains(&self) -> bool {
        self.machine.pgcfil.as_ref().is_some_and(|p| p.retains())
    }

    /// What the PLC compiler needs: declared packet-A connectors, SPL, CLO and the interface map.
    pub fn compiler_context(&self) -> Result<compiler::MachineContext, MachineError> {
        compiler_context(&self.machine.dir, self.iocfil())
    }

    /// The packet-A connectors IOCFIL declares, for the fieldbus I/O map.
    pub fn declared_connectors(&self) -> fieldbus::DeclaredConnectors {
        let io = self.iocfil();
        fieldbus::DeclaredConnectors {
            inputs: io.input_connectors(),
            outputs: io.output_connectors(),
        }
    }

    /// The AXCFIL axes, for the drive entries of the fieldbus I/O map.
    pub fn declared_axes(&self) -> Vec<fieldbus::DeclaredAxis> {
        declared_axes(&self.machine)
    }

    /// The 64 initial bytes of packet T (IOCFIL section 4; unset bytes are 0).
    pub fn t_init(&self) -> Vec<u8> {
        let mut t = vec![0u8; packets::Packet::T.len()];
        for (index, value) in self.iocfil().t_bytes() {
            if let Some(b) = t.get_mut(index) {
                *b = value;
            }
        }
        t
    }
}

/// Every AXCFIL axis of `machine` (process, name, TPA as written), for the fieldbus validation
/// of `[[canopen.drive]]` entries.
pub fn declared_axes(machine: &Machine) -> Vec<fieldbus::DeclaredAxis> {
    machine
        .axcfil
        .processes
        .iter()
        .flat_map(|p| {
            p.axes.iter().map(|a| fieldbus::DeclaredAxis {
                process: p.number,
                name: a.name,
                tpa: a.tpa.as_ref().map_or(0, |t| t.axis_type.raw),
                homes: a.mcz.is_some(),
            })
        })
        .collect()
}

/// The PLC compiler's view of the machine in `dir` with IOCFIL `io`: declared packet-A
/// connectors, SPL, CLO and the interface map (`ncplc check` builds it from the machine it
/// loaded, a run from its [`Facts`]).
pub fn compiler_context(dir: &Path, io: &Iocfil) -> Result<compiler::MachineContext, MachineError> {
    Ok(compiler_context_with(
        io,
        compiler::InterfaceMap::load_for_machine(dir)?,
    ))
}

/// [`compiler_context`] with the interface map already loaded (`ncplc check` reads it once).
pub fn compiler_context_with(
    io: &Iocfil,
    interface: compiler::InterfaceMap,
) -> compiler::MachineContext {
    compiler::MachineContext {
        a_inputs: io.input_connectors(),
        a_outputs: io.output_connectors(),
        spl: io.spl_or_default(),
        tick_ms: io.tick_logic_ms,
        time_slow_ms: io.time_slow_ms,
        interface,
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
    fn the_example_lathe_gives_its_iocfil_facts() {
        let facts = Facts::load(&example("lathe")).expect("the lathe loads");
        let ctx = facts.compiler_context().expect("interface map");
        assert_eq!(ctx.a_inputs, vec![0, 1]);
        assert_eq!(ctx.a_outputs, vec![4, 5]);
        assert_eq!((ctx.tick_ms, ctx.time_slow_ms), (10, 2));
        assert!(facts.plc_source().ends_with("MP0/PLCPRG"));
        assert_eq!(facts.declared_connectors().outputs, vec![4, 5]);
        assert_eq!(facts.t_init().len(), 64);
    }

    #[test]
    fn the_mill_declares_three_input_and_three_output_connectors() {
        let facts = Facts::load(&example("mill")).expect("the mill loads");
        let ctx = facts.compiler_context().expect("interface map");
        assert_eq!(ctx.a_inputs, vec![0, 1, 2]);
        assert_eq!(ctx.a_outputs, vec![4, 5, 6]);
    }

    #[test]
    fn the_mill_declares_its_axes_for_the_drive_entries() {
        let facts = Facts::load(&example("mill")).expect("the mill loads");
        let axes: Vec<_> = facts
            .declared_axes()
            .iter()
            .map(|a| (a.process, a.name, a.tpa))
            .collect();
        assert_eq!(
            axes,
            vec![
                (1, 'X', 0x1),
                (1, 'Y', 0x1),
                (1, 'Z', 0x1),
                (1, 'S', 0x820),
                (2, 'T', 0x2)
            ]
        );
    }

    #[test]
    fn a_broken_characterization_is_refused_with_its_errors() {
        let dir = tempfile::tempdir().expect("tempdir");
        std::fs::write(
            dir.path().join("FCRSYS"),
            "*1\nMP0=C:\\CNC32\\MP0\n*2\nAXCONF, AXCFIL/MP0\n*\n",
        )
        .expect("write");
        let err = Facts::load(dir.path()).expect_err("no AXCFIL");
        match err {
            MachineError::Invalid { report, .. } => assert!(report.contains("error["), "{report}"),
            other => panic!("unexpected {other}"),
        }
    }
}
