//! The OPC UA server's tables of io.toml: `[identification]` (the machine's nameplate) and
//! `[[stacklight]]` (the lamps, top first, each lit by a PLC output bit). Read with spans so that
//! every refusal is a located diagnostic (codes 3400–3419, docs/opcua.md):
//!
//! ```toml
//! [identification]
//! manufacturer = "Baltic Systems"     # Manufacturer (LocalizedText)
//! model = "NC-110 lathe"              # Model (LocalizedText)
//! serial = "L-0001"                   # SerialNumber
//! year = 2026                         # YearOfConstruction (1900..=9999)
//!
//! [[stacklight]]
//! color = "red"                       # off red green blue yellow purple cyan white
//! signal = "U5A0"                     # the output bit that lights it
//! ```
//!
//! **Invariant:** an unknown key, a wrong type, a year out of range, an unknown colour or a
//! signal that is not an output bit is an error with its line and column; nothing is ignored.

use std::ops::Range;

use diag::Diagnostic;
use packets::{Dir, Signal};
use serde::Deserialize;
use toml::Spanned;

/// Codes of the diagnostics.
pub mod codes {
    /// io.toml is not TOML, or a table has an unknown key or a wrong type.
    pub const SYNTAX: u32 = 3400;
    /// `year` out of 1900..=9999.
    pub const YEAR: u32 = 3401;
    /// An unknown stack-light colour.
    pub const COLOR: u32 = 3402;
    /// A stack-light signal that is not an output bit.
    pub const SIGNAL: u32 = 3403;
}

/// The machine's nameplate.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Identification {
    /// Manufacturer.
    pub manufacturer: String,
    /// Model.
    pub model: String,
    /// Serial number.
    pub serial: String,
    /// Year of construction.
    pub year: Option<u16>,
}

/// One lamp of the stack light.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Lamp {
    /// IA `SignalColor` value (0 Off, 1 Red, 2 Green, 3 Blue, 4 Yellow, 5 Purple, 6 Cyan, 7 White).
    pub color: i32,
    /// The output bit that lights it.
    pub signal: Signal,
}

/// The OPC UA tables of io.toml.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Tables {
    /// `[identification]` (None: not given).
    pub identification: Option<Identification>,
    /// `[[stacklight]]`, top first.
    pub stacklight: Vec<Lamp>,
}

#[derive(Deserialize)]
struct Raw {
    identification: Option<RawIdentification>,
    #[serde(default)]
    stacklight: Vec<RawLamp>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawIdentification {
    manufacturer: Option<String>,
    model: Option<String>,
    serial: Option<String>,
    year: Option<Spanned<i64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLamp {
    color: Spanned<String>,
    signal: Spanned<String>,
}

/// The IA colours in `SignalColor` order.
pub const COLORS: [&str; 8] = [
    "off", "red", "green", "blue", "yellow", "purple", "cyan", "white",
];

fn err(file: &str, code: u32, span: Range<usize>, msg: String, hint: &str) -> Diagnostic {
    Diagnostic::error(code, file, span, msg).with_hint(hint)
}

/// Parses the tables of io.toml's text `text` (named `file`); the other tables are fieldbus's.
pub fn parse(file: &str, text: &str) -> Result<Tables, Vec<Diagnostic>> {
    let hint = "[identification] takes manufacturer, model, serial, year; [[stacklight]] takes color and signal (docs/opcua.md)";
    let raw: Raw = diag::toml_keys::from_toml_diagnosed(text, file, codes::SYNTAX, hint)?;
    let mut diags = Vec::new();
    let identification = raw.identification.map(|i| Identification {
        manufacturer: i.manufacturer.unwrap_or_default(),
        model: i.model.unwrap_or_default(),
        serial: i.serial.unwrap_or_default(),
        year: i.year.and_then(|y| match u16::try_from(*y.get_ref()) {
            Ok(v) if (1900..=9999).contains(&v) => Some(v),
            _ => {
                diags.push(err(
                    file,
                    codes::YEAR,
                    y.span(),
                    format!("year {} is out of range", y.get_ref()),
                    "give the year of construction, 1900..9999",
                ));
                None
            }
        }),
    });
    let mut stacklight = Vec::new();
    for lamp in raw.stacklight {
        let color = COLORS
            .iter()
            .position(|c| c.eq_ignore_ascii_case(lamp.color.get_ref()))
            .and_then(|i| i32::try_from(i).ok());
        if color.is_none() {
            diags.push(err(
                file,
                codes::COLOR,
                lamp.color.span(),
                format!("unknown stack-light colour `{}`", lamp.color.get_ref()),
                "use off, red, green, blue, yellow, purple, cyan or white",
            ));
        }
        let signal = match lamp.signal.get_ref().parse::<Signal>() {
            Ok(s @ Signal::Bit { dir: Dir::Out, .. }) => Some(s),
            _ => {
                diags.push(err(
                    file,
                    codes::SIGNAL,
                    lamp.signal.span(),
                    format!("`{}` is not an output bit", lamp.signal.get_ref()),
                    "a lamp is lit by a PLC output bit, e.g. U5A0 or U40K3",
                ));
                None
            }
        };
        if let (Some(color), Some(signal)) = (color, signal) {
            stacklight.push(Lamp { color, signal });
        }
    }
    if diags.is_empty() {
        Ok(Tables {
            identification,
            stacklight,
        })
    } else {
        Err(diags)
    }
}

/// Reads the tables of `<machine>/io.toml` (none without the file).
pub fn load(machine_dir: &std::path::Path) -> Result<Tables, Vec<Diagnostic>> {
    match diag::read_config(&machine_dir.join("io.toml")) {
        Ok(text) => parse("io.toml", &text),
        Err(_) => Ok(Tables::default()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tables_parse_with_their_values() {
        let text = "[hmi]\nbind = \"127.0.0.1:1502\"\n[identification]\nmanufacturer = \"Baltic\"\nmodel = \"NC-110\"\nserial = \"L-1\"\nyear = 2026\n[[stacklight]]\ncolor = \"Red\"\nsignal = \"U5A0\"\n[[stacklight]]\ncolor = \"green\"\nsignal = \"U40K3\"\n";
        let t = parse("io.toml", text).expect("valid");
        assert_eq!(
            t.identification,
            Some(Identification {
                manufacturer: "Baltic".into(),
                model: "NC-110".into(),
                serial: "L-1".into(),
                year: Some(2026),
            })
        );
        assert_eq!(
            t.stacklight,
            vec![
                Lamp {
                    color: 1,
                    signal: "U5A0".parse().expect("signal")
                },
                Lamp {
                    color: 2,
                    signal: "U40K3".parse().expect("signal")
                },
            ]
        );
    }

    #[test]
    fn bad_tables_are_located_errors() {
        let text = "[identification]\nmaker = \"x\"\n";
        let d = parse("io.toml", text).expect_err("unknown key");
        assert_eq!(d[0].code, codes::SYNTAX);
        assert_eq!(&text[d[0].span.clone()], "maker");
        let text =
            "[identification]\nyear = 99999\n[[stacklight]]\ncolor = \"pink\"\nsignal = \"I0A1\"\n";
        let d = parse("io.toml", text).expect_err("bad values");
        let got: Vec<(u32, &str)> = d.iter().map(|d| (d.code, &text[d.span.clone()])).collect();
        assert_eq!(
            got,
            vec![
                (codes::YEAR, "99999"),
                (codes::COLOR, "\"pink\""),
                (codes::SIGNAL, "\"I0A1\""),
            ]
        );
    }
}
