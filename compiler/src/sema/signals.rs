//! Signal names against the packet limits and the machine's IOCFIL (docs/plc-language.md §3.1).
//!
//! Limits: connector per packet (A 0..31, K/N 0..255, T 0..15), contact 0..31, `W` byte 0..3, `S`
//! byte below the packet size. In packet A only connectors declared in IOCFIL `INx`/`OUx` may be
//! used, `I` only on input connectors (`c mod 8 < 4`), `U` only on output connectors, and the
//! logic never writes an input. Writing a K/N bit spelled with `I` is legal (the same bit as `U`)
//! but draws a warning.

use diag::Diagnostic;
use packets::{Dir, Packet, Signal, is_a_input_connector};

use super::codes;
use crate::ast::Span;
use crate::context::MachineContext;
use crate::lexer::{RawSignal, SignalKind};

/// Whether a signal is read or written at the place it is checked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// Read in an expression, or named by a `DEF`.
    Read,
    /// Assigned.
    Write,
}

fn list(c: &[u16]) -> String {
    if c.is_empty() {
        return "none".to_string();
    }
    c.iter().map(u16::to_string).collect::<Vec<_>>().join(", ")
}

/// Checks `raw` (written at `span`) and returns the signal when it is usable; problems go to `diags`.
pub fn check_signal(
    raw: &RawSignal,
    span: &Span,
    access: Access,
    ctx: &MachineContext,
    file: &str,
    diags: &mut Vec<Diagnostic>,
) -> Option<Signal> {
    let packet = raw.packet;
    let max_conn = u32::from(packet.connectors()) - 1;
    let err = |code: u32, msg: String, hint: String| {
        Diagnostic::error(code, file, span.clone(), msg).with_hint(hint)
    };
    let signal = match raw.kind {
        SignalKind::S => {
            if raw.number as usize >= packet.len() {
                diags.push(err(
                    codes::BYTE_RANGE,
                    format!(
                        "byte {} is past the end of packet {}",
                        raw.number,
                        packet.letter()
                    ),
                    format!("S{} bytes are 0..{}", packet.letter(), packet.len() - 1),
                ));
                return None;
            }
            Signal::Byte {
                packet,
                connector: (raw.number / 4) as u16,
                index: (raw.number % 4) as u8,
            }
        }
        kind => {
            if raw.connector > max_conn {
                diags.push(err(
                    codes::CONNECTOR_RANGE,
                    format!(
                        "connector {} does not exist in packet {}",
                        raw.connector,
                        packet.letter()
                    ),
                    format!("packet {} has connectors 0..{max_conn}", packet.letter()),
                ));
                return None;
            }
            let connector = raw.connector as u16;
            match kind {
                SignalKind::W => {
                    if raw.number > 3 {
                        diags.push(err(
                            codes::BYTE_RANGE,
                            format!("byte {} does not exist in a connector", raw.number),
                            "a connector has bytes 0..3 (W<c><P>0 .. W<c><P>3)".to_string(),
                        ));
                        return None;
                    }
                    Signal::Byte {
                        packet,
                        connector,
                        index: raw.number as u8,
                    }
                }
                _ => {
                    if raw.number > 31 {
                        diags.push(err(
                            codes::CONTACT_RANGE,
                            format!("contact {} does not exist in a connector", raw.number),
                            "contacts are 0..31".to_string(),
                        ));
                        return None;
                    }
                    let dir = if kind == SignalKind::I {
                        Dir::In
                    } else {
                        Dir::Out
                    };
                    Signal::Bit {
                        dir,
                        packet,
                        connector,
                        contact: raw.number as u8,
                    }
                }
            }
        }
    };
    let connector = match signal {
        Signal::Bit { connector, .. } | Signal::Byte { connector, .. } => connector,
    };
    if packet == Packet::A {
        if !ctx.a_declared(connector) {
            diags.push(err(
                codes::A_UNDECLARED,
                format!("packet A connector {connector} is not declared in IOCFIL"),
                format!(
                    "declared input connectors (INx): {}; output connectors (OUx): {}; add {connector} to an {} line",
                    list(&ctx.a_inputs),
                    list(&ctx.a_outputs),
                    if is_a_input_connector(connector) { "INx" } else { "OUx" }
                ),
            ));
            return None;
        }
        let input = is_a_input_connector(connector);
        match raw.kind {
            SignalKind::I if !input => {
                diags.push(err(
                    codes::I_ON_OUTPUT,
                    format!("`I` on output connector {connector}"),
                    format!(
                        "an output is written `U{connector}A{}`; inputs are on connectors {}",
                        raw.number,
                        list(&ctx.a_inputs)
                    ),
                ));
                return None;
            }
            SignalKind::U if input => {
                diags.push(err(
                    codes::U_ON_INPUT,
                    format!("`U` on input connector {connector}"),
                    format!(
                        "an input is written `I{connector}A{}`; outputs are on connectors {}",
                        raw.number,
                        list(&ctx.a_outputs)
                    ),
                ));
                return None;
            }
            _ => {}
        }
        if access == Access::Write && input {
            diags.push(err(
                codes::WRITE_INPUT,
                format!("{signal} is a physical input; the logic cannot write it"),
                format!(
                    "write an output connector ({}) or a free K/N signal instead",
                    list(&ctx.a_outputs)
                ),
            ));
            return None;
        }
    } else if access == Access::Write && raw.kind == SignalKind::I {
        diags.push(
            Diagnostic::warning(
                codes::WRITE_I_PREFIX,
                file,
                span.clone(),
                format!("the logic writes {signal}, spelled as a CNC→PLC input"),
            )
            .with_hint(format!(
                "it is the same bit as U{connector}{}{}; write it that way if the logic owns it",
                packet.letter(),
                raw.number
            )),
        );
    }
    Some(signal)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(text: &str, access: Access) -> (Option<Signal>, Vec<u32>) {
        let (tokens, _) = crate::lexer::tokenize(text);
        let crate::lexer::Tok::Signal(raw) = tokens[0].1 else {
            panic!("not a signal: {text}")
        };
        let mut d = Vec::new();
        let s = check_signal(
            &raw,
            &(0..text.len()),
            access,
            &MachineContext::lathe_like(),
            "t",
            &mut d,
        );
        (s, d.iter().map(|d| d.code).collect())
    }

    #[test]
    fn limits_and_packet_a_rules() {
        assert_eq!(
            check("I0A5", Access::Read),
            (Some("I0A5".parse().expect("sig")), vec![])
        );
        assert_eq!(
            check("U4A0", Access::Write),
            (Some("U4A0".parse().expect("sig")), vec![])
        );
        assert_eq!(
            check("U256K0", Access::Read).1,
            vec![codes::CONNECTOR_RANGE]
        );
        assert_eq!(check("I0K32", Access::Read).1, vec![codes::CONTACT_RANGE]);
        assert_eq!(check("W0K4", Access::Read).1, vec![codes::BYTE_RANGE]);
        assert_eq!(check("ST64", Access::Read).1, vec![codes::BYTE_RANGE]);
        assert_eq!(check("I2A0", Access::Read).1, vec![codes::A_UNDECLARED]);
        assert_eq!(check("I4A0", Access::Read).1, vec![codes::I_ON_OUTPUT]);
        assert_eq!(check("U1A0", Access::Read).1, vec![codes::U_ON_INPUT]);
        assert_eq!(check("I1A0", Access::Write).1, vec![codes::WRITE_INPUT]);
        assert_eq!(check("W0A1", Access::Write).1, vec![codes::WRITE_INPUT]);
        assert_eq!(
            check("I150K3", Access::Write).1,
            vec![codes::WRITE_I_PREFIX]
        );
        assert_eq!(
            check("SK13", Access::Read).0,
            Some("W3K1".parse().expect("sig"))
        );
    }
}
