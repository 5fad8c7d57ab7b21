//! Reading and validating `io.toml`: from the raw serde form to an [`IoMap`] plus located diagnostics.
//!
//! Every problem becomes a [`Diagnostic`] with a code in 3000–3499, the file, the line and column and
//! the byte span that toml's spans give. Nothing here panics on any input text. The checks: syntax and
//! unknown fields, signal names, connectors out of range, connectors IOCFIL does not declare (`INx` /
//! `OUx`), direction mismatches, overlapping mappings, unknown and duplicate devices, Modbus and
//! CANopen parameter ranges, healthy bits, the HMI window and the CiA 402 drive entries
//! ([`drives`]: against the AXCFIL axes when the caller gives them). The codes are listed in
//! `fieldbus/DIAGNOSTICS.md`.

use std::collections::{BTreeMap, HashMap};
use std::net::SocketAddr;
use std::ops::Range;
use std::path::Path;
use std::time::Duration;

use diag::Diagnostic;
use toml::Spanned;

use crate::map::*;

mod drives;
mod mappings;
mod sections;

use mappings::{attach, check_healthy_bits, check_pdo_overlaps, mapping};
use sections::{canopen, hmi, modbus_device};

/// Codes of the I/O map diagnostics (documented in `fieldbus/DIAGNOSTICS.md`).
pub mod codes {
    /// TOML syntax error, unknown field or wrong value type.
    pub const SYNTAX: u32 = 3000;
    /// The map file cannot be read.
    pub const UNREADABLE: u32 = 3001;
    /// A signal name does not parse.
    pub const BAD_SIGNAL: u32 = 3010;
    /// A mapped byte is not in packet A.
    pub const NOT_PACKET_A: u32 = 3011;
    /// A connector or byte range runs past packet A.
    pub const OUT_OF_RANGE: u32 = 3012;
    /// A mapped connector is not declared in IOCFIL (`INx` / `OUx`).
    pub const UNDECLARED: u32 = 3020;
    /// An input mapped onto an output connector or the other way round.
    pub const DIRECTION: u32 = 3021;
    /// Two mappings claim the same byte.
    pub const OVERLAP: u32 = 3022;
    /// A healthy bit is unusable (not a bit, wrong packet, taken).
    pub const HEALTHY: u32 = 3023;
    /// Two devices share a name or a CANopen node id.
    pub const DUPLICATE_DEVICE: u32 = 3030;
    /// A mapping names a device the map does not define.
    pub const UNKNOWN_DEVICE: u32 = 3031;
    /// A field that does not apply to the device's bus, or a required field is missing.
    pub const FIELD: u32 = 3032;
    /// A number out of its range (unit id, node id, address, PDO, sizes, timeouts).
    pub const VALUE: u32 = 3033;
    /// A socket address does not parse.
    pub const SOCKET_ADDR: u32 = 3034;
    /// A mapping gives both or neither of `connector` and `byte`.
    pub const WHERE: u32 = 3036;
    /// An output mapped onto a read-only Modbus table.
    pub const READ_ONLY_AREA: u32 = 3037;
    /// A bad HMI window.
    pub const HMI_WINDOW: u32 = 3040;
    /// An unknown CANopen transport or one missing its parameters.
    pub const TRANSPORT: u32 = 3041;
    /// An `[affinity]` CPU list names a CPU the machine does not have, is empty or repeats a CPU.
    pub const CPU: u32 = 3042;
    /// The selected bus has no devices in the map.
    pub const NO_DEVICES: u32 = 3050;
    /// The driver could not start (runtime, socket, CAN interface).
    pub const START: u32 = 3060;
    /// `open` was asked for the simulated I/O, which the runtime provides.
    pub const SIM: u32 = 3099;
    /// Warning: a declared connector no mapping uses.
    pub const UNMAPPED: u32 = 3090;
    /// A drive names no AXCFIL axis (or not an axis name).
    pub const DRIVE_AXIS: u32 = 3070;
    /// An axis is on two drive entries.
    pub const DRIVE_AXIS_TWICE: u32 = 3071;
    /// A drive's node id is an I/O node's or another drive's.
    pub const DRIVE_NODE: u32 = 3072;
    /// A drive's `counts_per_unit` is 0, negative or not finite.
    pub const DRIVE_SCALE: u32 = 3073;
    /// An unknown drive mode, or one that does not fit the axis type (spindle ↔ `csv`).
    pub const DRIVE_MODE: u32 = 3074;
    /// A drive mode that is not supported yet (`pp`).
    pub const DRIVE_MODE_NOT_YET: u32 = 3075;
    /// The axis type does not allow a bus drive (AXCFIL error 226's TPA codes, virtual axes).
    pub const DRIVE_AXIS_TYPE: u32 = 3076;
    /// A drive failed its start-up (no answer or an SDO abort): no drive is enabled.
    pub const DRIVE_START: u32 = 3077;
    /// A drive's `simulate` hooks are incomplete or not on the virtual bus.
    pub const DRIVE_SIMULATE: u32 = 3078;
}

/// Default HMI server address.
pub const DEFAULT_HMI_BIND: std::net::SocketAddr = std::net::SocketAddr::V4(
    std::net::SocketAddrV4::new(std::net::Ipv4Addr::LOCALHOST, 1502),
);

pub(crate) struct Ctx<'a> {
    file: &'a str,
    text: &'a str,
    /// Line index of `text`: each diagnostic is located without rescanning the file.
    lines: diag::LineIndex,
    diags: Vec<Diagnostic>,
}

impl Ctx<'_> {
    pub(crate) fn err(
        &mut self,
        code: u32,
        span: Range<usize>,
        msg: impl Into<String>,
        hint: impl Into<String>,
    ) {
        let d = Diagnostic::error(code, self.file, span, msg)
            .with_hint(hint)
            .locate_in(self.text, &self.lines);
        self.diags.push(d);
    }

    pub(crate) fn warn(&mut self, code: u32, span: Range<usize>, msg: impl Into<String>) {
        let d = Diagnostic::warning(code, self.file, span, msg).locate_in(self.text, &self.lines);
        self.diags.push(d);
    }

    pub(crate) fn line_of(&self, span: &Range<usize>) -> u32 {
        self.lines.line_column(self.text, span.start).0
    }

    pub(crate) fn addr(&mut self, s: &Spanned<String>) -> Option<SocketAddr> {
        match s.get_ref().trim().parse::<SocketAddr>() {
            Ok(a) => Some(a),
            Err(_) => {
                let msg = format!("`{}` is not a socket address", s.get_ref());
                self.err(
                    codes::SOCKET_ADDR,
                    s.span(),
                    msg,
                    "write an IP address and a port, e.g. \"127.0.0.1:502\"",
                );
                None
            }
        }
    }

    pub(crate) fn ms(&mut self, v: &Option<Spanned<u64>>, default: u64, what: &str) -> Duration {
        match v {
            Some(s) if *s.get_ref() == 0 || *s.get_ref() > 3_600_000 => {
                self.err(
                    codes::VALUE,
                    s.span(),
                    format!("{what} {} ms is out of range", s.get_ref()),
                    "use 1..3600000 ms",
                );
                Duration::from_millis(default)
            }
            Some(s) => Duration::from_millis(*s.get_ref()),
            None => Duration::from_millis(default),
        }
    }

    pub(crate) fn byte_value(&mut self, v: &Option<Spanned<u32>>, what: &str) -> u8 {
        match v {
            Some(s) => match u8::try_from(*s.get_ref()) {
                Ok(b) => b,
                Err(_) => {
                    self.err(
                        codes::VALUE,
                        s.span(),
                        format!("{what} {} does not fit a byte", s.get_ref()),
                        "use 0..255",
                    );
                    0
                }
            },
            None => 0,
        }
    }
}

/// Reads `<machine_dir>/io.toml` and validates it; the map is `Some` exactly when there are no errors.
/// Drive entries are checked without the machine's axes (see [`load_map_with_axes`]).
pub fn load_map(
    machine_dir: &Path,
    declared: &DeclaredConnectors,
) -> (Option<IoMap>, Vec<Diagnostic>) {
    load_map_with_axes(machine_dir, declared, None)
}

/// [`load_map`], with the drive entries checked against the AXCFIL `axes` when given.
pub fn load_map_with_axes(
    machine_dir: &Path,
    declared: &DeclaredConnectors,
    axes: Option<&[DeclaredAxis]>,
) -> (Option<IoMap>, Vec<Diagnostic>) {
    let path = machine_dir.join("io.toml");
    match diag::read_config(&path) {
        Ok(text) => parse_map_with_axes(&text, "io.toml", declared, axes),
        Err(e) => {
            let hint = if e.kind() == std::io::ErrorKind::FileTooLarge {
                "an I/O map is a few kilobytes of tables describing this machine's devices and signals (docs/io-toml.md)"
            } else {
                "write an I/O map <machine>/io.toml (see fieldbus/DIAGNOSTICS.md) or run with --io sim"
            };
            let d = Diagnostic::error(
                codes::UNREADABLE,
                "io.toml",
                0..0,
                format!("cannot read {}: {e}", path.display()),
            )
            .with_hint(hint);
            (None, vec![d])
        }
    }
}

/// Parses and validates the text of an I/O map named `file`; the map is `Some` exactly when there
/// are no errors (warnings may accompany it). Drive entries are checked without the axes.
pub fn parse_map(
    text: &str,
    file: &str,
    declared: &DeclaredConnectors,
) -> (Option<IoMap>, Vec<Diagnostic>) {
    parse_map_with_axes(text, file, declared, None)
}

/// [`parse_map`], with the drive entries checked against the AXCFIL `axes` when given (`None`:
/// every check but those needing the axes).
pub fn parse_map_with_axes(
    text: &str,
    file: &str,
    declared: &DeclaredConnectors,
    axes: Option<&[DeclaredAxis]>,
) -> (Option<IoMap>, Vec<Diagnostic>) {
    let mut cx = Ctx {
        file,
        text,
        lines: diag::LineIndex::new(text),
        diags: Vec::new(),
    };
    let hint = "see the io.toml format in fieldbus/DIAGNOSTICS.md";
    let raw: RawMap = match diag::toml_keys::from_toml_diagnosed(text, file, codes::SYNTAX, hint) {
        Ok(r) => r,
        Err(errors) => {
            let located = errors.into_iter().map(|d| d.locate_in(text, &cx.lines));
            cx.diags.extend(located);
            return (None, cx.diags);
        }
    };
    let mut map = IoMap {
        hmi: raw.hmi.as_ref().map(|h| hmi(&mut cx, h.get_ref())),
        io_cpus: raw
            .affinity
            .as_ref()
            .map(|a| io_cpus(&mut cx, a, crate::affinity::cpu_count()))
            .unwrap_or_default(),
        ..IoMap::default()
    };

    // Devices: name → (bus, index).
    let mut names: HashMap<String, (Bus, usize, Range<usize>)> = HashMap::new();
    let modbus_devices = raw
        .modbus
        .as_ref()
        .map(|m| m.device.as_slice())
        .unwrap_or(&[]);
    for d in modbus_devices {
        let dev = modbus_device(&mut cx, d.get_ref());
        register_name(
            &mut cx,
            &mut names,
            &d.get_ref().name,
            Bus::Modbus,
            map.modbus.len(),
        );
        map.modbus.push(dev);
    }
    if let Some(c) = &raw.canopen {
        let cfg = canopen(&mut cx, c.get_ref(), &c.span());
        let mut ids: HashMap<u8, Range<usize>> = HashMap::new();
        for (i, (n, raw_node)) in cfg.nodes.iter().zip(&c.get_ref().node).enumerate() {
            register_name(
                &mut cx,
                &mut names,
                &raw_node.get_ref().name,
                Bus::Canopen,
                i,
            );
            let span = raw_node.get_ref().node_id.span();
            if let Some(first) = ids.get(&n.node_id) {
                let line = cx.line_of(first);
                cx.err(
                    codes::DUPLICATE_DEVICE,
                    span,
                    format!("node id {} is used twice", n.node_id),
                    format!("first used on line {line}"),
                );
            } else {
                ids.insert(n.node_id, span);
            }
        }
        let mut cfg = cfg;
        let virtual_bus = cfg.transport == crate::map::TransportConfig::Virtual;
        cfg.drives = drives::drives(&mut cx, &c.get_ref().drive, &ids, axes, virtual_bus);
        map.canopen = Some(cfg);
    }

    let mut claimed: BTreeMap<(Bus, usize), Range<usize>> = BTreeMap::new();
    let mut used_connectors = std::collections::BTreeSet::new();
    for (dir, list) in [(Dir::In, &raw.input), (Dir::Out, &raw.output)] {
        for m in list {
            let Some(checked) = mapping(&mut cx, m, dir, declared, &names) else {
                continue;
            };
            for b in checked.range.start..checked.range.end() {
                used_connectors.insert(b / 4);
                if let Some(first) = claimed.get(&(checked.bus, b)) {
                    let line = cx.line_of(first);
                    let msg = format!("byte W{}A{} is already mapped", b / 4, b % 4);
                    cx.err(
                        codes::OVERLAP,
                        m.span(),
                        msg,
                        format!("the first mapping of it is on line {line}"),
                    );
                    break;
                }
                claimed.insert((checked.bus, b), m.span());
            }
            attach(&mut map, checked, dir);
        }
    }
    check_pdo_overlaps(&mut cx, &map, &raw);
    check_healthy_bits(&mut cx, &raw, &mut map, declared, &claimed);

    let has_devices =
        !map.modbus.is_empty() || map.canopen.as_ref().is_some_and(|c| !c.nodes.is_empty());
    if has_devices {
        for (c, kind) in declared
            .inputs
            .iter()
            .map(|c| (c, "IN"))
            .chain(declared.outputs.iter().map(|c| (c, "OU")))
        {
            if !used_connectors.contains(&usize::from(*c)) {
                cx.warn(
                    codes::UNMAPPED,
                    0..0,
                    format!("IOCFIL declares {kind}{c} but no mapping uses it"),
                );
            }
        }
    }
    let ok = !diag::has_errors(&cx.diags);
    (ok.then_some(map), cx.diags)
}

/// Checks `[affinity] io_cpus` against a machine of `count` CPUs; the valid, distinct indices.
fn io_cpus(cx: &mut Ctx, raw: &Spanned<RawAffinity>, count: usize) -> Vec<usize> {
    let Some(list) = &raw.get_ref().io_cpus else {
        return Vec::new();
    };
    if list.get_ref().is_empty() {
        cx.err(
            codes::CPU,
            list.span(),
            "`io_cpus` lists no CPU",
            "name at least one CPU, e.g. io_cpus = [1], or leave the key out to run unpinned",
        );
        return Vec::new();
    }
    let mut cpus: Vec<usize> = Vec::new();
    for c in list.get_ref() {
        let checked = usize::try_from(*c.get_ref())
            .map_err(|_| crate::affinity::NoSuchCpu {
                cpu: usize::MAX,
                count,
            })
            .and_then(|cpu| crate::affinity::check_cpu_of(cpu, count));
        match checked {
            Ok(cpu) if cpus.contains(&cpu) => {
                cx.err(
                    codes::CPU,
                    c.span(),
                    format!("CPU {cpu} is listed twice"),
                    "list each CPU once",
                );
            }
            Ok(cpu) => cpus.push(cpu),
            Err(_) => {
                let msg = format!(
                    "CPU {} does not exist: this machine has {count} CPU(s)",
                    c.get_ref()
                );
                cx.err(
                    codes::CPU,
                    c.span(),
                    msg,
                    format!("use CPU indices 0..{}", count.saturating_sub(1)),
                );
            }
        }
    }
    cpus
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) enum Bus {
    Modbus,
    Canopen,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Dir {
    In,
    Out,
}

fn register_name(
    cx: &mut Ctx,
    names: &mut HashMap<String, (Bus, usize, Range<usize>)>,
    name: &Spanned<String>,
    bus: Bus,
    i: usize,
) {
    if let Some((_, _, first)) = names.get(name.get_ref()) {
        let line = cx.line_of(first);
        cx.err(
            codes::DUPLICATE_DEVICE,
            name.span(),
            format!("device `{}` is defined twice", name.get_ref()),
            format!("first defined on line {line}"),
        );
    } else {
        names.insert(name.get_ref().clone(), (bus, i, name.span()));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cpus_on(text: &str, count: usize) -> (Vec<usize>, Vec<(u32, String)>) {
        let mut cx = Ctx {
            file: "io.toml",
            text,
            lines: diag::LineIndex::new(text),
            diags: Vec::new(),
        };
        let raw: RawMap = toml::from_str(text).expect("toml");
        let cpus = io_cpus(&mut cx, raw.affinity.as_ref().expect("[affinity]"), count);
        let diags = cx
            .diags
            .iter()
            .map(|d| (d.code, d.message.clone()))
            .collect();
        (cpus, diags)
    }

    #[test]
    fn io_cpus_beyond_the_machine_are_located_errors() {
        assert_eq!(
            cpus_on("[affinity]\nio_cpus = [1, 0]", 2),
            (vec![1, 0], vec![])
        );
        assert_eq!(cpus_on("[affinity]", 2), (vec![], vec![]));
        assert_eq!(
            cpus_on("[affinity]\nio_cpus = [2]", 2),
            (
                vec![],
                vec![(
                    codes::CPU,
                    "CPU 2 does not exist: this machine has 2 CPU(s)".into()
                )]
            )
        );
        assert_eq!(
            cpus_on("[affinity]\nio_cpus = [3, 3]", 4),
            (vec![3], vec![(codes::CPU, "CPU 3 is listed twice".into())])
        );
        assert_eq!(
            cpus_on("[affinity]\nio_cpus = []", 4),
            (vec![], vec![(codes::CPU, "`io_cpus` lists no CPU".into())])
        );
    }
}
