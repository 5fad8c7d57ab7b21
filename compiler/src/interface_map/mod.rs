//! The interface map: the fixed names of the K/N signals (MSTB, MFIN, FOLD, …) and their addresses,
//! for every process of the machine.
//!
//! The default table (docs/plc-interface-map.md §1, process 1) ships as `compiler/interface-map.toml`
//! and is embedded in the binary; a machine may override or extend it with
//! `<machine>/interface.toml` in the same format ([`InterfaceMap::load_for_machine`]). The PLC
//! compiler predeclares every name of the map; the runtime reads the handshake signals from it by
//! role ([`InterfaceMap::role`]).
//!
//! # Processes and roles
//! An entry may carry `process = n` (1..5, default 1) and `role`, the name of the fixed signal of
//! the default map it stands for in that process (`name = "MSTB2"`, `role = "MSTB"`,
//! `process = 2`): the integrator picks the PLC-visible name freely. Without `role`, an entry whose
//! name is a fixed signal's name has that role (so the default map is process 1's roles); any other
//! entry of process 1 is the integrator's own signal. An entry of process 2..5 needs a role.
//! RESET, MUSPE, ESTOP and PLCFAULT are machine-wide: they exist for process 1 only.
//! An override entry replaces the default entry of the same name and the one of the same
//! (process, role).
//!
//! # Checks (codes 1601–1609, `compiler/DIAGNOSTICS.md`)
//! Each error carries the file and the span of the offending value ([`InterfaceMapError`]):
//! bad TOML (1601); bad name, address, width, a name defined twice or a width that is not the
//! role's (1602); an unreadable override (1603); an unknown or machine-wide role (1604); a process
//! outside 1..5 (1605); a (process, role) given twice (1606); bits or bytes that overlap another
//! entry's (1607); a direction against the connector convention — K/N connectors 0..9 are
//! CNC→PLC (`in`), 10..99 PLC→CNC (`out`), 100..255 either —, against the `I`/`U` prefix of a bit
//! or against the role (1608). When AXCFIL declares NBP>1, every process 2..NBP must have the
//! handshake roles it needs ([`InterfaceMap::missing_roles`], 1609): MSTB, MFIN and MCODE always;
//! SSTB, SFIN, SCODE and TSTB, TFIN, TCODE when it has a spindle or a tool-change M function
//! ([`ProcessNeeds`]; the runtime decides this from the characterization).
//!
//! The run-time fault flag is [`FAULT_FLAG`] (`PLCFAULT`, default `U11K8`): the runtime sets it
//! when an integer division or MOD by zero happened in the logic (`ir::FAULT_DIV_ZERO`).

mod error;
mod roles;

use std::collections::HashMap;
use std::ops::Range;
use std::path::Path;

use packets::Signal;
use serde::Deserialize;
use toml::Spanned;

pub use error::{InterfaceMapError, MissingRole};
pub use roles::{MACHINE_WIDE, ProcessNeeds, fixed_signal};

/// The default map's TOML text.
pub const DEFAULT_MAP_TOML: &str = include_str!("../../interface-map.toml");

/// Name of the run-time fault flag (integer division by zero) in the map.
pub const FAULT_FLAG: &str = "PLCFAULT";

/// How many bits a map entry spans.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Width {
    /// One bit (`I…`/`U…` address).
    Bit,
    /// One byte (`W…` address).
    Byte,
    /// Two bytes from the `W…` address, little-endian, within one connector.
    Word,
    /// Four bytes from the `W…` address (byte 0 of the connector).
    Dword,
}

impl Width {
    /// Number of bytes (0 for a bit).
    pub const fn bytes(self) -> u8 {
        match self {
            Width::Bit => 0,
            Width::Byte => 1,
            Width::Word => 2,
            Width::Dword => 4,
        }
    }
}

/// Who writes a map entry.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize)]
pub enum Direction {
    /// The CNC writes it, the logic reads it.
    #[serde(rename = "in")]
    CncToPlc,
    /// The logic writes it, the CNC reads it.
    #[serde(rename = "out")]
    PlcToCnc,
}

/// Where an entry was written: the file and the spans of its values (for located errors).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Origin {
    /// The file.
    pub file: String,
    /// The `name` value.
    pub name: Range<usize>,
    /// The `address` value.
    pub address: Range<usize>,
    /// The `role` value, or the name when there is no `role`.
    pub role: Range<usize>,
}

/// One named interface signal.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InterfaceSignal {
    /// The name, upper case.
    pub name: String,
    /// The address: a bit, or the lowest byte of a byte/word/dword.
    pub signal: Signal,
    /// How wide the value is.
    pub width: Width,
    /// Who writes it.
    pub dir: Direction,
    /// What it means.
    pub meaning: String,
    /// The process (1..5) it belongs to.
    pub process: u8,
    /// The fixed signal it is for its process (`None`: the integrator's own signal).
    pub role: Option<String>,
    /// Where it was written.
    pub origin: Origin,
}

/// The file: `[[signal]]` tables only; any other table or key is an error (1601), not ignored.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMap {
    #[serde(default)]
    signal: Vec<RawEntry>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawEntry {
    name: Spanned<String>,
    address: Spanned<String>,
    width: Width,
    dir: Spanned<Direction>,
    #[serde(default)]
    meaning: String,
    process: Option<Spanned<i64>>,
    role: Option<Spanned<String>>,
}

/// The named interface signals of one machine.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InterfaceMap {
    signals: Vec<InterfaceSignal>,
    by_name: HashMap<String, usize>,
    by_role: HashMap<(u8, String), usize>,
}

impl Default for InterfaceMap {
    fn default() -> Self {
        Self::builtin()
    }
}

impl InterfaceMap {
    /// The default map shipped with ncplc.
    pub fn builtin() -> Self {
        // The embedded file is tested to parse; an empty map is the only possible fallback.
        Self::parse("interface-map.toml", DEFAULT_MAP_TOML).unwrap_or_else(|_| Self::empty())
    }

    /// A map without entries.
    pub fn empty() -> Self {
        InterfaceMap {
            signals: Vec::new(),
            by_name: HashMap::new(),
            by_role: HashMap::new(),
        }
    }

    /// Parses a map file's text (`file` names it in errors); the first error when there are any.
    pub fn parse(file: &str, text: &str) -> Result<Self, InterfaceMapError> {
        Self::parse_all(file, text).map_err(first)
    }

    /// Parses a map file's text and reports every error, in file order.
    pub fn parse_all(file: &str, text: &str) -> Result<Self, Vec<InterfaceMapError>> {
        let raw: RawMap =
            diag::toml_keys::from_toml(text, diag::DEFAULT_MAX_PER_FILE).map_err(|errors| {
                errors
                    .into_iter()
                    .map(|e| InterfaceMapError::Toml {
                        file: file.to_string(),
                        message: e.message,
                        span: e.span,
                    })
                    .collect::<Vec<_>>()
            })?;
        let mut map = Self::empty();
        let mut errors = Vec::new();
        for e in raw.signal {
            match roles::entry(file, e) {
                Ok(s) => {
                    if let Some(&i) = map.by_name.get(&s.name) {
                        errors.push(InterfaceMapError::Entry {
                            file: file.to_string(),
                            name: s.name.clone(),
                            message: format!("defined twice (first at {})", map.signals[i].signal),
                            span: s.origin.name.clone(),
                        });
                        continue;
                    }
                    if let Some(err) = roles::conflict(&map.signals, &s) {
                        errors.push(err);
                        continue;
                    }
                    map.signals.push(s);
                    map.reindex();
                }
                Err(err) => errors.push(err),
            }
        }
        if errors.is_empty() {
            Ok(map)
        } else {
            Err(errors)
        }
    }

    fn reindex(&mut self) {
        self.by_name.clear();
        self.by_role.clear();
        for (i, s) in self.signals.iter().enumerate() {
            self.by_name.insert(s.name.clone(), i);
            if let Some(role) = &s.role {
                self.by_role.insert((s.process, role.clone()), i);
            }
        }
    }

    /// This map with every entry of `overrides` added, replacing the entries of the same name and
    /// of the same (process, role); an override entry that overlaps a remaining entry's address is
    /// an error located in the override file.
    pub fn with_overrides(self, overrides: InterfaceMap) -> Result<Self, Vec<InterfaceMapError>> {
        let mut base: Vec<InterfaceSignal> = self
            .signals
            .into_iter()
            .filter(|b| {
                !overrides.signals.iter().any(|o| {
                    o.name == b.name
                        || (o.role.is_some() && o.process == b.process && o.role == b.role)
                })
            })
            .collect();
        let mut errors = Vec::new();
        for o in overrides.signals {
            match roles::conflict(&base, &o) {
                Some(err) => errors.push(err),
                None => base.push(o),
            }
        }
        if !errors.is_empty() {
            return Err(errors);
        }
        let mut map = Self::empty();
        map.signals = base;
        map.reindex();
        Ok(map)
    }

    /// The builtin map plus `<dir>/interface.toml` when that file exists (the first error).
    pub fn load_for_machine(dir: &Path) -> Result<Self, InterfaceMapError> {
        Self::load_for_machine_all(dir).map_err(first)
    }

    /// [`InterfaceMap::load_for_machine`] with every error of the override file.
    pub fn load_for_machine_all(dir: &Path) -> Result<Self, Vec<InterfaceMapError>> {
        let path = dir.join("interface.toml");
        if !path.exists() {
            return Ok(Self::builtin());
        }
        let file = path.display().to_string();
        let text = diag::read_config(&path).map_err(|e| {
            vec![InterfaceMapError::Io {
                file: file.clone(),
                message: e.to_string(),
            }]
        })?;
        Self::builtin().with_overrides(Self::parse_all(&file, &text)?)
    }

    /// The entry named `name` (case-insensitive).
    pub fn get(&self, name: &str) -> Option<&InterfaceSignal> {
        self.by_name
            .get(&name.to_ascii_uppercase())
            .map(|&i| &self.signals[i])
    }

    /// The address of `name` (case-insensitive).
    pub fn signal(&self, name: &str) -> Option<Signal> {
        self.get(name).map(|s| s.signal)
    }

    /// The entry that is fixed signal `role` (case-insensitive) of `process`.
    pub fn role(&self, process: u8, role: &str) -> Option<&InterfaceSignal> {
        self.by_role
            .get(&(process, role.to_ascii_uppercase()))
            .map(|&i| &self.signals[i])
    }

    /// The roles that processes 2..`nbp` need (`needs`, one per process) and the map lacks, in
    /// process order, then in the order of [`ProcessNeeds::roles`].
    pub fn missing_roles(&self, nbp: u8, needs: &[ProcessNeeds]) -> Vec<MissingRole> {
        let mut out = Vec::new();
        for p in 2..=nbp.min(5) {
            let need = needs
                .iter()
                .find(|n| n.process == p)
                .copied()
                .unwrap_or(ProcessNeeds::m_only(p));
            for role in need.roles() {
                if self.role(p, role).is_none() {
                    out.push(MissingRole {
                        process: p,
                        role,
                        nbp,
                    });
                }
            }
        }
        out
    }

    /// The run-time fault flag's address, when the map has one.
    pub fn fault_flag(&self) -> Option<Signal> {
        self.role(1, FAULT_FLAG).map(|s| s.signal)
    }

    /// All entries in file order.
    pub fn iter(&self) -> impl Iterator<Item = &InterfaceSignal> {
        self.signals.iter()
    }

    /// Number of entries.
    pub fn len(&self) -> usize {
        self.signals.len()
    }

    /// True when the map has no entries.
    pub fn is_empty(&self) -> bool {
        self.signals.is_empty()
    }
}

fn first(mut errors: Vec<InterfaceMapError>) -> InterfaceMapError {
    if errors.is_empty() {
        InterfaceMapError::Io {
            file: String::new(),
            message: "no error".into(),
        }
    } else {
        errors.swap_remove(0)
    }
}

#[cfg(test)]
mod tests;
