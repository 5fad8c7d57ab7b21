//! Validation of the `[[input]]` and `[[output]]` mappings, PDO byte overlaps and healthy bits.

use std::collections::{BTreeMap, HashMap};
use std::ops::Range;

use packets::{Packet, Signal, is_a_input_connector};
use toml::Spanned;

use super::{Bus, Ctx, Dir, codes};
use crate::map::*;

pub(super) struct Checked {
    pub(super) bus: Bus,
    pub(super) device: usize,
    pub(super) range: ByteRange,
    pub(super) modbus: Option<(ModbusArea, u16)>,
    pub(super) pdo: Option<(u8, u8)>,
    pub(super) fail: u8,
}

pub(super) fn mapping(
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

pub(super) fn attach(map: &mut IoMap, c: Checked, dir: Dir) {
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
pub(super) fn check_pdo_overlaps(cx: &mut Ctx, map: &IoMap, raw: &RawMap) {
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

pub(super) fn check_healthy_bits(
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
