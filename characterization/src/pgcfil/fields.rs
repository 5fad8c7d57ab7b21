//! Typed access to the parameters of PGCFIL and IOCFIL records, with located diagnostics.
//!
//! [`Emit`] carries the file, the current section and process and collects diagnostics; its
//! value methods turn a [`Param`] into a typed value or report the chapter-7 lexical error
//! (13–23) at the parameter's line and column. An empty parameter is `None` without an error:
//! the manual writes an omitted parameter as an empty field.

use std::ops::Range;

use diag::Diagnostic;
use serde::{Deserialize, Serialize};

use crate::reader::{ParsedFile, Param, Record};

/// A PLC signal identifier used as a "PLC variable" parameter (`I0A6`, `U10K5`, `U220K0`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct PlcVariable {
    /// `I` (read by the PLC) or `U` (written by the PLC).
    pub prefix: char,
    /// Connector number (0–255 for K and N, 0–31 for A, 0–15 for T).
    pub connector: u16,
    /// Packet letter `A`, `K`, `N` or `T`.
    pub packet: char,
    /// Contact (bit) number 0–31.
    pub contact: u8,
}

impl std::fmt::Display for PlcVariable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}{}{}{}", self.prefix, self.connector, self.packet, self.contact)
    }
}

/// Collects the diagnostics of one file while its records are decoded.
pub(crate) struct Emit<'f> {
    /// The file being decoded.
    pub file: &'f ParsedFile,
    /// Section of the record being decoded (0 before the first section).
    pub section: u32,
    /// Process of the record being decoded, when the section is per process.
    pub process: Option<u32>,
    /// Everything reported so far.
    pub diags: Vec<Diagnostic>,
}

impl<'f> Emit<'f> {
    /// A collector for `file`.
    pub fn new(file: &'f ParsedFile) -> Self {
        Emit { file, section: 0, process: None, diags: Vec::new() }
    }

    fn finish(&self, mut d: Diagnostic, hint: &str) -> Diagnostic {
        if !hint.is_empty() {
            d = d.with_hint(hint);
        }
        if self.section != 0 {
            d = d.with_section(self.section);
        }
        if let Some(p) = self.process {
            d = d.with_process(p);
        }
        d.locate(&self.file.text)
    }

    /// Reports error `code` at `span`.
    pub fn error(&mut self, code: u32, span: Range<usize>, message: impl Into<String>, hint: &str) {
        let d = Diagnostic::error(code, self.file.name.clone(), span, message);
        let d = self.finish(d, hint);
        self.diags.push(d);
    }

    /// Reports warning `code` at `span`.
    pub fn warning(&mut self, code: u32, span: Range<usize>, message: impl Into<String>, hint: &str) {
        let d = Diagnostic::warning(code, self.file.name.clone(), span, message);
        let d = self.finish(d, hint);
        self.diags.push(d);
    }

    /// Checks the parameter count of `rec` (errors 10 and 11); true when it is within `min..=max`.
    pub fn count(&mut self, rec: &Record, min: usize, max: usize) -> bool {
        let n = rec.params.len();
        let want = if min == max { format!("{min}") } else { format!("{min} to {max}") };
        if n < min {
            self.error(10, rec.span.clone(), format!("{} has {n} parameter(s), {want} expected", rec.key), "write every parameter; an omitted one is an empty field between commas");
            false
        } else if n > max {
            let span = rec.params.get(max).map_or(rec.span.clone(), |p| p.span.clone());
            self.error(11, span, format!("{} has {n} parameters, {want} expected", rec.key), "remove the extra parameters");
            false
        } else {
            true
        }
    }

    /// An "integer" parameter (−32768…32767): errors 13 and 14.
    pub fn integer(&mut self, p: &Param) -> Option<i32> {
        let t = p.text.as_str();
        if t.is_empty() {
            return None;
        }
        let digits = t.strip_prefix(['+', '-']).unwrap_or(t);
        if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
            self.error(13, p.span.clone(), format!("'{t}' is not an INTEGER"), "an INTEGER is decimal digits with an optional sign");
            return None;
        }
        match t.parse::<i64>() {
            Ok(v) if (-32768..=32767).contains(&v) => i32::try_from(v).ok(),
            _ => {
                self.error(14, p.span.clone(), format!("INTEGER {t} overflows"), "an INTEGER is within -32768 ... 32767");
                None
            }
        }
    }

    /// A "word" parameter (0…65535): errors 15 and 16.
    pub fn word(&mut self, p: &Param) -> Option<u32> {
        let t = p.text.as_str();
        if t.is_empty() {
            return None;
        }
        if !t.bytes().all(|b| b.is_ascii_digit()) {
            self.error(15, p.span.clone(), format!("'{t}' is not a WORD"), "a WORD is decimal digits only");
            return None;
        }
        match t.parse::<u64>() {
            Ok(v) if v <= 65535 => u32::try_from(v).ok(),
            _ => {
                self.error(16, p.span.clone(), format!("WORD {t} overflows"), "a WORD is within 0 ... 65535");
                None
            }
        }
    }

    /// A "real" parameter: error 20.
    pub fn real(&mut self, p: &Param) -> Option<f64> {
        let t = p.text.as_str();
        if t.is_empty() {
            return None;
        }
        let body = t.strip_prefix(['+', '-']).unwrap_or(t);
        let dots = body.bytes().filter(|&b| b == b'.').count();
        let ok = dots <= 1 && body.bytes().any(|b| b.is_ascii_digit()) && body.bytes().all(|b| b.is_ascii_digit() || b == b'.');
        match (ok, t.parse::<f64>()) {
            (true, Ok(v)) => Some(v),
            _ => {
                self.error(20, p.span.clone(), format!("'{t}' is not a REAL"), "a REAL is a decimal number such as 12, -0.5 or .7");
                None
            }
        }
    }

    /// A "hexadecimal (N digits)" parameter: errors 21 and 22.
    pub fn hex(&mut self, p: &Param, digits: usize) -> Option<u16> {
        let t = p.text.as_str();
        if t.is_empty() {
            return None;
        }
        if !t.bytes().all(|b| b.is_ascii_hexdigit()) {
            self.error(21, p.span.clone(), format!("'{t}' is not hexadecimal"), "hexadecimal digits are 0-9 and A-F");
            return None;
        }
        if t.len() > digits {
            self.error(22, p.span.clone(), format!("hexadecimal {t} has {} digits, at most {digits} allowed", t.len()), &format!("write at most {digits} hexadecimal digits"));
            return None;
        }
        u16::from_str_radix(t, 16).ok()
    }

    /// An "ASCII string" parameter (at most 10 characters): error 23.
    pub fn ascii(&mut self, p: &Param) -> Option<String> {
        let t = p.text.as_str();
        if t.is_empty() {
            return None;
        }
        if t.chars().count() > 10 {
            self.error(23, p.span.clone(), format!("ASCII parameter '{t}' is longer than 10 characters"), "an ASCII parameter has at most 10 characters");
            return None;
        }
        Some(t.to_string())
    }

    /// A "PLC variable" parameter: errors 17, 18 and 19.
    pub fn plc_variable(&mut self, p: &Param) -> Option<PlcVariable> {
        let t = p.text.as_str();
        if t.is_empty() {
            return None;
        }
        match parse_plc_variable(t) {
            Ok(v) => Some(v),
            Err((code, msg, hint)) => {
                self.error(code, p.span.clone(), msg, hint);
                None
            }
        }
    }

    /// A one-character name of `what` (interpolator names may be digits), reporting `code` otherwise.
    pub fn axis_name_like(&mut self, p: &Param, code: u32, what: &str) -> Option<char> {
        let t = self.ascii(p)?;
        let mut chars = t.chars();
        match (chars.next(), chars.next()) {
            (Some(c), None) if c.is_ascii_alphanumeric() => Some(c.to_ascii_uppercase()),
            _ => {
                self.error(code, p.span.clone(), format!("{what} name '{t}' must be one character"), &format!("an {what} name is one letter or digit"));
                None
            }
        }
    }

    /// A one-character axis name, reporting `code` when the text is longer.
    pub fn axis_name(&mut self, p: &Param, code: u32) -> Option<char> {
        let t = self.ascii(p)?;
        let mut chars = t.chars();
        match (chars.next(), chars.next()) {
            (Some(c), None) if c.is_ascii_alphabetic() => Some(c.to_ascii_uppercase()),
            _ => {
                self.error(code, p.span.clone(), format!("axis name '{t}' must be one letter"), "an axis name is a single letter such as X");
                None
            }
        }
    }
}

/// Parses `I0A6`-style identifiers; the error is (code, message, hint).
pub(crate) fn parse_plc_variable(t: &str) -> Result<PlcVariable, (u32, String, &'static str)> {
    let mut chars = t.chars();
    let prefix = match chars.next() {
        Some(c @ ('I' | 'U' | 'i' | 'u')) => c.to_ascii_uppercase(),
        _ => return Err((17, format!("PLC signal '{t}' must start with I or U"), "write a PLC signal such as I0K2 or U10K5")),
    };
    let rest = chars.as_str();
    let conn_len = rest.bytes().take_while(u8::is_ascii_digit).count();
    let (conn, rest) = rest.split_at(conn_len);
    let mut rest_chars = rest.chars();
    let packet = rest_chars.next().map(|c| c.to_ascii_uppercase());
    let contact = rest_chars.as_str();
    let packet = match packet {
        Some(c @ ('A' | 'K' | 'N' | 'T')) => c,
        _ => return Err((19, format!("PLC signal '{t}' has no packet letter K, N, A or T"), "the packet letter is K, N, A or T, as in U10K5")),
    };
    let bad = || (18, format!("wrong connector or contact number in PLC signal '{t}'"), "connector <= 255 (K, N), <= 31 (A), <= 15 (T); contact <= 31");
    if conn.is_empty() || contact.is_empty() || !contact.bytes().all(|b| b.is_ascii_digit()) || conn.len() > 5 || contact.len() > 5 {
        return Err(bad());
    }
    let connector: u32 = conn.parse().map_err(|_| bad())?;
    let contact: u32 = contact.parse().map_err(|_| bad())?;
    let max_conn = match packet {
        'A' => 31,
        'T' => 15,
        _ => 255,
    };
    if connector > max_conn || contact > 31 {
        return Err(bad());
    }
    Ok(PlcVariable { prefix, connector: u16::try_from(connector).map_err(|_| bad())?, packet, contact: u8::try_from(contact).map_err(|_| bad())? })
}
