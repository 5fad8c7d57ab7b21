//! Validation of the `[hmi]`, `[[modbus.device]]` and `[canopen]` tables.

use std::net::SocketAddr;
use std::ops::Range;
use std::time::Duration;

use packets::{Packet, Signal};
use toml::Spanned;

use super::{Ctx, codes};
use crate::map::*;

pub(super) fn hmi(cx: &mut Ctx, raw: &RawHmi) -> HmiConfig {
    let bind = raw
        .bind
        .as_ref()
        .and_then(|b| cx.addr(b))
        .unwrap_or(super::DEFAULT_HMI_BIND);
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
    HmiConfig {
        bind,
        holding,
        limits: hmi_limits(cx, raw),
    }
}

/// The `[hmi]` unit id and limits, each checked against its range.
fn hmi_limits(cx: &mut Ctx, raw: &RawHmi) -> HmiLimits {
    let d = HmiLimits::default();
    let mut ranged = |v: &Option<Spanned<u32>>,
                      range: std::ops::RangeInclusive<u32>,
                      default: u32,
                      what: &str| match v {
        Some(s) if !range.contains(s.get_ref()) => {
            cx.err(
                codes::VALUE,
                s.span(),
                format!("{what} {} is out of range", s.get_ref()),
                format!("use {}..{}", range.start(), range.end()),
            );
            default
        }
        Some(s) => *s.get_ref(),
        None => default,
    };
    let unit = ranged(&raw.unit, 0..=255, u32::from(d.unit), "unit");
    let conns = ranged(
        &raw.max_connections,
        1..=1024,
        d.max_connections as u32,
        "max_connections",
    );
    let rate = ranged(
        &raw.max_requests_per_s,
        1..=100_000,
        d.max_requests_per_s,
        "max_requests_per_s",
    );
    let idle = cx.ms(
        &raw.idle_timeout_ms,
        d.idle_timeout.as_millis() as u64,
        "idle_timeout_ms",
    );
    HmiLimits {
        unit: u8::try_from(unit).unwrap_or(d.unit),
        max_connections: conns as usize,
        max_requests_per_s: rate,
        idle_timeout: idle,
    }
}

pub(super) fn modbus_device(cx: &mut Ctx, d: &RawModbusDevice) -> ModbusDevice {
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
        write_connection: d.write_connection.as_ref().is_none_or(|w| *w.get_ref()),
        direct_write: d.direct_write.as_ref().is_none_or(|w| *w.get_ref()),
        alarm_ticks,
        reconnect_min,
        reconnect_max,
        healthy: None,
        inputs: Vec::new(),
        outputs: Vec::new(),
    }
}

pub(super) fn canopen(cx: &mut Ctx, c: &RawCanopen, span: &Range<usize>) -> CanopenConfig {
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
        check_sdo_writes(cx, &r.sdo);
        let simulate = r.simulate.as_ref().map_or_else(NodeSimHooks::default, |h| {
            if kind != "virtual" {
                cx.err(
                    codes::DRIVE_SIMULATE,
                    h.span(),
                    "`simulate` rehearses faults on simulated nodes: it needs transport = \"virtual\"",
                    "remove it for a real bus",
                );
            }
            NodeSimHooks {
                silent_at_sync: h.get_ref().silent_at_sync,
            }
        });
        nodes.push(CanNode {
            name: r.name.get_ref().clone(),
            node_id,
            heartbeat: cx.ms(&r.heartbeat_ms, 100, "heartbeat_ms"),
            healthy: None,
            sdo: r.sdo.iter().map(|s| *s.get_ref()).collect(),
            inputs: Vec::new(),
            outputs: Vec::new(),
            simulate,
        });
    }
    CanopenConfig {
        transport,
        sdo_timeout: cx.ms(&c.sdo_timeout_ms, 100, "sdo_timeout_ms"),
        nodes,
        drives: Vec::new(),
    }
}

/// Checks that each SDO write's value fits its size (1, 2 or 4 bytes).
pub(super) fn check_sdo_writes(cx: &mut Ctx, writes: &[toml::Spanned<SdoWrite>]) {
    for s in writes {
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
}
