//! The JSON Lines trace form.
//!
//! ```text
//! {"format":"ncplc-trace","version":1,"tick_ms":10}
//! {"t":0,"in":{"I0A5":1,"W3K0":145},"out":{"U4A0":1}}
//! ```
//! Empty `in`/`out` objects are left out when writing and accepted when reading. A tick where an
//! HMI force overrode the logic's result also has `"forced":{"U4A0":1}` (written after the scan).

use std::io::Write;

use packets::Signal;
use serde_json::Value;

use super::{
    AxisId, AxisValue, PartHeader, SignalValue, TickRecord, Trace, TraceError, TraceSink, VERSION,
};

/// Streams records as JSON Lines.
pub struct TextWriter<W: Write> {
    out: W,
    line: String,
}

impl<W: Write> TextWriter<W> {
    /// Writes the header line.
    pub fn new(out: W, tick_ms: u32) -> Result<Self, TraceError> {
        Self::with_part(out, tick_ms, None)
    }

    /// Writes the header line, with the `part` object of a part run.
    pub fn with_part(
        mut out: W,
        tick_ms: u32,
        part: Option<&PartHeader>,
    ) -> Result<Self, TraceError> {
        write!(
            out,
            "{{\"format\":\"ncplc-trace\",\"version\":{VERSION},\"tick_ms\":{tick_ms}"
        )?;
        if let Some(p) = part {
            let json = serde_json::to_string(p).map_err(|e| TraceError::Text {
                line: 1,
                message: e.to_string(),
            })?;
            write!(out, ",\"part\":{json}")?;
        }
        writeln!(out, "}}")?;
        Ok(TextWriter {
            out,
            line: String::new(),
        })
    }

    /// The underlying writer (the durable recorder stages each line in a buffer).
    pub fn get_mut(&mut self) -> &mut W {
        &mut self.out
    }
}

/// Formats one record as a line (without the newline).
pub fn format_record(r: &TickRecord, line: &mut String) {
    use std::fmt::Write as _;
    line.clear();
    let _ = write!(line, "{{\"t\":{}", r.t);
    for (key, list) in [
        ("in", &r.inputs),
        ("out", &r.outputs),
        ("forced", &r.forced),
    ] {
        if list.is_empty() {
            continue;
        }
        let _ = write!(line, ",\"{key}\":{{");
        for (i, (s, v)) in list.iter().enumerate() {
            let sep = if i == 0 { "" } else { "," };
            let _ = write!(line, "{sep}\"{s}\":{v}");
        }
        line.push('}');
    }
    if !r.commands.is_empty()
        && let Ok(json) = serde_json::to_string(&r.commands)
    {
        line.push_str(",\"cmd\":");
        line.push_str(&json);
    }
    if !r.drives.is_empty()
        && let Ok(json) = serde_json::to_string(&r.drives)
    {
        line.push_str(",\"drives\":");
        line.push_str(&json);
    }
    if !r.nodes_lost.is_empty()
        && let Ok(json) = serde_json::to_string(&r.nodes_lost)
    {
        line.push_str(",\"nodes_lost\":");
        line.push_str(&json);
    }
    if !r.positions.is_empty() {
        line.push_str(",\"pos\":{");
        for (i, (a, bits)) in r.positions.iter().enumerate() {
            let sep = if i == 0 { "" } else { "," };
            let _ = write!(line, "{sep}\"{a}\":\"{bits:016x}\"");
        }
        line.push('}');
    }
    line.push('}');
}

impl<W: Write> TraceSink for TextWriter<W> {
    fn record(&mut self, rec: &TickRecord) -> Result<(), TraceError> {
        format_record(rec, &mut self.line);
        self.line.push('\n');
        self.out.write_all(self.line.as_bytes())?;
        Ok(())
    }

    fn flush(&mut self) -> Result<(), TraceError> {
        self.out.flush()?;
        Ok(())
    }
}

impl<W: Write> TextWriter<W> {
    /// Writes one record (same as the [`TraceSink`] method, usable without the trait object).
    pub fn record(&mut self, rec: &TickRecord) -> Result<(), TraceError> {
        TraceSink::record(self, rec)
    }
}

/// The order signals have inside a record: by image byte, bits before the byte, then by bit.
pub fn canonical_key(s: &Signal) -> (usize, u8, Signal) {
    (s.image_byte(), s.bit().unwrap_or(8), *s)
}

/// Parses a whole text trace.
pub fn parse(bytes: &[u8]) -> Result<Trace, TraceError> {
    crate::reader::Reader::with_form(bytes, Some(true))?.collect_trace()
}

/// A located error of text line `n` (0-based).
fn err(n: usize, message: String) -> TraceError {
    TraceError::Text {
        line: n + 1,
        message,
    }
}

/// Reads the header line (line `n`, 0-based): the tick and the part-run header.
pub(crate) fn parse_header(n: usize, line: &str) -> Result<(u32, Option<PartHeader>), TraceError> {
    let header: Value = serde_json::from_str(line).map_err(|e| err(n, e.to_string()))?;
    if header.get("format").and_then(Value::as_str) != Some("ncplc-trace") {
        return Err(err(
            n,
            "the first line must be {\"format\":\"ncplc-trace\",...}".into(),
        ));
    }
    let version = header.get("version").and_then(Value::as_u64);
    if version != Some(u64::from(VERSION)) {
        return Err(err(
            n,
            format!("unsupported trace version {version:?} (this ncplc reads version {VERSION})"),
        ));
    }
    let tick_ms = header
        .get("tick_ms")
        .and_then(Value::as_u64)
        .and_then(|v| u32::try_from(v).ok())
        .filter(|&v| v > 0)
        .ok_or_else(|| err(n, "the header needs a positive \"tick_ms\"".into()))?;
    let part = match header.get("part") {
        None => None,
        Some(v) => Some(
            serde_json::from_value::<PartHeader>(v.clone())
                .map_err(|e| err(n, format!("\"part\": {e}")))?,
        ),
    };
    Ok((tick_ms, part))
}

/// Reads the tick record of line `n` (0-based); `prev_t` is the previous record's tick.
pub(crate) fn parse_tick(
    n: usize,
    line: &str,
    prev_t: Option<u64>,
) -> Result<TickRecord, TraceError> {
    let v: Value = serde_json::from_str(line).map_err(|e| err(n, e.to_string()))?;
    let obj = v
        .as_object()
        .ok_or_else(|| err(n, "a tick line must be a JSON object".into()))?;
    let t = obj
        .get("t")
        .and_then(Value::as_u64)
        .ok_or_else(|| err(n, "missing tick number \"t\"".into()))?;
    if let Some(prev) = prev_t
        && prev >= t
    {
        return Err(err(n, format!("tick {t} does not follow tick {prev}")));
    }
    for key in obj.keys() {
        if !matches!(
            key.as_str(),
            "t" | "in" | "out" | "forced" | "pos" | "cmd" | "drives" | "nodes_lost"
        ) {
            return Err(err(
                n,
                format!(
                    "unknown key \"{key}\" (expected t, in, out, forced, pos, cmd, drives, nodes_lost)"
                ),
            ));
        }
    }
    Ok(TickRecord {
        t,
        inputs: parse_map(obj.get("in")).map_err(|m| err(n, m))?,
        outputs: parse_map(obj.get("out")).map_err(|m| err(n, m))?,
        forced: parse_map(obj.get("forced")).map_err(|m| err(n, m))?,
        positions: parse_positions(obj.get("pos")).map_err(|m| err(n, m))?,
        commands: json_list(obj, "cmd", n)?,
        drives: json_list(obj, "drives", n)?,
        nodes_lost: json_list(obj, "nodes_lost", n)?,
    })
}

/// The list under `key` of line `n`'s object (empty when absent).
fn json_list<T: serde::de::DeserializeOwned>(
    obj: &serde_json::Map<String, Value>,
    key: &str,
    n: usize,
) -> Result<Vec<T>, TraceError> {
    match obj.get(key) {
        None => Ok(Vec::new()),
        Some(v) => serde_json::from_value(v.clone()).map_err(|e| err(n, format!("\"{key}\": {e}"))),
    }
}

fn parse_map(v: Option<&Value>) -> Result<Vec<SignalValue>, String> {
    let Some(v) = v else { return Ok(Vec::new()) };
    let obj = v
        .as_object()
        .ok_or("\"in\", \"out\" and \"forced\" must be objects")?;
    let mut out = Vec::with_capacity(obj.len());
    for (name, value) in obj {
        let sig: Signal = name.parse().map_err(|e| format!("{e}"))?;
        let value = value
            .as_u64()
            .ok_or_else(|| format!("{name}: the value must be a number"))?;
        let max = if sig.bit().is_some() { 1 } else { 255 };
        if value > max {
            return Err(format!("{name}: value {value} is out of range (0..{max})"));
        }
        out.push((sig, value as u8));
    }
    // JSON objects are unordered: use the recorder's order (image byte, then bit).
    out.sort_by_key(|(s, _)| canonical_key(s));
    Ok(out)
}

/// Reads `"pos":{"1X":"<16 hex digits>"}`: axis positions as f64 bits.
fn parse_positions(v: Option<&Value>) -> Result<Vec<AxisValue>, String> {
    let Some(v) = v else { return Ok(Vec::new()) };
    let obj = v.as_object().ok_or("\"pos\" must be an object")?;
    let mut out = Vec::with_capacity(obj.len());
    for (name, value) in obj {
        let axis: AxisId = name.parse()?;
        let bits = value
            .as_str()
            .filter(|h| h.len() == 16)
            .and_then(|h| u64::from_str_radix(h, 16).ok())
            .ok_or_else(|| format!("{name}: a position is 16 hex digits (the bits of an f64)"))?;
        out.push((axis, bits));
    }
    out.sort_by_key(|(a, _)| *a);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sig(s: &str) -> Signal {
        s.parse().expect("signal")
    }

    #[test]
    fn round_trip_keeps_records() {
        let trace = Trace {
            part: None,
            tick_ms: 10,
            ticks: vec![
                TickRecord {
                    nodes_lost: Vec::new(),
                    commands: Vec::new(),
                    drives: Vec::new(),
                    t: 0,
                    inputs: vec![(sig("I0A5"), 1), (sig("W3K0"), 145)],
                    outputs: vec![(sig("U4A0"), 1)],
                    forced: vec![],
                    positions: Vec::new(),
                },
                TickRecord {
                    nodes_lost: Vec::new(),
                    commands: Vec::new(),
                    drives: Vec::new(),
                    t: 7,
                    inputs: vec![],
                    outputs: vec![(sig("U4A0"), 0)],
                    forced: vec![],
                    positions: Vec::new(),
                },
            ],
        };
        let mut buf = Vec::new();
        trace.write_text(&mut buf).expect("write");
        let text = String::from_utf8(buf.clone()).expect("utf8");
        assert_eq!(
            text,
            "{\"format\":\"ncplc-trace\",\"version\":1,\"tick_ms\":10}\n\
             {\"t\":0,\"in\":{\"I0A5\":1,\"W3K0\":145},\"out\":{\"U4A0\":1}}\n\
             {\"t\":7,\"out\":{\"U4A0\":0}}\n"
        );
        assert_eq!(parse(&buf).expect("parse"), trace);
    }

    #[test]
    fn bad_lines_name_the_line() {
        let e = parse(b"{\"format\":\"ncplc-trace\",\"version\":1,\"tick_ms\":10}\n{\"t\":1,\"in\":{\"I0A5\":2}}\n");
        assert_eq!(
            e.map_err(|e| e.to_string()).err().as_deref(),
            Some("line 2: I0A5: value 2 is out of range (0..1)")
        );
        let e = parse(b"{\"format\":\"ncplc-trace\",\"version\":2,\"tick_ms\":10}\n");
        assert!(e.is_err());
        let e = parse(
            b"{\"format\":\"ncplc-trace\",\"version\":1,\"tick_ms\":10}\n{\"t\":3}\n{\"t\":3}\n",
        );
        assert_eq!(
            e.map_err(|e| e.to_string()).err().as_deref(),
            Some("line 3: tick 3 does not follow tick 3")
        );
    }
}
