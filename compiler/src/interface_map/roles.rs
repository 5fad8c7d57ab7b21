//! Roles and the checks of one map entry: the fixed signals of the default map, which of them are
//! machine-wide, the connector direction convention, address overlaps and what a process 2..5
//! needs for its M/S/T handshake.

use std::collections::HashMap;
use std::sync::LazyLock;

use packets::{Dir, Packet, Signal};

use super::{
    DEFAULT_MAP_TOML, Direction, InterfaceMapError, InterfaceSignal, Origin, RawEntry, RawMap,
    Width,
};

/// The fixed signals that exist once for the machine (process 1 only): general reset, power-off
/// permission, emergency stop and the run-time fault flag.
pub const MACHINE_WIDE: [&str; 4] = ["RESET", "MUSPE", "ESTOP", "PLCFAULT"];

static FIXED: LazyLock<HashMap<String, (Width, Direction)>> = LazyLock::new(|| {
    // The embedded file is tested to parse; no roles is the only possible fallback.
    toml::from_str::<RawMap>(DEFAULT_MAP_TOML)
        .map(|m| {
            m.signal
                .into_iter()
                .map(|e| {
                    (
                        e.name.get_ref().to_ascii_uppercase(),
                        (e.width, *e.dir.get_ref()),
                    )
                })
                .collect()
        })
        .unwrap_or_default()
});

/// The width and direction of fixed signal `role` (a name of the default map), upper case.
pub fn fixed_signal(role: &str) -> Option<(Width, Direction)> {
    FIXED.get(role).copied()
}

/// What the handshake of one process needs from the map (the runtime decides it from the
/// characterization: a spindle — IOCFIL `ASM`, an AXCFIL interpolator spindle or a spindle-type
/// axis — and tool functions — a spindle, or an IOCFIL M function with the tool-offset request).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ProcessNeeds {
    /// The process (1..5).
    pub process: u8,
    /// It has a spindle: S functions (SSTB, SFIN, SCODE).
    pub spindle: bool,
    /// It has tool functions: T functions (TSTB, TFIN, TCODE).
    pub tools: bool,
}

impl ProcessNeeds {
    /// A process with M functions only.
    pub const fn m_only(process: u8) -> ProcessNeeds {
        ProcessNeeds {
            process,
            spindle: false,
            tools: false,
        }
    }

    /// The roles it needs: MSTB, MFIN, MCODE, then the S and T ones when it has them.
    pub fn roles(&self) -> Vec<&'static str> {
        let mut r = vec!["MSTB", "MFIN", "MCODE"];
        if self.spindle {
            r.extend(["SSTB", "SFIN", "SCODE"]);
        }
        if self.tools {
            r.extend(["TSTB", "TFIN", "TCODE"]);
        }
        r
    }
}

/// Checks one raw entry and turns it into a signal.
pub(super) fn entry(file: &str, e: RawEntry) -> Result<InterfaceSignal, InterfaceMapError> {
    let name_span = e.name.span();
    let name = e.name.get_ref().to_ascii_uppercase();
    let bad = |message: String, span: std::ops::Range<usize>| InterfaceMapError::Entry {
        file: file.to_string(),
        name: name.clone(),
        message,
        span,
    };
    let valid_name = name.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    if !valid_name {
        return Err(bad(
            "a name is letters, digits and `_`, starting with a letter".into(),
            name_span,
        ));
    }
    let address_span = e.address.span();
    let signal: Signal = e
        .address
        .get_ref()
        .parse()
        .map_err(|err: packets::SignalError| bad(err.to_string(), address_span.clone()))?;
    match (signal, e.width) {
        (Signal::Bit { .. }, Width::Bit) => {}
        (Signal::Byte { index, .. }, w) if w != Width::Bit => {
            if index + w.bytes() > 4 {
                return Err(bad(
                    format!("a {w:?} at {signal} runs past the end of its connector"),
                    address_span,
                ));
            }
        }
        _ => {
            return Err(bad(
                format!(
                    "width {:?} does not fit address {signal} (bits use I/U, bytes W)",
                    e.width
                ),
                address_span,
            ));
        }
    }
    let process = match &e.process {
        None => 1,
        Some(p) => match u8::try_from(*p.get_ref()) {
            Ok(n @ 1..=5) => n,
            _ => {
                return Err(InterfaceMapError::ProcessRange {
                    file: file.to_string(),
                    name,
                    process: *p.get_ref(),
                    span: p.span(),
                });
            }
        },
    };
    let (role, role_span) = match &e.role {
        Some(r) => (Some(r.get_ref().to_ascii_uppercase()), r.span()),
        None => (
            fixed_signal(&name).is_some().then(|| name.clone()),
            name_span.clone(),
        ),
    };
    let unknown = |message: String| InterfaceMapError::UnknownRole {
        file: file.to_string(),
        name: name.clone(),
        message,
        span: role_span.clone(),
    };
    let dir = *e.dir.get_ref();
    let direction = |message: String| InterfaceMapError::Direction {
        file: file.to_string(),
        name: name.clone(),
        message,
        span: e.dir.span(),
    };
    match &role {
        None if process != 1 => {
            return Err(unknown(format!(
                "an entry of process {process} needs a `role` (the fixed signal it stands for)"
            )));
        }
        None => {}
        Some(r) => {
            let Some((width, fixed_dir)) = fixed_signal(r) else {
                return Err(unknown(format!("role `{r}` is not a fixed signal")));
            };
            if process != 1 && MACHINE_WIDE.contains(&r.as_str()) {
                return Err(unknown(format!(
                    "role `{r}` is machine-wide: it exists for process 1 only"
                )));
            }
            if width != e.width {
                return Err(bad(
                    format!("role {r} is a {width:?}, not a {:?}", e.width),
                    address_span,
                ));
            }
            if fixed_dir != dir {
                return Err(direction(format!("role {r} is {}", dir_text(fixed_dir))));
            }
        }
    }
    convention(signal, dir).map_err(direction)?;
    Ok(InterfaceSignal {
        name,
        signal,
        width: e.width,
        dir,
        meaning: e.meaning,
        process,
        role,
        origin: Origin {
            file: file.to_string(),
            name: name_span,
            address: address_span,
            role: role_span,
        },
    })
}

fn dir_text(d: Direction) -> &'static str {
    match d {
        Direction::CncToPlc => "CNC→PLC (`in`)",
        Direction::PlcToCnc => "PLC→CNC (`out`)",
    }
}

/// The direction convention (docs/plc-interface-map.md): K/N connectors 0..9 are written by the CNC,
/// 10..99 by the logic, 100..255 either; a bit's `I`/`U` prefix says the same as `dir`.
fn convention(signal: Signal, dir: Direction) -> Result<(), String> {
    if let Signal::Bit { dir: prefix, .. } = signal {
        let agrees = matches!(
            (prefix, dir),
            (Dir::In, Direction::CncToPlc) | (Dir::Out, Direction::PlcToCnc)
        );
        if !agrees {
            return Err(format!(
                "{signal} is spelled for the other direction than {}",
                dir_text(dir)
            ));
        }
    }
    let (packet, connector) = match signal {
        Signal::Bit {
            packet, connector, ..
        }
        | Signal::Byte {
            packet, connector, ..
        } => (packet, connector),
    };
    if !matches!(packet, Packet::K | Packet::N) {
        return Ok(());
    }
    let expected = match connector {
        0..=9 => Direction::CncToPlc,
        10..=99 => Direction::PlcToCnc,
        _ => return Ok(()),
    };
    if expected == dir {
        Ok(())
    } else {
        Err(format!(
            "connector {connector}{} is {}, not {}",
            packet.letter(),
            dir_text(expected),
            dir_text(dir)
        ))
    }
}

/// The image bytes and bit masks an entry occupies.
fn footprint(s: &InterfaceSignal) -> Vec<(usize, u8)> {
    let at = s.signal.image_byte();
    match s.signal.bit() {
        Some(bit) => vec![(at, 1u8 << (bit % 8))],
        None => (0..usize::from(s.width.bytes()))
            .map(|i| (at + i, 0xFF))
            .collect(),
    }
}

/// The first way `s` conflicts with one of `existing`: the same (process, role), or overlapping
/// bits or bytes.
pub(super) fn conflict(
    existing: &[InterfaceSignal],
    s: &InterfaceSignal,
) -> Option<InterfaceMapError> {
    if let Some(role) = &s.role
        && let Some(other) = existing
            .iter()
            .find(|o| o.process == s.process && o.role.as_ref() == Some(role))
    {
        return Some(InterfaceMapError::DuplicateRole {
            file: s.origin.file.clone(),
            name: s.name.clone(),
            other: other.name.clone(),
            process: s.process,
            role: role.clone(),
            span: s.origin.role.clone(),
        });
    }
    let mine = footprint(s);
    let other = existing.iter().find(|o| {
        footprint(o)
            .iter()
            .any(|(b, m)| mine.iter().any(|(b2, m2)| b == b2 && m & m2 != 0))
    })?;
    Some(InterfaceMapError::AddressClash {
        file: s.origin.file.clone(),
        name: s.name.clone(),
        address: s.signal,
        other: other.name.clone(),
        other_address: other.signal,
        span: s.origin.address.clone(),
    })
}
