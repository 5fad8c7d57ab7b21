//! Decodes a read IOCFIL into [`Iocfil`], checking every rule that needs no other file.

use std::collections::BTreeSet;

use diag::{Diagnostic, Sink};

use crate::pgcfil::fields::Emit;
use crate::pgcfil::structure::{Blocks, not_allowed};
use crate::reader::{ParsedFile, Record, Section};

use super::equipment::section3;
use super::model::{ConnectorGroup, IoProcess, Iocfil, MFlags, MFunction, Sequencing, TRecord};

const S1: &str = "ALM, IN0 ... IN3, OU0 ... OU3, CLO, SPL";
const S2: &str = "PRO, M00 ... M99, GPS";
const S4: &str = "T01 ... T64";

/// Packet-A connectors of input modules.
pub const INPUT_CONNECTORS: [u16; 16] = [0, 1, 2, 3, 8, 9, 10, 11, 16, 17, 18, 19, 24, 25, 26, 27];
/// Packet-A connectors of output modules.
pub const OUTPUT_CONNECTORS: [u16; 16] =
    [4, 5, 6, 7, 12, 13, 14, 15, 20, 21, 22, 23, 28, 29, 30, 31];

/// Decodes `file` (read by [`crate::reader::read`]) into an [`Iocfil`] and the diagnostics of every
/// rule that needs no other file; cross-file rules are in [`super::check_against`].
pub fn parse(file: &ParsedFile) -> (Iocfil, Vec<Diagnostic>) {
    let mut diags = Sink::unbounded();
    let io = parse_into(file, &mut diags);
    (io, diags.into_vec())
}

/// [`parse`] pushing the diagnostics into `diags` (a sink that may store only the first of them).
pub fn parse_into(file: &ParsedFile, diags: &mut Sink) -> Iocfil {
    let mut e = Emit::new(file, diags);
    e.diags
        .extend(crate::reader::check_section_count(file, 4, 4));
    let mut io = Iocfil::default();
    let mut done = BTreeSet::new();
    let mut clo_seen = false;
    for section in &file.sections {
        if !(1..=4).contains(&section.number) || !done.insert(section.number) {
            continue;
        }
        e.section = section.number;
        e.process = None;
        match section.number {
            1 => clo_seen = section1(&mut e, section, &mut io),
            2 | 3 => per_process(&mut e, section, &mut io),
            _ => section4(&mut e, section, &mut io),
        }
    }
    if !clo_seen {
        let section = file.section(1);
        e.section = 1;
        e.process = None;
        let span = section.map_or_else(|| file.end_span(), |s| s.span.clone());
        e.error(
            116,
            span,
            "CLO is missing: the PLC scan timing is not declared",
            "write CLO=tick_logic,time_slow in section *1, e.g. CLO=10,2",
        );
    }
    io.processes.sort_by_key(|p| p.number);
    io
}

/// The number after `prefix` in `key` when it is 1–2 digits within `range`.
pub(crate) fn indexed(
    key: &str,
    prefix: &str,
    range: std::ops::RangeInclusive<u32>,
) -> Option<u32> {
    let digits = key.strip_prefix(prefix)?;
    if digits.is_empty() || digits.len() > 2 || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok().filter(|n| range.contains(n))
}

/// Section 1; returns whether CLO was written.
fn section1(e: &mut Emit<'_>, section: &Section, io: &mut Iocfil) -> bool {
    let mut keys = BTreeSet::new();
    let mut ins: Vec<u16> = Vec::new();
    let mut outs: Vec<u16> = Vec::new();
    let mut clo = false;
    for rec in &section.records {
        let input = indexed(&rec.key, "IN", 0..=3);
        let output = indexed(&rec.key, "OU", 0..=3);
        if !matches!(rec.key.as_str(), "ALM" | "CLO" | "SPL") && input.is_none() && output.is_none()
        {
            not_allowed(e, rec, S1);
            continue;
        }
        if !keys.insert(rec.key.clone()) {
            e.error(
                101,
                rec.key_span.clone(),
                format!("instruction {} is duplicated", rec.key),
                "write each instruction once",
            );
            continue;
        }
        let p = &rec.params;
        match rec.key.as_str() {
            "ALM" => {
                if e.count(rec, 1, 1) {
                    io.alm = Some(e.hex(&p[0], 4).unwrap_or(0));
                }
            }
            "SPL" => {
                if e.count(rec, 1, 1) {
                    match e.word(&p[0]) {
                        Some(n) if n > 5000 => e.error(
                            107,
                            p[0].span.clone(),
                            format!("SPL={n} is above 5000"),
                            "at most 5000 symbolic names (13 bytes each); default 1",
                        ),
                        n => io.spl = n,
                    }
                }
            }
            "CLO" => {
                clo = true;
                clo_record(e, rec, io);
            }
            _ => {
                if !e.count(rec, 8, 8) {
                    continue;
                }
                let is_input = input.is_some();
                let index = input.or(output).unwrap_or(0) as u8;
                let mut group = ConnectorGroup {
                    index,
                    connectors: Vec::new(),
                };
                for par in p {
                    let Some(c) = e.word(par) else { continue };
                    let c = c as u16;
                    let kind = if is_input { "input" } else { "output" };
                    let bad = if is_input {
                        if outs.contains(&c) {
                            Some((
                                109,
                                format!("input connector {c} is already declared in OUx"),
                                "a connector is either an input (INx) or an output (OUx)",
                            ))
                        } else if ins.contains(&c) {
                            Some((
                                108,
                                format!("input connector {c} is already declared in INx"),
                                "declare each connector once",
                            ))
                        } else {
                            None
                        }
                    } else if outs.contains(&c) {
                        Some((
                            110,
                            format!("output connector {c} is already declared in OUx"),
                            "declare each connector once",
                        ))
                    } else if ins.contains(&c) {
                        Some((
                            111,
                            format!("connector {c} declared in INx is declared in OUx"),
                            "a connector is either an input (INx) or an output (OUx)",
                        ))
                    } else {
                        None
                    };
                    let set = if is_input {
                        &INPUT_CONNECTORS
                    } else {
                        &OUTPUT_CONNECTORS
                    };
                    if let Some((code, msg, hint)) = bad {
                        e.error(code, par.span.clone(), msg, hint);
                    } else if !set.contains(&c) {
                        let hint = if is_input {
                            "input connectors of packet A are 0-3, 8-11, 16-19, 24-27"
                        } else {
                            "output connectors of packet A are 4-7, 12-15, 20-23, 28-31"
                        };
                        e.error(
                            107,
                            par.span.clone(),
                            format!("{c} is not a packet-A {kind} connector"),
                            hint,
                        );
                    } else {
                        group.connectors.push(c);
                        if is_input { ins.push(c) } else { outs.push(c) }
                    }
                }
                if is_input {
                    io.inputs.push(group)
                } else {
                    io.outputs.push(group)
                }
            }
        }
    }
    clo
}

fn clo_record(e: &mut Emit<'_>, rec: &Record, io: &mut Iocfil) {
    if !e.count(rec, 2, 2) {
        return;
    }
    let p = &rec.params;
    let tick = e.word(&p[0]);
    let slow = e.word(&p[1]);
    match tick {
        Some(t @ 1..=255) => io.tick_logic_ms = t,
        Some(t) => e.error(
            103,
            p[0].span.clone(),
            format!("logic tick {t} ms is 0 or above 255"),
            "tick_logic is 1 ... 255 ms and a multiple of the CPU tick (AXCFIL TIM)",
        ),
        None if p[0].is_empty() => e.error(
            103,
            p[0].span.clone(),
            "logic tick is missing",
            "tick_logic is 1 ... 255 ms and a multiple of the CPU tick (AXCFIL TIM)",
        ),
        None => {}
    }
    match slow {
        Some(s) if io.tick_logic_ms != 0 && s * 2 > io.tick_logic_ms => {
            e.error(
                106,
                p[1].span.clone(),
                format!(
                    "slow-logic time {s} ms is more than half the logic tick {} ms",
                    io.tick_logic_ms
                ),
                &format!(
                    "time_slow is at most {} ms and at least the CPU tick",
                    io.tick_logic_ms / 2
                ),
            );
        }
        Some(s) => io.time_slow_ms = s,
        None if p[1].is_empty() => e.error(
            106,
            p[1].span.clone(),
            "slow-logic time is missing",
            "time_slow is at most half of tick_logic and at least the CPU tick",
        ),
        None => {}
    }
}

/// The process with `n`, created when first seen.
fn process_mut(io: &mut Iocfil, n: u32) -> &mut IoProcess {
    let i = match io.processes.iter().position(|p| p.number == n) {
        Some(i) => i,
        None => {
            io.processes.push(IoProcess {
                number: n,
                ..IoProcess::default()
            });
            io.processes.len() - 1
        }
    };
    &mut io.processes[i]
}

fn per_process(e: &mut Emit<'_>, section: &Section, io: &mut Iocfil) {
    let mut blocks = Blocks::default();
    let mut scratch = IoProcess::default();
    for rec in &section.records {
        if rec.key == "PRO" {
            blocks.open(e, rec);
            continue;
        }
        let proc = match blocks.record(e) {
            Some(n) => process_mut(io, n),
            None => &mut scratch,
        };
        if section.number == 2 {
            section2(e, &mut blocks, rec, proc);
        } else {
            section3(e, &mut blocks, rec, proc);
        }
    }
}

fn section2(e: &mut Emit<'_>, blocks: &mut Blocks, rec: &Record, proc: &mut IoProcess) {
    if rec.key == "GPS" {
        if blocks.first_time(e, rec) && e.count(rec, 1, 1) {
            match e.hex(&rec.params[0], 2) {
                Some(0) => proc.gps = Some(Sequencing::Sequential),
                Some(1) => proc.gps = Some(Sequencing::Parallel),
                Some(v) => e.error(
                    130,
                    rec.params[0].span.clone(),
                    format!("GPS={v:X} is neither 0 nor 1"),
                    "0 = sequential S, T, M (default); 1 = parallel",
                ),
                None => {}
            }
        }
        return;
    }
    let Some(number) = indexed(&rec.key, "M", 0..=99) else {
        return not_allowed(e, rec, S2);
    };
    let number = number as u8;
    if proc.m_function(number).is_some() {
        return e.error(
            101,
            rec.key_span.clone(),
            format!("M{number:02} is declared twice"),
            "declare each M function once per process",
        );
    }
    if !e.count(rec, 3, 3) {
        return;
    }
    let p = &rec.params;
    let m_type = e.hex(&p[0], 2);
    let m_request = e.hex(&p[1], 2);
    let class = e.hex(&p[2], 2);
    let Some(m_type) = m_type.map(|v| v as u8) else {
        if p[0].is_empty() {
            e.error(113, p[0].span.clone(), format!("M{number:02} has no m_type"), "m_type is a non-zero sum of 01 before motion, 02 after motion, 04 in STOP, 08 hidden, 10 immediate, 40 modal, 80 shown after reset");
        }
        return;
    };
    if m_type == 0 {
        return e.error(113, p[0].span.clone(), format!("m_type of M{number:02} is 0"), "m_type is a non-zero sum of 01 before motion, 02 after motion, 04 in STOP, 08 hidden, 10 immediate, 40 modal, 80 shown after reset");
    }
    let m_request = m_request.unwrap_or(0) as u8;
    if m_request & 0x30 != 0 && m_request & 0x04 == 0 {
        e.error(962, p[1].span.clone(), format!("M{number:02} requests a tool-offset change or a reset (m_request {m_request:02X}) without blocking the calculation"), &format!("add 04: m_request {:02X}", m_request | 0x04));
    }
    let class = class.unwrap_or(0) as u8;
    proc.m_functions.push(MFunction {
        number,
        m_type,
        m_request,
        class,
        flags: MFlags::decode(m_type, m_request),
    });
}

fn section4(e: &mut Emit<'_>, section: &Section, io: &mut Iocfil) {
    for rec in &section.records {
        let Some(n) = indexed(&rec.key, "T", 1..=64) else {
            not_allowed(e, rec, S4);
            continue;
        };
        let record = n as u8;
        if io.t_records.iter().any(|t| t.record == record) {
            e.error(
                101,
                rec.key_span.clone(),
                format!("T{record:02} is written twice"),
                "write each packet-T byte once",
            );
            continue;
        }
        if !e.count(rec, 1, 1) {
            continue;
        }
        match e.hex(&rec.params[0], 2) {
            Some(v) => io.t_records.push(TRecord {
                record,
                value: v as u8,
            }),
            None if rec.params[0].is_empty() => e.error(
                10,
                rec.params[0].span.clone(),
                format!("T{record:02} has no value"),
                "write a hexadecimal byte 00 ... FF",
            ),
            None => {}
        }
    }
}
