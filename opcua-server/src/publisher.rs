//! The server's side of the signals: a task that wakes ten times a logic tick, takes every new
//! [`Frame`] and sets the variables whose value changed (one `set_values` call, one lock of the
//! address space, off the scan thread). Client writes are [`crate::node_manager`]'s.
//!
//! **Invariant:** a variable's source timestamp is `origin + tick × tick_ms`, where `tick` is the
//! tick whose image holds the value and `origin` the server's start time: a client can tell the
//! tick of every value it receives (the `Tick` variable gives the origin), and a test can check
//! it against the recorded trace.

use std::sync::Arc;
use std::time::Duration;

use crate::node_manager::OwnManager;
use opcua::nodes::{BaseEventType, Event};
use opcua::server::SubscriptionCache;
use opcua::types::{ByteString, DataValue, DateTime, NodeId, NumericRange, StatusCode, Variant};

use crate::handoff::Frame;
use crate::signals::SignalNode;
use crate::space::TICK;
use crate::values::Evaluator;
use crate::variables::{Field, Layout};

/// Frames published between two yields to the stack's tasks.
const YIELD_EVERY: u32 = 8;

/// OPC UA time ticks (100 ns) per ms.
const TICKS_PER_MS: i64 = 10_000;

/// The variables of each image byte, to set when that byte changes.
pub struct Nodes {
    /// Per packet byte: (node, bit) — `None` for a byte variable.
    by_byte: Vec<Vec<(NodeId, Option<u8>)>>,
    tick: NodeId,
    /// The PLC variables: node, what it shows, offset in the frame's variable bytes.
    vars: Vec<(NodeId, Field, usize)>,
}

impl Nodes {
    /// Indexes `table` (namespace `ns`) by image byte, and the PLC variables of `layout`.
    pub fn new(ns: u16, table: &[SignalNode], layout: &Layout) -> Nodes {
        let mut by_byte = vec![Vec::new(); packets::PACKETS_LEN];
        for n in table {
            if let Some(slot) = by_byte.get_mut(n.signal.image_byte()) {
                slot.push((NodeId::new(ns, n.id.as_str()), n.signal.bit()));
            }
        }
        Nodes {
            by_byte,
            tick: NodeId::new(ns, TICK),
            vars: layout
                .vars
                .iter()
                .map(|v| (NodeId::new(ns, v.id.as_str()), v.ty, v.at))
                .collect(),
        }
    }
}

/// The PLC variables whose bytes changed between two frames (every one without `prev`), as data
/// values; once the layout is stale, `BadOutOfService` for every variable (once).
fn var_changes<'a>(
    nodes: &'a Nodes,
    prev: Option<&Frame>,
    frame: &Frame,
    time: DateTime,
    server: DateTime,
) -> Vec<(&'a NodeId, Option<&'a NumericRange>, DataValue)> {
    let mut out = Vec::new();
    let was_valid = prev.is_none_or(|p| p.vars_valid);
    for (id, ty, at) in &nodes.vars {
        let bytes = |f: &Frame| f.vars.get(*at..*at + ty.size()).map(<[u8]>::to_vec);
        if !frame.vars_valid {
            if was_valid {
                let mut dv = stamped(Variant::Empty, time, server);
                dv.status = Some(StatusCode::BadOutOfService);
                out.push((id, None, dv));
            }
            continue;
        }
        if prev.is_some_and(|p| bytes(p) == bytes(frame)) {
            continue;
        }
        let now = bytes(frame).unwrap_or_default();
        out.push((id, None, stamped(ty.decode(&now), time, server)));
    }
    out
}

/// A value stamped with its tick's time (source) and the scan's copy (server). No picoseconds:
/// the timestamps are whole µs, and asyncua 2.1 misreads a server timestamp that follows source
/// picoseconds (it read 9999-12-31).
pub fn stamped(v: Variant, source: DateTime, server: DateTime) -> DataValue {
    DataValue {
        value: Some(v),
        status: Some(StatusCode::Good),
        source_timestamp: Some(source),
        source_picoseconds: None,
        server_timestamp: Some(server),
        server_picoseconds: None,
    }
}

/// The OPC UA time of `us` µs since the Unix epoch.
pub fn unix_time(us: i64) -> DateTime {
    // 1601-01-01 to 1970-01-01 in 100 ns ticks.
    const UNIX_EPOCH_TICKS: i64 = 116_444_736_000_000_000;
    DateTime::from(UNIX_EPOCH_TICKS.saturating_add(us.saturating_mul(10)))
}

/// What changed between two images, as data values stamped with `time` (the tick's) and `server`.
pub fn changes<'a>(
    nodes: &'a Nodes,
    prev: Option<&[u8]>,
    frame: &Frame,
    time: DateTime,
    server: DateTime,
) -> Vec<(&'a NodeId, Option<&'a NumericRange>, DataValue)> {
    let mut out = Vec::new();
    for (at, slot) in nodes.by_byte.iter().enumerate() {
        let now = frame.image.get(at).copied().unwrap_or(0);
        let before = prev.and_then(|p| p.get(at).copied());
        if before == Some(now) {
            continue;
        }
        for (id, bit) in slot {
            let v = match bit {
                Some(b) => {
                    let old = before.map(|x| (x >> b) & 1);
                    let new = (now >> b) & 1;
                    if old == Some(new) {
                        continue;
                    }
                    Variant::Boolean(new != 0)
                }
                None => Variant::Byte(now),
            };
            out.push((id, None, stamped(v, time, server)));
        }
    }
    out.push((
        &nodes.tick,
        None,
        stamped(Variant::UInt64(frame.tick), time, server),
    ));
    out
}

/// The source time of `tick`.
pub fn tick_time(origin: i64, tick: u64, tick_ms: u32) -> DateTime {
    let ms = i64::try_from(tick)
        .unwrap_or(i64::MAX / TICKS_PER_MS)
        .saturating_mul(i64::from(tick_ms));
    DateTime::from(origin.saturating_add(ms.saturating_mul(TICKS_PER_MS)))
}

/// What the publisher task owns.
pub struct Publisher {
    /// The node manager of the server's namespace.
    pub nm: Arc<OwnManager>,
    /// The stack's subscriptions.
    pub subs: Arc<SubscriptionCache>,
    /// The signal nodes by image byte.
    pub nodes: Nodes,
    /// The Machine Tools values.
    pub model: Evaluator,
    /// The `Messages` object (source of the alarm events) and the event type.
    pub messages: (NodeId, NodeId),
    /// The server's half of the hand-over.
    pub side: crate::handoff::ServerSide,
    /// The logic tick.
    pub tick_ms: u32,
    /// The source time of tick 0 (OPC UA ticks).
    pub origin: i64,
}

/// Runs until cancelled: ten times a tick ([`crate::limits::poll_ms`]), publishes the alarms and every frame's changes in tick
/// order (one `set_values`, one lock of the address space, per frame).
pub async fn run(mut p: Publisher) {
    let mut every = tokio::time::interval(Duration::from_millis(crate::limits::poll_ms(p.tick_ms)));
    every.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Skip);
    let mut prev: Option<Box<Frame>> = None;
    let mut events = 0u64;
    let mut stages = crate::latency::Stages::default();
    loop {
        every.tick().await;
        while let Ok((raised, text, tick)) = p.side.alarms.try_recv() {
            events += 1;
            let time = tick_time(p.origin, tick, p.tick_ms);
            let message = if raised {
                text
            } else {
                format!("cleared: {text}")
            };
            let evt = BaseEventType::new(
                p.messages.1.clone(),
                ByteString::from(events.to_be_bytes().to_vec()),
                message.as_str(),
                time,
            )
            .set_source_node(p.messages.0.clone())
            .set_source_name("ncplc".into())
            .set_severity(if raised { 700 } else { 100 });
            p.subs
                .notify_events([(&evt as &dyn Event, &p.messages.0)].into_iter());
        }
        while let Ok(m) = p.side.messages.try_recv() {
            events += 1;
            notify_message(&p, &m, events);
        }
        let mut done = 0u32;
        while let Ok(frame) = p.side.frames.pop() {
            publish_frame(&mut p, &frame, prev.as_deref());
            stages.applied(frame.wall_us);
            // The frame is the next one's previous; the one before goes back to the pool.
            if let Some(old) = prev.replace(frame) {
                p.side.recycle(old);
            }
            // A scan in virtual time fills the ring as fast as the publisher empties it: let the
            // stack's tasks (the clients' requests) run between batches on the one worker.
            done += 1;
            if done.is_multiple_of(YIELD_EVERY) {
                tokio::task::yield_now().await;
            }
        }
    }
}

/// A PLC message as an event of `Messages` (docs/plc-messages.md): the message text (`cleared: `
/// before it when its bit fell), its severity (raised; 100 when cleared), the process's channel
/// as the source (`SourceName` `process n`), stamped with the time of its tick.
fn notify_message(p: &Publisher, m: &crate::handoff::MessageNote, n: u64) {
    let time = tick_time(p.origin, m.tick, p.tick_ms);
    let message = if m.raised {
        m.text.clone()
    } else {
        format!("cleared: {}", m.text)
    };
    let channel = NodeId::new(
        p.messages.0.namespace,
        format!("MachineTool/Monitoring/Channel{}", m.process),
    );
    let evt = BaseEventType::new(
        p.messages.1.clone(),
        ByteString::from(n.to_be_bytes().to_vec()),
        message.as_str(),
        time,
    )
    .set_source_node(channel)
    .set_source_name(format!("process {}", m.process).into())
    .set_severity(if m.raised { m.severity } else { 100 });
    p.subs
        .notify_events([(&evt as &dyn Event, &p.messages.0)].into_iter());
}

/// Sets the values `frame` changed against `before`, the frame published last.
fn publish_frame(p: &mut Publisher, frame: &Frame, before: Option<&Frame>) {
    {
        let time = tick_time(p.origin, frame.tick, p.tick_ms);
        let server = unix_time(frame.wall_us);
        let mut values = changes(&p.nodes, before.map(|f| &f.image[..]), frame, time, server);
        values.extend(var_changes(&p.nodes, before, frame, time, server));
        let model = p.model.changes(frame);
        values.extend(
            model
                .iter()
                .map(|(id, v)| (id, None, stamped(v.clone(), time, server))),
        );
        // A failure names a node that is not there: the table and the space are built from the
        // same lists, so there is nothing to recover.
        let _ = p.nm.set_values(&p.subs, values.into_iter());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::signals::{Origin, SignalNode};

    fn node(id: &str, signal: &str) -> SignalNode {
        SignalNode {
            id: id.into(),
            name: id.into(),
            signal: signal.parse().expect("signal"),
            meaning: String::new(),
            origin: Origin::Interface,
            writable: false,
        }
    }

    #[test]
    fn only_changed_bytes_and_bits_are_set_with_the_tick_s_time() {
        let table = vec![
            node("W3K0", "W3K0"),
            node("MFIN", "U11K0"),
            node("SFIN", "U11K1"),
        ];
        let nodes = Nodes::new(2, &table, &Layout::default());
        let mut image = vec![0u8; packets::PACKETS_LEN];
        let frame = |image: &[u8], tick| {
            let mut f = Frame {
                tick,
                image: [0; packets::PACKETS_LEN],
                wall_us: 0,
                kernel: Default::default(),
                vars: [0; crate::variables::VARS_MAX],
                vars_valid: true,
            };
            f.image.copy_from_slice(image);
            f
        };
        let t = tick_time(0, 7, 10);
        assert_eq!(t.checked_ticks(), 7 * 10 * 10_000);
        let s = unix_time(0);
        let first = changes(&nodes, None, &frame(&image, 7), t, s);
        // No previous image: every node, then Tick.
        assert_eq!(first.len(), 4);
        let prev = image.clone();
        let k11 = packets::Packet::K.offset() + 44;
        image[k11] = 0b10; // SFIN rises, MFIN stays 0
        let next = changes(&nodes, Some(&prev), &frame(&image, 8), t, s);
        let ids: Vec<String> = next.iter().map(|(id, _, _)| id.to_string()).collect();
        assert_eq!(ids, ["ns=2;s=SFIN", "ns=2;s=Signals/Tick"]);
        assert_eq!(next[0].2.value, Some(Variant::Boolean(true)));
        assert_eq!(next[0].2.source_timestamp, Some(t));
        assert_eq!(next[1].2.value, Some(Variant::UInt64(8)));
    }

    #[test]
    fn unix_time_is_the_opc_ua_epoch_shifted() {
        // 2026-01-01T00:00:00Z = 1767225600 s since the Unix epoch.
        let t = unix_time(1_767_225_600_000_000);
        assert_eq!(t.to_rfc3339(), "2026-01-01T00:00:00.000Z");
        let now = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| i64::try_from(d.as_micros()).unwrap_or(i64::MAX));
        let secs = now / 1_000_000;
        let back = unix_time(now).as_chrono().timestamp();
        assert_eq!(back, secs);
    }
}
