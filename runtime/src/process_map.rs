//! The interface map checked against the machine's processes (docs/plc-interface-map.md §1: "process
//! 2..5: the map file must give their addresses before NBP>1 runs").
//!
//! [`needs`] decides from the characterization which handshakes each process has: M always; S
//! when the process has a spindle (IOCFIL section 3 `ASM`, an AXCFIL `INx` spindle, a section-2
//! axis of spindle type, or a spindle shared with `COM`); T when it has a spindle (the T function
//! is the tool mounted in the spindle) or declares an M function with the tool-offset request
//! (IOCFIL section 2, m_request 10). [`missing`] locates every role a process 2..NBP lacks at its
//! AXCFIL section-1 `PRO` record (code 1609); [`check`] is what `ncplc check` adds to the
//! characterization's diagnostics; [`require`] is `ncplc run`'s refusal.

use std::path::{Path, PathBuf};

use characterization::Machine;
use compiler::interface_map::{InterfaceMap, MissingRole, ProcessNeeds};
use diag::{Diagnostic, Sources};

/// The machine's NBP (1..5).
pub fn nbp(machine: &Machine) -> u8 {
    u8::try_from(machine.axcfil.nbp.clamp(1, 5)).unwrap_or(1)
}

fn is_spindle(machine: &Machine, process: u32, axis: char) -> bool {
    machine.axcfil.process(process).is_some_and(|p| {
        p.interpolators.iter().any(|i| i.spindle == Some(axis))
            || p.axis(axis)
                .and_then(|a| a.tpa.as_ref())
                .is_some_and(|t| t.axis_type.spindle())
    })
}

/// What the handshake of each process 1..NBP needs.
pub fn needs(machine: &Machine) -> Vec<ProcessNeeds> {
    (1..=nbp(machine))
        .map(|p| {
            let n = u32::from(p);
            let io = machine.iocfil.as_ref().and_then(|i| i.process(n));
            let ax = machine.axcfil.process(n);
            let spindle = io.is_some_and(|i| i.spindle.is_some())
                || ax.is_some_and(|a| {
                    a.interpolators.iter().any(|i| i.spindle.is_some())
                        || a.axes.iter().any(|x| is_spindle(machine, n, x.name))
                        || a.common
                            .iter()
                            .any(|c| c.axes.iter().any(|&x| is_spindle(machine, c.process, x)))
                });
            let tools = spindle
                || io.is_some_and(|i| i.m_functions.iter().any(|m| m.flags.tool_offset_request));
            ProcessNeeds {
                process: p,
                spindle,
                tools,
            }
        })
        .collect()
}

/// The roles processes 2..NBP lack in `map`, as diagnostics at their AXCFIL `PRO` records.
pub fn missing(machine: &Machine, map: &InterfaceMap) -> Vec<Diagnostic> {
    let file = machine
        .paths
        .axcfil
        .as_deref()
        .map(|p| characterization::machine::display_name(&machine.dir, p))
        .unwrap_or_else(|| "AXCFIL".into());
    map.missing_roles(nbp(machine), &needs(machine))
        .iter()
        .map(|m| {
            let span = machine
                .axcfil
                .process(u32::from(m.process))
                .map_or(0..0, |p| p.span.clone());
            Diagnostic::error(MissingRole::CODE, file.clone(), span, m.to_string())
                .with_hint(m.hint())
                .with_section(1)
                .with_process(u32::from(m.process))
        })
        .collect()
}

/// What `ncplc check` adds for the map of `dir`: the override file's errors (named
/// `interface.toml`, its text added to `sources`), or else the roles processes 2..NBP lack. Also
/// the map when it has no error (the built-in one without an override file), for the checks of
/// the files compiled or read against it (`sim.toml`, the PLC program; the file is read once):
/// `run` refuses a map with errors before it reads those, so checking them against it would only
/// add follow-on errors.
pub fn check(
    dir: &Path,
    machine: &Machine,
    sources: &mut Sources,
) -> (Vec<Diagnostic>, Option<InterfaceMap>) {
    let path = dir.join("interface.toml");
    let map = if path.exists() {
        let name = "interface.toml";
        let text = match diag::read_config(&path) {
            Ok(t) => t,
            Err(e) => {
                let err = compiler::interface_map::InterfaceMapError::Io {
                    file: name.into(),
                    message: e.to_string(),
                };
                return (vec![err.to_diagnostic(None)], None);
            }
        };
        sources.add(name, text.clone());
        let parsed = InterfaceMap::parse_all(name, &text)
            .and_then(|o| InterfaceMap::builtin().with_overrides(o));
        match parsed {
            Ok(map) => map,
            Err(errors) => {
                return (
                    errors
                        .iter()
                        .map(|e| e.to_diagnostic(Some(&text)))
                        .collect(),
                    None,
                );
            }
        }
    } else {
        InterfaceMap::builtin()
    };
    let mut out = missing(machine, &map);
    for d in &mut out {
        if let Some(text) = sources.get(&d.file) {
            *d = d.clone().locate(text);
        }
    }
    let usable = (!diag::has_errors(&out)).then_some(map);
    (out, usable)
}

/// `ncplc run`'s refusal: processes 2..NBP lack handshake signals in the interface map.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{}", self.render())]
pub struct MissingHandshakes {
    /// The machine directory.
    pub dir: PathBuf,
    /// AXCFIL NBP.
    pub nbp: u8,
    /// Every (process, role) that is missing, in process order.
    pub missing: Vec<MissingRole>,
}

impl MissingHandshakes {
    fn render(&self) -> String {
        let mut lines = Vec::new();
        for p in 2..=self.nbp {
            let roles: Vec<&str> = self
                .missing
                .iter()
                .filter(|m| m.process == p)
                .map(|m| m.role)
                .collect();
            if !roles.is_empty() {
                lines.push(format!("  process {p}: {}", roles.join(", ")));
            }
        }
        let hint = self
            .missing
            .first()
            .map(MissingRole::hint)
            .unwrap_or_default();
        format!(
            "error[E{:04}]: {}: AXCFIL NBP={}, but the interface map does not give these processes \
             their handshake signals:\n{}\nhelp: {}\n(see `ncplc check {}`)",
            MissingRole::CODE,
            self.dir.display(),
            self.nbp,
            lines.join("\n"),
            hint,
            self.dir.display()
        )
    }
}

/// `ncplc run`'s rule: every process 2..NBP has its handshake roles, or the list of what is
/// missing, process by process.
pub fn require(machine: &Machine, map: &InterfaceMap) -> Result<(), MissingHandshakes> {
    let missing = map.missing_roles(nbp(machine), &needs(machine));
    if missing.is_empty() {
        return Ok(());
    }
    Err(MissingHandshakes {
        dir: machine.dir.clone(),
        nbp: nbp(machine),
        missing,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn example(name: &str) -> Machine {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../plc-programs")
            .join(name);
        characterization::load_machine(&dir)
            .machine
            .expect("the example loads")
    }

    #[test]
    fn the_mill_magazine_process_needs_m_only_and_process_1_everything() {
        let mill = example("mill");
        assert_eq!(nbp(&mill), 2);
        assert_eq!(
            needs(&mill),
            vec![
                ProcessNeeds {
                    process: 1,
                    spindle: true,
                    tools: true
                },
                ProcessNeeds::m_only(2)
            ]
        );
    }

    #[test]
    fn the_builtin_map_lacks_process_2_and_the_error_says_so() {
        let mill = example("mill");
        let map = InterfaceMap::builtin();
        let d = missing(&mill, &map);
        let got: Vec<(u32, Option<u32>, &str)> = d
            .iter()
            .map(|d| (d.code, d.process, d.message.as_str()))
            .collect();
        assert_eq!(
            got,
            vec![
                (
                    1609,
                    Some(2),
                    "process 2 has no MSTB in the interface map (AXCFIL NBP=2)"
                ),
                (
                    1609,
                    Some(2),
                    "process 2 has no MFIN in the interface map (AXCFIL NBP=2)"
                ),
                (
                    1609,
                    Some(2),
                    "process 2 has no MCODE in the interface map (AXCFIL NBP=2)"
                ),
            ]
        );
        assert_eq!(d[0].file, "MP0/AXCFIL");
        let err = require(&mill, &map).expect_err("refused");
        assert_eq!(err.missing.len(), 3);
        let text = err.to_string();
        assert!(text.contains("  process 2: MSTB, MFIN, MCODE\n"), "{text}");
        // The lathe has one process: nothing to require.
        assert!(require(&example("lathe"), &map).is_ok());
    }
}
