//! Reading and validating `io.toml`: from the raw serde form to an [`IoMap`] plus located diagnostics.
//!
//! Every problem becomes a [`Diagnostic`] with a code in 3000–3499, the file, the line and column and
//! the byte span that toml's spans give. Nothing here panics on any input text. The checks: syntax and
//! unknown fields, signal names, connectors out of range, connectors IOCFIL does not declare (`INx` /
//! `OUx`), direction mismatches, overlapping mappings, unknown and duplicate devices, Modbus and
//! CANopen parameter ranges, healthy bits and the HMI window. The codes are listed in
//! `fieldbus/DIAGNOSTICS.md`.

use std::collections::{BTreeMap, HashMap};
use std::net::SocketAddr;
use std::ops::Range;
use std::path::Path;
use std::time::Duration;

use diag::Diagnostic;
use packets::{Packet, Signal, is_a_input_connector};
use toml::Spanned;

use crate::map::*;

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
    /// The selected bus has no devices in the map.
    pub const NO_DEVICES: u32 = 3050;
    /// The driver could not start (runtime, socket, CAN interface).
    pub const START: u32 = 3060;
    /// `open` was asked for the simulated I/O, which the runtime provides.
    pub const SIM: u32 = 3099;
    /// Warning: a declared connector no mapping uses.
    pub const UNMAPPED: u32 = 3090;
}

/// Default HMI server address.
pub const DEFAULT_HMI_BIND: &str = "127.0.0.1:1502";

struct Ctx<'a> {
    file: &'a str,
    text: &'a str,
    diags: Vec<Diagnostic>,
}

impl Ctx<'_> {
    fn err(
        &mut self,
        code: u32,
        span: Range<usize>,
        msg: impl Into<String>,
        hint: impl Into<String>,
    ) {
        let d = Diagnostic::error(code, self.file, span, msg)
            .with_hint(hint)
            .locate(self.text);
        self.diags.push(d);
    }

    fn warn(&mut self, code: u32, span: Range<usize>, msg: impl Into<String>) {
        let d = Diagnostic::warning(code, self.file, span, msg).locate(self.text);
        self.diags.push(d);
    }

    fn line_of(&self, span: &Range<usize>) -> u32 {
        diag::line_column(self.text, span.start).0
    }

    fn addr(&mut self, s: &Spanned<String>) -> Option<SocketAddr> {
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

    fn ms(&mut self, v: &Option<Spanned<u64>>, default: u64, what: &str) -> Duration {
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

    fn byte_value(&mut self, v: &Option<Spanned<u32>>, what: &str) -> u8 {
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
pub fn load_map(
    machine_dir: &Path,
    declared: &DeclaredConnectors,
) -> (Option<IoMap>, Vec<Diagnostic>) {
    let path = machine_dir.join("io.toml");
    match std::fs::read_to_string(&path) {
        Ok(text) => parse_map(&text, "io.toml", declared),
        Err(e) => {
            let d = Diagnostic::error(codes::UNREADABLE, "io.toml", 0..0, format!("cannot read {}: {e}", path.display()))
                .with_hint("write an I/O map <machine>/io.toml (see fieldbus/DIAGNOSTICS.md) or run with --io sim");
            (None, vec![d])
        }
    }
}

/// Parses and validates the text of an I/O map named `file`; the map is `Some` exactly when there
/// are no errors (warnings may accompany it).
pub fn parse_map(
    text: &str,
    file: &str,
    declared: &DeclaredConnectors,
) -> (Option<IoMap>, Vec<Diagnostic>) {
    let mut cx = Ctx {
        file,
        text,
        diags: Vec::new(),
    };
    let raw: RawMap = match toml::from_str(text) {
        Ok(r) => r,
        Err(e) => {
            let span = e.span().unwrap_or(0..0);
            let msg = e.message().trim().to_string();
            cx.err(
                codes::SYNTAX,
                span,
                msg,
                "see the io.toml format in fieldbus/DIAGNOSTICS.md",
            );
            return (None, cx.diags);
        }
    };
    let mut map = IoMap {
        hmi: raw.hmi.as_ref().map(|h| hmi(&mut cx, h.get_ref())),
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

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
enum Bus {
    Modbus,
    Canopen,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Dir {
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

fn hmi(cx: &mut Ctx, raw: &RawHmi) -> HmiConfig {
    let default: SocketAddr = SocketAddr::from(([127, 0, 0, 1], 1502));
    let bind = raw
        .bind
        .as_ref()
        .and_then(|b| cx.addr(b))
        .unwrap_or(default);
    let mut holding: Vec<HmiWindow> = Vec::new();
    for w in &raw.holding {
        let w_ref = w.get_ref();
        let sig = match w_ref.byte.get_ref().parse::<Signal>() {
            Ok(s) => s,
            Err(e) => {
                cx.err(
                    codes::BAD_SIGNAL,
                    w_ref.byte.span(),
                    e.to_string(),
                    "name a K or N byte, e.g. \"W200K0\"",
                );
                continue;
            }
        };
        let packet = sig.packet();
        if !matches!(sig, Signal::Byte { .. }) || !matches!(packet, Packet::K | Packet::N) {
            cx.err(
                codes::HMI_WINDOW,
                w_ref.byte.span(),
                format!("`{sig}` is not a K or N byte"),
                "the HMI may write only K and N bytes (W<c>K<b>, W<c>N<b>)",
            );
            continue;
        }
        let len = w_ref.len.as_ref().map_or(1, |l| *l.get_ref() as usize);
        let in_packet = sig.packet_byte();
        if len == 0 || in_packet + len > packet.len() {
            let span = w_ref.len.as_ref().map_or(w.span(), |l| l.span());
            cx.err(
                codes::HMI_WINDOW,
                span,
                format!(
                    "window of {len} bytes from {sig} does not fit packet {}",
                    packet.letter()
                ),
                format!("use 1..{} bytes", packet.len() - in_packet),
            );
            continue;
        }
        if in_packet % 2 != 0 || len % 2 != 0 {
            cx.err(codes::HMI_WINDOW, w.span(), format!("window of {len} bytes from {sig} does not hold whole registers"), "holding registers are 16 bits: start on an even byte (W<c>K0 or W<c>K2) and give an even len");
            continue;
        }
        let win = HmiWindow {
            start: sig.image_byte(),
            len,
        };
        if holding
            .iter()
            .any(|h| h.start < win.start + win.len && win.start < h.start + h.len)
        {
            cx.err(
                codes::HMI_WINDOW,
                w.span(),
                "HMI windows overlap",
                "list each byte once",
            );
            continue;
        }
        holding.push(win);
    }
    HmiConfig { bind, holding }
}

fn modbus_device(cx: &mut Ctx, d: &RawModbusDevice) -> ModbusDevice {
    let address = cx
        .addr(&d.address)
        .unwrap_or_else(|| SocketAddr::from(([127, 0, 0, 1], 502)));
    let unit = match &d.unit {
        Some(u) => u8::try_from(*u.get_ref()).unwrap_or_else(|_| {
            cx.err(
                codes::VALUE,
                u.span(),
                format!("unit id {} is out of range", u.get_ref()),
                "Modbus unit ids are 0..255",
            );
            1
        }),
        None => 1,
    };
    let alarm_ticks = match &d.alarm_ticks {
        Some(a) if *a.get_ref() == 0 => {
            cx.err(
                codes::VALUE,
                a.span(),
                "alarm_ticks must be at least 1",
                "the number of ticks without an answer before the alarm",
            );
            5
        }
        Some(a) => *a.get_ref(),
        None => 5,
    };
    let poll = match &d.poll_us {
        Some(p) if *p.get_ref() > 1_000_000 => {
            cx.err(
                codes::VALUE,
                p.span(),
                format!("poll_us {} is out of range", p.get_ref()),
                "use 0..1000000 µs",
            );
            Duration::from_micros(1000)
        }
        Some(p) => Duration::from_micros(*p.get_ref()),
        None => Duration::from_micros(1000),
    };
    let reconnect_min = cx.ms(&d.reconnect_ms, 100, "reconnect_ms");
    let reconnect_max = cx
        .ms(&d.reconnect_max_ms, 2000, "reconnect_max_ms")
        .max(reconnect_min);
    ModbusDevice {
        name: d.name.get_ref().clone(),
        address,
        unit,
        timeout: cx.ms(&d.timeout_ms, 50, "timeout_ms"),
        poll,
        alarm_ticks,
        reconnect_min,
        reconnect_max,
        healthy: None,
        inputs: Vec::new(),
        outputs: Vec::new(),
    }
}

fn canopen(cx: &mut Ctx, c: &RawCanopen, span: &Range<usize>) -> CanopenConfig {
    let kind = c
        .transport
        .as_ref()
        .map_or("virtual", |t| t.get_ref().as_str());
    let transport = match kind {
        "virtual" => TransportConfig::Virtual,
        "socketcan" => match &c.interface {
            Some(i) => TransportConfig::SocketCan {
                interface: i.get_ref().clone(),
            },
            None => {
                cx.err(
                    codes::TRANSPORT,
                    span.clone(),
                    "transport \"socketcan\" needs `interface`",
                    "add interface = \"can0\"",
                );
                TransportConfig::Virtual
            }
        },
        "cannelloni" => match (&c.local, &c.remote) {
            (Some(l), Some(r)) => match (cx.addr(l), cx.addr(r)) {
                (Some(local), Some(remote)) => TransportConfig::Cannelloni { local, remote },
                _ => TransportConfig::Virtual,
            },
            _ => {
                cx.err(
                    codes::TRANSPORT,
                    span.clone(),
                    "transport \"cannelloni\" needs `local` and `remote`",
                    "add local = \"0.0.0.0:20000\" and remote = \"<peer>:20000\"",
                );
                TransportConfig::Virtual
            }
        },
        other => {
            let s = c.transport.as_ref().map_or(span.clone(), |t| t.span());
            cx.err(
                codes::TRANSPORT,
                s,
                format!("unknown CANopen transport `{other}`"),
                "use \"virtual\", \"socketcan\" or \"cannelloni\"",
            );
            TransportConfig::Virtual
        }
    };
    let mut nodes = Vec::new();
    for n in &c.node {
        let r = n.get_ref();
        let node_id = match u8::try_from(*r.node_id.get_ref()) {
            Ok(id @ 1..=127) => id,
            _ => {
                cx.err(
                    codes::VALUE,
                    r.node_id.span(),
                    format!("node id {} is out of range", r.node_id.get_ref()),
                    "CANopen node ids are 1..127",
                );
                1
            }
        };
        for s in &r.sdo {
            let w = s.get_ref();
            let fits = match w.size {
                1 => w.value <= 0xFF,
                2 => w.value <= 0xFFFF,
                4 => true,
                _ => false,
            };
            if !fits {
                cx.err(
                    codes::VALUE,
                    s.span(),
                    format!("SDO value {} does not fit size {}", w.value, w.size),
                    "size is 1, 2 or 4 bytes and the value must fit it",
                );
            }
        }
        nodes.push(CanNode {
            name: r.name.get_ref().clone(),
            node_id,
            heartbeat: cx.ms(&r.heartbeat_ms, 100, "heartbeat_ms"),
            healthy: None,
            sdo: r.sdo.iter().map(|s| *s.get_ref()).collect(),
            inputs: Vec::new(),
            outputs: Vec::new(),
        });
    }
    CanopenConfig {
        transport,
        sdo_timeout: cx.ms(&c.sdo_timeout_ms, 100, "sdo_timeout_ms"),
        nodes,
    }
}

struct Checked {
    bus: Bus,
    device: usize,
    range: ByteRange,
    modbus: Option<(ModbusArea, u16)>,
    pdo: Option<(u8, u8)>,
    fail: u8,
}

fn mapping(
    cx: &mut Ctx,
    m: &Spanned<RawMapping>,
    dir: Dir,
    declared: &DeclaredConnectors,
    names: &HashMap<String, (Bus, usize, Range<usize>)>,
) -> Option<Checked> {
    let r = m.get_ref();
    let what = if dir == Dir::In { "input" } else { "output" };
    let Some(&(bus, device, _)) = names.get(r.device.get_ref()) else {
        let mut known: Vec<&String> = names.keys().collect();
        known.sort();
        let hint = if known.is_empty() {
            "define the device under [[modbus.device]] or [[canopen.node]]".to_string()
        } else {
            format!(
                "known devices: {}",
                known
                    .iter()
                    .map(|s| s.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        };
        cx.err(
            codes::UNKNOWN_DEVICE,
            r.device.span(),
            format!("unknown device `{}`", r.device.get_ref()),
            hint,
        );
        return None;
    };
    // Where in packet A.
    let range = match (&r.connector, &r.byte) {
        (Some(c), None) => {
            let n = *c.get_ref();
            if n >= 32 {
                cx.err(
                    codes::OUT_OF_RANGE,
                    c.span(),
                    format!("connector {n} is out of range"),
                    "packet A has connectors 0..31",
                );
                return None;
            }
            let len = r.len.as_ref().map_or(4, |l| *l.get_ref() as usize);
            (
                ByteRange {
                    start: n as usize * 4,
                    len,
                },
                c.span(),
            )
        }
        (None, Some(b)) => {
            let sig = match b.get_ref().parse::<Signal>() {
                Ok(s @ Signal::Byte { .. }) => s,
                Ok(s) => {
                    cx.err(
                        codes::BAD_SIGNAL,
                        b.span(),
                        format!("`{s}` is a bit, not a byte"),
                        "name a byte, e.g. \"W0A1\"",
                    );
                    return None;
                }
                Err(e) => {
                    cx.err(
                        codes::BAD_SIGNAL,
                        b.span(),
                        e.to_string(),
                        "name a byte, e.g. \"W0A1\"",
                    );
                    return None;
                }
            };
            if sig.packet() != Packet::A {
                cx.err(
                    codes::NOT_PACKET_A,
                    b.span(),
                    format!("`{sig}` is not in packet A"),
                    "devices map packet-A bytes (W<c>A<b>)",
                );
                return None;
            }
            let len = r.len.as_ref().map_or(1, |l| *l.get_ref() as usize);
            (
                ByteRange {
                    start: sig.packet_byte(),
                    len,
                },
                b.span(),
            )
        }
        _ => {
            cx.err(
                codes::WHERE,
                m.span(),
                format!("an {what} needs exactly one of `connector` and `byte`"),
                "e.g. connector = 0, or byte = \"W0A1\" with len = 2",
            );
            return None;
        }
    };
    let (range, where_span) = range;
    if range.len == 0 || range.end() > Packet::A.len() {
        let span = r.len.as_ref().map_or(where_span.clone(), |l| l.span());
        cx.err(
            codes::OUT_OF_RANGE,
            span,
            format!(
                "{} bytes from byte {} run past packet A",
                range.len, range.start
            ),
            format!(
                "use 1..{} bytes",
                Packet::A.len() - range.start.min(Packet::A.len() - 1)
            ),
        );
        return None;
    }
    let mut ok = true;
    let first_c = range.start / 4;
    let last_c = (range.end() - 1) / 4;
    for c in first_c..=last_c {
        let c16 = c as u16;
        let is_in = is_a_input_connector(c16);
        if is_in != (dir == Dir::In) {
            let (kind, want) = if is_in {
                ("an input", "inputs")
            } else {
                ("an output", "outputs")
            };
            cx.err(
                codes::DIRECTION,
                where_span.clone(),
                format!("connector {c} is {kind} connector but is mapped as an {what}"),
                format!(
                    "connector c is an input when c mod 8 < 4; map {want} from [[{}]]",
                    if is_in { "input" } else { "output" }
                ),
            );
            ok = false;
            continue;
        }
        let list = if dir == Dir::In {
            &declared.inputs
        } else {
            &declared.outputs
        };
        if !list.contains(&c16) {
            let prefix = if dir == Dir::In { "IN" } else { "OU" };
            let mut decl: Vec<String> = list.iter().map(|d| format!("{prefix}{d}")).collect();
            decl.sort();
            cx.err(
                codes::UNDECLARED,
                where_span.clone(),
                format!("connector {c} is not declared in IOCFIL as {prefix}{c}"),
                if decl.is_empty() {
                    format!("IOCFIL declares no {what} connectors")
                } else {
                    format!("IOCFIL declares {}", decl.join(", "))
                },
            );
            ok = false;
        }
    }
    let (fail_field, other_field, other_name) = if dir == Dir::In {
        (&r.fail, &r.safe, "safe")
    } else {
        (&r.safe, &r.fail, "fail")
    };
    if let Some(o) = other_field {
        cx.err(
            codes::FIELD,
            o.span(),
            format!("`{other_name}` does not apply to an {what}"),
            if dir == Dir::In {
                "inputs take `fail`"
            } else {
                "outputs take `safe`"
            },
        );
        ok = false;
    }
    let fail = cx.byte_value(fail_field, if dir == Dir::In { "fail" } else { "safe" });
    let mut checked = Checked {
        bus,
        device,
        range,
        modbus: None,
        pdo: None,
        fail,
    };
    match bus {
        Bus::Modbus => {
            for (f, name) in [(&r.pdo, "pdo"), (&r.offset, "offset")] {
                if let Some(f) = f {
                    cx.err(
                        codes::FIELD,
                        f.span(),
                        format!("`{name}` does not apply to a Modbus device"),
                        "Modbus mappings take `area` and `address`",
                    );
                    ok = false;
                }
            }
            let Some(area) = &r.area else {
                cx.err(
                    codes::FIELD,
                    m.span(),
                    format!("a Modbus {what} needs `area`"),
                    if dir == Dir::In {
                        "discrete_inputs, coils, input_registers or holding_registers"
                    } else {
                        "coils or holding_registers"
                    },
                );
                return None;
            };
            let a = *area.get_ref();
            if dir == Dir::Out
                && matches!(a, ModbusArea::DiscreteInputs | ModbusArea::InputRegisters)
            {
                cx.err(
                    codes::READ_ONLY_AREA,
                    area.span(),
                    "outputs cannot be written to a read-only Modbus table",
                    "write outputs to coils or holding_registers",
                );
                ok = false;
            }
            if !a.is_bits() && range.len % 2 != 0 {
                cx.err(
                    codes::VALUE,
                    where_span.clone(),
                    format!("{} bytes do not fill whole registers", range.len),
                    "map an even number of bytes onto registers",
                );
                ok = false;
            }
            let address = r.address.as_ref().map_or(0, |x| *x.get_ref());
            let items = a.items(range.len);
            let max_items = match (a.is_bits(), dir) {
                (true, Dir::In) => 2000,
                (true, Dir::Out) => 1968,
                (false, Dir::In) => 125,
                (false, Dir::Out) => 123,
            };
            if items > max_items || address as usize + items > 65536 {
                let span = r.address.as_ref().map_or(m.span(), |x| x.span());
                cx.err(
                    codes::VALUE,
                    span,
                    format!("{items} items from address {address} do not fit one Modbus request"),
                    format!("at most {max_items} items per request, addresses 0..65535"),
                );
                ok = false;
            }
            checked.modbus = Some((a, address.min(65535) as u16));
        }
        Bus::Canopen => {
            for (f, name) in [
                (r.area.as_ref().map(|a| a.span()), "area"),
                (r.address.as_ref().map(|a| a.span()), "address"),
            ] {
                if let Some(span) = f {
                    cx.err(
                        codes::FIELD,
                        span,
                        format!("`{name}` does not apply to a CANopen node"),
                        "CANopen mappings take `pdo` and `offset`",
                    );
                    ok = false;
                }
            }
            let Some(pdo) = &r.pdo else {
                cx.err(
                    codes::FIELD,
                    m.span(),
                    format!("a CANopen {what} needs `pdo`"),
                    "pdo = 1..4",
                );
                return None;
            };
            let p = *pdo.get_ref();
            if !(1..=4).contains(&p) {
                cx.err(
                    codes::VALUE,
                    pdo.span(),
                    format!("PDO {p} is out of range"),
                    "use PDO 1..4",
                );
                ok = false;
            }
            let offset = r.offset.as_ref().map_or(0, |o| *o.get_ref());
            if offset as usize + range.len > 8 {
                let span = r.offset.as_ref().map_or(where_span.clone(), |o| o.span());
                cx.err(
                    codes::VALUE,
                    span,
                    format!("{} bytes from offset {offset} do not fit a PDO", range.len),
                    "a PDO carries 8 data bytes",
                );
                ok = false;
            }
            checked.pdo = Some((p.min(4) as u8, offset.min(7) as u8));
        }
    }
    ok.then_some(checked)
}

fn attach(map: &mut IoMap, c: Checked, dir: Dir) {
    match (c.bus, c.modbus, c.pdo) {
        (Bus::Modbus, Some((area, address)), _) => {
            if let Some(d) = map.modbus.get_mut(c.device) {
                let m = ModbusMapping {
                    range: c.range,
                    area,
                    address,
                    fail: c.fail,
                };
                if dir == Dir::In {
                    d.inputs.push(m)
                } else {
                    d.outputs.push(m)
                }
            }
        }
        (Bus::Canopen, _, Some((pdo, offset))) => {
            if let Some(n) = map
                .canopen
                .as_mut()
                .and_then(|cfg| cfg.nodes.get_mut(c.device))
            {
                let m = PdoMapping {
                    range: c.range,
                    pdo,
                    offset,
                    fail: c.fail,
                };
                if dir == Dir::In {
                    n.inputs.push(m)
                } else {
                    n.outputs.push(m)
                }
            }
        }
        _ => {}
    }
}

/// Two mappings into the same PDO bytes of one node would fight over them.
fn check_pdo_overlaps(cx: &mut Ctx, map: &IoMap, raw: &RawMap) {
    let Some(cfg) = &map.canopen else { return };
    let span = raw.canopen.as_ref().map_or(0..0, |c| c.span());
    for n in &cfg.nodes {
        for (list, what) in [(&n.inputs, "TPDO"), (&n.outputs, "RPDO")] {
            let mut used = [[false; 8]; 5];
            for m in list {
                for i in 0..m.range.len {
                    let b = m.offset as usize + i;
                    if b < 8 && used[m.pdo as usize][b] {
                        cx.err(
                            codes::OVERLAP,
                            span.clone(),
                            format!(
                                "node `{}`: byte {b} of {what}{} is mapped twice",
                                n.name, m.pdo
                            ),
                            "give each PDO byte one packet-A byte",
                        );
                        break;
                    }
                    if b < 8 {
                        used[m.pdo as usize][b] = true;
                    }
                }
            }
        }
    }
}

fn check_healthy_bits(
    cx: &mut Ctx,
    raw: &RawMap,
    map: &mut IoMap,
    declared: &DeclaredConnectors,
    claimed: &BTreeMap<(Bus, usize), Range<usize>>,
) {
    let mut seen: Vec<(Signal, Range<usize>)> = Vec::new();
    let mut bits: Vec<(Bus, usize, Option<Signal>)> = Vec::new();
    let modbus_raw = raw
        .modbus
        .as_ref()
        .map(|m| m.device.as_slice())
        .unwrap_or(&[]);
    let can_raw = raw
        .canopen
        .as_ref()
        .map(|c| c.get_ref().node.as_slice())
        .unwrap_or(&[]);
    let entries = modbus_raw
        .iter()
        .enumerate()
        .map(|(i, d)| (Bus::Modbus, i, d.get_ref().healthy.as_ref()))
        .chain(
            can_raw
                .iter()
                .enumerate()
                .map(|(i, n)| (Bus::Canopen, i, n.get_ref().healthy.as_ref())),
        );
    for (bus, i, h) in entries {
        let Some(h) = h else { continue };
        let sig = match h.get_ref().parse::<Signal>() {
            Ok(s) => s,
            Err(e) => {
                cx.err(
                    codes::BAD_SIGNAL,
                    h.span(),
                    e.to_string(),
                    "name an input bit, e.g. \"I100K0\"",
                );
                continue;
            }
        };
        let problem = match sig {
            Signal::Byte { .. } => Some("is a byte, not a bit".to_string()),
            Signal::Bit {
                packet: Packet::T, ..
            } => Some("is in packet T (constants)".to_string()),
            Signal::Bit {
                packet: Packet::A,
                connector,
                ..
            } if !is_a_input_connector(connector) => {
                Some(format!("is on output connector {connector}"))
            }
            Signal::Bit {
                packet: Packet::A,
                connector,
                ..
            } if !declared.inputs.contains(&connector) => Some(format!(
                "is on connector {connector}, which IOCFIL does not declare as IN{connector}"
            )),
            Signal::Bit {
                packet: Packet::A, ..
            } if claimed.contains_key(&(bus, sig.packet_byte())) => {
                Some("is in a byte a mapping already fills".to_string())
            }
            _ if seen.iter().any(|(s, _)| *s == sig) => {
                Some("is already another device's healthy bit".to_string())
            }
            _ if map.hmi.as_ref().is_some_and(|hm| {
                hm.holding
                    .iter()
                    .any(|w| (w.start..w.start + w.len).contains(&sig.image_byte()))
            }) =>
            {
                Some("is in the HMI's writable window".to_string())
            }
            _ => None,
        };
        if let Some(p) = problem {
            cx.err(
                codes::HEALTHY,
                h.span(),
                format!("healthy bit `{}` {p}", h.get_ref()),
                "use a free input bit of K, N or a declared A input connector, e.g. \"I100K0\"",
            );
            continue;
        }
        seen.push((sig, h.span()));
        bits.push((bus, i, Some(sig)));
    }
    for (bus, i, sig) in bits {
        match bus {
            Bus::Modbus => {
                if let Some(d) = map.modbus.get_mut(i) {
                    d.healthy = sig;
                }
            }
            Bus::Canopen => {
                if let Some(n) = map.canopen.as_mut().and_then(|c| c.nodes.get_mut(i)) {
                    n.healthy = sig;
                }
            }
        }
    }
}
