//! Hover: what the thing under the cursor is. A signal: its interface-map name and meaning,
//! direction, packet/connector/bit, width, the IOCFIL line of its connector, who writes it (and
//! where this program does); a name: its `DEF` and type, a timer's or counter's preset and tick
//! base; a keyword, type or function: its one-line syntax from the language reference.

use std::fmt::Write;

use compiler::interface_map::{Direction, InterfaceSignal, Width};
use packets::Packet;

use crate::analysis::Analysis;
use crate::index::{Addr, DefKind, Ref, Use};
use crate::keywords;
use crate::machine::Machine;
use crate::text::Text;

/// The Markdown hover at byte `offset` of the document, with the span it is about.
pub fn hover(
    a: &Analysis,
    machine: &Machine,
    text: &Text,
    offset: usize,
) -> Option<(String, std::ops::Range<usize>)> {
    let src = text.as_str();
    if let Some(r) = a.index.at(a.from_doc(offset)) {
        let span = a.to_doc(&r.span);
        let spelled = src.get(span.clone()).unwrap_or("");
        let md = place(a, machine, text, r, spelled);
        return Some((md.trim_end().to_string(), span));
    }
    let span = word_at(src, offset)?;
    let word = src.get(span.clone())?;
    keywords::describe(word).map(|d| (format!("**{}**: {d}", word.to_ascii_uppercase()), span))
}

/// The identifier-like word around `offset`.
pub fn word_at(src: &str, offset: usize) -> Option<std::ops::Range<usize>> {
    let b = src.as_bytes();
    let is_word = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    let offset = offset.min(b.len());
    let mut s = offset;
    while s > 0 && is_word(b[s - 1]) {
        s -= 1;
    }
    let mut e = offset;
    while e < b.len() && is_word(b[e]) {
        e += 1;
    }
    (e > s).then_some(s..e)
}

fn place(a: &Analysis, machine: &Machine, text: &Text, r: &Ref, spelled: &str) -> String {
    let mut out = String::new();
    if let Some(name) = &r.name {
        if let Some(d) = a.index.def(name) {
            let def_text = text
                .as_str()
                .get(a.to_doc(&d.span))
                .unwrap_or("")
                .lines()
                .next()
                .unwrap_or("");
            let line = text.position(a.to_doc(&d.span).start).line + 1;
            let _ = writeln!(out, "```plc\n{}\n```", def_text.trim());
            let _ = write!(out, "`{name}`: defined at line {line}");
            match &d.kind {
                DefKind::Alias(_) => out.push_str(", a name for the signal below\n\n"),
                DefKind::Var { ty, preset, at } => {
                    let _ = writeln!(out, ", type {ty}");
                    out.push('\n');
                    describe_var(&mut out, ty, preset.as_deref(), machine);
                    if let Some(s) = at {
                        let _ = writeln!(
                            out,
                            "A typed view of the bytes from `{}` upwards.\n",
                            crate::index::signal_text(s)
                        );
                    }
                }
            }
        } else if machine.ctx.interface.get(name).is_none() {
            let _ = write!(
                out,
                "`{name}`: not defined (no `DEF` and not in the interface map)"
            );
            return out;
        }
    }
    if let Some(addr) = r.addr {
        signal(
            &mut out,
            a,
            machine,
            text,
            addr,
            r.name.is_none().then_some(spelled),
        );
    }
    if out.is_empty() {
        let _ = write!(out, "`{spelled}`");
    }
    out
}

fn describe_var(out: &mut String, ty: &str, preset: Option<&str>, machine: &Machine) {
    let tick = machine.ctx.tick_ms.max(1);
    match ty {
        "TON" | "TOF" | "TP" => {
            let what = match ty {
                "TON" => "on-delay timer",
                "TOF" => "off-delay timer",
                _ => "pulse timer",
            };
            let _ = write!(out, "{ty} {what}");
            if let Some(p) = preset {
                let _ = write!(out, ", preset {p}");
                if let Some(ms) = p.strip_suffix(" ms").and_then(|v| v.parse::<f64>().ok()) {
                    let ticks = (ms / f64::from(tick)).ceil();
                    let _ = write!(
                        out,
                        " = {ticks} ticks of the {tick} ms logic tick (IOCFIL `CLO` tick_logic; the preset is rounded up to whole ticks)"
                    );
                }
            }
            out.push_str(". Reads: `t` / `t.Q`, `t.ET` (ms).\n\n");
        }
        "CTU" | "CTD" => {
            let what = if ty == "CTU" {
                "up counter"
            } else {
                "down counter"
            };
            let _ = write!(out, "{ty} {what}");
            if let Some(p) = preset {
                let _ = write!(out, ", preset {p} (counts rising edges, one per execution)");
            }
            out.push_str(". Reads: `c` / `c.Q`, `c.CV`.\n\n");
        }
        _ => {
            if let Some(d) = keywords::describe(ty) {
                let _ = writeln!(out, "{d}\n");
            }
        }
    }
}

/// The interface-map entries that cover `addr`.
pub fn entries(machine: &Machine, addr: Addr) -> Vec<&InterfaceSignal> {
    machine
        .ctx
        .interface
        .iter()
        .filter(|e| match (addr, Addr::of_signal(&e.signal)) {
            (Addr::Bit(..), b @ Addr::Bit(..)) => b == addr,
            (Addr::Byte(p, c, i), Addr::Byte(p2, c2, i2)) => {
                p == p2 && c == c2 && i >= i2 && i < i2 + u32::from(e.width.bytes().max(1))
            }
            _ => false,
        })
        .collect()
}

fn signal(
    out: &mut String,
    a: &Analysis,
    machine: &Machine,
    text: &Text,
    addr: Addr,
    spelled: Option<&str>,
) {
    let (packet, c, n, bit) = match addr {
        Addr::Bit(p, c, n) => (p, c, n, true),
        Addr::Byte(p, c, n) => (p, c, n, false),
        Addr::Pulse(n) => {
            let _ = write!(
                out,
                "**P{n}**: one-shot, 1 only in the scan in which its input went from 0 to 1 (§4)"
            );
            writes(out, a, text, addr);
            return;
        }
    };
    if let Some(s) = spelled {
        let _ = writeln!(out, "**{}**\n", s.to_ascii_uppercase());
    }
    for e in entries(machine, addr) {
        let dir = match e.dir {
            Direction::CncToPlc => "in (CNC → PLC)",
            Direction::PlcToCnc => "out (PLC → CNC)",
        };
        let width = match e.width {
            Width::Bit => "bit",
            Width::Byte => "byte",
            Width::Word => "word (2 bytes, little-endian)",
            Width::Dword => "dword (4 bytes, little-endian)",
        };
        let _ = writeln!(
            out,
            "Interface map: **{}** ({}) — {}; width {width}, direction {dir}, process {}\n",
            e.name, e.signal, e.meaning, e.process
        );
    }
    let pos = if bit {
        format!("bit {n}")
    } else {
        format!("byte {n} (contacts {}..{})", 8 * n, 8 * n + 7)
    };
    let _ = writeln!(
        out,
        "Packet {}, connector {c}, {pos}; width {}\n",
        packet.letter(),
        if bit { "bit" } else { "byte" }
    );
    let who = match packet {
        Packet::A => {
            let input = c % 8 < 4;
            let decl = u16::try_from(c).ok().and_then(|c| machine.iocfil_line(c));
            let side = if input { "input" } else { "output" };
            match (decl, machine.dir.is_some()) {
                (Some((line, l)), _) => {
                    let _ = writeln!(
                        out,
                        "IOCFIL line {line} `{l}` declares {side} connector {c}\n"
                    );
                }
                (None, true) => {
                    let _ = writeln!(
                        out,
                        "Connector {c} is not declared in IOCFIL (`IN`/`OU` lines)\n"
                    );
                }
                (None, false) => {}
            }
            if input {
                "written by the I/O (a physical input), read by the PLC"
            } else {
                "written by the PLC, driven to a physical output by the I/O"
            }
        }
        Packet::K | Packet::N if c < 10 => "written by the CNC, read by the PLC",
        Packet::K | Packet::N if c < 100 => "written by the PLC, read by the CNC",
        Packet::K | Packet::N => "free for the integrator: written and read by the PLC",
        _ => "set by IOCFIL section 4 (`Txx=`) at start; read and possibly written by the PLC",
    };
    let _ = write!(out, "Who writes it: {who}.");
    writes(out, a, text, addr);
}

/// "Written in this file at lines …".
fn writes(out: &mut String, a: &Analysis, text: &Text, addr: Addr) {
    let lines: Vec<String> = a
        .index
        .refs
        .iter()
        .filter(|r| r.usage == Use::Write && r.addr == Some(addr))
        .map(|r| (text.position(a.to_doc(&r.span).start).line + 1).to_string())
        .collect();
    if lines.is_empty() {
        out.push_str(" This program does not write it.");
    } else {
        let _ = write!(out, " This program writes it at line {}.", lines.join(", "));
    }
}
