//! The interface map: the fixed names of the K/N signals (MSTB, MFIN, FOLD, …) and their addresses.
//!
//! The default table (plc-interface-map.md §1) ships as `compiler/interface-map.toml` and is
//! embedded in the binary; a machine may override or extend it with `<machine>/interface.toml`
//! in the same format ([`InterfaceMap::load_for_machine`]). The PLC compiler predeclares every name
//! of the map; the runtime reads the handshake signals from it ([`InterfaceMap::signal`]).
//!
//! The run-time fault flag is [`FAULT_FLAG`] (`PLCFAULT`, default `U11K8`): the runtime sets it
//! when an integer division or MOD by zero happened in the logic (`ir::FAULT_DIV_ZERO`).

use std::collections::HashMap;
use std::path::Path;

use packets::Signal;
use serde::Deserialize;

/// The default map's TOML text.
pub const DEFAULT_MAP_TOML: &str = include_str!("../interface-map.toml");

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
}

/// Why a map file was rejected.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum InterfaceMapError {
    /// The TOML text does not have the map's shape.
    #[error("{file}: {message}")]
    Toml {
        /// The file.
        file: String,
        /// The TOML parser's message.
        message: String,
    },
    /// An entry's address, width or name is invalid.
    #[error("{file}: entry `{name}`: {message}")]
    Entry {
        /// The file.
        file: String,
        /// The entry's name.
        name: String,
        /// What is wrong.
        message: String,
    },
    /// The override file exists but cannot be read.
    #[error("{file}: {message}")]
    Io {
        /// The file.
        file: String,
        /// The OS error.
        message: String,
    },
}

#[derive(Deserialize)]
struct RawMap {
    #[serde(default)]
    signal: Vec<RawEntry>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawEntry {
    name: String,
    address: String,
    width: Width,
    dir: Direction,
    #[serde(default)]
    meaning: String,
}

/// The named interface signals of one machine.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InterfaceMap {
    signals: Vec<InterfaceSignal>,
    by_name: HashMap<String, usize>,
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
        }
    }

    /// Parses a map file's text (`file` names it in errors).
    pub fn parse(file: &str, text: &str) -> Result<Self, InterfaceMapError> {
        let raw: RawMap = toml::from_str(text).map_err(|e| InterfaceMapError::Toml {
            file: file.to_string(),
            message: e.to_string(),
        })?;
        let mut map = Self::empty();
        for e in raw.signal {
            let bad = |message: String| InterfaceMapError::Entry {
                file: file.to_string(),
                name: e.name.clone(),
                message,
            };
            let name = e.name.to_ascii_uppercase();
            let valid_name = name.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
                && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
            if !valid_name {
                return Err(bad(
                    "a name is letters, digits and `_`, starting with a letter".into(),
                ));
            }
            let signal: Signal = e
                .address
                .parse()
                .map_err(|err: packets::SignalError| bad(err.to_string()))?;
            match (signal, e.width) {
                (Signal::Bit { .. }, Width::Bit) => {}
                (Signal::Byte { index, .. }, w) if w != Width::Bit => {
                    if index + w.bytes() > 4 {
                        return Err(bad(format!(
                            "a {w:?} at {signal} runs past the end of its connector"
                        )));
                    }
                }
                _ => {
                    return Err(bad(format!(
                        "width {:?} does not fit address {signal} (bits use I/U, bytes W)",
                        e.width
                    )));
                }
            }
            if map.by_name.contains_key(&name) {
                return Err(bad("defined twice".into()));
            }
            map.insert(InterfaceSignal {
                name,
                signal,
                width: e.width,
                dir: e.dir,
                meaning: e.meaning,
            });
        }
        Ok(map)
    }

    fn insert(&mut self, s: InterfaceSignal) {
        match self.by_name.get(&s.name) {
            Some(&i) => self.signals[i] = s,
            None => {
                self.by_name.insert(s.name.clone(), self.signals.len());
                self.signals.push(s);
            }
        }
    }

    /// This map with every entry of `overrides` added, replacing entries of the same name.
    pub fn with_overrides(mut self, overrides: InterfaceMap) -> Self {
        for s in overrides.signals {
            self.insert(s);
        }
        self
    }

    /// The builtin map plus `<dir>/interface.toml` when that file exists.
    pub fn load_for_machine(dir: &Path) -> Result<Self, InterfaceMapError> {
        let path = dir.join("interface.toml");
        if !path.exists() {
            return Ok(Self::builtin());
        }
        let file = path.display().to_string();
        let text = std::fs::read_to_string(&path).map_err(|e| InterfaceMapError::Io {
            file: file.clone(),
            message: e.to_string(),
        })?;
        Ok(Self::builtin().with_overrides(Self::parse(&file, &text)?))
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

    /// The run-time fault flag's address, when the map has one.
    pub fn fault_flag(&self) -> Option<Signal> {
        self.signal(FAULT_FLAG)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_map_has_the_documented_entries() {
        let map = InterfaceMap::parse("default", DEFAULT_MAP_TOML).expect("the shipped map parses");
        assert_eq!(map.len(), 49);
        assert_eq!(map.signal("mstb"), Some("I1K0".parse().expect("signal")));
        assert_eq!(map.signal("MFIN"), Some("U11K0".parse().expect("signal")));
        assert_eq!(map.signal("RABI3"), Some("U10K10".parse().expect("signal")));
        let scode = map.get("SCODE").expect("SCODE");
        assert_eq!(
            (scode.width, scode.dir),
            (Width::Dword, Direction::CncToPlc)
        );
        assert_eq!(map.fault_flag(), Some("U11K8".parse().expect("signal")));
    }

    #[test]
    fn overrides_replace_and_extend() {
        let o = InterfaceMap::parse(
            "o",
            "[[signal]]\nname='mfin'\naddress='U12K0'\nwidth='bit'\ndir='out'\n\
             [[signal]]\nname='DOOR'\naddress='I0K5'\nwidth='bit'\ndir='in'\nmeaning='door closed'\n",
        )
        .expect("valid override");
        let map = InterfaceMap::builtin().with_overrides(o);
        assert_eq!(map.len(), 50);
        assert_eq!(map.signal("MFIN"), Some("U12K0".parse().expect("signal")));
        assert_eq!(
            map.get("door").map(|s| s.meaning.as_str()),
            Some("door closed")
        );
    }

    #[test]
    fn bad_entries_are_rejected_with_the_reason() {
        let e = InterfaceMap::parse(
            "f",
            "[[signal]]\nname='X'\naddress='W0K2'\nwidth='dword'\ndir='in'\n",
        );
        assert!(
            matches!(e, Err(InterfaceMapError::Entry { ref name, .. }) if name == "X"),
            "{e:?}"
        );
        let e = InterfaceMap::parse(
            "f",
            "[[signal]]\nname='X'\naddress='I0K2'\nwidth='byte'\ndir='in'\n",
        );
        assert!(matches!(e, Err(InterfaceMapError::Entry { .. })), "{e:?}");
        let e = InterfaceMap::parse("f", "[[signal]]\nname='X'\naddress='I0K2'\n");
        assert!(matches!(e, Err(InterfaceMapError::Toml { .. })), "{e:?}");
    }
}
