//! Why an interface map file was rejected, with a stable code (1601–1608) and the byte span of the
//! offending value, and the NBP>1 rule's finding ([`MissingRole`], code 1609).
//!
//! [`InterfaceMapError::to_diagnostic`] turns an error into the shared `diag::Diagnostic`, located
//! in the map file's text when the caller has it (`ncplc check` prints it rustc-style).

use std::ops::Range;

use crate::sema::codes;

/// Why a map file was rejected.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum InterfaceMapError {
    /// The TOML text does not have the map's shape (code 1601).
    #[error("{file}: {message}")]
    Toml {
        /// The file.
        file: String,
        /// The TOML parser's message.
        message: String,
        /// Where the parser stopped, when it says.
        span: Option<Range<usize>>,
    },
    /// An entry's address, width or name is invalid, or the name is defined twice (code 1602).
    #[error("{file}: entry `{name}`: {message}")]
    Entry {
        /// The file.
        file: String,
        /// The entry's name.
        name: String,
        /// What is wrong.
        message: String,
        /// The offending value.
        span: Range<usize>,
    },
    /// The override file exists but cannot be read (code 1603).
    #[error("{file}: {message}")]
    Io {
        /// The file.
        file: String,
        /// The OS error.
        message: String,
    },
    /// `role` names no fixed signal, names a machine-wide one for process 2..5, or an entry of
    /// process 2..5 has no role (code 1604).
    #[error("{file}: entry `{name}`: {message}")]
    UnknownRole {
        /// The file.
        file: String,
        /// The entry's name.
        name: String,
        /// What is wrong.
        message: String,
        /// The role (or the name when no role is given).
        span: Range<usize>,
    },
    /// `process` is outside 1..5 (code 1605).
    #[error("{file}: entry `{name}`: process {process} is outside 1..5")]
    ProcessRange {
        /// The file.
        file: String,
        /// The entry's name.
        name: String,
        /// The process given.
        process: i64,
        /// The `process` value.
        span: Range<usize>,
    },
    /// Two entries are the same fixed signal of the same process (code 1606).
    #[error("{file}: entry `{name}`: process {process} already has its {role} in entry `{other}`")]
    DuplicateRole {
        /// The file.
        file: String,
        /// The entry's name.
        name: String,
        /// The entry that already has the role.
        other: String,
        /// The process.
        process: u8,
        /// The role.
        role: String,
        /// The role (or name) of the later entry.
        span: Range<usize>,
    },
    /// The entry's bits or bytes overlap another entry's (code 1607).
    #[error("{file}: entry `{name}`: address {address} overlaps entry `{other}` ({other_address})")]
    AddressClash {
        /// The file.
        file: String,
        /// The entry's name.
        name: String,
        /// Its address.
        address: packets::Signal,
        /// The entry it overlaps.
        other: String,
        /// That entry's address.
        other_address: packets::Signal,
        /// The address of the later entry.
        span: Range<usize>,
    },
    /// `dir` goes against the connector convention, the `I`/`U` prefix or the role (code 1608).
    #[error("{file}: entry `{name}`: {message}")]
    Direction {
        /// The file.
        file: String,
        /// The entry's name.
        name: String,
        /// What is wrong.
        message: String,
        /// The `dir` value.
        span: Range<usize>,
    },
}

impl InterfaceMapError {
    /// The stable diagnostic code (`compiler::sema::codes::MAP_*`).
    pub fn code(&self) -> u32 {
        match self {
            InterfaceMapError::Toml { .. } => codes::MAP_TOML,
            InterfaceMapError::Entry { .. } => codes::MAP_ENTRY,
            InterfaceMapError::Io { .. } => codes::MAP_IO,
            InterfaceMapError::UnknownRole { .. } => codes::MAP_UNKNOWN_ROLE,
            InterfaceMapError::ProcessRange { .. } => codes::MAP_PROCESS_RANGE,
            InterfaceMapError::DuplicateRole { .. } => codes::MAP_DUPLICATE_ROLE,
            InterfaceMapError::AddressClash { .. } => codes::MAP_ADDRESS_CLASH,
            InterfaceMapError::Direction { .. } => codes::MAP_DIRECTION,
        }
    }

    /// The file the error is in.
    pub fn file(&self) -> &str {
        match self {
            InterfaceMapError::Toml { file, .. }
            | InterfaceMapError::Entry { file, .. }
            | InterfaceMapError::Io { file, .. }
            | InterfaceMapError::UnknownRole { file, .. }
            | InterfaceMapError::ProcessRange { file, .. }
            | InterfaceMapError::DuplicateRole { file, .. }
            | InterfaceMapError::AddressClash { file, .. }
            | InterfaceMapError::Direction { file, .. } => file,
        }
    }

    /// The byte span of the offending value (`None`: the whole file).
    pub fn span(&self) -> Option<Range<usize>> {
        match self {
            InterfaceMapError::Toml { span, .. } => span.clone(),
            InterfaceMapError::Io { .. } => None,
            InterfaceMapError::Entry { span, .. }
            | InterfaceMapError::UnknownRole { span, .. }
            | InterfaceMapError::ProcessRange { span, .. }
            | InterfaceMapError::DuplicateRole { span, .. }
            | InterfaceMapError::AddressClash { span, .. }
            | InterfaceMapError::Direction { span, .. } => Some(span.clone()),
        }
    }

    /// The message without the file name.
    fn message(&self) -> String {
        let full = self.to_string();
        let prefix = format!("{}: ", self.file());
        full.strip_prefix(&prefix).unwrap_or(&full).to_string()
    }

    fn hint(&self) -> &'static str {
        match self {
            InterfaceMapError::Toml { .. } => {
                "each entry is a [[signal]] table with name, address, width, dir and optionally \
                 meaning, process, role"
            }
            InterfaceMapError::Entry { .. } => {
                "names are letters, digits and `_`; bits use I/U addresses, byte/word/dword W \
                 addresses within one connector; the width of a role is the fixed signal's"
            }
            InterfaceMapError::Io { .. } => "make the file readable or remove it",
            InterfaceMapError::UnknownRole { .. } => {
                "a role is the name of a fixed signal of compiler/interface-map.toml (MSTB, MFIN, \
                 MCODE, …); RESET, MUSPE, ESTOP and PLCFAULT exist once, for process 1"
            }
            InterfaceMapError::ProcessRange { .. } => "processes are numbered 1..5 (AXCFIL NBP)",
            InterfaceMapError::DuplicateRole { .. } => {
                "give each fixed signal of a process one entry"
            }
            InterfaceMapError::AddressClash { .. } => {
                "pick a free address: a fixed signal on a free K/N connector of its direction \
                 (0..9 CNC→PLC, 10..99 PLC→CNC), the integrator's own on 100..255"
            }
            InterfaceMapError::Direction { .. } => {
                "K/N connectors 0..9 are CNC→PLC (`in`, `I` bits), 10..99 PLC→CNC (`out`, `U` \
                 bits), 100..255 either"
            }
        }
    }

    /// The diagnostic form; `source` is the file's text (line and column are filled from it).
    pub fn to_diagnostic(&self, source: Option<&str>) -> diag::Diagnostic {
        let span = self.span();
        let mut d = diag::Diagnostic::error(
            self.code(),
            self.file(),
            span.clone().unwrap_or(0..0),
            self.message(),
        )
        .with_hint(self.hint());
        if let (Some(src), Some(_)) = (source, span) {
            d = d.locate(src);
        }
        d
    }
}

/// A fixed signal that a process 2..NBP needs and the map does not give (code 1609).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("process {process} has no {role} in the interface map (AXCFIL NBP={nbp})")]
pub struct MissingRole {
    /// The process.
    pub process: u8,
    /// The role (`MSTB`, `MFIN`, `MCODE`, …).
    pub role: &'static str,
    /// The machine's NBP.
    pub nbp: u8,
}

impl MissingRole {
    /// The stable diagnostic code.
    pub const CODE: u32 = codes::MAP_MISSING_ROLE;

    /// What to write in `<machine>/interface.toml`.
    pub fn hint(&self) -> String {
        let (width, dir) = match super::fixed_signal(self.role) {
            Some((w, d)) => (
                format!("{w:?}").to_ascii_lowercase(),
                match d {
                    super::Direction::CncToPlc => "in",
                    super::Direction::PlcToCnc => "out",
                },
            ),
            None => ("bit".to_string(), "in"),
        };
        let connectors = if dir == "in" { "0..9" } else { "10..99" };
        format!(
            "add to <machine>/interface.toml: [[signal]] name = \"{}{}\", role = \"{}\", \
             process = {}, width = \"{width}\", dir = \"{dir}\", address = a free address on K/N \
             connectors {connectors}",
            self.role, self.process, self.role, self.process
        )
    }
}
